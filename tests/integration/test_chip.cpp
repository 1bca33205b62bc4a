// SPDX-License-Identifier: MIT
// The chip, its link and its peripherals through the typed Device calls
// (Documentation/commands-chip.rst), on the device of ECMXF_TEST_URI.
// Expected values: the simulated chip's configuration (firmware 0x30,
// build id "ecmxf-simulator", ECM-XF series; sim.hpp ChipConfig and
// sim-peripherals.rst), the manuals' power-on format (112-byte data
// section) and the driver's probe (CRC-32, driver.rst).

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdint>
#include <string>

#include "integration.hpp"
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/chip/peripherals.hpp>

using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using ecmxf::CheckType;
using integ::Rig;

namespace {

/// Puts the link format back as the test found it (CRC_TYPE_SET,
/// SPI_RECONFIG_OP), even when a check failed half-way.
struct FormatGuard {
	ecmxf::Device &d;
	CheckType check;
	~FormatGuard()
	{
		try {
			if (d.chip().queryDataSize() != ecmxf::kDataDefault)
				d.chip().setDataSize(static_cast<std::uint16_t>(ecmxf::kDataDefault));
			if (d.checkType() != check)
				d.chip().setCheckType(check);
		} catch (...) {
		}
	}
};

} // namespace

TEST_CASE("chip: firmware version, format, counters and the chip summary", "[chip]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	const ecmxf::FirmwareVersion fw = d.chip().firmwareVersion();
	CHECK(fw.version == 0x30);
	CHECK(fw.detailed);
	CHECK(fw.extendedVersion == 0);
	CHECK(fw.seriesCode == 0);
	CHECK(fw.series == ecmxf::MasterSeries::XF);
	CHECK(fw.buildId == "ecmxf-simulator");

	const ecmxf::ChipInfo info = d.chip().info();
	CHECK(info.firmware.version == 0x30);
	CHECK(info.dataSize == 112);   // power-on size; ecmxf.ko keeps it (data_size=0)
	CHECK(info.packetSize == 144); // 24 + 112 + 8
	CHECK(info.checkType == integ::startCheckType(r.u));
	CHECK(d.checkType() == integ::startCheckType(r.u));
	CHECK(d.dataSize() == 112);
	CHECK(d.chip().queryDataSize() == 112);
	// ECM status bits 1-0: the check word in use
	CHECK((info.ecmStatus & 0x03) == static_cast<unsigned>(integ::startCheckType(r.u)));

	// the WKC limit: 255 (none) at power-on, set and put back
	CHECK(d.chip().wkcErrorLimit() == ecmxf::kWkcNoLimit);
	d.chip().setWkcErrorLimit(10);
	CHECK(d.chip().wkcErrorLimit() == 10);
	d.chip().setWkcErrorLimit(ecmxf::kWkcNoLimit);
	CHECK(d.chip().wkcErrorLimit() == ecmxf::kWkcNoLimit);

	// no bus yet: no consecutive WKC errors; CRC counts clear to 0
	integ::initBus(d);
	CHECK(d.chip().wkcContinuousErrorCount() == 0);
	(void)d.chip().clearCrcErrorCount();
	CHECK(d.chip().clearCrcErrorCount() == 0);
	const ecmxf::ResponseHeader h = d.chip().infoUpdate();
	CHECK(h.code == 0);   // INFO_UPDATE_OP answered
	CHECK(h.crcErrCnt == 0);
	CHECK(h.ecatState == 1); // INIT after ECAT_INIT_OP
	CHECK(d.lastHeader().ecatState == 1);
	// nothing runs: clearing the async busy flag is harmless
	d.chip().resetAsyncCommand(ecmxf::async_reset::kClearBusy);
	CHECK(d.bus().slaveCount() == 3);
}

TEST_CASE("chip: interrupt enables are written and read back, polarities kept", "[chip]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	const ecmxf::InterruptConfig before = d.chip().interruptConfig();
	// power-on: nothing enabled, INT0 active high, INT1 active low (050)
	CHECK(before == ecmxf::InterruptConfig{});
	ecmxf::InterruptConfig c;
	c.sources = ecmxf::irq::kWkcError | ecmxf::irq::kCrcError;
	c.gpioLines = 0x0005;
	c.qeiOverflow = true;
	d.chip().setInterruptConfig(c);
	const ecmxf::InterruptConfig back = d.chip().interruptConfig();
	d.chip().setInterruptConfig(ecmxf::InterruptConfig{});
	CHECK(back == c);
	CHECK(d.chip().interruptConfig() == ecmxf::InterruptConfig{});
}

TEST_CASE("chip: the link format changes (SPI_RECONFIG_OP, CRC_TYPE_SET) and the library follows", "[chip][link]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	const CheckType start = integ::startCheckType(r.u);
	FormatGuard guard{ d, start };
	d.chip().setDataSize(256);
	CHECK(d.chip().queryDataSize() == 256);
	CHECK(d.dataSize() == 256);
	CHECK(d.pdoDataCapacity() == 256);
	CHECK(d.chip().firmwareVersion().version == 0x30);
	const CheckType other = start == CheckType::Crc32 ? CheckType::Fixed : CheckType::Crc32;
	d.chip().setCheckType(other);
	CHECK(d.chip().firmwareVersion().version == 0x30);
	CHECK(d.checkType() == other);
	CHECK(d.chip().info().checkType == other);
	d.chip().setCheckType(start);
	d.chip().setDataSize(112);
	CHECK(d.chip().queryDataSize() == 112);
	CHECK(d.checkType() == start);
	CHECK(d.chip().firmwareVersion().version == 0x30);

	// the engine's format can be told only to a byte transport
	if (r.isKernel()) {
		const ecmxf::Error e = integ::thrown([&] { d.assumeFormat(112, start); });
		CHECK(e.errnoValue() == EOPNOTSUPP);
	} else {
		d.assumeFormat(112, start); // what it is already
		CHECK(d.chip().firmwareVersion().version == 0x30);
	}
}

TEST_CASE("chip: WARM_RESET brings back the power-on format and settings", "[chip][reset]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	const CheckType start = integ::startCheckType(r.u);
	FormatGuard guard{ d, start };
	d.chip().setWkcErrorLimit(7);
	d.peripherals().gpioSetMode(0x0001, ecmxf::GpioMode::Output);
	d.chip().warmReset();
	// power-on: 112 bytes, fixed check word, WKC limit 255, GPIOs inputs
	CHECK(d.checkType() == CheckType::Fixed);
	CHECK(d.chip().queryDataSize() == 112);
	CHECK(d.checkType() == CheckType::Fixed);
	CHECK(d.chip().wkcErrorLimit() == ecmxf::kWkcNoLimit);
	CHECK(d.chip().firmwareVersion().version == 0x30);
	// the chip forgot the network: ECAT_SLV_CNT_GET counts none
	CHECK(d.bus().slaveCount() == 0);
	d.chip().setCheckType(start);
	CHECK(d.checkType() == start);
	CHECK(d.chip().firmwareVersion().version == 0x30);
}

TEST_CASE("peripherals: GPIO modes, pulls, outputs read back, edge interrupts", "[periph][gpio]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	constexpr std::uint32_t kAll = 0xFFFFF; // GPIO 0..19
	struct Restore {
		ecmxf::Device &d;
		~Restore()
		{
			try {
				d.peripherals().gpioSetInterrupt(5, ecmxf::GpioEdge::Disabled);
				d.peripherals().gpioClearInterrupts(kAll);
				d.peripherals().gpioSetMode(kAll, ecmxf::GpioMode::Input); // power-on
				d.peripherals().gpioSetDebounce(kAll, false);
			} catch (...) {
			}
		}
	} restore{ d };

	d.peripherals().gpioSetMode(kAll, ecmxf::GpioMode::Input);
	d.peripherals().gpioSetDebounce(kAll, false);
	// outputs read back what they drive (sim-peripherals.rst: the input
	// values are the pin levels in every mode)
	d.peripherals().gpioSetMode(0x0003 | 1u << 17, ecmxf::GpioMode::Output);
	d.peripherals().gpioWrite(0x0001);
	CHECK((d.peripherals().gpioRead() & 0x0003) == 0x0001);
	d.peripherals().gpioWriteAll(0x0002 | 1u << 17);
	CHECK((d.peripherals().gpioReadAll() & (0x0003 | 1u << 17)) == (0x0002 | 1u << 17));
	// an input with a pull reads the pull; a floating one reads low
	d.peripherals().gpioSetMode(1u << 4, ecmxf::GpioMode::Input, ecmxf::GpioPull::Up);
	CHECK((d.peripherals().gpioRead() >> 4 & 1) == 1);
	d.peripherals().gpioSetMode(1u << 4, ecmxf::GpioMode::Input, ecmxf::GpioPull::Down);
	CHECK((d.peripherals().gpioRead() >> 4 & 1) == 0);
	d.peripherals().gpioSetMode(1u << 4, ecmxf::GpioMode::Input, ecmxf::GpioPull::None);
	CHECK((d.peripherals().gpioRead() >> 4 & 1) == 0);

	// a rising edge on GPIO 5 (an output driven 0 -> 1) raises its flag
	d.peripherals().gpioSetMode(1u << 5, ecmxf::GpioMode::Output);
	d.peripherals().gpioWrite(0x0000);
	d.peripherals().gpioClearInterrupts(1u << 5);
	d.peripherals().gpioSetInterrupt(5, ecmxf::GpioEdge::Rising);
	CHECK((d.peripherals().gpioInterruptFlags() & 1u << 5) == 0);
	d.peripherals().gpioWrite(1u << 5);
	CHECK((d.peripherals().gpioInterruptFlags() & 1u << 5) == 1u << 5);
	CHECK((d.peripherals().gpioInterruptFlagsAll() & 1u << 5) == 1u << 5);
	// the falling edge does not count for a rising-edge line
	d.peripherals().gpioClearInterrupts(1u << 5);
	d.peripherals().gpioWrite(0x0000);
	CHECK((d.peripherals().gpioInterruptFlags() & 1u << 5) == 0);

	// debounce at 192 MHz, 2^0 periods: a level is taken within ns
	d.peripherals().gpioSetDebounceClock(0, ecmxf::DebounceClock::Core192MHz);
	d.peripherals().gpioSetDebounce(1u << 4, true);
	d.peripherals().gpioSetMode(1u << 4, ecmxf::GpioMode::Input, ecmxf::GpioPull::Up);
	d.chip().infoUpdate();
	CHECK((d.peripherals().gpioRead() >> 4 & 1) == 1);

	// a bad argument is refused before anything is sent
	const ecmxf::Error e = integ::thrown([&] { d.peripherals().gpioSetMode(1u << 20, ecmxf::GpioMode::Output); });
	CHECK(e.errnoValue() == EINVAL);
}

TEST_CASE("peripherals: QEI, DAC, ADC and the PHY on MDIO", "[periph]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	// QEI: EncOpen clears the counter; nothing turns the shaft
	d.peripherals().qeiOpen(ecmxf::QeiMode::X4Free);
	CHECK(d.peripherals().qeiCount() == 0);
	d.peripherals().qeiStart();
	CHECK(d.peripherals().qeiCount() == 0);
	d.peripherals().qeiStop();
	CHECK(d.peripherals().qeiCount() == 0);

	// DAC: open, delay, data, conversion, close (the output is outside)
	d.peripherals().dacOpen(ecmxf::DacTrigger::StartConv);
	d.peripherals().dacSetDelay(960);
	d.peripherals().dacWrite(2048);
	d.peripherals().dacStartConversion();
	d.peripherals().dacClose();
	const ecmxf::Error e = integ::thrown([&] { d.peripherals().dacWrite(4096); });
	CHECK(e.errnoValue() == EINVAL);

	// ADC: differential, the manuals' module 12 converts the pair (12, 13),
	// both at 0 V: (V12 - V13 + 4096) / 2 = 2048 (sim-peripherals.rst)
	d.peripherals().adcOpen(ecmxf::AdcInputMode::Differential);
	CHECK(d.peripherals().adcConvert() == 2048);
	// single-ended, module 3 bound to channel 3 (0 V): 0
	d.peripherals().adcOpen(ecmxf::AdcInputMode::SingleEnded);
	d.peripherals().adcConfigureModule(3, 3);
	d.peripherals().adcStart(1u << 3);
	std::uint16_t valid = 0;
	for (int i = 0; i < 100 && !valid; i++)
		valid = d.peripherals().adcValidFlags(1u << 3);
	CHECK(valid == 1u << 3);
	CHECK(d.peripherals().adcRead(3) == 0);
	d.peripherals().adcClose();

	// MDIO: the PHY at address 1 (050), an IP101G: BMSR 0x786D, PHY id
	// 0x0243/0x0C54; no PHY at address 5 reads the idle line 0xFFFF
	CHECK(d.peripherals().mdioRead(1, 1) == 0x786D);
	CHECK(d.peripherals().mdioRead(1, 2) == 0x0243);
	CHECK(d.peripherals().mdioRead(1, 3) == 0x0C54);
	CHECK(d.peripherals().mdioRead(5, 0) == 0xFFFF);
	d.peripherals().mdioWrite(1, 4, 0x01E1); // ANAR, its default value
	CHECK(d.peripherals().mdioRead(1, 4) == 0x01E1);
}
