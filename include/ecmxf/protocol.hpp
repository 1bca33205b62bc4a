// SPDX-License-Identifier: MIT
/**
 * @file protocol.hpp
 * @brief The ECM-XF protocol as C++ users see it: packet geometry,
 *        check words and the command table.
 *
 * The exchange rules themselves live in the sans-I/O C core that the kernel
 * module shares; this header gives C++ callers typed access to what is
 * static about the protocol.
 */
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include <ecmxf/export.hpp>

namespace ecmxf {

/// Library version, "MAJOR.MINOR.PATCH".
/// The first line of every packet trace file (Documentation/trace.rst):
/// the links write it (Device::startTrace()), decodeTrace()
/// (<ecmxf/trace/trace.hpp>) checks it.
inline constexpr std::string_view kTraceMagic = "ecmxf-trace 1";

[[nodiscard]] ECMXF_EXPORT std::string_view version() noexcept;

/// Check word types (ECM status bits 1-0, CRC_TYPE_SET parameter).
enum class CheckType : std::uint8_t {
	Fixed = 0,  ///< constant 0x12345678
	Crc8 = 1,   ///< CRC-8 poly 0x07 (firmware ver. 038 only)
	Ccitt = 2,  ///< CRC-CCITT-FALSE (firmware ver. 038 only)
	Crc32 = 3,  ///< CRC-32 (zlib/Ethernet)
};

/// Which bytes a CRC check word covers: firmware variants
/// (Documentation/protocol-core.rst, "Firmware variants").
enum class CrcCoverage : std::uint8_t {
	Unknown = 0, ///< not found yet (no CRC in force, or no answer told the rules apart)
	Frame = 1,   ///< header and the whole data section (manual ver. 050)
	Valid = 2,   ///< header and the valid data length rounded up to 4 bytes (NEXTW's example host code)
};

/// "unknown", "frame", "valid" (the words of sysfs and of the simulator's
/// crc32-coverage option).
[[nodiscard]] ECMXF_EXPORT std::string_view crcCoverageName(CrcCoverage coverage) noexcept;

inline constexpr std::size_t kHeaderSize = 24;
inline constexpr std::size_t kTrailerSize = 8;
inline constexpr std::size_t kDataMin = 32;
inline constexpr std::size_t kDataMax = 1408;
inline constexpr std::size_t kDataDefault = 112;

/// Packet size on the wire for a data section of @p dataSize bytes.
[[nodiscard]] constexpr std::size_t packetSize(std::size_t dataSize) noexcept
{
	return kHeaderSize + dataSize + kTrailerSize;
}

/// CRC-8 (poly 0x07, init 0).
[[nodiscard]] ECMXF_EXPORT std::uint8_t crc8(std::span<const std::uint8_t> bytes) noexcept;
/// CRC-CCITT-FALSE (poly 0x1021, init 0xFFFF).
[[nodiscard]] ECMXF_EXPORT std::uint16_t crcCcitt(std::span<const std::uint8_t> bytes) noexcept;
/// CRC-32 as zlib computes it.
[[nodiscard]] ECMXF_EXPORT std::uint32_t crc32(std::span<const std::uint8_t> bytes) noexcept;

/// One row of the command table (both manual versions).
struct CommandInfo {
	std::uint8_t code;          ///< command code
	std::string_view name;      ///< manual name without the ECM_CMD_ prefix
	bool async;                 ///< async ("blocking"): busy until done
	bool asyncOnlyParam0;       ///< async only with command parameter 0
	bool inV038;                ///< documented in manual ver. 038
	bool inV050;                ///< documented in manual ver. 050
	bool idempotent;            ///< a pure read, safe to re-issue
	std::optional<std::uint8_t> partner; ///< *_GET that fetches the result
	std::uint32_t timeoutMs;    ///< default time allowed, incl. completion
};

/// The row for @p code, or std::nullopt when neither manual has it.
[[nodiscard]] ECMXF_EXPORT std::optional<CommandInfo> commandInfo(std::uint8_t code) noexcept;

/// Number of commands in the table.
[[nodiscard]] ECMXF_EXPORT std::size_t commandCount() noexcept;

/// The @p i-th row in code order (@p i < commandCount()).
[[nodiscard]] ECMXF_EXPORT CommandInfo commandAt(std::size_t i) noexcept;

} // namespace ecmxf
