// SPDX-License-Identifier: MIT
// GPIO, QEI, DAC, ADC and MDIO through the typed calls, against the model
// of Documentation/sim-peripherals.rst: output lines read back what they
// drive, floating inputs read low, pulls and quasi-bidirectional lines
// read high, edge interrupts, debounce, the ADC's sample modules over
// unconnected (0 V) inputs, the PHY at MDIO address 1.

#include "helpers.hpp"
#include <ecmxf/chip/peripherals.hpp>

#include <cerrno>

using namespace chiptest;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using ecmxf::GpioEdge;
using ecmxf::GpioMode;
using ecmxf::GpioPull;

TEST_CASE("GPIO: outputs read back what they drive, floating inputs low, pull-ups high", "[lib][chip][gpio]")
{
	SimDevice s;
	auto &d = *s.dev;
	CHECK(d.peripherals().gpioRead() == 0x0000); // power-on: floating inputs
	d.peripherals().gpioSetMode(0x000F, GpioMode::Output);
	CHECK(d.peripherals().gpioRead() == 0x000F); // latches power up at 1
	d.peripherals().gpioWrite(0x0005);
	CHECK(d.peripherals().gpioRead() == 0x0005);
	CHECK(d.lastHeader().gpioIn[0] == 0x05);
	CHECK(d.lastHeader().gpioIn[1] == 0x00);
	d.peripherals().gpioSetMode(0x00F0, GpioMode::Input, GpioPull::Up);
	CHECK(d.peripherals().gpioRead() == 0x00F5);
	d.peripherals().gpioSetMode(0x0030, GpioMode::Input, GpioPull::Down);
	CHECK(d.peripherals().gpioRead() == 0x00C5);
	// quasi-bidirectional: latch 0 drives low, latch 1 is a weak pull-up
	d.peripherals().gpioSetMode(1u << 8, GpioMode::QuasiBidirectional);
	CHECK(d.peripherals().gpioRead() == 0x00C5);
	d.peripherals().gpioWrite(0x0105);
	CHECK(d.peripherals().gpioRead() == 0x01C5);
	// open-drain: latch 1 releases the line, the pull-up pulls it high
	d.peripherals().gpioSetMode(1u << 9, GpioMode::OpenDrain, GpioPull::Up);
	CHECK(d.peripherals().gpioRead() == 0x01C5);
	d.peripherals().gpioWrite(0x0305);
	CHECK(d.peripherals().gpioRead() == 0x03C5);

	// GPIO 16..19 through the extended commands
	d.peripherals().gpioSetMode(0xF0000, GpioMode::Output);
	d.peripherals().gpioWriteAll(0xA0305);
	CHECK(d.peripherals().gpioReadAll() == 0xA03C5u);
	CHECK(d.peripherals().gpioRead() == 0x03C5);
}

TEST_CASE("GPIO: edge interrupts, flags, clear, and the extended lines", "[lib][chip][gpio]")
{
	SimDevice s;
	auto &d = *s.dev;
	d.peripherals().gpioSetMode(0x0001, GpioMode::Output);
	d.peripherals().gpioWrite(0x0000);
	d.peripherals().gpioSetInterrupt(0, GpioEdge::Rising);
	d.peripherals().gpioWrite(0x0000);
	CHECK(d.peripherals().gpioInterruptFlags() == 0);
	d.peripherals().gpioWrite(0x0001); // rising edge
	CHECK(d.peripherals().gpioInterruptFlags() == 0x0001);
	CHECK(d.peripherals().gpioInterruptFlagsAll() == 0x00001u);
	CHECK(d.lastHeader().gpioIntFlag[0] == 0x01);
	d.peripherals().gpioWrite(0x0000); // falling: no new flag, the old one stays
	CHECK(d.peripherals().gpioInterruptFlags() == 0x0001);
	d.peripherals().gpioClearInterrupts(0x0001);
	CHECK(d.peripherals().gpioInterruptFlags() == 0);

	d.peripherals().gpioSetMode(1u << 17, GpioMode::Output);
	d.peripherals().gpioSetInterrupt(17, GpioEdge::Falling);
	d.peripherals().gpioWriteAll(0x00000); // latch 1 -> 0: falling edge
	CHECK(d.peripherals().gpioInterruptFlagsAll() == (1u << 17));
	CHECK(d.peripherals().gpioInterruptFlags() == 0);
	d.peripherals().gpioClearInterrupts(1u << 17);
	CHECK(d.peripherals().gpioInterruptFlagsAll() == 0);

	d.peripherals().gpioSetInterrupt(17, GpioEdge::Both);
	d.peripherals().gpioWriteAll(1u << 17);
	d.peripherals().gpioWriteAll(0);
	CHECK(d.peripherals().gpioInterruptFlagsAll() == (1u << 17));
	d.peripherals().gpioSetInterrupt(17, GpioEdge::Disabled);
	d.peripherals().gpioClearInterrupts(1u << 17);
	d.peripherals().gpioWriteAll(1u << 17);
	CHECK(d.peripherals().gpioInterruptFlagsAll() == 0);
}

TEST_CASE("GPIO: a debounced line holds its level until the debounce time passed", "[lib][chip][gpio]")
{
	SimDevice s;
	auto &d = *s.dev;
	d.peripherals().gpioSetMode(0x0002, GpioMode::Output);
	d.peripherals().gpioWrite(0x0000);
	CHECK(d.peripherals().gpioRead() == 0x0000);
	// 2 x 2^15 periods of 10 kHz = 6.55 s: far longer than a few exchanges
	d.peripherals().gpioSetDebounceClock(15, ecmxf::DebounceClock::LowSpeed10kHz);
	d.peripherals().gpioSetDebounce(0x0002, true);
	d.peripherals().gpioWrite(0x0002);
	CHECK(d.peripherals().gpioRead() == 0x0000);
	CHECK(d.peripherals().gpioRead() == 0x0000);
	// disabling debounce lets the pending level through at once
	d.peripherals().gpioSetDebounce(0x0002, false);
	CHECK(d.peripherals().gpioRead() == 0x0002);

	// the extended lines use sub-operation 9 (no error is the check here)
	d.peripherals().gpioSetDebounce(0xF0000, true);
	d.peripherals().gpioSetDebounceClock(0, ecmxf::DebounceClock::Core192MHz);
	CHECK((d.lastHeader().errStatus & 0x80) == 0);
}

TEST_CASE("GPIO: arguments out of range are refused before anything is sent", "[lib][chip][gpio]")
{
	SimDevice s;
	auto &d = *s.dev;
	auto e = thrown([&] { d.peripherals().gpioSetMode(0, GpioMode::Output); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("GPIO_CONFIG_SET (GpioSetMode): no GPIO line selected (line mask 0)"));
	e = thrown([&] { d.peripherals().gpioSetMode(1u << 20, GpioMode::Output); });
	CHECK_THAT(e.what(), Equals("GPIO_CONFIG_SET (GpioSetMode): line mask 0x00100000 names lines above GPIO 19 "
				    "(the ECM-XF has GPIO 0..19)"));
	e = thrown([&] { d.peripherals().gpioSetMode(1, static_cast<GpioMode>(4)); });
	CHECK_THAT(e.what(), Equals("GPIO_CONFIG_SET (GpioSetMode): mode 4 is out of range (0 input, 1 output, 2 "
				    "open-drain, 3 quasi-bidirectional)"));
	e = thrown([&] { d.peripherals().gpioSetMode(1, GpioMode::Input, static_cast<GpioPull>(3)); });
	CHECK_THAT(e.what(), Equals("GPIO_CONFIG_SET (GpioSetMode): pull 3 is out of range (0 none, 1 up, 2 down)"));
	e = thrown([&] { d.peripherals().gpioSetInterrupt(20, GpioEdge::Both); });
	CHECK_THAT(e.what(), Equals("GPIO_CONFIG_SET (GpioIntEnable): GPIO line 20 is out of range (0..19)"));
	e = thrown([&] { d.peripherals().gpioSetInterrupt(0, static_cast<GpioEdge>(4)); });
	CHECK_THAT(e.what(), Contains("interrupt type 4 is out of range (0 disabled, 1 both edges, 2 falling, 3 rising)"));
	e = thrown([&] { d.peripherals().gpioSetDebounceClock(16, ecmxf::DebounceClock::Core192MHz); });
	CHECK_THAT(e.what(), Equals("GPIO_CONFIG_SET (GpioSetDebounceClock): cycle 16 is out of range (0..15: "
				    "2^cycle clock periods)"));
	e = thrown([&] { d.peripherals().gpioSetDebounce(0x100000, true); });
	CHECK_THAT(e.what(), Contains("GPIO_CONFIG_SET (GpioEnableDebounce): line mask 0x00100000 names lines above"));
	e = thrown([&] { d.peripherals().gpioClearInterrupts(0); });
	CHECK_THAT(e.what(), Equals("GPIO_CONFIG_SET (GpioIntClear): no GPIO line selected (line mask 0)"));
	e = thrown([&] { d.peripherals().gpioWriteAll(0x100000); });
	CHECK_THAT(e.what(), Equals("GPIO_FUNC_OP (GpioExtSetValue): values 0x00100000 name lines above GPIO 19 (the "
				    "ECM-XF has GPIO 0..19)"));
	CHECK(s.chip().stats().exchanges == 0); // nothing was sent
}

TEST_CASE("QEI: open, start, count, stop (no shaft motion: count 0)", "[lib][chip][qei]")
{
	SimDevice s;
	auto &d = *s.dev;
	d.peripherals().qeiOpen(ecmxf::QeiMode::X2Free);
	d.peripherals().qeiStart();
	CHECK(d.peripherals().qeiCount() == 0);
	d.peripherals().qeiStop();
	CHECK(d.peripherals().qeiCount() == 0);
	d.peripherals().qeiOpen(ecmxf::QeiMode::X4Compare);
	CHECK((d.lastHeader().intFlags & ecmxf::irq::kEncoder) == 0);
	const auto e = thrown([&] { d.peripherals().qeiOpen(static_cast<ecmxf::QeiMode>(0x400)); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("QEI_FUNC_OP (EncOpen): mode 0x400 is out of range (0x000 X4 free, 0x100 X2 "
				    "free, 0x200 X4 compare, 0x300 X2 compare)"));
}

TEST_CASE("DAC: every sub-operation is accepted, ranges are checked", "[lib][chip][dac]")
{
	SimDevice s;
	auto &d = *s.dev;
	d.peripherals().dacOpen(ecmxf::DacTrigger::StartConv);
	d.peripherals().dacSetDelay(960);
	d.peripherals().dacWrite(4095);
	d.peripherals().dacStartConversion();
	d.peripherals().dacOpen(ecmxf::DacTrigger::PinRising);
	d.peripherals().dacClose();
	CHECK((d.lastHeader().errStatus & 0x80) == 0);
	auto e = thrown([&] { d.peripherals().dacWrite(4096); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("DAC_FUNC_OP (DacSetData): value 4096 is out of range (0..4095 = 0..3.3 V)"));
	e = thrown([&] { d.peripherals().dacSetDelay(1024); });
	CHECK_THAT(e.what(), Equals("DAC_FUNC_OP (DacSetDelayTime): delay 1024 is out of range (0..1023 in 1/96 us)"));
	e = thrown([&] { d.peripherals().dacOpen(static_cast<ecmxf::DacTrigger>(0x20)); });
	CHECK_THAT(e.what(), Equals("DAC_FUNC_OP (DacOpen): trigger 0x0020 is not one of 0x0000, 0x0010, 0x0030, "
				    "0x1030, 0x2030, 0x3030"));
}

TEST_CASE("ADC: conversions of unconnected inputs, single-ended 0 and differential 2048", "[lib][chip][adc]")
{
	SimDevice s;
	auto &d = *s.dev;
	// closed: StartConv is ignored, no result ever becomes valid
	auto e = thrown([&] { (void)d.peripherals().adcConvert(); });
	CHECK(e.errnoValue() == ETIMEDOUT);
	CHECK_THAT(e.what(), Equals("ADC_FUNC_OP (AdcGetDataValidFlag): sample module 12 had no valid result after "
				    "100 polls (is the ADC open and the module configured?)"));

	// the manuals' sequence: open, configure (0, 0), start 0x1000, valid 0x1000, data 12
	d.peripherals().adcOpen(ecmxf::AdcInputMode::SingleEnded);
	d.peripherals().adcConfigureModule(0, 0);
	CHECK(d.peripherals().adcValidFlags(0x1000) == 0);
	d.peripherals().adcStart(0x1000);
	CHECK(d.peripherals().adcValidFlags(0x1000) == 0x1000);
	CHECK(d.peripherals().adcRead(12) == 0);
	CHECK(d.peripherals().adcValidFlags(0x1000) == 0); // reading clears the flag
	CHECK(d.peripherals().adcConvert() == 0);

	// differential: (V(2k) - V(2k+1) + 4096) / 2 = 2048 at 0 V difference
	d.peripherals().adcOpen(ecmxf::AdcInputMode::Differential);
	CHECK(d.peripherals().adcConvert(12) == 2048);
	d.peripherals().adcConfigureModule(3, 5);
	CHECK(d.peripherals().adcConvert(3) == 2048);
	d.peripherals().adcClose();
	CHECK(d.peripherals().adcValidFlags(0xFFFF) == 0);

	e = thrown([&] { d.peripherals().adcConfigureModule(16, 0); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("ADC_FUNC_OP (AdcConfigSampleModule): sample module 16 is out of range (0..15)"));
	e = thrown([&] { d.peripherals().adcConfigureModule(0, 16); });
	CHECK_THAT(e.what(), Equals("ADC_FUNC_OP (AdcConfigSampleModule): channel 16 is out of range (0..15)"));
	e = thrown([&] { (void)d.peripherals().adcRead(16); });
	CHECK_THAT(e.what(), Equals("ADC_FUNC_OP (AdcGetConvData): sample module 16 is out of range (0..15)"));
	e = thrown([&] { d.peripherals().adcStart(0); });
	CHECK_THAT(e.what(), Equals("ADC_FUNC_OP (AdcStartConv): no sample module selected (module mask 0)"));
	e = thrown([&] { d.peripherals().adcOpen(static_cast<ecmxf::AdcInputMode>(0x200)); });
	CHECK_THAT(e.what(), Equals("ADC_FUNC_OP (AdcOpen): input mode 0x200 is out of range (0x000 single-ended, "
				    "0x100 differential)"));
}

TEST_CASE("MDIO: the PHY at address 1 (IP101G registers), no PHY elsewhere, writes and BMCR reset",
	  "[lib][chip][mdio]")
{
	SimDevice s;
	auto &d = *s.dev;
	CHECK(d.peripherals().mdioRead(1, 0) == 0x3100); // BMCR: 100 Mbit/s, auto-negotiation, full duplex
	CHECK(d.peripherals().mdioRead(1, 1) == 0x786D); // BMSR: link up
	CHECK(d.peripherals().mdioRead(1, 2) == 0x0243); // PHY identifier 1
	CHECK(d.peripherals().mdioRead(1, 3) == 0x0C54); // PHY identifier 2
	CHECK(d.peripherals().mdioRead(1, 4) == 0x01E1);
	CHECK(d.peripherals().mdioRead(1, 5) == 0xC5E1);
	CHECK(d.peripherals().mdioRead(1, 6) == 0x0003);
	CHECK(d.peripherals().mdioRead(0, 2) == 0xFFFF); // no PHY: the idle MDIO line
	CHECK(d.peripherals().mdioRead(31, 31) == 0xFFFF);

	d.peripherals().mdioWrite(1, 4, 0x0061);
	CHECK(d.peripherals().mdioRead(1, 4) == 0x0061);
	d.peripherals().mdioWrite(1, 2, 0x1234); // read-only
	CHECK(d.peripherals().mdioRead(1, 2) == 0x0243);
	d.peripherals().mdioWrite(1, 0, 0x8000); // BMCR reset restores the defaults
	CHECK(d.peripherals().mdioRead(1, 4) == 0x01E1);
	CHECK(d.peripherals().mdioRead(1, 0) == 0x3100);

	auto e = thrown([&] { (void)d.peripherals().mdioRead(32, 0); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("MDIO (read): PHY address 32 is out of range (0..31)"));
	e = thrown([&] { d.peripherals().mdioWrite(1, 32, 0); });
	CHECK_THAT(e.what(), Equals("MDIO (write): PHY register 32 is out of range (0..31)"));
}
