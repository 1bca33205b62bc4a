// SPDX-License-Identifier: MIT
// The chip and its link: FW_VERSION_GET, SPI_PACK_SIZE_GET, SPI_RECONFIG_OP,
// CRC_TYPE_SET, CRC_ERR_CNT_CLR, INFO_UPDATE_OP, the WKC counters, the
// interrupt enables, ASYNCCMD_RESET, WARM_RESET and Device::info(), against
// the simulator's documented behaviour (Documentation/simulator.rst).

#include "helpers.hpp"
#include <ecmxf/bus/slave_access.hpp>
#include <ecmxf/chip/chip.hpp>

#include <cerrno>
#include <chrono>
#include <span>

#include <ecmxf/model/status.hpp>
#include <ecmxf/link/link.hpp>

using namespace chiptest;
using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;

namespace {

/// A chip with firmware of manual ver. 038: FW_VERSION_GET answers the
/// version only (data length 0). The simulator answers as ver. 050; this
/// channel clears the data length of those answers (the fixed check word
/// does not cover it).
class V038Channel : public ecmxf::ByteChannel
{
public:
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override
	{
		sim.exchange(mosi, miso);
		if (miso.size() > 0x10 && miso[0x0C] == 56 && !(miso[0x0A] & 0x20)) {
			miso[0x0E] = 0;
			miso[0x0F] = 0;
		}
	}
	bool waitReady(std::chrono::nanoseconds t) override { return sim.waitReady(t); }
	std::chrono::nanoseconds now() const override { return sim.now(); }
	void sleepFor(std::chrono::nanoseconds d) override { sim.sleepFor(d); }
	std::string name() const override { return "sim: as ver. 038"; }

	ecmxf::SimChannel sim;
};

} // namespace

TEST_CASE("firmwareVersion: the simulator's power-on firmware 0x30, series ECM-XF, build id",
	  "[lib][chip][link]")
{
	SimDevice s;
	const ecmxf::FirmwareVersion v = s.dev->chip().firmwareVersion();
	CHECK(v.version == 0x30);
	CHECK(v.detailed);
	CHECK(v.extendedVersion == 0);
	CHECK(v.seriesCode == 0);
	REQUIRE(v.series);
	CHECK(*v.series == ecmxf::MasterSeries::XF);
	CHECK(v.buildId == "ecmxf-simulator");
	CHECK(v.buildIdBytes[0] == 'e');
	CHECK(v.buildIdBytes[14] == 'r');
	CHECK(v.buildIdBytes[15] == 0);
}

TEST_CASE("firmwareVersion decodes every field of a configured answer", "[lib][chip][link]")
{
	ecmxf::sim::ChipConfig cfg;
	cfg.fwVersion = 0x41;
	cfg.fwVersionData = { 0, 7, 0, 2, 'b', 'u', 'i', 'l', 'd' };
	SimDevice s({}, cfg);
	const ecmxf::FirmwareVersion v = s.dev->chip().firmwareVersion();
	CHECK(v.version == 0x41);
	CHECK(v.detailed);
	CHECK(v.extendedVersion == 7);
	CHECK(v.seriesCode == 2);
	REQUIRE(v.series);
	CHECK(*v.series == ecmxf::MasterSeries::XFU);
	CHECK(v.buildId == "build");

	// a series the library does not know, a binary build id: hex digits
	cfg.fwVersionData = { 0, 1, 0, 9, 0x01, 0xFF };
	SimDevice b({}, cfg);
	const ecmxf::FirmwareVersion w = b.dev->chip().firmwareVersion();
	CHECK(w.seriesCode == 9);
	CHECK_FALSE(w.series);
	CHECK(w.buildId == "01ff0000000000000000000000000000");
}

TEST_CASE("firmwareVersion of ver. 038 firmware: the version only", "[lib][chip][link]")
{
	auto t = std::make_unique<V038Channel>();
	ecmxf::Device dev(std::move(t));
	const ecmxf::FirmwareVersion v = dev.chip().firmwareVersion();
	CHECK(v.version == 0x30);
	CHECK_FALSE(v.detailed);
	CHECK(v.seriesCode == 0);
	CHECK_FALSE(v.series);
	CHECK(v.buildId.empty());
	// info() still works
	CHECK(dev.chip().info().firmware.version == 0x30);
}

TEST_CASE("data size: power-on 112, SPI_RECONFIG_OP changes it and the library follows",
	  "[lib][chip][link]")
{
	SimDevice s;
	CHECK(s.dev->dataSize() == 112);
	CHECK(s.dev->chip().queryDataSize() == 112);
	s.dev->chip().setDataSize(256);
	CHECK(s.dev->dataSize() == 256);
	CHECK(s.chip().dataSize() == 256);
	CHECK(s.chip().packetSize() == 24 + 256 + 8);
	CHECK(s.dev->chip().queryDataSize() == 256);
	CHECK(s.dev->chip().firmwareVersion().version == 0x30);
	s.dev->chip().setDataSize(32);
	CHECK(s.dev->chip().queryDataSize() == 32);
	s.dev->chip().setDataSize(1408);
	CHECK(s.dev->chip().queryDataSize() == 1408);

	auto e = thrown([&] { s.dev->chip().setDataSize(31); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("SPI_RECONFIG_OP: data section size 31 is out of range (32..1408 bytes)"));
	e = thrown([&] { s.dev->chip().setDataSize(1409); });
	CHECK_THAT(e.what(), Equals("SPI_RECONFIG_OP: data section size 1409 is out of range (32..1408 bytes)"));
	CHECK(s.dev->dataSize() == 1408);
}

TEST_CASE("check type: CRC_TYPE_SET to CRC-32 and back, the header's bits 1-0 agree", "[lib][chip][link]")
{
	SimDevice s;
	CHECK(s.dev->checkType() == ecmxf::CheckType::Fixed);
	s.dev->chip().setCheckType(ecmxf::CheckType::Crc32);
	CHECK(s.dev->checkType() == ecmxf::CheckType::Crc32);
	CHECK(s.dev->chip().firmwareVersion().version == 0x30);
	CHECK(ecmxf::checkTypeOfEcmStatus(s.dev->lastHeader().ecmStatus) == ecmxf::CheckType::Crc32);
	CHECK(s.dev->lastHeader().crcErrCnt == 0);
	s.dev->chip().setCheckType(ecmxf::CheckType::Fixed);
	CHECK(s.dev->chip().queryDataSize() == 112);
	CHECK(ecmxf::checkTypeOfEcmStatus(s.dev->lastHeader().ecmStatus) == ecmxf::CheckType::Fixed);

	const auto e = thrown([&] { s.dev->chip().setCheckType(static_cast<ecmxf::CheckType>(4)); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(),
		   Equals("CRC_TYPE_SET: check type 4 is out of range (0 fixed, 1 CRC-8, 2 CRC-CCITT, 3 CRC-32)"));
}

TEST_CASE("CRC_ERR_CNT_CLR returns the count it cleared, INFO_UPDATE_OP can clear it too", "[lib][chip][link]")
{
	SimDevice s;
	s.chip().faults().mosiBitErrors = 2;
	CHECK(s.dev->chip().queryDataSize() == 112); // the engine re-sends the rejected packets
	CHECK(s.dev->lastHeader().crcErrCnt == 2);
	CHECK(s.dev->chip().clearCrcErrorCount() == 2);
	CHECK(s.dev->lastHeader().crcErrCnt == 0);

	s.chip().faults().mosiBitErrors = 3;
	CHECK(s.dev->chip().infoUpdate().crcErrCnt == 3);
	ecmxf::InfoUpdateOptions o;
	o.clearCrcErrorCount = true;
	o.clearErrorBits = 0x40; // SPI CRC error
	const ecmxf::ResponseHeader h = s.dev->chip().infoUpdate(o);
	CHECK(h.code == 0);
	CHECK(h.crcErrCnt == 0);
	CHECK((h.errStatus & 0x40) == 0);

	o.clearErrorBits = 0x01;
	const auto e = thrown([&] { s.dev->chip().infoUpdate(o); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("INFO_UPDATE_OP: error bits 0x01 include bits 0..2, which cannot be cleared "
				    "(clearable: bits 3..7 = 0xF8)"));
}

TEST_CASE("WKC counters: power-on limit 255 (none), set and read back, running count 0", "[lib][chip][link]")
{
	SimDevice s;
	CHECK(s.dev->chip().wkcErrorLimit() == ecmxf::kWkcNoLimit);
	CHECK(s.dev->chip().wkcContinuousErrorCount() == 0);
	s.dev->chip().setWkcErrorLimit(9);
	CHECK(s.dev->chip().wkcErrorLimit() == 9);
	s.dev->chip().setWkcErrorLimit(255);
	CHECK(s.dev->chip().wkcErrorLimit() == 255);
	const auto e = thrown([&] { s.dev->chip().setWkcErrorLimit(0); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("ECAT_WKC_CONTI_ERR_MAX_SET: limit 0 is out of range (1..254 errors, 255 = no "
				    "limit)"));
}

TEST_CASE("interrupt enables: power-on polarities, a full configuration read back", "[lib][chip][link]")
{
	SimDevice s;
	const ecmxf::InterruptConfig p = s.dev->chip().interruptConfig();
	CHECK(p.sources == 0);
	CHECK(p.gpioLines == 0);
	CHECK_FALSE(p.qeiIndex);
	CHECK_FALSE(p.qeiCompare);
	CHECK_FALSE(p.qeiOverflow);
	CHECK(p.int0ActiveHigh);      // ver. 050: INT0 active high by default
	CHECK_FALSE(p.int1ActiveHigh); // INT1 active low by default

	ecmxf::InterruptConfig c;
	c.sources = ecmxf::irq::kEcatPacket | ecmxf::irq::kWkcError | ecmxf::irq::kRxFifoLow;
	c.gpioLines = 0x0A05;
	c.qeiIndex = true;
	c.qeiOverflow = true;
	c.int0ActiveHigh = false;
	c.int1ActiveHigh = true;
	s.dev->chip().setInterruptConfig(c);
	CHECK(s.dev->chip().interruptConfig() == c);
	// INT1 active high now, no enabled event pending: the line is low
	CHECK_FALSE(s.chip().int1());

	ecmxf::InterruptConfig bad;
	bad.sources = ecmxf::irq::kEncoder;
	auto e = thrown([&] { s.dev->chip().setInterruptConfig(bad); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("ECAT_INT_SET_ENABLE: interrupt sources 0x20000000 include bits that cannot be "
				    "enabled (allowed: bits 31, 25, 24, 23, 22 = 0x83C00000; the encoder is "
				    "enabled by the QEI sources)"));
	bad = {};
	bad.gpioLines = 0x1000;
	e = thrown([&] { s.dev->chip().setInterruptConfig(bad); });
	CHECK_THAT(e.what(), Equals("ECAT_INT_SET_ENABLE: GPIO lines 0x1000 include lines above GPIO 11 (GPIO "
				    "interrupts to INT1: GPIO 0..11)"));
}

TEST_CASE("a command the chip refuses: error status bit 7 in words, and the bit is cleared afterwards",
	  "[lib][chip][link]")
{
	SimDevice s;
	// DIRECT_ASSIGN needs the bus initialised (ECAT_INIT_OP)
	const auto e = thrown([&] { s.dev->slaves().setDirectAssign(0, true); });
	CHECK(e.errnoValue() == EINVAL);
	REQUIRE(e.errorStatus());
	CHECK((*e.errorStatus() & 0x80) == 0x80);
	CHECK_THAT(e.what(), Equals("DIRECT_ASSIGN: the chip refused the command (error status bit 7, command "
				    "error: slave 0 does not exist or the bus is not initialised (ECAT_INIT_OP)); "
				    "the command exists only in firmware of manual ver. 050"));
	CHECK((s.dev->lastHeader().errStatus & 0x80) == 0);
	CHECK(s.dev->chip().firmwareVersion().version == 0x30);
}

TEST_CASE("ASYNCCMD_RESET ends a stuck async command, bad actions are refused", "[lib][chip][link]")
{
	SimDevice s;
	s.chip().faults().asyncStuckBusy = true;
	auto e = thrown([&] { (void)s.dev->slaves().eepromRead(0, 0x0008); });
	CHECK(e.errnoValue() == ETIMEDOUT);
	CHECK_THAT(e.what(), Equals("EEPROM read of slave 0, word 0x0008: EEPROM_REQ: timed out after 3000 ms "
				    "waiting for the async command to complete"));
	CHECK((s.dev->lastHeader().ecmStatus & 0x80) == 0x80); // still busy on the chip
	s.dev->chip().resetAsyncCommand(ecmxf::async_reset::kClearBusy);
	CHECK((s.dev->chip().infoUpdate().ecmStatus & 0x80) == 0);
	CHECK(s.dev->slaves().eepromRead(0, 0x0008) == 0x0E5C);

	e = thrown([&] { s.dev->chip().resetAsyncCommand(0); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("ASYNCCMD_RESET: actions 0x00 are out of range (bit 0 clear busy, bit 1 skip "
				    "link wait, bit 2 abandon the command: 0x01..0x07)"));
	e = thrown([&] { s.dev->chip().resetAsyncCommand(8); });
	CHECK_THAT(e.what(), Contains("actions 0x08 are out of range"));
}

TEST_CASE("WARM_RESET restores the power-on format and settings, the library follows", "[lib][chip][link]")
{
	SimDevice s;
	s.dev->chip().setDataSize(64);
	s.dev->chip().setCheckType(ecmxf::CheckType::Crc32);
	s.dev->chip().setWkcErrorLimit(9);
	ecmxf::InterruptConfig c;
	c.sources = ecmxf::irq::kCrcError;
	c.int1ActiveHigh = true;
	s.dev->chip().setInterruptConfig(c);
	s.dev->chip().warmReset();
	CHECK(s.dev->dataSize() == 112);
	CHECK(s.dev->checkType() == ecmxf::CheckType::Fixed);
	CHECK(s.dev->chip().queryDataSize() == 112);
	CHECK(s.dev->chip().wkcErrorLimit() == 255);
	CHECK(s.dev->chip().interruptConfig() == ecmxf::InterruptConfig{});
	CHECK(s.chip().dataSize() == 112);
}

TEST_CASE("info(): the simulator's power-on firmware, format, status and counters", "[lib][chip][link]")
{
	SimDevice s;
	const ecmxf::ChipInfo i = s.dev->chip().info();
	CHECK(i.firmware.version == 0x30);
	CHECK(i.firmware.buildId == "ecmxf-simulator");
	CHECK(i.dataSize == 112);
	CHECK(i.packetSize == 144);
	CHECK(i.checkType == ecmxf::CheckType::Fixed);
	CHECK(i.ecatState == 0x00);   // no network before INIT_OP
	CHECK(i.errorStatus == 0x01); // link present
	CHECK(i.ecmStatus == 0x40);   // FIFO enabled at power-on
	CHECK(i.interruptFlags == 0);
	CHECK(i.crcErrors == 0);
	CHECK(i.wkcErrors == 0);
	REQUIRE(i.wkcContinuousErrors);
	CHECK(*i.wkcContinuousErrors == 0);
	CHECK(i.wkcErrorLimit == 255);
	CHECK(ecmxf::ecatStateName(i.ecatState) == "NONE");
	CHECK(ecmxf::describeErrorStatus(i.errorStatus) == "link (bit 0)");
	CHECK(ecmxf::describeEcmStatus(i.ecmStatus) == "FIFO enabled (bit 6)");

	s.dev->chip().setDataSize(200);
	s.dev->chip().setCheckType(ecmxf::CheckType::Crc32);
	const ecmxf::ChipInfo j = s.dev->chip().info();
	CHECK(j.dataSize == 200);
	CHECK(j.packetSize == 232);
	CHECK(j.checkType == ecmxf::CheckType::Crc32);
	CHECK(j.ecmStatus == 0x43);
}
