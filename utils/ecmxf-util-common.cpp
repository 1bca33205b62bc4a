// SPDX-License-Identifier: MIT
/*
 * ecmxf-util - helpers shared by the command units.
 */
#include "ecmxf-util.hpp"

#include <cstdio>

namespace ecmxf_util {

bool parseFlags(std::string_view cmd, const Args &args, Globals &g, const char *help,
		const std::vector<Flag> &flags)
{
	for (const std::string_view a : args) {
		if (a == "-h" || a == "--help") {
			std::fputs(help, stdout);
			return true;
		}
		if (a == "--json") {
			g.json = true;
			continue;
		}
		bool known = false;
		for (const Flag &f : flags) {
			if ((!f.shortName.empty() && a == f.shortName) || a == f.longName) {
				*f.value = true;
				known = true;
			}
		}
		if (!known)
			throw UsageError(std::string(cmd) + ": unknown argument '" + std::string(a) +
					 "' (try 'ecmxf-util " + std::string(cmd) + " --help')");
	}
	return false;
}

std::string jsonString(std::string_view s)
{
	std::string out = "\"";
	for (const char ch : s) {
		const auto c = static_cast<unsigned char>(ch);
		if (c == '"' || c == '\\') {
			out += '\\';
			out += ch;
		} else if (c < 0x20 || c == 0x7F) {
			char buf[8];
			std::snprintf(buf, sizeof(buf), "\\u%04x", c);
			out += buf;
		} else {
			out += ch;
		}
	}
	return out + "\"";
}

ecmxf::Command simpleCommand(std::uint8_t code, std::uint8_t param)
{
	ecmxf::Command c;
	c.code = code;
	c.param = param;
	return c;
}

std::uint16_t le16(const ecmxf::Response &r, std::string_view what)
{
	if (r.data.size() < 2)
		throw std::runtime_error(std::string(what) + ": answer of " + std::to_string(r.data.size()) +
					 " bytes, expected 2");
	return static_cast<std::uint16_t>(r.data[0] | r.data[1] << 8);
}

std::uint32_t le32(const ecmxf::Response &r, std::string_view what)
{
	if (r.data.size() < 4)
		throw std::runtime_error(std::string(what) + ": answer of " + std::to_string(r.data.size()) +
					 " bytes, expected 4");
	return static_cast<std::uint32_t>(r.data[0]) | static_cast<std::uint32_t>(r.data[1]) << 8 |
	       static_cast<std::uint32_t>(r.data[2]) << 16 | static_cast<std::uint32_t>(r.data[3]) << 24;
}

std::string stateName(std::uint8_t state)
{
	switch (state) {
	case 0x00: return "NONE";
	case 0x01: return "INIT";
	case 0x02: return "PREOP";
	case 0x03: return "BOOT";
	case 0x04: return "SAFEOP";
	case 0x08: return "OP";
	case 0x10: return "ERROR";
	default: {
		char buf[8];
		std::snprintf(buf, sizeof(buf), "0x%02x", state);
		return buf;
	}
	}
}

} // namespace ecmxf_util
