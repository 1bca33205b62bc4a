// SPDX-License-Identifier: MIT
// ProcessImage: frame layout and the typed accessors against bit layouts
// worked out by hand (golden bytes), and every lookup error.

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdint>
#include <vector>

#include <ecmxf/error.hpp>
#include <ecmxf/pdo/process_image.hpp>

#include "bus.hpp"
#include "../common/thrown.hpp"

using Catch::Matchers::Equals;
using pdotest::entry;

namespace {

using ecmxftest::thrown;

using Bytes = std::vector<std::uint8_t>;

Bytes bytes(std::span<const std::uint8_t> s, std::size_t from, std::size_t n)
{
	return Bytes(s.begin() + static_cast<std::ptrdiff_t>(from), s.begin() + static_cast<std::ptrdiff_t>(from + n));
}

/// Slave 0 (4 bytes each way): a 16-bit value at bit 4, a 12-bit value at
/// bit 20. Slave 1 (19 bytes each way): eight single bits 0..7, a 64-bit
/// value at bit 8 (bytes 1..8), 3 bits of padding, a 64-bit value at bit 75
/// (bytes 9..17, from bit 3 of byte 9). Slave 2 (4 bytes each way): a
/// 32-bit float at bit 0. Inputs are mapped the same as outputs.
std::vector<ecmxf::SlavePdos> layout()
{
	ecmxf::SlavePdos s0;
	s0.outputs = { entry(0x1600, 0x2000, 1, 16, 4, "Word at bit 4"), entry(0x1600, 0x2000, 2, 12, 20) };
	s0.inputs = s0.outputs;
	s0.outputBytes = s0.inputBytes = 4;

	ecmxf::SlavePdos s1;
	for (std::uint8_t i = 0; i < 8; i++)
		s1.outputs.push_back(entry(0x1600, 0x7000, static_cast<std::uint8_t>(i + 1), 1, i));
	s1.outputs.push_back(entry(0x1601, 0x3000, 1, 64, 8));
	s1.outputs.push_back(entry(0x1601, 0x0000, 0, 3, 72)); // padding
	s1.outputs.push_back(entry(0x1601, 0x3000, 2, 64, 75));
	s1.inputs = s1.outputs;
	s1.outputBytes = s1.inputBytes = 19;

	ecmxf::SlavePdos s2;
	s2.outputs = { entry(0x1600, 0x4000, 0, 32, 0, "Real") };
	s2.inputs = s2.outputs;
	s2.outputBytes = s2.inputBytes = 4;
	return { s0, s1, s2 };
}

} // namespace

TEST_CASE("ProcessImage: slaves are laid out back to back in bus order", "[lib][pdo][image]")
{
	ecmxf::ProcessImage img(pdotest::defaultPdos());
	CHECK(img.slaveCount() == 3);
	CHECK(img.outputs().size() == 25);
	CHECK(img.inputs().size() == 35);
	CHECK(img.outputOffset(0) == 0);
	CHECK(img.outputOffset(1) == 12);
	CHECK(img.outputOffset(2) == 24);
	CHECK(img.inputOffset(2) == 34);
	CHECK(img.slaveOutputs(1).size() == 12);
	CHECK(img.slaveInputs(2).size() == 1);
	// slave 1's position actual (0x6064, bit 24 of its inputs): frame bit
	// 17 x 8 + 24 = 160
	const auto pos = img.input<std::int32_t>(1, 0x6064, 0);
	CHECK(pos.bitOffset() == 160);
	CHECK(pos.bitLength() == 32);
	CHECK(img.inputEntry(1, 0x6064, 0).name == "Position actual value");
	for (const auto b : img.outputs())
		CHECK(b == 0);
}

TEST_CASE("ProcessImage: a 16-bit value at bit 4 and a signed 12-bit value at bit 20", "[lib][pdo][image]")
{
	ecmxf::ProcessImage img(layout());
	auto w = img.output<std::uint16_t>(0, 0x2000, 1);
	auto s12 = img.output<std::int16_t>(0, 0x2000, 2);
	w.set(0xABCD);
	// bits 4..19: byte 0 high nibble D, byte 1 BC, byte 2 low nibble A
	CHECK(bytes(img.outputs(), 0, 4) == Bytes{ 0xD0, 0xBC, 0x0A, 0x00 });
	s12.set(-3);
	// -3 in 12 bits = 0xFFD at bits 20..31: byte 2 high nibble D, byte 3 FF
	CHECK(bytes(img.outputs(), 0, 4) == Bytes{ 0xD0, 0xBC, 0xDA, 0xFF });
	CHECK(w.get() == 0xABCD);
	CHECK(s12.get() == -3);
	CHECK(img.output<std::uint16_t>(0, 0x2000, 2).get() == 0x0FFD);
	// the largest and smallest 12-bit values; bits beyond 12 are not written
	s12.set(2047);
	CHECK(bytes(img.outputs(), 0, 4) == Bytes{ 0xD0, 0xBC, 0xFA, 0x7F });
	s12.set(-2048);
	CHECK(bytes(img.outputs(), 0, 4) == Bytes{ 0xD0, 0xBC, 0x0A, 0x80 });
	CHECK(s12.get() == -2048);
	// found by name, the same place
	CHECK(img.output<std::uint16_t>(0, "Word at bit 4").bitOffset() == 4);
}

TEST_CASE("ProcessImage: inputs read sign-extended from their bit length", "[lib][pdo][image]")
{
	ecmxf::ProcessImage img(layout());
	// little-endian 0x80008030: bits 4..19 = 0x0803, bits 20..31 = 0x800
	const Bytes golden{ 0x30, 0x80, 0x00, 0x80 };
	std::copy(golden.begin(), golden.end(), img.inputs().begin());
	CHECK(img.input<std::uint16_t>(0, 0x2000, 1).get() == 0x0803);
	// 12 bits at 20: 0x800 -> -2048 signed, 2048 unsigned
	CHECK(img.input<std::int16_t>(0, 0x2000, 2).get() == -2048);
	CHECK(img.input<std::uint16_t>(0, 0x2000, 2).get() == 2048);
	CHECK(img.input<std::int32_t>(0, 0x2000, 2).get() == -2048);
	CHECK(img.input<std::int64_t>(0, 0x2000, 2).get() == -2048);
	// the 16-bit field as signed: 0x0803 is positive
	CHECK(img.input<std::int16_t>(0, 0x2000, 1).get() == 0x0803);
}

TEST_CASE("ProcessImage: single bits at their own offsets, neighbours untouched", "[lib][pdo][image]")
{
	ecmxf::ProcessImage img(layout());
	auto b0 = img.output<bool>(1, 0x7000, 1);
	auto b3 = img.output<bool>(1, 0x7000, 4);
	auto b7 = img.output<bool>(1, 0x7000, 8);
	const std::size_t at = img.outputOffset(1); // 4
	REQUIRE(at == 4);
	b3.set(true);
	CHECK(img.outputs()[at] == 0x08);
	b0.set(true);
	CHECK(img.outputs()[at] == 0x09);
	b7.set(true);
	CHECK(img.outputs()[at] == 0x89);
	b3.set(false);
	CHECK(img.outputs()[at] == 0x81);
	CHECK(b0.get());
	CHECK_FALSE(b3.get());
	CHECK(b7.get());
	// an integer handle on a bit works too
	auto b7u = img.output<std::uint8_t>(1, 0x7000, 8);
	CHECK(b7u.get() == 1);
	b7u.set(2); // only bit 0 of the value is written
	CHECK(img.outputs()[at] == 0x01);
	// the bytes before and after are not touched
	CHECK(img.outputs()[at - 1] == 0);
	CHECK(img.outputs()[at + 1] == 0);

	img.inputs()[at] = 0x42;
	CHECK(img.input<bool>(1, 0x7000, 2).get());
	CHECK(img.input<bool>(1, 0x7000, 7).get());
	CHECK_FALSE(img.input<bool>(1, 0x7000, 1).get());
}

TEST_CASE("ProcessImage: 64-bit values, byte-aligned and at bit 3 of a byte", "[lib][pdo][image]")
{
	ecmxf::ProcessImage img(layout());
	const std::size_t at = img.outputOffset(1);
	auto aligned = img.output<std::uint64_t>(1, 0x3000, 1);
	auto odd = img.output<std::int64_t>(1, 0x3000, 2);
	CHECK(aligned.bitOffset() == 8 * at + 8);
	CHECK(odd.bitOffset() == 8 * at + 75);

	aligned.set(0x8877665544332211u);
	CHECK(bytes(img.outputs(), at + 1, 8) == Bytes{ 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88 });
	CHECK(aligned.get() == 0x8877665544332211u);

	// 0x0123456789ABCDEF << 3 = 0x091A2B3C4D5E6F78 over bytes 9..17
	odd.set(0x0123456789ABCDEF);
	CHECK(bytes(img.outputs(), at + 9, 9) == Bytes{ 0x78, 0x6F, 0x5E, 0x4D, 0x3C, 0x2B, 0x1A, 0x09, 0x00 });
	CHECK(odd.get() == 0x0123456789ABCDEF);

	// -2 << 3 in 67 bits: F0 FF FF FF FF FF FF FF 07
	odd.set(-2);
	CHECK(bytes(img.outputs(), at + 9, 9) == Bytes{ 0xF0, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x07 });
	CHECK(odd.get() == -2);

	// the 3 bits below and the 5 bits above the value are kept
	std::fill(img.outputs().begin(), img.outputs().end(), std::uint8_t{ 0xFF });
	odd.set(0);
	CHECK(bytes(img.outputs(), at + 8, 11) ==
	      Bytes{ 0xFF, 0x07, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xF8, 0xFF });
	CHECK(aligned.get() == 0xFFFFFFFFFFFFFFFFu);
}

TEST_CASE("ProcessImage: a 32-bit float entry", "[lib][pdo][image]")
{
	ecmxf::ProcessImage img(layout());
	auto f = img.output<float>(2, "Real");
	f.set(1.5f);
	// IEEE 754: 1.5 = 0x3FC00000
	CHECK(bytes(img.outputs(), img.outputOffset(2), 4) == Bytes{ 0x00, 0x00, 0xC0, 0x3F });
	CHECK(f.get() == 1.5f);
}

TEST_CASE("ProcessImage: lookups that fail name the slave and the object", "[lib][pdo][image]")
{
	ecmxf::ProcessImage img(layout());
	ecmxf::Error e = thrown([&] { (void)img.output<std::uint16_t>(0, 0x6041, 0); });
	CHECK_THAT(e.what(), Equals("ProcessImage: slave 0 maps no output object 0x6041:00"));
	CHECK(e.errnoValue() == EINVAL);
	e = thrown([&] { (void)img.input<std::uint16_t>(2, "Statusword"); });
	CHECK_THAT(e.what(), Equals("ProcessImage: slave 2 maps no input object named \"Statusword\""));
	e = thrown([&] { (void)img.output<std::uint8_t>(0, 0x2000, 1); });
	CHECK_THAT(e.what(), Equals("ProcessImage: output 0x2000:01 (Word at bit 4) of slave 0 is 16 bits; it "
				    "does not fit a 8-bit integer type"));
	e = thrown([&] { (void)img.input<bool>(0, 0x2000, 2); });
	CHECK_THAT(e.what(), Equals("ProcessImage: input 0x2000:02 of slave 0 is 12 bits; bool needs a 1-bit entry"));
	e = thrown([&] { (void)img.output<double>(2, 0x4000, 0); });
	CHECK_THAT(e.what(), Equals("ProcessImage: output 0x4000:00 (Real) of slave 2 is 32 bits; a 64-bit "
				    "floating-point type needs exactly 64 bits"));
	e = thrown([&] { (void)img.output<std::uint8_t>(3, 0x7000, 1); });
	CHECK_THAT(e.what(), Equals("ProcessImage: there is no slave 3 (the image has 3 slaves, positions 0..2)"));
	e = thrown([&] { (void)img.outputOffset(7); });
	CHECK_THAT(e.what(), Equals("ProcessImage: there is no slave 7 (the image has 3 slaves, positions 0..2)"));
	e = thrown([&] { (void)img.outputEntry(1, 0x3000, 3); });
	CHECK_THAT(e.what(), Equals("ProcessImage: slave 1 maps no output object 0x3000:03"));
	// padding is not an object
	e = thrown([&] { (void)img.output<std::uint8_t>(1, 0x0000, 0); });
	CHECK_THAT(e.what(), Equals("ProcessImage: slave 1 maps no output object 0x0000:00"));
}

TEST_CASE("ProcessImage: mappings that do not fit their slave are refused", "[lib][pdo][image]")
{
	ecmxf::SlavePdos s;
	s.outputs = { entry(0x1600, 0x2000, 1, 16, 30) };
	s.outputBytes = 4;
	ecmxf::Error e = thrown([&] { ecmxf::ProcessImage img({ s }); });
	CHECK_THAT(e.what(), Equals("ProcessImage: output 0x2000:01 of slave 0 at bits 30..45 lies beyond the "
				    "slave's 4 output bytes"));
	CHECK(e.errnoValue() == EINVAL);

	ecmxf::SlavePdos z;
	z.inputs = { entry(0x1A00, 0x6000, 1, 0, 0, "Nothing") };
	z.inputBytes = 1;
	e = thrown([&] { ecmxf::ProcessImage img({ ecmxf::SlavePdos{}, z }); });
	CHECK_THAT(e.what(), Equals("ProcessImage: input 0x6000:01 (Nothing) of slave 1 is 0 bits long; entries "
				    "are 1..64 bits"));
}

TEST_CASE("ProcessImage: handles stay valid when the image is moved", "[lib][pdo][image]")
{
	ecmxf::ProcessImage a(layout());
	auto w = a.output<std::uint16_t>(0, 0x2000, 1);
	ecmxf::ProcessImage b(std::move(a));
	w.set(0x1234);
	CHECK(b.output<std::uint16_t>(0, 0x2000, 1).get() == 0x1234);
	// an unbound handle reads 0 and ignores writes
	ecmxf::OutputVar<std::uint32_t> none;
	none.set(5);
	CHECK(none.get() == 0);
	CHECK_FALSE(none.bound());
}
