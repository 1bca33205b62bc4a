// SPDX-License-Identifier: MIT
// The text trace reader's hex (lib/trace/trace_reader.cpp): random packets
// written with random digit case and separators, in and out of the writer's
// groups of eight digits, read back byte for byte; a character that is not
// a hex digit anywhere in a group is refused by name. The expected bytes
// are the ones the test wrote, not another decoder's output.
#include <catch2/catch.hpp>

#include <cstdint>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <ecmxf/error.hpp>

#include "../common/thrown.hpp"
#include "trace/trace_reader.hpp"

namespace {

/// One '>' record of @p bytes: each digit in random case, a separator
/// (space or tab) before each 4-byte group as the writer does, or at
/// random places (also between the two digits of a byte).
std::string record(const std::vector<std::uint8_t> &bytes, std::mt19937 &rng, bool writerGroups)
{
	static const char lo[] = "0123456789abcdef", up[] = "0123456789ABCDEF";
	std::string s = "0.000001000 >";
	for (std::size_t i = 0; i < bytes.size(); i++) {
		for (int half = 0; half < 2; half++) {
			const bool sep = writerGroups ? (half == 0 && i % 4 == 0) : rng() % 5 == 0;
			if (sep)
				s += rng() % 2 ? ' ' : '\t';
			const unsigned d = half == 0 ? bytes[i] >> 4 : bytes[i] & 15u;
			s += rng() % 2 ? lo[d] : up[d];
		}
	}
	if (s[13] != ' ')
		s.insert(13, " "); // the record's own separator is a space

	return s;
}

/// The one record of a trace holding @p line; throws what the reader throws.
ecmxf::detail::TraceRecord parseOne(const std::string &line)
{
	std::istringstream in("ecmxf-trace 1\n" + line + "\n");
	ecmxf::detail::TraceReader r(in);
	ecmxf::detail::TraceRecord rec, end;
	if (!r.next(rec) || r.next(end))
		throw std::logic_error("not one record");
	return rec;
}

std::vector<std::uint8_t> readOne(const std::string &line)
{
	const ecmxf::detail::TraceRecord rec = parseOne(line);
	CHECK(rec.kind == '>');
	CHECK(rec.ns == 1000u);
	return rec.bytes;
}

} // namespace

TEST_CASE("the reader's hex gives back every byte written, in any case and grouping", "[trace][reader]")
{
	std::mt19937 rng(20261203);
	for (int round = 0; round < 2000; round++) {
		std::vector<std::uint8_t> bytes(64 + rng() % 200);
		for (auto &b : bytes)
			b = static_cast<std::uint8_t>(rng());
		const bool groups = round % 2 == 0;
		const std::string line = record(bytes, rng, groups);
		INFO("line " << line);
		REQUIRE(readOne(line) == bytes);
	}
}

TEST_CASE("a character that is not a hex digit is refused wherever it stands in a group", "[trace][reader]")
{
	// next to the digits' and letters' ranges, the case bit set or clear
	// (0x10..0x19 | 0x20 are digits, 0x41..0x46 | 0x80 high), a high byte
	const std::vector<unsigned char> bad = { '/', ':', '@', 'G', '`', 'g', 'z', 'Z', 0x10, 0x19,
						 0x7F, 0x80, 0xB0, 0xC1, 0xE6, 0xFF, '-', 'x' };
	std::mt19937 rng(7);
	std::vector<std::uint8_t> bytes(64);
	for (auto &b : bytes)
		b = static_cast<std::uint8_t>(rng());
	const std::string good = record(bytes, rng, true);
	REQUIRE(readOne(good) == bytes);
	for (const unsigned char c : bad) {
		for (std::size_t at = 14; at < good.size(); at++) {
			if (good[at] == ' ' || good[at] == '\t')
				continue;
			std::string line = good;
			line[at] = static_cast<char>(c);
			INFO("character 0x" << std::hex << unsigned{ c } << " at " << std::dec << at);
			const ecmxf::Error e = ecmxftest::thrown([&] { (void)parseOne(line); });
			CHECK(e.what() == "trace line 2: '" + std::string(1, static_cast<char>(c)) + "' is not a hex digit");
		}
	}
}
