// SPDX-License-Identifier: MIT
/**
 * @file pdo_mapping.hpp
 * @brief Where each mapped object of each slave lies in the process image.
 *
 * Master::pdos() fills these from the slaves' PDO assignment and mapping
 * (0x1C12/0x1C13, 0x16xx/0x1Axx read back by SDO, or what the chip reports
 * for slaves without a mailbox); ProcessImage builds its typed accessors
 * from them.
 */
#pragma once

#include <ecmxf/export.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ecmxf {

/// One object mapped into a slave's outputs (RxPDO) or inputs (TxPDO).
struct PdoEntryInfo {
	std::uint16_t pdo = 0;        ///< the PDO it is mapped by (0x16xx / 0x1Axx)
	std::uint16_t index = 0;      ///< object index (0 for padding)
	std::uint8_t sub = 0;         ///< object subindex
	std::uint8_t bitLength = 0;   ///< mapped length in bits (1..64)
	/// Offset in bits from the start of the slave's output (or input)
	/// bytes; entries follow each other without gaps, as mapped.
	std::uint32_t bitOffset = 0;
	std::string name;             ///< the object's name when known, else empty
};

/// One slave's process data as mapped.
struct SlavePdos {
	std::vector<PdoEntryInfo> outputs;  ///< RxPDO entries (master to slave)
	std::vector<PdoEntryInfo> inputs;   ///< TxPDO entries (slave to master)
	std::uint32_t outputBytes = 0;      ///< the slave's output bytes (SLV_INFO)
	std::uint32_t inputBytes = 0;       ///< the slave's input bytes (SLV_INFO)
};

/// Does the entry name @p name match what a user typed, @p text? Case,
/// spaces, '_' and '-' are ignored ("TargetPosition", "target_position"
/// and "Target position" are one name); an empty @p name matches nothing.
/// What `ecmxf-util data --set` and the scope's signals (Recorder) use.
[[nodiscard]] ECMXF_EXPORT bool entryNameMatches(std::string_view name, std::string_view text);

} // namespace ecmxf
