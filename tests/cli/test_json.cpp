// SPDX-License-Identifier: MIT
// The tests' JSON parser (tests/cli/json.hpp): what it accepts, what it
// decodes, what it rejects. Expected values follow RFC 8259.

#include <catch2/catch.hpp>

#include "json.hpp"

using testjson::Json;
using testjson::parse;
using testjson::parseLines;
using Catch::Matchers::Contains;

TEST_CASE("json: scalars of every kind", "[json]")
{
	CHECK(parse("null").kind == Json::Null);
	CHECK(parse(" true ").b);
	CHECK(parse("true").kind == Json::Bool);
	CHECK_FALSE(parse("false").b);
	CHECK(parse("0").num == 0);
	CHECK(parse("-0").num == 0);
	CHECK(parse("42").num == 42);
	CHECK(parse("-2.5e3").num == -2500);
	CHECK(parse("1E+2").num == 100);
	CHECK(parse("0.125").num == 0.125);
	CHECK(parse("4294967295").num == 4294967295.0);
	CHECK(parse("\"abc\"").str == "abc");
}

TEST_CASE("json: string escapes decode to UTF-8", "[json]")
{
	CHECK(parse(R"("a\"b\\c\/d")").str == "a\"b\\c/d");
	CHECK(parse(R"("\b\f\n\r\t")").str == "\b\f\n\r\t");
	CHECK(parse(R"("\u0041\u0001")").str == std::string("A\x01"));
	CHECK(parse(R"("\u00e9")").str == "\xc3\xa9");              // é
	CHECK(parse(R"("\u20AC")").str == "\xe2\x82\xac");          // €
	CHECK(parse(R"("\ud83d\ude00")").str == "\xf0\x9f\x98\x80"); // U+1F600
	CHECK(parse("\"\xc3\xa9\"").str == "\xc3\xa9");               // raw UTF-8 passes through
}

TEST_CASE("json: objects and arrays, nested", "[json]")
{
	const Json j = parse(R"({"a": [1, -2.5e3, true, null, "x\"y"], "b": {"c": []}, "d": {}})");
	REQUIRE(j.kind == Json::Object);
	CHECK(j.size() == 3);
	CHECK(j.contains("a"));
	CHECK_FALSE(j.contains("z"));
	REQUIRE(j["a"].size() == 5);
	CHECK(j["a"][0].num == 1);
	CHECK(j["a"][1].num == -2500);
	CHECK(j["a"][2].b);
	CHECK(j["a"][3].kind == Json::Null);
	CHECK(j["a"][4].str == "x\"y");
	CHECK(j["b"]["c"].kind == Json::Array);
	CHECK(j["b"]["c"].size() == 0);
	CHECK(j["d"].kind == Json::Object);
	CHECK_THROWS_WITH(j["z"], "JSON: no key z");
	CHECK_THROWS_WITH(j["a"][5], "JSON: index 5 out of range");
	CHECK_THROWS_WITH(j["a"]["x"], Contains("not an object"));
}

TEST_CASE("json: what is not JSON is rejected with the offset", "[json]")
{
	CHECK_THROWS_WITH(parse("{\"a\": 1,}"), "JSON: expected a string key at offset 8");
	CHECK_THROWS_WITH(parse("{\"a\": 1} x"), "JSON: trailing characters at offset 9");
	CHECK_THROWS(parse("[0x10]"));
	CHECK_THROWS(parse("[01]"));
	CHECK_THROWS(parse("{'a': 1}"));
	CHECK_THROWS(parse("[1,]"));
	CHECK_THROWS(parse("[1 2]"));
	CHECK_THROWS(parse("\"abc"));
	CHECK_THROWS(parse("\"a\nb\""));
	CHECK_THROWS(parse(R"("\x41")"));
	CHECK_THROWS(parse(R"("\u12")"));
	CHECK_THROWS(parse(R"("\ud83d")"));
	CHECK_THROWS(parse(R"("\ude00")"));
	CHECK_THROWS(parse("{\"a\": 1, \"a\": 2}"));
	CHECK_THROWS(parse("tru"));
	CHECK_THROWS(parse("-"));
	CHECK_THROWS(parse("1."));
	CHECK_THROWS(parse("1e"));
	CHECK_THROWS(parse(""));
	CHECK_THROWS(parse(std::string(300, '[') + std::string(300, ']')));
}

TEST_CASE("json: JSON Lines, one document per line, blank lines skipped", "[json]")
{
	const auto v = parseLines("{\"n\": 1}\n\n{\"n\": 2}\n[3]");
	REQUIRE(v.size() == 3);
	CHECK(v[0]["n"].num == 1);
	CHECK(v[1]["n"].num == 2);
	CHECK(v[2][0].num == 3);
	CHECK(parseLines("").empty());
	CHECK_THROWS(parseLines("{\"n\": 1}\n{\"n\": \n2}"));
}
