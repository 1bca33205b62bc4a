// SPDX-License-Identifier: MIT
/*
 * ecmxf-util download - write one object of a slave by SDO download.
 */
#include "ecmxf-util.hpp"
#include "ecmxf-util-sk.hpp"

#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/model/objects.hpp>
#include <ecmxf/verbs.hpp>

namespace ecmxf_util {

const char *const kDownloadHelp =
	"Usage: ecmxf-util [global options] download -p N INDEX[:SUB] VALUE [-t TYPE]\n"
	"       ecmxf-util [global options] download -p N INDEX SUB VALUE [-t TYPE]\n"
	"\n"
	"Write VALUE to one object of the slave at position N by SDO download\n"
	"(ECAT_SDO_REQ). INDEX and SUB are decimal or 0x hex each; IgH's form,\n"
	"INDEX SUB VALUE as three arguments, is taken too.\n"
	"\n"
	"TYPE: bool, int8, int16, int32, int64, uint8, uint16, uint32, uint64,\n"
	"float, double, string, octet_string (VALUE as hex bytes, e.g. 0a0b0c),\n"
	"IgH's unicode_string, sm8..sm64 (sign and magnitude) and raw (= hex\n"
	"bytes), aliases sint8..sint64, real32, real64. A float or double VALUE\n"
	"must be finite and within the type's range (1e99 is refused for float,\n"
	"not sent as +inf); inf, -inf and nan are taken when spelled so; integer\n"
	"types take integers only (no nan, no inf, no negative number for an\n"
	"unsigned type): a VALUE outside the type's range is refused naming it.\n"
	"\n"
	"The standard CiA 402 objects the tools know (0x6040 controlword, 0x607A\n"
	"target position, 0x6081 profile velocity...) have their type from CiA\n"
	"402, with or without -t: VALUE must fit it, and -t must be an integer\n"
	"type. Any other object without -t is uploaded first to learn its size\n"
	"(the masters have no SDO information service): an object of 1, 2, 4 or\n"
	"8 bytes takes VALUE as an unsigned integer of that size (decimal or 0x\n"
	"hex; a negative VALUE needs -t intN); other sizes need -t.\n"
	"\n"
	"A fresh bus is brought up to PRE-OP first; a bus that is already up is\n"
	"used as it is. An SDO abort fails with the abort code and its text.\n"
	"Prints nothing on success.\n"
	"\n"
	"On an ECM-SK (-d sk-...): SDO_WR through the board's SDO slot; -t TYPE is\n"
	"required but for the standard objects (1, 2 or 4 bytes: the board cannot\n"
	"tell an object's size), and\n"
	"--json prints {position, index, sub, size}.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  the slave (bus position, from 0); required\n"
	"  -t, --type TYPE   the object's data type\n"
	"  -h, --help        show this help\n";

int cmdDownload(Globals &g, const Args &args)
{
	std::optional<std::string> posText, typeText;
	const auto pos = parseArgs("download", args, g, kDownloadHelp,
				   { { "-p", "--position", nullptr, &posText },
				     { "-t", "--type", nullptr, &typeText } });
	if (!pos)
		return 0;
	if (pos->size() < 2 || pos->size() > 3)
		throw UsageError(pos->size() < 2 ? "download: needs INDEX[:SUB] VALUE (download -p N INDEX[:SUB] VALUE)"
						 : "download: too many arguments (try 'ecmxf-util download --help')");
	std::uint8_t position = parsePosition("download", posText);
	// INDEX:SUB VALUE, or IgH's INDEX SUB VALUE
	const ObjectAddress obj = pos->size() == 3 ? parseObjectAddress("download", (*pos)[0], (*pos)[1])
						   : parseObjectAddress("download", (*pos)[0]);
	const std::string &valueText = pos->back();
	std::vector<std::uint8_t> bytes;
	// a standard object's type (CiA 402) decides VALUE's range, with or
	// without -t: the masters cannot ask a slave for an object's type
	const auto known = ecmxf::standardObject(obj.index, obj.sub);
	const auto knownText = [&] {
		return objectName(obj) + " " + std::string(known->name) + " is " +
		       std::string(ecmxf::objectTypeName(known->type));
	};
	const auto encodeKnown = [&] {
		try {
			return encodeValue("download", dataTypeOf(known->type), valueText);
		} catch (const UsageError &e) {
			throw UsageError(std::string(e.what()) + " (" + knownText() + ")");
		}
	};
	if (typeText) {
		const DataType type = parseType("download", *typeText);
		checkSdoType(g, "download", type);
		bytes = encodeValue("download", type, valueText);
		if (known && !integerType(type))
			throw UsageError("download: -t " + std::string(typeName(type)) + ": " + knownText() +
					 " (CiA 402), an integer");
		if (known)
			(void)encodeKnown();
	} else if (known) {
		bytes = encodeKnown();
	} else if (skDevice(g)) {
		throw UsageError("download: -t TYPE is required (the ECM-SK cannot tell an object's size)");
	}

	const auto master = openMaster(g); // either master: MasterVerbs
	position = sdoPosition(g, *master, position);
	if (!typeText && !known) {
		// the size probe is an upload: a failure is the download's
		std::size_t n = 0;
		try {
			n = master->upload(position, obj.index, obj.sub).size();
		} catch (const ecmxf::Error &e) {
			throw ecmxf::Error("SDO download " + objectName(obj) + " to slave " + std::to_string(position) +
						   ": its size could not be read (give -t TYPE to skip that): " + e.what(),
					   e.errnoValue());
		}
		if (n != 1 && n != 2 && n != 4 && n != 8)
			throw UsageError("download: slave " + std::to_string(position) + " " + objectName(obj) +
					 " has " + std::to_string(n) +
					 " bytes: give its type with -t (e.g. -t string or -t octet_string)");
		const DataType u = n == 1 ? DataType::Uint8 : n == 2 ? DataType::Uint16 : n == 4 ? DataType::Uint32
												    : DataType::Uint64;
		const DataType s = n == 1 ? DataType::Int8 : n == 2 ? DataType::Int16 : n == 4 ? DataType::Int32
												  : DataType::Int64;
		// its size is all that is known: a negative VALUE could be meant
		// for a signed object or wrap round in an unsigned one
		if (!valueText.empty() && valueText[0] == '-')
			throw UsageError("download: VALUE " + valueText + ": slave " + std::to_string(position) + " " +
					 objectName(obj) + " has " + std::to_string(n) +
					 " bytes and a type the master cannot learn (no SDO information service): "
					 "give -t " + std::string(typeName(s)) + " if it is signed");
		bytes = encodeValue("download", u, valueText);
	}
	master->download(position, obj.index, obj.sub, bytes);
	if (g.json && master->kind() == ecmxf::MasterKind::EcmSk) // as the ECM-SK's download always did
		std::printf("{\"position\": %u, \"index\": %u, \"sub\": %u, \"size\": %zu}\n", position, obj.index,
			    obj.sub, bytes.size());
	return 0;
}

} // namespace ecmxf_util
