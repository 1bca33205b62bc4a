// SPDX-License-Identifier: MIT
// Internal: the one little-endian reader and writer of the library (the
// chip's and the slaves' byte order), header-only so that every layer and
// the simulator use the same lines.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace ecmxf::detail {

/// The 16/32-bit little-endian value at @p p.
[[nodiscard]] inline std::uint16_t le16(const std::uint8_t *p) noexcept
{
	return static_cast<std::uint16_t>(p[0] | p[1] << 8);
}
[[nodiscard]] inline std::uint32_t le32(const std::uint8_t *p) noexcept
{
	return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
	       static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

/// Little-endian reads from @p d at @p off; bytes past the end read as 0.
[[nodiscard]] inline std::uint32_t leBytes(std::span<const std::uint8_t> d, std::size_t off, std::size_t n) noexcept
{
	std::uint32_t v = 0;
	for (std::size_t i = 0; i < n && off + i < d.size(); i++)
		v |= static_cast<std::uint32_t>(d[off + i]) << (8 * i);
	return v;
}
[[nodiscard]] inline std::uint16_t le16(std::span<const std::uint8_t> d, std::size_t off = 0) noexcept
{
	return static_cast<std::uint16_t>(leBytes(d, off, 2));
}
[[nodiscard]] inline std::uint32_t le32(std::span<const std::uint8_t> d, std::size_t off = 0) noexcept
{
	return leBytes(d, off, 4);
}

/// Little-endian writes at @p p.
inline void put16(std::uint8_t *p, std::uint32_t v) noexcept
{
	p[0] = static_cast<std::uint8_t>(v);
	p[1] = static_cast<std::uint8_t>(v >> 8);
}
inline void put32(std::uint8_t *p, std::uint32_t v) noexcept
{
	put16(p, v);
	put16(p + 2, v >> 16);
}

/// Little-endian appends to @p d.
inline void put16(std::vector<std::uint8_t> &d, std::uint16_t v)
{
	d.push_back(static_cast<std::uint8_t>(v));
	d.push_back(static_cast<std::uint8_t>(v >> 8));
}
inline void put32(std::vector<std::uint8_t> &d, std::uint32_t v)
{
	put16(d, static_cast<std::uint16_t>(v));
	put16(d, static_cast<std::uint16_t>(v >> 16));
}

/// Little-endian writes into @p d at @p off (which must hold them).
inline void put16At(std::vector<std::uint8_t> &d, std::size_t off, std::uint32_t v) noexcept
{
	put16(d.data() + off, v);
}
inline void put32At(std::vector<std::uint8_t> &d, std::size_t off, std::uint32_t v) noexcept
{
	put32(d.data() + off, v);
}

} // namespace ecmxf::detail
