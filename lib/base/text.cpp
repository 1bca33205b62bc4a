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

std::string printable(std::string_view s)
{
	std::string o;
	o.reserve(s.size());
	const auto esc = [&](unsigned char c) {
		static constexpr char kHex[] = "0123456789abcdef";
		o += "\\x";
		o += kHex[c >> 4];
		o += kHex[c & 15];
	};
	for (std::size_t i = 0; i < s.size();) {
		const auto c = static_cast<unsigned char>(s[i]);
		if (c == '\\') {
			o += "\\\\";
			i++;
			continue;
		}
		if (c < 0x20 || c == 0x7F) {
			esc(c);
			i++;
			continue;
		}
		if (c < 0x80) {
			o += static_cast<char>(c);
			i++;
			continue;
		}
		// a UTF-8 sequence: its length by the lead byte, continuation
		// bytes 10xxxxxx, no overlong or surrogate lead (C0, C1, F5..)
		const std::size_t n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
		bool ok = n != 0 && i + n <= s.size();
		for (std::size_t k = 1; ok && k < n; k++)
			ok = (static_cast<unsigned char>(s[i + k]) & 0xC0) == 0x80;
		if (!ok) {
			esc(c);
			i++;
			continue;
		}
		o.append(s.substr(i, n));
		i += n;
	}
	return o;
}

} // namespace ecmxf::detail
