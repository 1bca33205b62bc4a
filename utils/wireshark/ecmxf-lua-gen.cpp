// SPDX-License-Identifier: MIT
/*
 * ecmxf-lua-gen - writes the Wireshark Lua dissector ecmxf.lua
 * (Documentation/trace.rst, "Wireshark"). The build runs it: the command
 * codes, names and flags and the header's bit names come from the protocol
 * core's tables (lib/core/ecmxf-cmds.c, ecmxf-bits.c, ecmsk-frame.c) and the CRC check values from its
 * CRC code (lib/core/ecmxf-crc.c), so the dissector cannot drift from the
 * library. The dissector's own logic is ecmxf.lua.in beside this file.
 *
 * Usage: ecmxf-lua-gen TEMPLATE OUT
 */
#include <cctype>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "ecmsk-proto.h"
#include "ecmxf-proto.h"

namespace {

std::string xfCommands()
{
	std::size_t count = 0;
	const ecmxf_cmd_info *t = ecmxf_cmd_table(&count);
	std::string out;
	char line[256];
	for (std::size_t i = 0; i < count; i++) {
		const ecmxf_cmd_info &c = t[i];
		std::string partner = "nil";
		if (c.partner >= 0)
			partner = std::to_string(c.partner);
		std::snprintf(line, sizeof(line),
			      "  [0x%02X] = { name = \"%s\", async = %s, async_param0 = %s, idempotent = %s, "
			      "partner = %s },\n",
			      c.code, c.name, (c.flags & ECMXF_CMDF_ASYNC) ? "true" : "false",
			      (c.flags & ECMXF_CMDF_ASYNC_PARAM0) ? "true" : "false",
			      (c.flags & ECMXF_CMDF_IDEMPOTENT) ? "true" : "false", partner.c_str());
		out += line;
	}
	return out;
}

std::string skCommands()
{
	std::string out;
	char line[128];
	for (unsigned code = 0; code <= 0xFF; code++) {
		if (!ecmsk_cmd_known(static_cast<u16>(code)))
			continue;
		std::snprintf(line, sizeof(line), "  [0x%02X] = { name = \"%s\", slave = %s },\n", code,
			      ecmsk_cmd_name(static_cast<u16>(code)),
			      ecmsk_cmd_is_slave(static_cast<u8>(code)) ? "true" : "false");
		out += line;
	}
	return out;
}

/// The header's bit names (lib/core/ecmxf-bits.c), per field: the Lua
/// dissector's bit fields are made from them.
std::string headerBits()
{
	static const struct {
		ecmxf_bits_field field;
		const char *key;
	} fields[] = {
		{ ECMXF_BITS_CONTROL, "control" },       { ECMXF_BITS_RESERVED, "reserved" },
		{ ECMXF_BITS_ERR_STATUS, "err_status" }, { ECMXF_BITS_ECM_STATUS, "ecm_status" },
		{ ECMXF_BITS_INT, "int" },
	};
	std::string out;
	char line[256];
	for (const auto &f : fields) {
		std::size_t count = 0;
		const ecmxf_bit_name *t = ecmxf_bit_names(f.field, &count);
		out += "  ";
		out += f.key;
		out += " = {\n";
		for (std::size_t i = 0; i < count; i++) {
			std::string slug;
			for (const char *c = t[i].name; *c; c++)
				slug += std::isalnum(static_cast<unsigned char>(*c))
						? static_cast<char>(std::tolower(static_cast<unsigned char>(*c)))
						: '_';
			std::snprintf(line, sizeof(line), "    { bit = %u, name = \"%s\", abbr = \"%s\" },\n", t[i].bit,
				      t[i].name, slug.c_str());
			out += line;
		}
		out += "  },\n";
	}
	return out;
}

std::string constants()
{
	static const unsigned char check[] = "123456789";
	char buf[1024];
	std::snprintf(buf, sizeof(buf),
		      "local HDR_SIZE = %u\nlocal TRAILER_SIZE = %u\nlocal START_WORD = 0x%08X\n"
		      "local END_WORD = 0x%08X\nlocal FIXED_CHECK = 0x%08X\nlocal NOT_READY_WORD = 0x%08X\n"
		      "local SK_CRC_OFFSET = %u\nlocal SK_CRC_INIT = 0x%02X\n"
		      "local SK_FRAME12 = %u\nlocal SK_FRAME16 = %u\nlocal SK_RSP_OP = 0x%02X\n"
		      "-- the core's CRCs of \"123456789\": the Lua ones are checked against them at load\n"
		      "local CHECK_CRC8 = 0x%02X\nlocal CHECK_CCITT = 0x%04X\nlocal CHECK_CRC32 = 0x%08X\n",
		      ECMXF_HDR_SIZE, ECMXF_TRAILER_SIZE, ECMXF_START_WORD, ECMXF_END_WORD, ECMXF_FIXED_CHECK,
		      ECMXF_NOT_READY_WORD, ECMSK_CRC_OFFSET, ECMSK_CRC_INIT, ECMSK_FRAME12, ECMSK_FRAME16, ECMSK_RSP_OP,
		      ecmxf_crc8(check, 9), ecmxf_crc_ccitt(check, 9), ecmxf_crc32(check, 9));
	return buf;
}

void replace(std::string &s, const std::string &key, const std::string &value)
{
	const auto at = s.find(key);
	if (at == std::string::npos) {
		std::cerr << "ecmxf-lua-gen: the template has no " << key << '\n';
		std::exit(1);
	}
	s.replace(at, key.size(), value);
}

} // namespace

int main(int argc, char **argv)
{
	if (argc != 3) {
		std::cerr << "usage: ecmxf-lua-gen TEMPLATE OUT\n";
		return 2;
	}
	std::ifstream in(argv[1]);
	if (!in) {
		std::cerr << "ecmxf-lua-gen: cannot read " << argv[1] << '\n';
		return 1;
	}
	std::stringstream ss;
	ss << in.rdbuf();
	std::string lua = ss.str();
	replace(lua, "@CONSTANTS@", constants());
	replace(lua, "@XF_COMMANDS@", xfCommands());
	replace(lua, "@SK_COMMANDS@", skCommands());
	replace(lua, "@HEADER_BITS@", headerBits());
	std::ofstream out(argv[2], std::ios::binary | std::ios::trunc);
	out << lua;
	out.close();
	if (!out) {
		std::cerr << "ecmxf-lua-gen: cannot write " << argv[2] << '\n';
		return 1;
	}
	return 0;
}
