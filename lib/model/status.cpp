// SPDX-License-Identifier: MIT
// Names for the header status bytes, interrupt flags, EtherCAT states,
// check types, master series and FoE error codes (include/ecmxf/model/status.hpp;
// bit meanings from manual ver. 050, table 2 and ECM_CMD_ECAT_INT_SET_ENABLE).

#include <ecmxf/model/status.hpp>
#include <ecmxf/model/types_bus.hpp>

#include <cstdio>

namespace ecmxf {

namespace {

constexpr std::string_view kErrNames[8] = {
	"link",          // bit 0: PIN 52 LINK (1 = linked in the simulator)
	"link at INIT_OP", // bit 1: PHY link checked by ECAT_INIT_OP
	"reserved",      // bit 2
	"async command error",
	"SPI error",
	"FIFO error",
	"SPI CRC error",
	"command error",
};

constexpr std::string_view kEcmNames[8] = {
	"", "", // bits 1-0: the check type
	"DC stable",
	"Ethernet initialised",
	"PDO configured",
	"NOP",
	"FIFO enabled",
	"async command busy",
};

std::string joined(const std::vector<StatusBit> &bits)
{
	if (bits.empty())
		return "none";
	std::string s;
	for (const StatusBit &b : bits) {
		if (!s.empty())
			s.append(", ");
		s.append(b.name).append(" (bit ").append(std::to_string(b.bit)).append(")");
	}
	return s;
}

std::string_view intName(unsigned bit)
{
	switch (bit) {
	case 31:
		return "EtherCAT packet";
	case 29:
		return "encoder";
	case 25:
		return "RxFIFO low mark";
	case 24:
		return "TxFIFO high mark";
	case 23:
		return "CRC error";
	case 22:
		return "WKC error";
	default:
		return "reserved";
	}
}

} // namespace

std::vector<StatusBit> errorStatusBits(std::uint8_t status)
{
	std::vector<StatusBit> out;
	for (unsigned b = 0; b < 8; b++)
		if (status & (1u << b))
			out.push_back({ b, kErrNames[b] });
	return out;
}

std::string describeErrorStatus(std::uint8_t status)
{
	return joined(errorStatusBits(status));
}

std::vector<StatusBit> ecmStatusBits(std::uint8_t status)
{
	std::vector<StatusBit> out;
	for (unsigned b = 2; b < 8; b++)
		if (status & (1u << b))
			out.push_back({ b, kEcmNames[b] });
	return out;
}

std::string describeEcmStatus(std::uint8_t status)
{
	return joined(ecmStatusBits(status));
}

std::string_view checkTypeName(CheckType type) noexcept
{
	switch (type) {
	case CheckType::Fixed:
		return "fixed";
	case CheckType::Crc8:
		return "CRC-8";
	case CheckType::Ccitt:
		return "CRC-CCITT";
	case CheckType::Crc32:
		return "CRC-32";
	}
	return "unknown";
}

std::vector<StatusBit> interruptFlagBits(std::uint32_t flags)
{
	std::vector<StatusBit> out;
	for (unsigned b = 32; b-- > 0;)
		if (flags & (1u << b))
			out.push_back({ b, intName(b) });
	return out;
}

std::string describeInterruptFlags(std::uint32_t flags)
{
	return joined(interruptFlagBits(flags));
}

std::string ecatStateName(std::uint8_t state)
{
	// the names are stateName()'s (lib/bus/al_status.cpp): one table
	const bool error = (state & 0x10u) != 0;
	const auto base = static_cast<std::uint8_t>(state & 0x0Fu);
	const std::string name = base == 0 ? std::string(error ? "" : "NONE") : stateName(static_cast<State>(base));
	if ((state & 0xE0u) != 0 || name.rfind("0x", 0) == 0) {
		char buf[24];
		std::snprintf(buf, sizeof(buf), "unknown (0x%02X)", state);
		return buf;
	}
	if (error)
		return name.empty() ? "ERROR" : name + "+ERROR";
	return name;
}

std::string masterSeriesName(std::uint8_t seriesCode)
{
	switch (seriesCode) {
	case static_cast<std::uint8_t>(MasterSeries::XF):
		return "ECM-XF";
	case static_cast<std::uint8_t>(MasterSeries::XFL):
		return "ECM-XFL";
	case static_cast<std::uint8_t>(MasterSeries::XFU):
		return "ECM-XFU";
	case static_cast<std::uint8_t>(MasterSeries::XM):
		return "ECM-XM";
	default:
		return std::string("unknown (").append(std::to_string(seriesCode)).append(")");
	}
}

std::string_view foeErrorText(std::uint32_t code) noexcept
{
	switch (code) {
	// ETG.1000.6, FoE error request
	case 0x8000:
		return "not defined";
	case 0x8001:
		return "file not found";
	case 0x8002:
		return "access denied";
	case 0x8003:
		return "disk full";
	case 0x8004:
		return "illegal";
	case 0x8005:
		return "packet number wrong";
	case 0x8006:
		return "file already exists";
	case 0x8007:
		return "no user";
	case 0x8008:
		return "bootstrap only";
	case 0x8009:
		return "not in bootstrap";
	case 0x800A:
		return "no rights";
	case 0x800B:
		return "program error";
	case 0x800C:
		return "checksum error";
	// the chip's own codes (the SDO abort code table of manual ver. 050)
	case 0x05040000:
		return "timeout (the slave did not answer)";
	case 0x05040005:
		return "out of memory (the file does not fit the flash)";
	case 0x08000000:
		return "general error (e.g. the slave has no FoE)";
	case 0x08000022:
		return "cannot transfer in the slave's present state";
	default:
		return "unknown error code";
	}
}

} // namespace ecmxf
