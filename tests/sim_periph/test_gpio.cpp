// SPDX-License-Identifier: MIT
// GPIO_CONFIG_SET (31), GPIO_FUNC_OP (32) and the GPIO fields of the packet
// headers, with commands laid out as in the manuals (038 p. 35-42, 050 same
// sections) and the choices of Documentation/sim-peripherals.rst.

#include <catch2/catch.hpp>

#include <chrono>

#include "bench.hpp"

using namespace periph_test;
using namespace std::chrono_literals;

namespace {

// GPIO_CONFIG_SET sub-operations (command parameter)
constexpr std::uint8_t kSetMode = 0, kIntEnable = 1, kDebounce = 2, kDebounceClock = 3,
		       kIntClear = 4, kIntClearExt = 6, kSetModeExt = 8, kDebounceExt = 9;
// GPIO_FUNC_OP sub-operations
constexpr std::uint8_t kSetValue = 0, kGetValue = 1, kSetValueExt = 2, kGetValueExt = 3,
		       kGetIntFlag = 5, kGetIntFlagExt = 7;
// mode / pull / interrupt type codes of the manuals
constexpr std::uint8_t kInput = 0, kOutput = 1, kOpenDrain = 2, kQuasi = 3;
constexpr std::uint8_t kNoPull = 0, kPullUp = 1, kPullDown = 2;
constexpr std::uint8_t kBoth = 1, kFalling = 2, kRising = 3;

// Run a command that must succeed and answer @p len data bytes.
Result ok(Bench &b, const Cmd &c, std::size_t len = 0)
{
	Result r = b.run(c);
	REQUIRE_FALSE(r.reply.cmdError);
	REQUIRE(r.reply.ret == 0);
	REQUIRE(r.reply.len == len);
	return r;
}

std::uint32_t getValueExt(Bench &b)
{
	return ok(b, Cmd(kGpioFuncOp, kGetValueExt), 4).le(0, 4);
}

} // namespace

TEST_CASE("GPIO lines power up as floating inputs that read low and raise no flags", "[gpio]")
{
	Bench b;
	for (unsigned i = 0; i < 20; i++)
		CHECK_FALSE(b.p.pin(i));
	CHECK(getValueExt(b) == 0);
	CHECK(ok(b, Cmd(kGpioFuncOp, kGetIntFlagExt), 4).le(0, 4) == 0);
	const RspFields h = b.header();
	CHECK(h.gpioIn[0] == 0);
	CHECK(h.gpioIn[1] == 0);
	CHECK(h.gpioIntFlag[0] == 0);
	CHECK(h.gpioIntFlag[1] == 0);
	CHECK(h.intFlags == 0);
}

TEST_CASE("GpioSetMode selects lines by the command data 0/1 masks and applies the data 2 mode "
	  "and data 3 pull",
	  "[gpio]")
{
	Bench b;
	// lines 0 and 9: input with pull-up; line 1: input with pull-down
	ok(b, Cmd(kGpioConfigSet, kSetMode).cmdData(0x01, 0x02, kInput, kPullUp));
	ok(b, Cmd(kGpioConfigSet, kSetMode).cmdData(0x02, 0x00, kInput, kPullDown));
	CHECK(b.p.pin(0));
	CHECK(b.p.pin(9));
	CHECK_FALSE(b.p.pin(1));
	CHECK_FALSE(b.p.pin(8)); // not selected: still floating
	CHECK(getValueExt(b) == 0x0201u);

	SECTION("an outside driver overrides a pull")
	{
		b.p.setPin(0, false);
		b.p.setPin(1, true);
		CHECK_FALSE(b.p.pin(0));
		CHECK(b.p.pin(1));
		CHECK(getValueExt(b) == 0x0202u);
	}
	SECTION("a push-pull output drives its latch whatever the outside does")
	{
		ok(b, Cmd(kGpioFuncOp, kSetValue).cmdData(0x00, 0x00));
		ok(b, Cmd(kGpioConfigSet, kSetMode).cmdData(0x01, 0x00, kOutput, kNoPull));
		b.p.setPin(0, true);
		CHECK_FALSE(b.p.pin(0));
		ok(b, Cmd(kGpioFuncOp, kSetValue).cmdData(0x01, 0x00));
		b.p.setPin(0, false);
		CHECK(b.p.pin(0));
	}
	SECTION("open-drain pulls low on 0 and releases the pin on 1")
	{
		ok(b, Cmd(kGpioFuncOp, kSetValue).cmdData(0x00, 0x00));
		ok(b, Cmd(kGpioConfigSet, kSetMode).cmdData(0x04, 0x00, kOpenDrain, kPullUp));
		CHECK_FALSE(b.p.pin(2));
		ok(b, Cmd(kGpioFuncOp, kSetValue).cmdData(0x04, 0x00));
		CHECK(b.p.pin(2)); // released: the pull-up wins
		b.p.setPin(2, false);
		CHECK_FALSE(b.p.pin(2)); // another open-drain device pulls low
	}
	SECTION("quasi-bidirectional drives 0 strongly and 1 weakly")
	{
		ok(b, Cmd(kGpioConfigSet, kSetMode).cmdData(0x08, 0x00, kQuasi, kNoPull));
		ok(b, Cmd(kGpioFuncOp, kSetValue).cmdData(0x08, 0x00));
		CHECK(b.p.pin(3)); // weak high, no outside driver
		b.p.setPin(3, false);
		CHECK_FALSE(b.p.pin(3)); // outside overrides the weak high
		b.p.setPin(3, true);
		ok(b, Cmd(kGpioFuncOp, kSetValue).cmdData(0x00, 0x00));
		CHECK_FALSE(b.p.pin(3)); // strong low
	}
}

TEST_CASE("The GpioSetMode extension (parameter 8) configures GPIO 16..19 from command data 0 "
	  "bits 0..3",
	  "[gpio]")
{
	Bench b;
	ok(b, Cmd(kGpioConfigSet, kSetModeExt).cmdData(0x05, 0x00, kInput, kPullUp));
	CHECK(b.p.pin(16));
	CHECK_FALSE(b.p.pin(17));
	CHECK(b.p.pin(18));
	CHECK_FALSE(b.p.pin(19));
	CHECK_FALSE(b.p.pin(0)); // data 0 bit 0 is GPIO 16, not GPIO 0
	CHECK(getValueExt(b) == 0x50000u);
	// Plain GetValue reports only lines 0..15 in two bytes.
	CHECK(ok(b, Cmd(kGpioFuncOp, kGetValue), 2).le(0, 2) == 0);
}

TEST_CASE("GpioSetValue sets GPIO 0..15 from command data 0/1 and GpioExtSetValue also GPIO "
	  "16..19 from data 2",
	  "[gpio]")
{
	Bench b;
	ok(b, Cmd(kGpioConfigSet, kSetMode).cmdData(0xFF, 0xFF, kOutput, kNoPull));
	ok(b, Cmd(kGpioConfigSet, kSetModeExt).cmdData(0x0F, 0x00, kOutput, kNoPull));

	ok(b, Cmd(kGpioFuncOp, kSetValue).cmdData(0xA5, 0x3C));
	for (unsigned i = 0; i < 16; i++)
		CHECK(b.p.pin(i) == (((0x3CA5u >> i) & 1u) != 0));
	CHECK(ok(b, Cmd(kGpioFuncOp, kGetValue), 2).data == std::vector<std::uint8_t>{ 0xA5, 0x3C });

	ok(b, Cmd(kGpioFuncOp, kSetValueExt).cmdData(0x01, 0x80, 0x09));
	CHECK(b.p.pin(0));
	CHECK_FALSE(b.p.pin(2));
	CHECK(b.p.pin(15));
	CHECK(b.p.pin(16));
	CHECK_FALSE(b.p.pin(17));
	CHECK_FALSE(b.p.pin(18));
	CHECK(b.p.pin(19));
	CHECK(ok(b, Cmd(kGpioFuncOp, kGetValueExt), 4).data ==
	      std::vector<std::uint8_t>{ 0x01, 0x80, 0x09, 0x00 });
}

TEST_CASE("Header 0x16/0x17 drive GPIO 0..15 only when header 0x08 bit 15 is set, with GPIO 12 "
	  "and 13 swapped as in firmware 0x1E and later",
	  "[gpio][header]")
{
	Bench b;
	ok(b, Cmd(kGpioConfigSet, kSetMode).cmdData(0xFF, 0xFF, kOutput, kNoPull));
	ok(b, Cmd(kGpioFuncOp, kSetValue).cmdData(0x00, 0x00));

	// Without bit 15 the output bytes are ignored.
	ok(b, Cmd(kGpioFuncOp, kGetValue).gpioOut(0xFF, 0xFF), 2);
	for (unsigned i = 0; i < 16; i++)
		CHECK_FALSE(b.p.pin(i));

	// 0x16 = GPIO 0..7, 0x17 bits 0..3 = GPIO 8..11
	ok(b, Cmd(kGpioFuncOp, kGetValue).reserved(0x8000).gpioOut(0x81, 0x09), 2);
	CHECK(b.p.pin(0));
	CHECK(b.p.pin(7));
	CHECK_FALSE(b.p.pin(1));
	CHECK(b.p.pin(8));
	CHECK(b.p.pin(11));
	CHECK_FALSE(b.p.pin(9));

	// 0x17 bit 4 (header bit 12) drives GPIO 13, bit 5 (header bit 13) GPIO 12
	ok(b, Cmd(kGpioFuncOp, kGetValue).reserved(0x8000).gpioOut(0x00, 0x10), 2);
	CHECK(b.p.pin(13));
	CHECK_FALSE(b.p.pin(12));
	ok(b, Cmd(kGpioFuncOp, kGetValue).reserved(0x8000).gpioOut(0x00, 0x20), 2);
	CHECK(b.p.pin(12));
	CHECK_FALSE(b.p.pin(13));
	// bits 6, 7 drive GPIO 14, 15
	ok(b, Cmd(kGpioFuncOp, kGetValue).reserved(0x8000).gpioOut(0x00, 0xC0), 2);
	CHECK(b.p.pin(14));
	CHECK(b.p.pin(15));
	CHECK_FALSE(b.p.pin(12));
	CHECK_FALSE(b.p.pin(0)); // the header carries the whole image of 0..15
}

TEST_CASE("Levels driven onto input pins appear in GpioGetValue, GpioExtGetValue and response "
	  "header 0x16/0x17",
	  "[gpio][header]")
{
	Bench b;
	b.p.setPin(1, true);
	b.p.setPin(10, true);
	b.p.setPin(15, true);
	b.p.setPin(19, true);
	const Result r = ok(b, Cmd(kGpioFuncOp, kGetValue), 2);
	CHECK(r.data == std::vector<std::uint8_t>{ 0x02, 0x84 });
	CHECK(getValueExt(b) == 0x88402u);
	const RspFields h = b.header();
	CHECK(h.gpioIn[0] == 0x02);
	CHECK(h.gpioIn[1] == 0x84);
	b.p.setPin(10, false);
	CHECK(b.header().gpioIn[1] == 0x80);
}

TEST_CASE("A debounced input accepts a new level only after it held for two sampling periods "
	  "of the debounce clock",
	  "[gpio][debounce]")
{
	Bench b;
	// 10 kHz source (bit 4), cycle 3: sampling period 2^3 * 100 us = 800 us,
	// so a level must hold 1.6 ms.
	ok(b, Cmd(kGpioConfigSet, kDebounceClock).cmdData(0x13));
	// debounce on GPIO 1 (data 0 bit 1) and GPIO 9 (data 1 bit 1): data 2 = 1 enable
	ok(b, Cmd(kGpioConfigSet, kDebounce).cmdData(0x02, 0x02, 1));

	b.p.setPin(1, true);
	b.p.setPin(2, true); // not debounced: seen at once
	CHECK(b.p.pin(1));   // the pad is high at once...
	CHECK(getValueExt(b) == 0x4u); // ...the input buffer is not
	b.p.advance(1500us);
	CHECK(getValueExt(b) == 0x4u);
	b.p.advance(100us);
	CHECK(getValueExt(b) == 0x6u);

	SECTION("a pulse shorter than the debounce time is filtered out")
	{
		b.p.setPin(9, true);
		b.p.advance(1000us);
		b.p.setPin(9, false);
		b.p.advance(5ms);
		CHECK(getValueExt(b) == 0x6u);
		CHECK(b.header().gpioIn[1] == 0x00);
	}
	SECTION("a bounce restarts the count")
	{
		b.p.setPin(9, true);
		b.p.advance(1000us);
		b.p.setPin(9, false);
		b.p.setPin(9, true);
		b.p.advance(1000us);
		CHECK(b.header().gpioIn[1] == 0x00);
		b.p.advance(600us);
		CHECK(b.header().gpioIn[1] == 0x02);
	}
	SECTION("disabling debounce (data 2 = 0) lets a pending level through at once")
	{
		b.p.setPin(9, true);
		ok(b, Cmd(kGpioConfigSet, kDebounce).cmdData(0x00, 0x02, 0));
		CHECK(b.header().gpioIn[1] == 0x02);
	}
	SECTION("the 192 MHz source with cycle 15 gives 2 * 32768 / 192 MHz = 341.33 us")
	{
		ok(b, Cmd(kGpioConfigSet, kDebounceClock).cmdData(0x0F));
		b.p.setPin(9, true);
		b.p.advance(341us);
		CHECK(b.header().gpioIn[1] == 0x00);
		b.p.advance(1us);
		CHECK(b.header().gpioIn[1] == 0x02);
	}
}

TEST_CASE("The GpioEnableDebounce extension (parameter 9) debounces GPIO 16..19", "[gpio][debounce]")
{
	Bench b;
	ok(b, Cmd(kGpioConfigSet, kDebounceClock).cmdData(0x10)); // 10 kHz, 1 clock: 200 us
	ok(b, Cmd(kGpioConfigSet, kDebounceExt).cmdData(0x08, 0x00, 1)); // GPIO 19
	b.p.setPin(19, true);
	b.p.setPin(18, true);
	CHECK(getValueExt(b) == 0x40000u);
	b.p.advance(200us);
	CHECK(getValueExt(b) == 0xC0000u);
}

TEST_CASE("GPIO interrupts flag rising, falling or both edges per GpioIntEnable type, in the "
	  "response header and GpioGetIntFlag",
	  "[gpio][irq]")
{
	Bench b;
	// command data 0 = channel, data 1 = type
	ok(b, Cmd(kGpioConfigSet, kIntEnable).cmdData(3, kRising));
	ok(b, Cmd(kGpioConfigSet, kIntEnable).cmdData(4, kFalling));
	ok(b, Cmd(kGpioConfigSet, kIntEnable).cmdData(10, kBoth));
	ok(b, Cmd(kGpioConfigSet, kIntEnable).cmdData(17, kBoth));

	b.p.setPin(3, true);  // rising: flag
	b.p.setPin(4, true);  // rising on a falling-edge line: nothing
	b.p.setPin(10, true); // both: flag
	b.p.setPin(17, true); // both: flag (extension line)
	b.p.setPin(5, true);  // no interrupt configured
	RspFields h = b.header();
	CHECK(h.gpioIntFlag[0] == 0x08);
	CHECK(h.gpioIntFlag[1] == 0x04);
	CHECK(b.p.gpioIntFlags() == 0x0408u);
	CHECK(ok(b, Cmd(kGpioFuncOp, kGetIntFlag), 2).data == std::vector<std::uint8_t>{ 0x08, 0x04 });
	CHECK(ok(b, Cmd(kGpioFuncOp, kGetIntFlagExt), 4).data ==
	      std::vector<std::uint8_t>{ 0x08, 0x04, 0x02, 0x00 });

	b.p.setPin(4, false); // falling: flag
	b.p.setPin(3, false); // falling on a rising-edge line: nothing new
	CHECK(b.p.gpioIntFlags() == 0x0418u);

	SECTION("GpioIntClear (parameter 4) clears the lines of command data 0/1")
	{
		ok(b, Cmd(kGpioConfigSet, kIntClear).cmdData(0x08, 0x04));
		CHECK(b.p.gpioIntFlags() == 0x0010u);
		CHECK(ok(b, Cmd(kGpioFuncOp, kGetIntFlagExt), 4).le(0, 4) == 0x20010u);
	}
	SECTION("the GpioIntClear extension (parameter 6) clears GPIO 16..19 from command data 2")
	{
		ok(b, Cmd(kGpioConfigSet, kIntClearExt).cmdData(0x00, 0x00, 0x02));
		CHECK(ok(b, Cmd(kGpioFuncOp, kGetIntFlagExt), 4).le(0, 4) == 0x0418u);
	}
	SECTION("command header 0x14/0x15 clear flags 0..7 and 8..15")
	{
		b.run(Cmd(0, 0).gpioIntClear(0x10, 0x04)); // any command header clears
		h = b.header();
		CHECK(h.gpioIntFlag[0] == 0x08);
		CHECK(h.gpioIntFlag[1] == 0x00);
	}
	SECTION("type 0 disables the interrupt; the flag stays until cleared")
	{
		ok(b, Cmd(kGpioConfigSet, kIntEnable).cmdData(10, 0));
		b.p.setPin(10, false);
		CHECK(b.p.gpioIntFlags() == 0x0418u);
		ok(b, Cmd(kGpioConfigSet, kIntClear).cmdData(0x00, 0x04));
		b.p.setPin(10, true);
		CHECK(b.p.gpioIntFlags() == 0x0018u);
	}
}

TEST_CASE("A debounced line raises its interrupt when the debounced level changes", "[gpio][irq]")
{
	Bench b;
	ok(b, Cmd(kGpioConfigSet, kDebounceClock).cmdData(0x10)); // 200 us
	ok(b, Cmd(kGpioConfigSet, kDebounce).cmdData(0x01, 0x00, 1));
	ok(b, Cmd(kGpioConfigSet, kIntEnable).cmdData(0, kRising));
	b.p.setPin(0, true);
	CHECK(b.p.gpioIntFlags() == 0);
	b.p.advance(199us);
	CHECK(b.p.gpioIntFlags() == 0);
	b.p.advance(1us);
	CHECK(b.p.gpioIntFlags() == 1u);
}

TEST_CASE("GPIO commands with a bad parameter are refused as command errors", "[gpio][errors]")
{
	Bench b;
	const Cmd bad[] = {
		Cmd(kGpioConfigSet, 5),                                     // no such sub-operation
		Cmd(kGpioConfigSet, 7),
		Cmd(kGpioConfigSet, 10),
		Cmd(kGpioConfigSet, kSetMode).cmdData(0x01, 0x00, 4, 0),    // mode 4
		Cmd(kGpioConfigSet, kSetMode).cmdData(0x01, 0x00, 0, 3),    // pull 3
		Cmd(kGpioConfigSet, kSetModeExt).cmdData(0x10, 0x00, 0, 0), // GPIO 20
		Cmd(kGpioConfigSet, kDebounce).cmdData(0x01, 0x00, 2),      // neither 0 nor 1
		Cmd(kGpioConfigSet, kDebounceExt).cmdData(0x20, 0x00, 1),   // GPIO 21
		Cmd(kGpioConfigSet, kDebounceClock).cmdData(0x20),          // bit 5
		Cmd(kGpioConfigSet, kIntEnable).cmdData(20, kBoth),         // channel 20
		Cmd(kGpioConfigSet, kIntEnable).cmdData(0, 4),              // type 4
		Cmd(kGpioFuncOp, 4),
		Cmd(kGpioFuncOp, 6),
		Cmd(kGpioFuncOp, 8),
	};
	for (const Cmd &c : bad) {
		const Result r = b.run(c);
		CHECK(r.reply.cmdError);
		CHECK(r.reply.len == 0);
	}
	// nothing was changed by the refused commands
	for (unsigned i = 0; i < 20; i++)
		CHECK_FALSE(b.p.pin(i));
	b.p.setPin(0, true);
	CHECK(b.p.gpioIntFlags() == 0);
}

TEST_CASE("Pin access from outside names a line that does not exist", "[gpio][errors]")
{
	Bench b;
	CHECK_THROWS_AS(b.p.setPin(20, true), std::out_of_range);
	CHECK_THROWS_AS((void)b.p.pin(20), std::out_of_range);
}
