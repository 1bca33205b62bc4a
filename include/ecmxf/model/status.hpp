// SPDX-License-Identifier: MIT
/**
 * @file status.hpp
 * @brief Names for the status words a user reads: the response header's
 *        error status, ECM status, EtherCAT state and interrupt flags,
 *        check types, master series and FoE error codes.
 *
 * The bit meanings are those of manual ver. 050, table 2 (response header)
 * and ECM_CMD_ECAT_INT_SET_ENABLE; Documentation/commands-chip.rst lists
 * them. Every function is pure and allocation is limited to the returned
 * strings.
 */
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/export.hpp>
#include <ecmxf/protocol.hpp>
#include <ecmxf/model/types_chip.hpp>

namespace ecmxf {

/// One named bit of a status byte or word.
struct StatusBit {
	unsigned bit;          ///< bit number
	std::string_view name; ///< e.g. "async command error"

	friend bool operator==(const StatusBit &, const StatusBit &) = default;
};

/// The set bits of an error-status byte (response header 0x09), low bit
/// first: 0 "link", 1 "link at INIT_OP", 2 "reserved", 3 "async command
/// error", 4 "SPI error", 5 "FIFO error", 6 "SPI CRC error", 7 "command
/// error". Bits 0 and 1 report the link's presence, not a fault.
[[nodiscard]] ECMXF_EXPORT std::vector<StatusBit> errorStatusBits(std::uint8_t status);

/// The error-status byte in words: "link (bit 0), async command error
/// (bit 3)"; "none" when no bit is set.
[[nodiscard]] ECMXF_EXPORT std::string describeErrorStatus(std::uint8_t status);

/// The set bits 2..7 of an ECM-status byte (response header 0x0A): 2 "DC
/// stable", 3 "Ethernet initialised", 4 "PDO configured", 5 "NOP", 6 "FIFO
/// enabled", 7 "async command busy". Bits 1-0 are the check type
/// (checkTypeOfEcmStatus()), not flags.
[[nodiscard]] ECMXF_EXPORT std::vector<StatusBit> ecmStatusBits(std::uint8_t status);

/// Bits 2..7 of the ECM-status byte in words: "FIFO enabled (bit 6)";
/// "none" when none is set. The check type (bits 1-0) is left out: see
/// checkTypeOfEcmStatus() and checkTypeName().
[[nodiscard]] ECMXF_EXPORT std::string describeEcmStatus(std::uint8_t status);

/// The check type in ECM-status bits 1-0.
[[nodiscard]] constexpr CheckType checkTypeOfEcmStatus(std::uint8_t status) noexcept
{
	return static_cast<CheckType>(status & 0x03u);
}

/// "fixed", "CRC-8", "CRC-CCITT", "CRC-32".
[[nodiscard]] ECMXF_EXPORT std::string_view checkTypeName(CheckType type) noexcept;

/// The set bits of the interrupt flags (response header 0x10, also the
/// enable word of ECAT_INT_SET_ENABLE): 31 "EtherCAT packet", 29
/// "encoder", 25 "RxFIFO low mark", 24 "TxFIFO high mark", 23 "CRC error",
/// 22 "WKC error"; any other set bit as "reserved".
[[nodiscard]] ECMXF_EXPORT std::vector<StatusBit> interruptFlagBits(std::uint32_t flags);

/// The interrupt flags in words: "EtherCAT packet (bit 31), encoder
/// (bit 29)"; "none" when no bit is set.
[[nodiscard]] ECMXF_EXPORT std::string describeInterruptFlags(std::uint32_t flags);

/// An EtherCAT state byte (response header 0x08, ECAT_STATE_GET, AL
/// status): "NONE" (0), "INIT", "PRE-OP", "BOOT", "SAFE-OP", "OP", and with
/// bit 4 "+ERROR" ("SAFE-OP+ERROR"; 0x10 alone is "ERROR"). Other values:
/// "unknown (0x05)".
[[nodiscard]] ECMXF_EXPORT std::string ecatStateName(std::uint8_t state);

/// "ECM-XF", "ECM-XFL", "ECM-XFU", "ECM-XM" for the series codes 0..3,
/// "unknown (7)" for others (FW_VERSION_GET data byte 3).
[[nodiscard]] ECMXF_EXPORT std::string masterSeriesName(std::uint8_t seriesCode);

/// An FoE error code (ETG.1000.6: 0x8000..0x800C "not found", "access
/// denied"...) or one of the abort codes the chip reports for a failed FoE
/// transfer (0x05040000 timeout, 0x08000000 general error / no FoE,
/// 0x08000022 wrong state, 0x05040005 out of memory); "unknown error code".
[[nodiscard]] ECMXF_EXPORT std::string_view foeErrorText(std::uint32_t code) noexcept;

} // namespace ecmxf
