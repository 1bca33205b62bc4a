// SPDX-License-Identifier: MIT
// Internal: the words the library's messages share (command names, hex,
// bits, durations); the little-endian helpers are lib/base/bytes.hpp. The
// mapping between the wire's headers and RawRequest / ResponseHeader is
// lib/link/wire_header.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "base/bytes.hpp"

namespace ecmxf::detail {

/// The manual name of @p code ("ECAT_SDO_REQ"), or "command 0x4D".
std::string commandName(std::uint8_t code);
/// "0x1D" style: @p v in hex with @p digits digits.
std::string hex(std::uint64_t v, int digits);
/// "0x5A".
std::string hex8(unsigned v);
/// Bit numbers set in @p status: "bit 3" / "bits 3, 7".
std::string bitList(std::uint8_t status);
/// "10000 ms", or "250 us" for times that are not whole milliseconds.
std::string durationUs(std::uint64_t us);
/// @p s in double quotes.
std::string quoted(std::string_view s);
/// @p s safe for a terminal: control bytes (0x00..0x1F, 0x7F) and bytes
/// that are not valid UTF-8 as \xNN, a backslash as \\; valid UTF-8
/// passes unchanged.
std::string printable(std::string_view s);

/// A row of a code table for textOf().
template <typename Code>
struct CodeText {
	Code code;
	std::string_view text;
};

/// The text of @p code in a table of { code, text } rows (the manuals'
/// code tables: AL status, SDO abort...), or @p unknown. An empty
/// @p unknown leaves the text of a code not in the table to the caller.
template <typename Row, std::size_t N, typename Code>
[[nodiscard]] constexpr std::string_view textOf(const Row (&table)[N], Code code, std::string_view unknown) noexcept
{
	for (const auto &row : table)
		if (row.code == code)
			return row.text;
	return unknown;
}

} // namespace ecmxf::detail
