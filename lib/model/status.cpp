// SPDX-License-Identifier: MIT
// Names for the header status bytes, interrupt flags, EtherCAT states,
// check types, master series and FoE error codes (include/ecmxf/model/status.hpp;
// bit meanings from manual ver. 050, table 2 and ECM_CMD_ECAT_INT_SET_ENABLE).

#include <ecmxf/model/status.hpp>
#include <ecmxf/model/types_bus.hpp>

#include <cstdio>

#include "base/text.hpp"

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

/// The interrupt flag bits with a name; the others are reserved.
constexpr detail::CodeText<unsigned> kIntNames[] = {
	{ 31, "EtherCAT packet" },
	{ 29, "encoder" },
	{ 25, "RxFIFO low mark" },
	{ 24, "TxFIFO high mark" },
	{ 23, "CRC error" },
	{ 22, "WKC error" },
};

constexpr detail::CodeText<CheckType> kCheckTypeNames[] = {
	{ CheckType::Fixed, "fixed" },
	{ CheckType::Crc8, "CRC-8" },
	{ CheckType::Ccitt, "CRC-CCITT" },
	{ CheckType::Crc32, "CRC-32" },
};

constexpr detail::CodeText<MasterSeries> kSeriesNames[] = {
	{ MasterSeries::XF, "ECM-XF" },
	{ MasterSeries::XFL, "ECM-XFL" },
	{ MasterSeries::XFU, "ECM-XFU" },
	{ MasterSeries::XM, "ECM-XM" },
};

/// FoE error codes in words.
constexpr detail::CodeText<std::uint32_t> kFoeErrorTexts[] = {
	// ETG.1000.6, FoE error request
	{ 0x8000, "not defined" },
	{ 0x8001, "file not found" },
	{ 0x8002, "access denied" },
	{ 0x8003, "disk full" },
	{ 0x8004, "illegal" },
	{ 0x8005, "packet number wrong" },
	{ 0x8006, "file already exists" },
	{ 0x8007, "no user" },
	{ 0x8008, "bootstrap only" },
	{ 0x8009, "not in bootstrap" },
	{ 0x800A, "no rights" },
	{ 0x800B, "program error" },
	{ 0x800C, "checksum error" },
	// the chip's own codes (the SDO abort code table of manual ver. 050)
	{ 0x05040000, "timeout (the slave did not answer)" },
	{ 0x05040005, "out of memory (the file does not fit the flash)" },
	{ 0x08000000, "general error (e.g. the slave has no FoE)" },
	{ 0x08000022, "cannot transfer in the slave's present state" },
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

/// The bits of @p status from bit @p first up that are set, with their
/// names from @p names.
std::vector<StatusBit> namedBits(std::uint8_t status, const std::string_view (&names)[8], unsigned first)
{
	std::vector<StatusBit> out;
	for (unsigned b = first; b < 8; b++)
		if (status & (1u << b))
			out.push_back({ b, names[b] });
	return out;
}

} // namespace

std::vector<StatusBit> errorStatusBits(std::uint8_t status)
{
	return namedBits(status, kErrNames, 0);
}

std::string describeErrorStatus(std::uint8_t status)
{
	return joined(errorStatusBits(status));
}

std::vector<StatusBit> ecmStatusBits(std::uint8_t status)
{
	return namedBits(status, kEcmNames, 2); // bits 1-0 are the check type
}

std::string describeEcmStatus(std::uint8_t status)
{
	return joined(ecmStatusBits(status));
}

std::string_view checkTypeName(CheckType type) noexcept
{
	return detail::textOf(kCheckTypeNames, type, "unknown");
}

std::vector<StatusBit> interruptFlagBits(std::uint32_t flags)
{
	std::vector<StatusBit> out;
	for (unsigned b = 32; b-- > 0;)
		if (flags & (1u << b))
			out.push_back({ b, detail::textOf(kIntNames, b, "reserved") });
	return out;
}

std::string describeInterruptFlags(std::uint32_t flags)
{
	return joined(interruptFlagBits(flags));
}

std::string ecatStateName(std::uint8_t state)
{
	// the names are stateName()'s (lib/model/al_status.cpp): one table
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
	const std::string_view name = detail::textOf(kSeriesNames, static_cast<MasterSeries>(seriesCode), {});
	if (name.empty())
		return std::string("unknown (").append(std::to_string(seriesCode)).append(")");
	return std::string(name);
}

std::string_view foeErrorText(std::uint32_t code) noexcept
{
	return detail::textOf(kFoeErrorTexts, code, "unknown error code");
}

} // namespace ecmxf
