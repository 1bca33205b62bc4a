// SPDX-License-Identifier: MIT
/*
 * fuzz_cli.cpp - the values ecmxf-util parses from its command line
 * (utils/ecmxf-util-common.cpp, utils/ecmxf-util-types.cpp): numbers,
 * INDEX[:SUB], positions (-p N, lists and ranges), SDO data types (-t) and SDO values (the value
 * codec of `download`, and its formatting for `upload`).
 *
 * Input: byte 0 selects the parser (and, for values, the type), the rest
 * is the text. Invariants: each parser returns a value within its
 * documented range or throws UsageError, nothing else; an address prints
 * back ("0x%04x:%02x") to itself; a type's name parses back to the type;
 * an encoded value has the type's size (the fixed types) and formats as
 * text and as JSON without error.
 */
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>

#include "ecmxf-util.hpp"
#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

using namespace ecmxf_util;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	const std::uint8_t sel = data[0];
	const std::string_view text(reinterpret_cast<const char *>(data + 1), size - 1);
	try {
		switch (sel % 7) {
		case 0: {
			const std::uint64_t max = sel & 0x80 ? 0xFFFF : UINT64_MAX;
			const std::uint64_t v = parseUnsigned("fuzz", "n", text, max, sel & 0x40 ? 1 : 0);
			FUZZ_ASSERT(v <= max && (!(sel & 0x40) || v >= 1));
			// a negative number is out of any unsigned range (but -0)
			FUZZ_ASSERT(text.empty() || text[0] != '-' || v == 0);
			break;
		}
		case 1: {
			const std::int64_t v = parseSigned("fuzz", "n", text, -1000, 1000);
			FUZZ_ASSERT(v >= -1000 && v <= 1000);
			break;
		}
		case 2:
			(void)parseReal("fuzz", "x", text);
			break;
		case 3: {
			const ObjectAddress a = parseObjectAddress("fuzz", text);
			const ObjectAddress b = parseObjectAddress("fuzz", objectName(a));
			FUZZ_ASSERT(a.index == b.index && a.sub == b.sub);
			break;
		}
		case 4: {
			if (sel & 0x80) {
				// -p lists and ranges: ascending, each once, 0..127
				const Positions ps = parsePositions("fuzz", text);
				FUZZ_ASSERT(!ps.list.empty());
				for (std::size_t i = 0; i < ps.list.size(); i++) {
					FUZZ_ASSERT(ps.list[i] <= 127);
					FUZZ_ASSERT(i == 0 || ps.list[i - 1] < ps.list[i]);
					FUZZ_ASSERT(ps.has(ps.list[i]));
				}
				break;
			}
			const std::uint8_t p = parsePosition("fuzz", std::string(text));
			FUZZ_ASSERT(p <= 127);
			break;
		}
		case 5: {
			const DataType t = parseType("fuzz", text);
			FUZZ_ASSERT(parseType("fuzz", typeName(t)) == t);
			break;
		}
		default: {
			const auto t = static_cast<DataType>((sel >> 3) % 13);
			const std::vector<std::uint8_t> b = encodeValue("fuzz", t, text);
			if (typeSize(t))
				FUZZ_ASSERT(b.size() == typeSize(t));
			(void)formatValue(t, b);
			(void)jsonValue(t, b);
			(void)formatValue(std::nullopt, b);
			break;
		}
		}
	} catch (const UsageError &) {
	}
	return 0;
}
