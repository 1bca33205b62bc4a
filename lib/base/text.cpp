// SPDX-License-Identifier: MIT
// Internal message words shared by Device and the command transports
// (lib/base/text.hpp).

#include "base/text.hpp"

#include <ecmxf/protocol.hpp>

#include <cinttypes>
#include <cstdio>

namespace ecmxf::detail {

std::string commandName(std::uint8_t code)
{
	if (const auto info = commandInfo(code))
		return std::string(info->name);
	char buf[32];
	std::snprintf(buf, sizeof(buf), "command 0x%02X", code);
	return buf;
}

std::string hex(std::uint64_t v, int digits)
{
	char buf[32];
	std::snprintf(buf, sizeof(buf), "0x%0*" PRIX64, digits, v);
	return buf;
}

std::string hex8(unsigned v)
{
	char buf[8];
	std::snprintf(buf, sizeof(buf), "0x%02X", v & 0xFFu);
	return buf;
}

std::string bitList(std::uint8_t status)
{
	std::string bits;
	unsigned n = 0;
	for (unsigned b = 0; b < 8; b++) {
		if (!(status & (1u << b)))
			continue;
		if (n++)
			bits += ", ";
		bits += std::to_string(b);
	}
	return (n == 1 ? "bit " : "bits ") + bits;
}

std::string durationUs(std::uint64_t us)
{
	char buf[48];
	if (us % 1000u == 0)
		std::snprintf(buf, sizeof(buf), "%" PRIu64 " ms", us / 1000u);
	else
		std::snprintf(buf, sizeof(buf), "%" PRIu64 " us", us);
	return buf;
}

std::string quoted(std::string_view s)
{
	std::string q(1, '"');
	q.append(s).push_back('"');
	return q;
}

} // namespace ecmxf::detail
