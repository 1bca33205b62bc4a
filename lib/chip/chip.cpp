// SPDX-License-Identifier: MIT
// Chip (include/ecmxf/chip/chip.hpp): the chip itself: firmware and link
// format, counters, interrupts, resets (Documentation/commands-chip.rst).
// Every call builds its command at the offsets of manual ver. 050 (ver. 038
// where only it documents the command), checks its arguments first, and
// runs it through the one command runner (lib/device/runner.hpp).

#include <ecmxf/chip/chip.hpp>

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/protocol.hpp>
#include <ecmxf/model/status.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <string>

#include "device/runner.hpp"
#include "ecmxf-proto.h"

namespace ecmxf {

using namespace detail; // the command runner and its helpers

Chip Device::chip() noexcept
{
	return Chip(*this);
}

ResponseHeader Chip::infoUpdate(const InfoUpdateOptions &options) const
{
	const std::string what = "INFO_UPDATE_OP";
	if (options.clearErrorBits & ~ECMXF_ERR_FAULT_MASK)
		invalid(what, "error bits " + hex(options.clearErrorBits, 2) +
				      " include bits 0..2, which cannot be cleared (clearable: bits 3..7 = 0xF8)");
	Command c = detail::cmd(ECMXF_CMD_INFO_UPDATE_OP);
	c.control = static_cast<std::uint8_t>(options.clearErrorBits | (options.refreshEcatState ? ECMXF_CTL_REFRESH_STATE : 0u) |
					      (options.clearCrcErrorCount ? ECMXF_CTL_CLR_CRC_CNT : 0u));
	return dev_->command(c).header;
}

FirmwareVersion Chip::firmwareVersion() const
{
	const Response r = immediate(*dev_, detail::cmd(ECMXF_CMD_FW_VERSION_GET));
	FirmwareVersion v;
	v.version = r.ret;
	if (r.data.size() < 4)
		return v; // firmware of manual ver. 038: the return value only
	v.detailed = true;
	v.extendedVersion = r.data[1];
	v.seriesCode = r.data[3];
	if (v.seriesCode <= static_cast<std::uint8_t>(MasterSeries::XM))
		v.series = static_cast<MasterSeries>(v.seriesCode);
	const std::size_t n = std::min<std::size_t>(r.data.size(), 20) - 4;
	std::copy_n(r.data.begin() + 4, n, v.buildIdBytes.begin());
	bool printable = true;
	std::string text;
	for (std::uint8_t b : v.buildIdBytes) {
		if (b == 0)
			break;
		if (b < 0x20 || b > 0x7E)
			printable = false;
		text.push_back(static_cast<char>(b));
	}
	if (printable) {
		v.buildId = text;
	} else {
		for (std::uint8_t b : v.buildIdBytes) {
			char buf[4];
			std::snprintf(buf, sizeof(buf), "%02x", b);
			v.buildId.append(buf);
		}
	}
	return v;
}

ChipInfo Chip::info() const
{
	ChipInfo i;
	i.firmware = firmwareVersion();
	i.dataSize = queryDataSize();
	i.packetSize = packetSize(i.dataSize);
	i.wkcErrorLimit = wkcErrorLimit();
	try {
		i.wkcContinuousErrors = wkcContinuousErrorCount();
	} catch (const Error &e) {
		// firmware of manual ver. 038 does not know command 130
		if (!(e.errnoValue() == EINVAL && e.errorStatus() && (*e.errorStatus() & ECMXF_ERR_CMD)))
			throw;
	}
	i.checkType = dev_->checkType();
	i.crcCoverage = dev_->link().crcCoverage();
	const ResponseHeader h = dev_->lastHeader();
	i.ecatState = h.ecatState;
	i.errorStatus = h.errStatus;
	i.ecmStatus = h.ecmStatus;
	i.interruptFlags = h.intFlags;
	i.crcErrors = h.crcErrCnt;
	i.wkcErrors = h.wkcErrCnt;
	return i;
}

std::uint16_t Chip::queryDataSize() const
{
	const Response r = immediate(*dev_, detail::cmd(ECMXF_CMD_SPI_PACK_SIZE_GET));
	needData("SPI_PACK_SIZE_GET", r, 2);
	return le16(r.data, 0);
}

void Chip::setDataSize(std::uint16_t bytes) const
{
	if (bytes < kDataMin || bytes > kDataMax)
		invalid("SPI_RECONFIG_OP", "data section size " + std::to_string(bytes) +
						   " is out of range (32..1408 bytes)");
	Command c = detail::cmd(ECMXF_CMD_SPI_RECONFIG_OP);
	c.len = bytes;
	immediate(*dev_, c, {}, "the firmware does not accept this size (an ECM-XFU has a fixed 992)");
}

void Chip::setCheckType(CheckType type) const
{
	const auto t = static_cast<unsigned>(type);
	if (t > 3)
		invalid("CRC_TYPE_SET", "check type " + std::to_string(t) +
						" is out of range (0 fixed, 1 CRC-8, 2 CRC-CCITT, 3 CRC-32)");
	immediate(*dev_, detail::cmd(ECMXF_CMD_CRC_TYPE_SET, static_cast<std::uint8_t>(t)), {},
		  "check type " + std::string(checkTypeName(type)) + " is unknown to this firmware");
}

std::uint8_t Chip::clearCrcErrorCount() const
{
	return immediate(*dev_, detail::cmd(ECMXF_CMD_CRC_ERR_CNT_CLR)).ret;
}

std::uint8_t Chip::wkcContinuousErrorCount() const
{
	return immediate(*dev_, detail::cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_CNT_GET)).ret;
}

std::uint8_t Chip::wkcErrorLimit() const
{
	return immediate(*dev_, detail::cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET)).ret;
}

void Chip::setWkcErrorLimit(std::uint8_t limit) const
{
	if (limit == 0)
		invalid("ECAT_WKC_CONTI_ERR_MAX_SET", "limit 0 is out of range (1..254 errors, 255 = no limit)");
	immediate(*dev_, detail::cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET, limit));
}

void Chip::setInterruptConfig(const InterruptConfig &config) const
{
	const std::string what = "ECAT_INT_SET_ENABLE";
	if (config.sources & ~irq::kEnableMask)
		invalid(what, "interrupt sources " + hex(config.sources, 8) +
				      " include bits that cannot be enabled (allowed: bits 31, 25, 24, 23, 22 = " +
				      hex(irq::kEnableMask, 8) + "; the encoder is enabled by the QEI sources)");
	if (config.gpioLines & ~0x0FFFu)
		invalid(what, "GPIO lines " + hex(config.gpioLines, 4) +
				      " include lines above GPIO 11 (GPIO interrupts to INT1: GPIO 0..11)");
	Command c = detail::cmd(ECMXF_CMD_ECAT_INT_SET_ENABLE,
			   static_cast<std::uint8_t>((config.int1ActiveHigh ? 1u : 0u) | (config.int0ActiveHigh ? 2u : 0u)));
	c.payload.assign(6, 0);
	put32At(c.payload, 0, config.sources);
	c.payload[4] = static_cast<std::uint8_t>(config.gpioLines);
	c.payload[5] = static_cast<std::uint8_t>(((config.gpioLines >> 8) & 0x0Fu) | (config.qeiIndex ? 0x10u : 0u) |
						 (config.qeiCompare ? 0x20u : 0u) | (config.qeiOverflow ? 0x40u : 0u));
	immediate(*dev_, c);
}

InterruptConfig Chip::interruptConfig() const
{
	const Response r = immediate(*dev_, detail::cmd(ECMXF_CMD_ECAT_INT_GET_ENABLE));
	needData("ECAT_INT_GET_ENABLE", r, 6);
	InterruptConfig c;
	c.int1ActiveHigh = (r.ret & 1u) != 0;
	c.int0ActiveHigh = (r.ret & 2u) != 0;
	c.sources = le32(r.data, 0);
	c.gpioLines = static_cast<std::uint16_t>(r.data[4] | (r.data[5] & 0x0Fu) << 8);
	c.qeiIndex = (r.data[5] & 0x10u) != 0;
	c.qeiCompare = (r.data[5] & 0x20u) != 0;
	c.qeiOverflow = (r.data[5] & 0x40u) != 0;
	return c;
}

void Chip::resetAsyncCommand(std::uint8_t actions) const
{
	if (actions == 0 || actions > 7)
		invalid("ASYNCCMD_RESET", "actions " + hex(actions, 2) +
						  " are out of range (bit 0 clear busy, bit 1 skip link wait, bit 2 "
						  "abandon the command: 0x01..0x07)");
	// a link capability: the kernel module sends ASYNCCMD_RESET only
	// through ECMXF_IOC_RESET (ECMXF_IOC_CMD refuses code 75; driver.rst)
	dev_->link().reset(LinkReset::AsyncCmd, actions);
}

void Chip::warmReset() const
{
	// a link capability: the kernel module sends WARM_RESET only through
	// ECMXF_IOC_RESET; an engine link runs it and follows to the power-on
	// format
	dev_->link().reset(LinkReset::Warm);
}

} // namespace ecmxf
