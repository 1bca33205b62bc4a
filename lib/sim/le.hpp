// SPDX-License-Identifier: MIT
//
// le.hpp - little-endian reads and writes of the simulator's byte layouts
// (packets, datagrams, command data, SDO data).

#pragma once

#include <cstdint>

namespace ecmxf::sim {

/// Little-endian helpers for the packet and datagram layouts.
inline std::uint16_t le16(const std::uint8_t *p)
{
	return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
inline std::uint32_t le32(const std::uint8_t *p)
{
	return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
	       (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
inline void put16(std::uint8_t *p, std::uint16_t v)
{
	p[0] = static_cast<std::uint8_t>(v);
	p[1] = static_cast<std::uint8_t>(v >> 8);
}
inline void put32(std::uint8_t *p, std::uint32_t v)
{
	p[0] = static_cast<std::uint8_t>(v);
	p[1] = static_cast<std::uint8_t>(v >> 8);
	p[2] = static_cast<std::uint8_t>(v >> 16);
	p[3] = static_cast<std::uint8_t>(v >> 24);
}

} // namespace ecmxf::sim
