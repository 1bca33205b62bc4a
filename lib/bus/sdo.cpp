// SPDX-License-Identifier: MIT
// SDO upload/download through ECAT_SDO_REQ / ECAT_SDO_GET and the one
// SDO-abort map (bus::throwSdoAbort) (include/ecmxf/bus/sdo.hpp,
// Documentation/sdo.rst). The abort codes in words and SdoError are the
// shared vocabulary's (lib/model/sdo_abort.cpp).

#include <ecmxf/bus/sdo.hpp>

#include <ecmxf/bus/bus.hpp>

#include "bus/bus_internal.hpp"

#include <algorithm>
#include <cerrno>
#include <string>
#include <vector>

#include "ecmxf-proto.h"

namespace ecmxf {

namespace detail {

void throwSdoSizeMismatch(std::uint8_t slave, std::uint16_t index, std::uint8_t sub, std::size_t got,
			  std::size_t want)
{
	throw Error("SDO upload " + bus::objName(index, sub) + " from slave " + std::to_string(slave) +
			    ": the object has " + std::to_string(got) + " bytes, the value read has " +
			    std::to_string(want),
		    EPROTO);
}

} // namespace detail

void bus::throwSdoAbort(const Bus &b, const std::string &what, const Error &e)
{
	if (e.errnoValue() != EREMOTEIO)
		throw;
	const std::uint32_t ab = b.sdoAbortCode();
	if (ab == 0)
		throw SdoError(what + " failed: the chip reported an error (error status bit 3) but no abort code",
			       EREMOTEIO, 0, e.errorStatus());
	throw SdoError(what + " aborted: " + bus::hex(ab, 8) + " " + std::string(sdoAbortText(ab)), EREMOTEIO, ab,
		       e.errorStatus());
}

Sdo Device::sdo() noexcept
{
	return Sdo(*this);
}

namespace {

/// Time for the chip beyond the slave's own SDO timeout.
constexpr std::chrono::microseconds kChipMargin{ 1'000'000 };

std::string transferName(bool upload, std::uint8_t slave, std::uint16_t index, std::uint8_t sub)
{
	return std::string(upload ? "SDO upload " : "SDO download ") + bus::objName(index, sub) +
	       (upload ? " from slave " : " to slave ") + std::to_string(slave);
}

Command sdoRequest(bool upload, std::uint8_t slave, std::uint16_t index, std::uint8_t sub, std::uint16_t len,
		   const SdoOptions &o)
{
	Command c = bus::cmd(ECMXF_CMD_ECAT_SDO_REQ);
	c.payload = { static_cast<std::uint8_t>(upload ? 1 : 0), slave };
	bus::put16(c.payload, index);
	c.payload.push_back(sub);
	c.payload.push_back(0); // 0x05 reserved
	bus::put16(c.payload, len);
	const auto us = std::clamp<std::int64_t>(o.timeout.count(), 0, UINT32_MAX);
	bus::put32(c.payload, static_cast<std::uint32_t>(us)); // 0x08 timeout in µs, 0 = chip default
	if (us > 0)
		c.timeout = std::chrono::microseconds(us) + kChipMargin;
	return c;
}

void checkCommon(const std::string &what, std::uint8_t slave, const SdoOptions &o)
{
	bus::checkSlave(slave, what.c_str(), false);
	if (o.completeAccess)
		throw Error(what + ": complete access is not available: ECAT_SDO_REQ has no complete-access "
				   "field (byte 0x05 is reserved in manual ver. 038 and 050); transfer the "
				   "subindices one by one",
			    EOPNOTSUPP);
}

/// Runs the SDO_REQ (an upload: with its ECAT_SDO_GET as the fetch, whose
/// answer is returned); a failure on the bus becomes an SdoError with the
/// abort code and its text.
Response runSdo(const Sdo &sdo, const Command &c, const std::string &what, std::uint8_t slave, bool upload)
{
	try {
		if (upload)
			return detail::asyncWithFetch(sdo.device(), c, bus::cmd(ECMXF_CMD_ECAT_SDO_GET), what, slave);
		return detail::async(sdo.device(), c, what, {}, {}, slave);
	} catch (const Error &e) {
		bus::throwSdoAbort(sdo.device().bus(), what, e);
	}
}

} // namespace

std::vector<std::uint8_t> Sdo::upload(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
				      const SdoOptions &options) const
{
	const std::string what = transferName(true, slave, index, sub);
	checkCommon(what, slave, options);
	if (options.length > kSdoMaxBytes)
		throw Error(what + ": " + std::to_string(options.length) +
				    " bytes requested, the chip moves at most 256 bytes per SDO request",
			    EMSGSIZE);
	Response r = runSdo(*this, sdoRequest(true, slave, index, sub, options.length, options), what, slave, true);
	// the answer is clipped to the data section: a full section may
	// hide a longer object
	if (r.data.size() >= ECMXF_DATA_MIN && r.data.size() != options.length) {
		const Response s = detail::immediate(*dev_, bus::cmd(ECMXF_CMD_SPI_PACK_SIZE_GET), "SPI_PACK_SIZE_GET");
		const std::uint16_t section = bus::le16(s.data);
		if (r.data.size() >= section)
			throw Error(what + ": the answer fills the whole data section (" + std::to_string(section) +
					    " bytes), the object may be longer; enlarge the data section "
					    "(SPI_RECONFIG_OP) or pass SdoOptions::length",
				    EMSGSIZE);
	}
	return std::move(r.data);
}

void Sdo::download(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
		   std::span<const std::uint8_t> data, const SdoOptions &options) const
{
	const std::string what = transferName(false, slave, index, sub);
	checkCommon(what, slave, options);
	if (data.empty())
		throw Error(what + ": no data (1..256 bytes)", EINVAL);
	if (data.size() > kSdoMaxBytes)
		throw Error(what + ": " + std::to_string(data.size()) +
				    " bytes, the chip moves at most 256 bytes per SDO request",
			    EMSGSIZE);
	Command c = sdoRequest(false, slave, index, sub, static_cast<std::uint16_t>(data.size()), options);
	c.payload.insert(c.payload.end(), data.begin(), data.end()); // at 0x0C (the table's 0x12 is a typo)
	runSdo(*this, c, what, slave, false);
}

std::string Sdo::readString(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
			    const SdoOptions &options) const
{
	const std::vector<std::uint8_t> b = upload(slave, index, sub, options);
	std::string s(b.begin(), b.end());
	while (!s.empty() && s.back() == '\0')
		s.pop_back();
	return s;
}

void Sdo::writeString(std::uint8_t slave, std::uint16_t index, std::uint8_t sub, std::string_view value,
		      const SdoOptions &options) const
{
	download(slave, index, sub,
		 std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t *>(value.data()), value.size()),
		 options);
}

} // namespace ecmxf
