// SPDX-License-Identifier: MIT
// QEI_FUNC_OP (33): EncOpen (param 4, data section u32 mode), EncStart (5),
// EncStop (6), EncGetCount (21, 4 data bytes) — 038 p. 42-43, 050 same
// sections — and the encoder interrupt, header bit 29.

#include <catch2/catch.hpp>

#include "bench.hpp"

using namespace periph_test;

namespace {

constexpr std::uint8_t kOpen = 4, kStart = 5, kStop = 6, kGetCount = 21;
constexpr std::uint32_t kX4Free = 0x000, kX2Free = 0x100, kX4Compare = 0x200, kX2Compare = 0x300;
constexpr std::uint32_t kEncoderInt = 1u << 29; // header 0x10 bit 29

void ok(Bench &b, const Cmd &c)
{
	const Result r = b.run(c);
	REQUIRE_FALSE(r.reply.cmdError);
	REQUIRE(r.reply.len == 0);
}

void open(Bench &b, std::uint32_t mode)
{
	ok(b, Cmd(kQeiFuncOp, kOpen).length(4).data32(0, mode));
}

std::uint32_t count(Bench &b)
{
	const Result r = b.run(Cmd(kQeiFuncOp, kGetCount));
	REQUIRE_FALSE(r.reply.cmdError);
	REQUIRE(r.reply.len == 4);
	return r.le(0, 4);
}

} // namespace

TEST_CASE("The encoder counts quadrature edges only between EncStart and EncStop", "[qei]")
{
	Bench b;
	open(b, kX4Free);
	b.p.encoderMove(50); // not started: not counted
	CHECK(count(b) == 0);
	ok(b, Cmd(kQeiFuncOp, kStart));
	b.p.encoderMove(100);
	CHECK(count(b) == 100);
	b.p.encoderMove(-30);
	CHECK(count(b) == 70);
	ok(b, Cmd(kQeiFuncOp, kStop));
	b.p.encoderMove(1000);
	CHECK(count(b) == 70); // stopped: the count holds
	ok(b, Cmd(kQeiFuncOp, kStart));
	b.p.encoderMove(-5);
	CHECK(count(b) == 65);
}

TEST_CASE("X2 modes count every second quadrature edge, X4 modes every edge", "[qei]")
{
	Bench b;
	SECTION("X2 free-counting")
	{
		open(b, kX2Free);
		ok(b, Cmd(kQeiFuncOp, kStart));
		b.p.encoderMove(100);
		CHECK(count(b) == 50);
		b.p.encoderMove(-40);
		CHECK(count(b) == 30);
		for (int i = 0; i < 10; i++)
			b.p.encoderMove(1); // ten single edges = five counts
		CHECK(count(b) == 35);
	}
	SECTION("X2 compare-counting")
	{
		open(b, kX2Compare);
		ok(b, Cmd(kQeiFuncOp, kStart));
		b.p.encoderMove(20);
		CHECK(count(b) == 10);
	}
	SECTION("X4 compare-counting")
	{
		open(b, kX4Compare);
		ok(b, Cmd(kQeiFuncOp, kStart));
		b.p.encoderMove(20);
		CHECK(count(b) == 20);
	}
}

TEST_CASE("The 32-bit encoder count wraps below zero and raises the encoder interrupt, header "
	  "bit 29, which header 0x10 bit 29 clears",
	  "[qei][irq]")
{
	Bench b;
	open(b, kX4Free);
	ok(b, Cmd(kQeiFuncOp, kStart));
	b.p.encoderMove(3);
	CHECK(b.header().intFlags == 0);
	b.p.encoderMove(-5);
	CHECK(count(b) == 0xFFFFFFFEu); // -2 as a 32-bit two's complement count
	CHECK(b.header().intFlags == kEncoderInt);
	CHECK(b.p.intFlags() == kEncoderInt);
	CHECK(b.p.qeiIntFlags() == 0x40); // over/underflow, u8PeripIntEnable bit 6

	// a header without bit 29 leaves it; with bit 29 clears it
	b.run(Cmd(kQeiFuncOp, kGetCount).intClear(1u << 31));
	CHECK(b.header().intFlags == kEncoderInt);
	b.run(Cmd(kQeiFuncOp, kGetCount).intClear(kEncoderInt));
	CHECK(b.header().intFlags == 0);
	CHECK(b.p.qeiIntFlags() == 0);

	b.p.encoderMove(2); // overflow back through zero
	CHECK(count(b) == 0);
	CHECK(b.header().intFlags == kEncoderInt);
}

TEST_CASE("An index pulse while counting raises the encoder interrupt", "[qei][irq]")
{
	Bench b;
	open(b, kX4Free);
	b.p.encoderIndex(); // not started
	CHECK(b.p.intFlags() == 0);
	ok(b, Cmd(kQeiFuncOp, kStart));
	b.p.encoderIndex();
	CHECK(b.header().intFlags == kEncoderInt);
	CHECK(b.p.qeiIntFlags() == 0x10); // index, u8PeripIntEnable bit 4
}

TEST_CASE("EncOpen stops the encoder and clears its count", "[qei]")
{
	Bench b;
	open(b, kX4Free);
	ok(b, Cmd(kQeiFuncOp, kStart));
	b.p.encoderMove(7);
	open(b, kX4Free);
	CHECK(count(b) == 0);
	b.p.encoderMove(7);
	CHECK(count(b) == 0);
}

TEST_CASE("QEI commands with a bad parameter are refused as command errors", "[qei][errors]")
{
	Bench b;
	const Cmd bad[] = {
		Cmd(kQeiFuncOp, kOpen).length(4).data32(0, 0x400),
		Cmd(kQeiFuncOp, kOpen).length(4).data32(0, 0x001),
		Cmd(kQeiFuncOp, 0),
		Cmd(kQeiFuncOp, 7),
		Cmd(kQeiFuncOp, 20),
		Cmd(kQeiFuncOp, 22),
	};
	for (const Cmd &c : bad)
		CHECK(b.run(c).reply.cmdError);
	// the encoder was neither opened in an odd mode nor started
	b.p.encoderMove(4);
	CHECK(count(b) == 0);
}
