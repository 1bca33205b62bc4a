// SPDX-License-Identifier: MIT
// ecmxf-util's shared helpers as units: numbers, object addresses, the
// -t types' encoding and formatting (values computed by hand from the
// little-endian rule and IEEE 754).

#include <catch2/catch.hpp>

#include "ecmxf-util.hpp"

using namespace ecmxf_util;
using Catch::Matchers::Equals;

TEST_CASE("util: INDEX[:SUB] parts are decimal or 0x hex each", "[cli][units]")
{
	auto a = parseObjectAddress("upload", "0x6064:00");
	CHECK(a.index == 0x6064);
	CHECK(a.sub == 0);
	a = parseObjectAddress("upload", "0x1A00:0x0a");
	CHECK(a.index == 0x1A00);
	CHECK(a.sub == 10);
	a = parseObjectAddress("upload", "4096");
	CHECK(a.index == 0x1000);
	CHECK(objectName(a) == "0x1000:00");
	// printed so that it parses back (fuzz-cli found "0x6064:100" printed
	// as "0x6064:64", which reads as subindex 64)
	CHECK(objectName({ 0x1A00, 10 }) == "0x1a00:0x0a");
	for (unsigned sub : { 0u, 9u, 10u, 16u, 100u, 255u }) {
		const ObjectAddress o{ 0x6064, static_cast<std::uint8_t>(sub) };
		const ObjectAddress back = parseObjectAddress("upload", objectName(o));
		CHECK(back.index == 0x6064);
		CHECK(back.sub == sub);
	}
	CHECK_THROWS_WITH(parseObjectAddress("upload", "0x10000"), "upload: INDEX: 0x10000 is out of range 0..65535");
	CHECK_THROWS_WITH(parseObjectAddress("upload", "0x6064:256"), "upload: SUB: 256 is out of range 0..255");
	CHECK_THROWS_WITH(parseObjectAddress("upload", "0x6064:0a"),
			  "upload: SUB: '0a' is not a number (decimal or 0x hex)");
}

TEST_CASE("util: signed numbers and their ranges", "[cli][units]")
{
	CHECK(parseSigned("x", "V", "-128", -128, 127) == -128);
	CHECK(parseSigned("x", "V", "0x7f", -128, 127) == 127);
	CHECK_THROWS_WITH(parseSigned("x", "V", "-129", -128, 127), "x: V: -129 is out of range -128..127");
	CHECK_THROWS_WITH(parseSigned("x", "V", "-x", -128, 127), "x: V: '-x' is not a number (decimal or 0x hex)");
}

TEST_CASE("util: -t types encode VALUE little-endian", "[cli][units]")
{
	using B = std::vector<std::uint8_t>;
	CHECK(encodeValue("d", DataType::Int16, "-2") == B{ 0xFE, 0xFF });
	CHECK(encodeValue("d", DataType::Uint32, "0x12345678") == B{ 0x78, 0x56, 0x34, 0x12 });
	CHECK(encodeValue("d", parseType("d", "sint8"), "-128") == B{ 0x80 });
	// 1.5f = 0x3FC00000
	CHECK(encodeValue("d", parseType("d", "real32"), "1.5") == B{ 0x00, 0x00, 0xC0, 0x3F });
	CHECK(encodeValue("d", DataType::Bool, "true") == B{ 1 });
	CHECK(encodeValue("d", DataType::String, "ab") == B{ 'a', 'b' });
	CHECK(encodeValue("d", DataType::OctetString, "0a:0B") == B{ 0x0A, 0x0B });
	CHECK_THROWS_WITH(encodeValue("d", DataType::Uint8, "256"), "d: VALUE: 256 is out of range 0..255");
	CHECK_THROWS_WITH(encodeValue("d", DataType::Int8, "128"), "d: VALUE: 128 is out of range -128..127");
	CHECK_THROWS_WITH(parseType("d", "int24"), Catch::Matchers::StartsWith("d: unknown type 'int24' (bool, int8"));
}

TEST_CASE("util: object bytes as text and JSON", "[cli][units]")
{
	using B = std::vector<std::uint8_t>;
	// without a type: unsigned hex + decimal for 1/2/4/8 bytes, else bytes
	CHECK(formatValue(std::nullopt, B{ 0x92, 0x01, 0x03, 0x00 }) == "0x00030192 197010");
	CHECK(formatValue(std::nullopt, B{ 'E', 'S', 'T' }) == "45 53 54");
	CHECK(jsonValue(std::nullopt, B{ 'E', 'S', 'T' }) == "\"455354\"");
	CHECK(formatValue(DataType::Int32, B{ 0x18, 0xFC, 0xFF, 0xFF }) == "-1000");
	CHECK(formatValue(DataType::Uint16, B{ 0x50, 0x02 }) == "592");
	CHECK(formatValue(DataType::Float, B{ 0x00, 0x00, 0xC0, 0x3F }) == "1.5");
	CHECK(formatValue(DataType::String, B{ 'a', 'b', 0, 0 }) == "ab");
	CHECK(jsonValue(DataType::String, B{ 'a', '"' }) == "\"a\\\"\"");
	CHECK(formatValue(DataType::Bool, B{ 1 }) == "true");
}

TEST_CASE("util: -p lists and ranges: ascending, each once, bad items named", "[cli][units]")
{
	CHECK(parsePositions("slaves", "2").list == std::vector<unsigned>{ 2 });
	CHECK(parsePositions("slaves", "0,2").list == std::vector<unsigned>{ 0, 2 });
	CHECK(parsePositions("slaves", "0-3").list == std::vector<unsigned>{ 0, 1, 2, 3 });
	CHECK(parsePositions("slaves", "5,0-2,1,0x7f").list == std::vector<unsigned>{ 0, 1, 2, 5, 127 });
	const Positions p = parsePositions("slaves", "1,3");
	CHECK(p.has(1));
	CHECK_FALSE(p.has(2));
	CHECK_THROWS_WITH(parsePositions("slaves", "3-1"),
			  "slaves: -p 3-1: range 3-1 runs backwards (try 'ecmxf-util slaves --help')");
	CHECK_THROWS_WITH(parsePositions("slaves", "0,,2"),
			  "slaves: -p 0,,2: an empty item in the list (try 'ecmxf-util slaves --help')");
	CHECK_THROWS_WITH(parsePositions("slaves", "0,"),
			  "slaves: -p 0,: an empty item in the list (try 'ecmxf-util slaves --help')");
	CHECK_THROWS_WITH(parsePositions("slaves", "0-128"), Catch::Contains("128 is out of range 0..127"));
	CHECK_THROWS_WITH(parsePositions("slaves", "-1"), Catch::Contains("-1"));
	CHECK_THROWS_WITH(parsePositions("slaves", "a-b"), Catch::Contains("'a' is not a number"));
	CHECK_THROWS_WITH(parsePositions("slaves", "1-"), Catch::Contains("is not a number"));
	CHECK_THROWS_WITH(parsePositions("slaves", ""), Catch::Contains("no position given"));
}
