// SPDX-License-Identifier: MIT
// ecmxf::terminalText() (include/ecmxf/scope/terminal.hpp): golden rows
// worked out by hand from the braille dot numbering (dots 1 2 3 7 down a
// cell's left column are bits 0x01 0x02 0x04 0x40, dots 4 5 6 8 down its
// right column 0x08 0x10 0x20 0x80; the character is U+2800 + bits), and
// the bad arguments; over a Recorder and over a span of values.

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include <ecmxf/scope/recorder.hpp>
#include <ecmxf/scope/terminal.hpp>

#include "../common/thrown.hpp"

using ecmxftest::thrown;

namespace {

/// A recorder of one value signal holding @p values, in order (NaN: a
/// figure not sampled is recorded as NaN by the recorder itself, so NaN
/// values are not given here).
struct Samples {
	std::int64_t v = 0;
	ecmxf::Recorder rec;
	explicit Samples(std::initializer_list<std::int64_t> values) : rec(values.size())
	{
		rec.addValue("v", "inc", &v);
		rec.arm();
		int i = 0;
		for (const std::int64_t x : values) {
			v = x;
			(void)rec.sample(std::chrono::milliseconds(i++));
		}
	}
};

} // namespace

TEST_CASE("scope terminal: one row, a ramp 0 1 2 3 climbs one dot row per sample")
{
	Samples s{ 0, 1, 2, 3 };
	// 4 dot rows, min 0 max 3: value v on dot row v from the bottom.
	// cell 0: sample 0 bottom-left (dot 7, 0x40), sample 1 third row right
	// (dot 6, 0x20): U+2860; cell 1: sample 2 second row left (dot 2,
	// 0x02), sample 3 top right (dot 4, 0x08): U+280A
	ecmxf::TerminalRange r;
	CHECK(ecmxf::terminalText(s.rec, 0, 2, 1, &r) == std::vector<std::string>{ "\u2860\u280A" });
	CHECK(r.min == 0);
	CHECK(r.max == 3);
	// 4 cells wide: the ramp in the first two, the rest blank (U+2800)
	CHECK(ecmxf::terminalText(s.rec, 0, 4, 1) == std::vector<std::string>{ "\u2860\u280A\u2800\u2800" });
}

TEST_CASE("scope terminal: two rows, the minimum at the bottom of the lower, the maximum at the top of the upper")
{
	Samples s{ -50, 20 };
	// 8 dot rows: -50 on row 0 from the bottom (lower cell, dot 7: 0x40),
	// 20 on row 7 (upper cell, top right, dot 4: 0x08)
	CHECK(ecmxf::terminalText(s.rec, 0, 1, 2) == std::vector<std::string>{ "\u2808", "\u2840" });
	// a value between: 3 samples -50 -40 20 in 2 cells: -40 is 1/7 of the
	// way up (dot row 1 from the bottom: the lower cell's third row, right
	// column, dot 6, 0x20; with -50's dot 7: U+2860); 20 in cell 1, its
	// left column, top (dot 1, 0x01)
	Samples t{ -50, -40, 20 };
	CHECK(ecmxf::terminalText(t.rec, 0, 2, 2) == std::vector<std::string>{ "\u2800\u2801", "\u2860\u2800" });
}

TEST_CASE("scope terminal: a constant draws on the middle dot row, only the latest samples are drawn")
{
	Samples s{ 5, 5 };
	// 4 dot rows, all equal: row (4 - 1) / 2 = 1 from the bottom = the
	// third from the top: dots 3 (0x04) and 6 (0x20): U+2824
	ecmxf::TerminalRange r;
	CHECK(ecmxf::terminalText(s.rec, 0, 1, 1, &r) == std::vector<std::string>{ "\u2824" });
	CHECK(r.min == 5);
	CHECK(r.max == 5);
	// six samples, one cell: the last two (9 then 0) drawn, scaled to 0..9
	// alone: 9 top left (dot 1, 0x01), 0 bottom right (dot 8, 0x80): U+2881
	Samples w{ 100, -100, 7, 7, 9, 0 };
	CHECK(ecmxf::terminalText(w.rec, 0, 1, 1, &r) == std::vector<std::string>{ "\u2881" });
	CHECK(r.min == 0);
	CHECK(r.max == 9);
}

TEST_CASE("scope terminal: nothing recorded draws blank rows, bad arguments are EINVAL")
{
	std::int64_t v = 0;
	ecmxf::Recorder rec(10);
	rec.addValue("v", "", &v);
	ecmxf::TerminalRange r;
	CHECK(ecmxf::terminalText(rec, 0, 3, 2, &r) == std::vector<std::string>{ "\u2800\u2800\u2800", "\u2800\u2800\u2800" });
	CHECK(std::isnan(r.min));
	CHECK(std::isnan(r.max));
	const auto e = thrown([&] { (void)ecmxf::terminalText(rec, 1, 10, 2); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Catch::Matchers::Contains("signal 1 does not exist: the recorder has 1"));
	CHECK(thrown([&] { (void)ecmxf::terminalText(rec, 0, 0, 2); }).errnoValue() == EINVAL);
	CHECK(thrown([&] { (void)ecmxf::terminalText(rec, 0, 1001, 2); }).errnoValue() == EINVAL);
	CHECK(thrown([&] { (void)ecmxf::terminalText(rec, 0, 10, 0); }).errnoValue() == EINVAL);
	CHECK_THAT(thrown([&] { (void)ecmxf::terminalText(rec, 0, 10, 101); }).what(),
		   Catch::Matchers::Contains("height 101: 1..100 rows"));
}

// The drawing over a span of values (what the live view's drawing thread
// draws from its copy of the samples): the same rows as over a recorder.

TEST_CASE("scope terminal span: the same rows as the recorder overload, the latest 2 x width values drawn")
{
	const std::vector<double> ramp{ 0, 1, 2, 3 };
	ecmxf::TerminalRange r;
	CHECK(ecmxf::terminalText(ramp, 2, 1, &r) == std::vector<std::string>{ "\u2860\u280A" });
	CHECK(r.min == 0);
	CHECK(r.max == 3);
	CHECK(ecmxf::terminalText(ramp, 4, 1) == std::vector<std::string>{ "\u2860\u280A\u2800\u2800" });
	// six values, one cell: the last two (9 then 0), scaled to 0..9 alone
	const std::vector<double> six{ 100, -100, 7, 7, 9, 0 };
	CHECK(ecmxf::terminalText(six, 1, 1, &r) == std::vector<std::string>{ "\u2881" });
	CHECK(r.min == 0);
	CHECK(r.max == 9);
	// the recorder overload draws what the span one does of its samples
	Samples s{ 100, -100, 7, 7, 9, 0 };
	for (unsigned width = 1; width <= 4; width++)
		for (unsigned height = 1; height <= 3; height++)
			CHECK(ecmxf::terminalText(s.rec, 0, width, height) == ecmxf::terminalText(six, width, height));
}

TEST_CASE("scope terminal span: NaN draws no dot and is out of the range, no value draws blank rows")
{
	// 0 NaN 3 in 2 cells, 4 dot rows over 0..3: 0 bottom left of cell 0
	// (dot 7, 0x40), NaN nothing, 3 top left of cell 1 (dot 1, 0x01)
	const std::vector<double> gap{ 0, NAN, 3 };
	ecmxf::TerminalRange r;
	CHECK(ecmxf::terminalText(gap, 2, 1, &r) == std::vector<std::string>{ "\u2840\u2801" });
	CHECK(r.min == 0);
	CHECK(r.max == 3);
	CHECK(ecmxf::terminalText(std::span<const double>{}, 2, 2, &r) ==
	      std::vector<std::string>{ "\u2800\u2800", "\u2800\u2800" });
	CHECK(std::isnan(r.min));
	CHECK(std::isnan(r.max));
	const std::vector<double> nans{ NAN, NAN };
	CHECK(ecmxf::terminalText(nans, 1, 1, &r) == std::vector<std::string>{ "\u2800" });
	CHECK(std::isnan(r.min));
}

TEST_CASE("scope terminal span: bad width or height is EINVAL")
{
	const std::vector<double> v{ 1, 2 };
	CHECK(thrown([&] { (void)ecmxf::terminalText(v, 0, 2); }).errnoValue() == EINVAL);
	CHECK_THAT(thrown([&] { (void)ecmxf::terminalText(v, 1001, 2); }).what(),
		   Catch::Matchers::Contains("width 1001: 1..1000 cells"));
	CHECK(thrown([&] { (void)ecmxf::terminalText(v, 10, 0); }).errnoValue() == EINVAL);
	CHECK_THAT(thrown([&] { (void)ecmxf::terminalText(v, 10, 101); }).what(),
		   Catch::Matchers::Contains("height 101: 1..100 rows"));
	// the largest drawing is fine
	CHECK(ecmxf::terminalText(v, 1000, 100).size() == 100);
}
