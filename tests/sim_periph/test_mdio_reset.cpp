// SPDX-License-Identifier: MIT
// ECM_CMD_MDIO (81, manual ver. 050 only): command parameter 0 write,
// 1 read; command data byte 0 = PHY register, byte 1 = PHY address, bytes
// 2-3 = value to write; a read answers 2 data bytes. Then reset() and
// commands that are not peripheral commands at all.

#include <catch2/catch.hpp>

#include <chrono>
#include <initializer_list>

#include "bench.hpp"

using namespace periph_test;
using namespace std::chrono_literals;

namespace {

constexpr std::uint8_t kWrite = 0, kRead = 1;

std::uint16_t mdioRead(Bench &b, std::uint8_t phy, std::uint8_t reg)
{
	const Result r = b.run(Cmd(kMdio, kRead).cmdData(reg, phy));
	REQUIRE_FALSE(r.reply.cmdError);
	REQUIRE(r.reply.len == 2);
	return static_cast<std::uint16_t>(r.le(0, 2));
}

void mdioWrite(Bench &b, std::uint8_t phy, std::uint8_t reg, std::uint16_t v)
{
	const Result r = b.run(Cmd(kMdio, kWrite).cmdData(reg, phy, static_cast<std::uint8_t>(v),
							  static_cast<std::uint8_t>(v >> 8)));
	REQUIRE_FALSE(r.reply.cmdError);
	REQUIRE(r.reply.len == 0);
}

} // namespace

TEST_CASE("MDIO reads a PHY register as two little-endian data bytes", "[mdio]")
{
	Bench b;
	b.p.setPhyRegister(1, 16, 0xBEEF);
	const Result r = b.run(Cmd(kMdio, kRead).cmdData(16, 1));
	REQUIRE_FALSE(r.reply.cmdError);
	CHECK(r.data == std::vector<std::uint8_t>{ 0xEF, 0xBE });
}

TEST_CASE("MDIO writes reach the PHY register named by command data 0/1", "[mdio]")
{
	Bench b;
	mdioWrite(b, 1, 4, 0x1234);
	CHECK(mdioRead(b, 1, 4) == 0x1234);
	CHECK(mdioRead(b, 1, 0) != 0x1234); // register 0 untouched
	// a PHY added at address 3 is separate from the one at address 1
	b.p.setPhyRegister(3, 4, 0x0001);
	mdioWrite(b, 3, 4, 0x5678);
	CHECK(mdioRead(b, 3, 4) == 0x5678);
	CHECK(mdioRead(b, 1, 4) == 0x1234);
}

TEST_CASE("The chip's PHY answers at address 1 as an IEEE 802.3 10/100 PHY with link up",
	  "[mdio]")
{
	Bench b;
	const std::uint16_t bmsr = mdioRead(b, 1, 1);
	CHECK((bmsr & 0x0004) != 0); // link status
	CHECK((bmsr & 0x0020) != 0); // autonegotiation complete
	CHECK(mdioRead(b, 1, 2) == 0x0243); // documented PHY identifier
	CHECK(mdioRead(b, 1, 3) == 0x0C54);
	mdioWrite(b, 1, 2, 0x0000); // identifiers are read-only
	CHECK(mdioRead(b, 1, 2) == 0x0243);
	// BMCR bit 15 resets the PHY and clears itself
	mdioWrite(b, 1, 4, 0x0061);
	mdioWrite(b, 1, 0, 0x8000);
	CHECK(mdioRead(b, 1, 4) == 0x01E1);
	CHECK((mdioRead(b, 1, 0) & 0x8000) == 0);
}

TEST_CASE("An MDIO address without a PHY reads 0xFFFF and ignores writes", "[mdio]")
{
	Bench b;
	CHECK(mdioRead(b, 5, 0) == 0xFFFF);
	mdioWrite(b, 5, 0, 0x1234);
	CHECK(mdioRead(b, 5, 0) == 0xFFFF);
}

TEST_CASE("MDIO commands with a bad parameter are refused as command errors", "[mdio][errors]")
{
	Bench b;
	CHECK(b.run(Cmd(kMdio, 2).cmdData(0, 1)).reply.cmdError);
	CHECK(b.run(Cmd(kMdio, kRead).cmdData(32, 1)).reply.cmdError);
	CHECK(b.run(Cmd(kMdio, kRead).cmdData(0, 32)).reply.cmdError);
	CHECK(b.run(Cmd(kMdio, kWrite).cmdData(32, 1, 0x12, 0x34)).reply.cmdError);
	CHECK_THROWS_AS(b.p.setPhyRegister(32, 0, 0), std::out_of_range);
	CHECK_THROWS_AS(b.p.setPhyRegister(0, 32, 0), std::out_of_range);
}

TEST_CASE("Commands other than 31..35 and 81 are not the peripherals' and are refused",
	  "[errors]")
{
	Bench b;
	for (const std::uint8_t code : std::initializer_list<std::uint8_t>{ 0, 30, 36, 58, 80, 82, 127 })
		CHECK(b.run(Cmd(code, 0)).reply.cmdError);
}

TEST_CASE("reset() restores the peripherals' power-on state and keeps the outside world",
	  "[reset]")
{
	Bench b;
	// Configure everything away from its defaults.
	b.run(Cmd(kGpioConfigSet, 0).cmdData(0xFF, 0xFF, 1, 0)); // all outputs
	b.run(Cmd(kGpioFuncOp, 0).cmdData(0x0F, 0x00));
	b.run(Cmd(kGpioConfigSet, 0).cmdData(0x00, 0x03, 0, 2)); // GPIO 8, 9 pulled down
	b.run(Cmd(kGpioConfigSet, 1).cmdData(9, 1));             // GPIO 9 both edges
	b.run(Cmd(kGpioConfigSet, 3).cmdData(0x1F));             // slowest debounce
	b.run(Cmd(kGpioConfigSet, 2).cmdData(0x00, 0x02, 1));    // debounce GPIO 9
	b.p.setPin(9, true);
	b.p.setPin(10, true);
	b.p.advance(10s);
	REQUIRE(b.p.gpioIntFlags() != 0);
	b.run(Cmd(kQeiFuncOp, 4).length(4).data32(0, 0x100));
	b.run(Cmd(kQeiFuncOp, 5));
	b.p.encoderMove(-10);
	REQUIRE(b.p.intFlags() != 0);
	b.run(Cmd(kDacFuncOp, 20).length(4).data32(0, 0));
	b.run(Cmd(kDacFuncOp, 11).length(4).data32(0, 99));
	REQUIRE(b.p.dacOutput(0) == 99);
	b.p.setAnalog(1, 11);
	b.run(Cmd(kAdcFuncOp, 40).length(4).data32(0, 0));
	b.run(Cmd(kAdcFuncOp, 12).length(4).data32(0, 0x0002));
	b.p.advance(1us);
	b.p.setPhyRegister(1, 20, 0x4321);

	b.p.reset();

	// GPIO: floating inputs, no flags, no debounce, no interrupts
	for (unsigned i = 0; i < 20; i++)
		CHECK(b.p.pin(i) == (i == 9 || i == 10)); // only the outside drivers remain
	const RspFields h = b.header();
	CHECK(h.gpioIn[0] == 0x00);
	CHECK(h.gpioIn[1] == 0x06);
	CHECK(h.gpioIntFlag[0] == 0);
	CHECK(h.gpioIntFlag[1] == 0);
	CHECK(h.intFlags == 0);
	b.p.setPin(9, false); // no debounce, no interrupt any more
	CHECK(b.header().gpioIn[1] == 0x04);
	CHECK(b.p.gpioIntFlags() == 0);
	// QEI: stopped at 0 in X4 mode
	b.p.encoderMove(10);
	Result r = b.run(Cmd(kQeiFuncOp, 21));
	CHECK(r.le(0, 4) == 0);
	b.run(Cmd(kQeiFuncOp, 5));
	b.p.encoderMove(10);
	r = b.run(Cmd(kQeiFuncOp, 21));
	CHECK(r.le(0, 4) == 10);
	// DAC: closed, output 0
	CHECK(b.p.dacOutput(0) == 0);
	b.run(Cmd(kDacFuncOp, 11).length(4).data32(0, 5));
	CHECK(b.p.dacOutput(0) == 0);
	// ADC: closed, nothing valid
	r = b.run(Cmd(kAdcFuncOp, 17).length(4).data32(0, 0xFFFF));
	CHECK(r.le(0, 4) == 0);
	// outside world: analog inputs and the PHY keep their values
	b.run(Cmd(kAdcFuncOp, 40).length(4).data32(0, 0));
	b.run(Cmd(kAdcFuncOp, 12).length(4).data32(0, 0x0002));
	b.p.advance(1us);
	r = b.run(Cmd(kAdcFuncOp, 15).length(4).data32(0, 1));
	CHECK(r.le(0, 4) == 11);
	CHECK(mdioRead(b, 1, 20) == 0x4321);
}
