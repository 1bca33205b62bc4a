// SPDX-License-Identifier: MIT
/*
 * ecmxf-util upload - read one object of a slave by SDO upload.
 */
#include "ecmxf-util.hpp"
#include "ecmxf-util-sk.hpp"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/verbs.hpp>

namespace ecmxf_util {

const char *const kUploadHelp =
	"Usage: ecmxf-util [global options] upload -p N INDEX[:SUB] [-t TYPE] [-v] [--json]\n"
	"       ecmxf-util [global options] upload -p N INDEX SUB [-t TYPE] [-v] [--json]\n"
	"\n"
	"Read one object of the slave at position N by SDO upload (ECAT_SDO_REQ +\n"
	"ECAT_SDO_GET) and print its value. INDEX and SUB are decimal or 0x hex\n"
	"each (0x6064:0 or 0x6064 is subindex 0; 0x6064 0 as IgH's ethercat\n"
	"takes it is the same).\n"
	"\n"
	"TYPE: bool, int8, int16, int32, int64, uint8, uint16, uint32, uint64,\n"
	"float, double, string, octet_string, and IgH's unicode_string,\n"
	"sm8..sm64 (sign and magnitude) and raw (aliases sint8..sint64, real32,\n"
	"real64). The object must have the type's size. Without -t the type is\n"
	"not known (the ECM-XF has no SDO information service to ask the slave's\n"
	"object dictionary): an object of 1, 2, 4 or 8 bytes is printed as its\n"
	"unsigned little-endian value in hex and decimal (\"0x00030192 197010\"),\n"
	"any other size as its bytes in hex.\n"
	"\n"
	"A fresh bus is brought up to PRE-OP first (ECAT_INIT_OP, PRE-OP for all\n"
	"slaves); a bus that is already up is used as it is. An SDO abort fails\n"
	"with the abort code and its text.\n"
	"\n"
	"On an ECM-SK (-d sk-...): SDO_RD through the board's SDO slot, objects of\n"
	"1, 2 or 4 bytes; a board in INIT is brought to PRE-OP first.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  the slave (bus position, from 0); required\n"
	"  -t, --type TYPE   the object's data type\n"
	"  -v, --verbose     add the object's bytes in hex\n"
	"  --json            {position, index, sub, type, size, value, hex}\n"
	"  -h, --help        show this help\n";

int cmdUpload(Globals &g, const Args &args)
{
	std::optional<std::string> posText, typeText;
	bool verbose = false;
	const auto pos = parseArgs("upload", args, g, kUploadHelp,
				   { { "-p", "--position", nullptr, &posText },
				     { "-t", "--type", nullptr, &typeText },
				     { "-v", "--verbose", &verbose, nullptr } });
	if (!pos)
		return 0;
	if (pos->empty() || pos->size() > 2)
		throw UsageError(pos->empty() ? "upload: which object? (upload -p N INDEX[:SUB])"
					      : "upload: one INDEX[:SUB] or INDEX SUB only (try 'ecmxf-util upload --help')");
	std::uint8_t position = parsePosition("upload", posText);
	// INDEX:SUB, or IgH's INDEX SUB as two arguments
	const ObjectAddress obj = pos->size() == 2 ? parseObjectAddress("upload", (*pos)[0], (*pos)[1])
						   : parseObjectAddress("upload", pos->front());
	const std::optional<DataType> type =
		typeText ? std::optional<DataType>(parseType("upload", *typeText)) : std::nullopt;

	checkSdoType(g, "upload", type);
	const auto master = openMaster(g); // either master: MasterVerbs
	position = sdoPosition(g, *master, position);
	const std::vector<std::uint8_t> b = master->upload(position, obj.index, obj.sub);
	if (type && typeSize(*type) && b.size() != typeSize(*type))
		throw ecmxf::Error("slave " + std::to_string(position) + " " + objectName(obj) + " has " +
					   std::to_string(b.size()) + " bytes, type " + std::string(typeName(*type)) +
					   " has " + std::to_string(typeSize(*type)),
				   EPROTO);

	if (g.json) {
		std::printf("{\"position\": %u, \"index\": %u, \"sub\": %u, \"type\": %s, \"size\": %zu, "
			    "\"value\": %s, \"hex\": %s}\n",
			    position, obj.index, obj.sub,
			    type ? jsonString(typeName(*type)).c_str() : "null", b.size(),
			    jsonValue(type, b).c_str(), jsonString(hexBytes(b, "")).c_str());
		return 0;
	}
	std::printf("%s\n", formatValue(type, b).c_str());
	if (verbose)
		std::printf("bytes: %s\n", b.empty() ? "(none)" : hexBytes(b).c_str());
	return 0;
}

} // namespace ecmxf_util
