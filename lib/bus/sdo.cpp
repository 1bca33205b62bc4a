// SPDX-License-Identifier: MIT
// SDO upload/download through ECAT_SDO_REQ / ECAT_SDO_GET, the abort code
// of a failed transfer (ECAT_SDO_ABORTCODE_GET) in words, and SdoError
// (include/ecmxf/device.hpp section "bus", Documentation/sdo.rst).

#include "bus/bus_internal.hpp"

#include <algorithm>
#include <cerrno>
#include <string>
#include <vector>

#include "ecmxf-proto.h"

namespace ecmxf {

std::string_view sdoAbortText(std::uint32_t code) noexcept
{
	// The ETG table of manual ver. 050 (ECM_CMD_ECAT_SDO_ABORTCODE_GET),
	// its wording.
	switch (code) {
	case 0x00000000:
		return "No SDO error";
	case 0x05030000:
		return "Toggle bit not changed";
	case 0x05040000:
		return "SDO timeout";
	case 0x05040001:
		return "Command specifier unknown";
	case 0x05040005:
		return "Out of memory";
	case 0x06010000:
		return "Unsupported Access";
	case 0x06010001:
		return "Write only entry";
	case 0x06010002:
		return "Read only entry";
	case 0x06010003:
		return "Entry can not be written because Subindex0 is not 0";
	case 0x06010004:
		return "The object can not be accessed via complete access";
	case 0x06020000:
		return "Object not existing";
	case 0x06040041:
		return "Object can not be mapped to PDO";
	case 0x06040042:
		return "Mapped Object exceeds PDO";
	case 0x06040043:
		return "Parameter is incompatible";
	case 0x06040047:
		return "Device incompatibility";
	case 0x06060000:
		return "Hardware error";
	case 0x06070010:
		return "Parameter length error";
	case 0x06070012:
		return "Parameter is too long";
	case 0x06070013:
		return "Parameter is too short";
	case 0x06090011:
		return "Subindex (Entry) not exists";
	case 0x06090030:
		return "Value exceeds";
	case 0x06090031:
		return "Value is too great";
	case 0x06090032:
		return "Value is too small";
	case 0x06090033:
		return "Detected Module Ident List (0xF030) and Configured Module Ident list (0xF050) does not match";
	case 0x06090036:
		return "Value is less than minimum value";
	case 0x08000000:
		return "General error";
	case 0x08000020:
		return "Data can not be read or written";
	case 0x08000021:
		return "Data can not be accessed because of local control";
	case 0x08000022:
		return "Data can not be read or written in the current state";
	case 0x08000023:
		return "Object is not in the object dictionary";
	default:
		return "unknown abort code";
	}
}

SdoError::SdoError(const std::string &message, int errnoValue, std::uint32_t abortCode,
		   std::optional<std::uint8_t> errorStatus)
	: Error(message, errnoValue, errorStatus), abortCode_(abortCode)
{
}

SdoError::~SdoError() = default;

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

/// Runs the SDO_REQ; a failure on the bus becomes an SdoError with the
/// abort code and its text.
void runSdo(Device &dev, const Command &c, const std::string &what, std::uint8_t slave)
{
	try {
		bus::async(dev, c, what, slave);
	} catch (const Error &e) {
		if (e.errnoValue() != EREMOTEIO)
			throw;
		const std::uint32_t ab = dev.sdoAbortCode();
		if (ab == 0)
			throw SdoError(what + " failed: the chip reported an error (error status bit 3) but no abort "
					      "code",
				       EREMOTEIO, 0, e.errorStatus());
		throw SdoError(what + " aborted: " + bus::hex(ab, 8) + " " + std::string(sdoAbortText(ab)), EREMOTEIO,
			       ab, e.errorStatus());
	}
}

} // namespace

std::vector<std::uint8_t> Device::sdoUpload(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
					    const SdoOptions &options)
{
	const std::string what = transferName(true, slave, index, sub);
	checkCommon(what, slave, options);
	if (options.length > kSdoMaxBytes)
		throw Error(what + ": " + std::to_string(options.length) +
				    " bytes requested, the chip moves at most 256 bytes per SDO request",
			    EMSGSIZE);
	runSdo(*this, sdoRequest(true, slave, index, sub, options.length, options), what, slave);
	Response r = bus::immediate(*this, bus::cmd(ECMXF_CMD_ECAT_SDO_GET), what + ": ECAT_SDO_GET");
	// the answer is clipped to the data section: a full section may
	// hide a longer object
	if (r.data.size() >= ECMXF_DATA_MIN && r.data.size() != options.length) {
		const Response s = bus::immediate(*this, bus::cmd(ECMXF_CMD_SPI_PACK_SIZE_GET), "SPI_PACK_SIZE_GET");
		const std::uint16_t section = bus::le16(s.data);
		if (r.data.size() >= section)
			throw Error(what + ": the answer fills the whole data section (" + std::to_string(section) +
					    " bytes), the object may be longer; enlarge the data section "
					    "(SPI_RECONFIG_OP) or pass SdoOptions::length",
				    EMSGSIZE);
	}
	return std::move(r.data);
}

void Device::sdoDownload(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
			 std::span<const std::uint8_t> data, const SdoOptions &options)
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
	runSdo(*this, c, what, slave);
}

std::string Device::sdoReadString(std::uint8_t slave, std::uint16_t index, std::uint8_t sub,
				  const SdoOptions &options)
{
	const std::vector<std::uint8_t> b = sdoUpload(slave, index, sub, options);
	std::string s(b.begin(), b.end());
	while (!s.empty() && s.back() == '\0')
		s.pop_back();
	return s;
}

void Device::sdoWriteString(std::uint8_t slave, std::uint16_t index, std::uint8_t sub, std::string_view value,
			    const SdoOptions &options)
{
	sdoDownload(slave, index, sub,
		    std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t *>(value.data()), value.size()),
		    options);
}

} // namespace ecmxf
