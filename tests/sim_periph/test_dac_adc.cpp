// SPDX-License-Identifier: MIT
// DAC_FUNC_OP (34) and ADC_FUNC_OP (35), 038 p. 44-48, 050 same sections.
// Every value travels as a little-endian u32 in the data section.

#include <catch2/catch.hpp>

#include <chrono>

#include "bench.hpp"

using namespace periph_test;
using namespace std::chrono_literals;

namespace {

// DAC sub-operations
constexpr std::uint8_t kDacStartConv = 0, kDacSetData = 11, kDacOpen = 20, kDacClose = 21,
		       kDacSetDelay = 22;
// ADC sub-operations
constexpr std::uint8_t kAdcStartConv = 12, kAdcGetConvData = 15, kAdcGetValid = 17,
		       kAdcOpen = 40, kAdcClose = 41, kAdcConfig = 42;

Result ok(Bench &b, const Cmd &c, std::size_t len = 0)
{
	Result r = b.run(c);
	REQUIRE_FALSE(r.reply.cmdError);
	REQUIRE(r.reply.len == len);
	return r;
}

Cmd dac(std::uint8_t param, std::uint32_t value)
{
	return Cmd(kDacFuncOp, param).length(4).data32(0, value);
}

Cmd adc(std::uint8_t param, std::uint32_t value)
{
	return Cmd(kAdcFuncOp, param).length(4).data32(0, value);
}

// ConfigSampleModule: 12 bytes, 0x0 module, 0x4 trigger source, 0x8 channel
Cmd adcConfig(std::uint32_t module, std::uint32_t trigger, std::uint32_t channel)
{
	return Cmd(kAdcFuncOp, kAdcConfig).length(12).data32(0, module).data32(4, trigger).data32(
		8, channel);
}

std::uint32_t valid(Bench &b, std::uint32_t mask)
{
	return ok(b, adc(kAdcGetValid, mask), 4).le(0, 4);
}

std::uint32_t convData(Bench &b, std::uint32_t module)
{
	return ok(b, adc(kAdcGetConvData, module), 4).le(0, 4);
}

} // namespace

TEST_CASE("In mode 0x0010 DAC data reaches the output on DacStartConv", "[dac]")
{
	Bench b;
	ok(b, dac(kDacOpen, 0x0010));
	ok(b, dac(kDacSetData, 2000));
	CHECK(b.p.dacOutput(0) == 0);
	ok(b, Cmd(kDacFuncOp, kDacStartConv));
	CHECK(b.p.dacOutput(0) == 2000);
	ok(b, dac(kDacSetData, 4095));
	CHECK(b.p.dacOutput(0) == 2000);
	ok(b, Cmd(kDacFuncOp, kDacStartConv));
	CHECK(b.p.dacOutput(0) == 4095);
}

TEST_CASE("In mode 0x0000 DacSetData itself triggers the conversion", "[dac]")
{
	Bench b;
	ok(b, dac(kDacOpen, 0x0000));
	ok(b, dac(kDacSetData, 1234));
	CHECK(b.p.dacOutput(0) == 1234);
}

TEST_CASE("The DAC output changes the delay time (1/96 us units) after the trigger", "[dac]")
{
	Bench b;
	ok(b, dac(kDacOpen, 0x0010));
	ok(b, dac(kDacSetDelay, 960)); // 10 us
	ok(b, dac(kDacSetData, 3000));
	ok(b, Cmd(kDacFuncOp, kDacStartConv));
	CHECK(b.p.dacOutput(0) == 0);
	b.p.advance(9us);
	CHECK(b.p.dacOutput(0) == 0);
	b.p.advance(1us);
	CHECK(b.p.dacOutput(0) == 3000);
}

TEST_CASE("DAC_ST pin modes convert on the configured level or edge", "[dac]")
{
	Bench b;
	SECTION("0x2030: rising edge")
	{
		ok(b, dac(kDacOpen, 0x2030));
		ok(b, dac(kDacSetData, 100));
		ok(b, Cmd(kDacFuncOp, kDacStartConv)); // software trigger does nothing here
		CHECK(b.p.dacOutput(0) == 0);
		b.p.setDacTriggerPin(true);
		CHECK(b.p.dacOutput(0) == 100);
		ok(b, dac(kDacSetData, 200));
		b.p.setDacTriggerPin(false);
		CHECK(b.p.dacOutput(0) == 100);
	}
	SECTION("0x3030: falling edge")
	{
		b.p.setDacTriggerPin(true);
		ok(b, dac(kDacOpen, 0x3030));
		ok(b, dac(kDacSetData, 300));
		CHECK(b.p.dacOutput(0) == 0);
		b.p.setDacTriggerPin(false);
		CHECK(b.p.dacOutput(0) == 300);
	}
	SECTION("0x0030: while the pin is low")
	{
		b.p.setDacTriggerPin(true);
		ok(b, dac(kDacOpen, 0x0030));
		ok(b, dac(kDacSetData, 400));
		CHECK(b.p.dacOutput(0) == 0);
		b.p.setDacTriggerPin(false);
		CHECK(b.p.dacOutput(0) == 400);
		ok(b, dac(kDacSetData, 500));
		CHECK(b.p.dacOutput(0) == 500);
	}
	SECTION("0x1030: while the pin is high")
	{
		ok(b, dac(kDacOpen, 0x1030));
		ok(b, dac(kDacSetData, 600));
		CHECK(b.p.dacOutput(0) == 0);
		b.p.setDacTriggerPin(true);
		CHECK(b.p.dacOutput(0) == 600);
	}
}

TEST_CASE("DacClose returns the output to 0 and a closed DAC converts nothing", "[dac]")
{
	Bench b;
	ok(b, dac(kDacOpen, 0x0000));
	ok(b, dac(kDacSetData, 777));
	ok(b, Cmd(kDacFuncOp, kDacClose));
	CHECK(b.p.dacOutput(0) == 0);
	ok(b, dac(kDacSetData, 888));
	CHECK(b.p.dacOutput(0) == 0);
}

TEST_CASE("DAC commands with a bad parameter are refused as command errors", "[dac][errors]")
{
	Bench b;
	ok(b, dac(kDacOpen, 0x0000));
	const Cmd bad[] = {
		dac(kDacOpen, 0x0020), dac(kDacOpen, 0x4030), dac(kDacSetData, 4096),
		dac(kDacSetDelay, 1024), Cmd(kDacFuncOp, 1),  Cmd(kDacFuncOp, 12),
	};
	for (const Cmd &c : bad)
		CHECK(b.run(c).reply.cmdError);
	CHECK(b.p.dacOutput(0) == 0);
	CHECK_THROWS_AS((void)b.p.dacOutput(1), std::out_of_range);
}

TEST_CASE("An ADC conversion sets the valid flag after its conversion time and returns the "
	  "analog input (the manual's module 12 sequence)",
	  "[adc]")
{
	Bench b;
	b.p.setAnalog(12, 1234);
	ok(b, adc(kAdcOpen, 0x000));                // single-ended
	ok(b, adcConfig(0, 0, 0));                  // as the manual fills it
	ok(b, adc(kAdcStartConv, 0x1000));          // "reserved, set 0x1000"
	CHECK(valid(b, 0x1000) == 0);               // still converting
	b.p.advance(999ns);
	CHECK(valid(b, 0x1000) == 0);
	b.p.advance(1ns);                           // 1 us per conversion
	CHECK(valid(b, 0x1000) != 0);
	CHECK(convData(b, 12) == 1234);             // "reserved, set 12"
	CHECK(valid(b, 0x1000) == 0);               // reading consumed it

	SECTION("the next conversion samples the input again")
	{
		b.p.setAnalog(12, 4095);
		ok(b, adc(kAdcStartConv, 0x1000));
		b.p.advance(1us);
		CHECK(convData(b, 12) == 4095);
	}
}

TEST_CASE("ConfigSampleModule binds a sample module to a channel and the modules share one converter",
	  "[adc]")
{
	Bench b;
	b.p.setAnalog(7, 700);
	b.p.setAnalog(2, 200);
	ok(b, adc(kAdcOpen, 0x000));
	ok(b, adcConfig(3, 0, 7));
	ok(b, adc(kAdcStartConv, 0x000C)); // modules 2 and 3
	b.p.advance(1us);
	CHECK(valid(b, 0xFFFF) == 0x0004u); // module 2 first
	b.p.advance(1us);
	CHECK(valid(b, 0xFFFF) == 0x000Cu);
	CHECK(valid(b, 0x0008) == 0x0008u); // only the asked modules
	CHECK(convData(b, 3) == 700);
	CHECK(convData(b, 2) == 200);
}

TEST_CASE("Differential mode converts the pair difference around mid-scale", "[adc]")
{
	Bench b;
	b.p.setAnalog(4, 3000);
	b.p.setAnalog(5, 1000);
	ok(b, adc(kAdcOpen, 0x100));
	ok(b, adc(kAdcStartConv, 0x0010)); // module 4 = pair (4, 5)
	b.p.advance(1us);
	CHECK(convData(b, 4) == (3000 - 1000 + 4096) / 2);
}

TEST_CASE("A closed ADC converts nothing, and AdcClose drops results", "[adc]")
{
	Bench b;
	b.p.setAnalog(0, 10);
	ok(b, adc(kAdcStartConv, 0x0001));
	b.p.advance(10us);
	CHECK(valid(b, 0x0001) == 0);
	ok(b, adc(kAdcOpen, 0x000));
	ok(b, adc(kAdcStartConv, 0x0001));
	b.p.advance(1us);
	CHECK(valid(b, 0x0001) == 1);
	ok(b, Cmd(kAdcFuncOp, kAdcClose));
	CHECK(valid(b, 0x0001) == 0);
}

TEST_CASE("ADC commands with a bad parameter are refused as command errors", "[adc][errors]")
{
	Bench b;
	const Cmd bad[] = {
		adc(kAdcOpen, 0x200),     adcConfig(16, 0, 0),     adcConfig(0, 1, 0),
		adcConfig(0, 0, 16),      adc(kAdcStartConv, 0x10000), adc(kAdcGetValid, 0x10000),
		adc(kAdcGetConvData, 16), Cmd(kAdcFuncOp, 0),      Cmd(kAdcFuncOp, 43),
	};
	for (const Cmd &c : bad)
		CHECK(b.run(c).reply.cmdError);
	CHECK_THROWS_AS(b.p.setAnalog(16, 0), std::out_of_range);
}
