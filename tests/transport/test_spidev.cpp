// SPDX-License-Identifier: MIT
// SpidevChannel's logic over a fake spidev/GPIO backend played by the
// simulated chip (fake_spidev.hpp): a Device runs raw commands end to end
// over it, INT0 is waited for (or the 150 us fallback without it), INT0
// timeouts, INT1 events, and failed or short transfers and line reads
// become Errors that name the node and the call.

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/spidev_channel.hpp>

#include "fake_spidev.hpp"
#include "../common/thrown.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;

namespace {

constexpr std::uint8_t kInfoUpdate = 0;
constexpr std::uint8_t kInitOp = 1;
constexpr std::uint8_t kSlvCntGet = 16;
constexpr std::uint8_t kIntSetEnable = 58;
constexpr std::uint8_t kFwVersionGet = 56;

ecmxf::Command simple(std::uint8_t code, std::uint8_t param = 0)
{
	ecmxf::Command c;
	c.code = code;
	c.param = param;
	return c;
}

/// INIT_OP for all slaves (tests/lib/test_device.cpp): 0xFF 0x81,
/// AssignActivate 0x0300, SYNC0 1 ms, SYNC1 0, shift 0; length field 16.
ecmxf::Command initOp()
{
	ecmxf::Command c = simple(kInitOp);
	c.payload = { 0xFF, 0x81, 0x00, 0x03, 0x40, 0x42, 0x0F, 0x00, 0, 0, 0, 0, 0, 0, 0, 0 };
	c.len = 16;
	return c;
}

using ecmxftest::thrown;

} // namespace

TEST_CASE("spidev with INT0: INFO_UPDATE, SLV_CNT_GET and an async ECAT_INIT_OP run end to end",
	  "[transport][spidev]")
{
	test::SpidevRig r;
	const ecmxf::Response info = r.dev->command(simple(kInfoUpdate));
	CHECK(info.header.code == kInfoUpdate);
	CHECK(r.dev->command(simple(kSlvCntGet)).ret == 0);

	const ecmxf::Response init = r.dev->command(initOp());
	CHECK((init.header.ecmStatus & 0x80) == 0); // busy bit clear: completed
	CHECK((init.header.errStatus & 0x08) == 0); // no async error
	CHECK(r.dev->lastHeader().ecatState == 1);   // INIT
	CHECK(r.dev->command(simple(kSlvCntGet)).ret == 3); // the default network

	// every exchange went through the fake, none while the chip was busy
	const auto &st = r.transport->stats();
	CHECK(st.exchanges == r.chip.stats().exchanges);
	CHECK(r.backend->transfers == st.exchanges);
	CHECK(r.chip.stats().busyExchanges == 0);
	CHECK(r.chip.stats().notReady == 0);
	CHECK(st.fallbackWaits == 0);
	CHECK(st.int0Ready >= st.exchanges);
	CHECK(st.int0Edges > 0); // the chip was busy after exchanges: waited for the edge
	CHECK(st.int0Timeouts == 0);
}

TEST_CASE("spidev without INT0 waits the 150 us fallback after each exchange", "[transport][spidev]")
{
	test::SpidevRig r(false);
	CHECK(r.dev->command(simple(kFwVersionGet)).ret == ecmxf::sim::ChipConfig{}.fwVersion);
	CHECK(r.dev->command(simple(kSlvCntGet)).ret == 0);
	const auto &st = r.transport->stats();
	REQUIRE(st.exchanges >= 4); // two commands, each answered one exchange late
	// the first wait had no exchange before it; every later one had to wait
	CHECK(st.fallbackWaits == st.exchanges - 1);
	CHECK(st.int0Ready == 0);
	CHECK(r.backend->lineReads == 0);
	CHECK(r.chip.stats().busyExchanges == 0); // 150 us > the chip's 50 us
	CHECK(r.chip.stats().notReady == 0);
}

TEST_CASE("spidev waitReady without INT0: ready only 150 us after the last exchange",
	  "[transport][spidev]")
{
	test::SpidevRig r(false);
	CHECK(r.transport->waitReady(0ns)); // nothing sent yet
	std::vector<std::uint8_t> mosi(r.chip.packetSize()), miso(mosi.size());
	r.transport->exchange(mosi, miso);
	const auto t0 = r.chip.now();
	CHECK_FALSE(r.transport->waitReady(100us)); // shorter than the fallback
	CHECK(r.chip.now() - t0 == 100us);
	CHECK(r.transport->waitReady(1ms)); // the remaining 50 us
	CHECK(r.chip.now() - t0 == 150us);
	CHECK(r.transport->waitReady(0ns)); // already passed: no wait
	CHECK(r.transport->stats().fallbackWaits == 2);
}

TEST_CASE("spidev INT0 stuck busy: waitReady times out and the command fails with ETIMEDOUT",
	  "[transport][spidev]")
{
	test::SpidevRig r;
	r.chip.faults().int0StuckBusy = true;
	const auto t0 = r.chip.now();
	CHECK_FALSE(r.transport->waitReady(2ms));
	CHECK(r.chip.now() - t0 >= 2ms);
	CHECK(r.transport->stats().int0Timeouts == 1);

	ecmxf::Command c = simple(kSlvCntGet);
	c.timeout = 5ms;
	const ecmxf::Error e = thrown([&] { r.dev->command(c); });
	CHECK_THAT(e.what(), Equals("ECAT_SLV_CNT_GET: timed out after 5 ms waiting for the chip's answer"));
	CHECK(e.errnoValue() == ETIMEDOUT);
	CHECK(r.backend->transfers == 0);
}

TEST_CASE("spidev INT0 polarity: ready=low reads a high INT0 as busy", "[transport][spidev]")
{
	test::SpidevRig r(true, false, test::SpidevRig::defaultConfig(), false);
	REQUIRE(r.chip.int0()); // ready, active high at power-on
	CHECK_FALSE(r.transport->waitReady(1ms));
	CHECK(r.transport->stats().int0Timeouts == 1);
}

TEST_CASE("spidev INT1: waitEvent sees the chip's event line after an enabled interrupt",
	  "[transport][spidev]")
{
	test::SpidevRig r(true, true);
	// enable the CRC error interrupt (bit 23), keep INT0 active high
	// (parameter bit 1) and INT1 active low (bit 0 clear)
	ecmxf::Command en = simple(kIntSetEnable, 0x02);
	en.payload = { 0x00, 0x00, 0x80, 0x00, 0x00, 0x00 };
	r.dev->command(en);
	CHECK_FALSE(r.transport->waitEvent(1ms));
	r.chip.faults().mosiBitErrors = 1; // the chip counts a CRC error, flags bit 23
	r.dev->command(simple(kSlvCntGet));
	CHECK(r.transport->waitEvent(0ns));
	CHECK(r.transport->stats().int1Events == 1);
}

TEST_CASE("spidev waitEvent without an INT1 line throws EOPNOTSUPP saying how to add one",
	  "[transport][spidev]")
{
	test::SpidevRig r;
	const ecmxf::Error e = thrown([&] { (void)r.transport->waitEvent(1ms); });
	CHECK_THAT(e.what(), Equals("spidev /dev/spidev-fake: no INT1 (event) line configured (add "
				    "int1=<chip>:<line> to the device URI)"));
	CHECK(e.errnoValue() == EOPNOTSUPP);
}

TEST_CASE("spidev transfer failures and short transfers become Errors naming the node",
	  "[transport][spidev]")
{
	SECTION("the ioctl fails")
	{
		test::SpidevRig r;
		r.faults.transferErrno = ESHUTDOWN;
		const ecmxf::Error e = thrown([&] { r.dev->command(simple(kSlvCntGet)); });
		CHECK_THAT(e.what(), Equals(std::string("ECAT_SLV_CNT_GET: spidev /dev/spidev-fake: SPI transfer of 144 bytes failed "
							"(SPI_IOC_MESSAGE): ") +
					    std::strerror(ESHUTDOWN)));
		CHECK(e.errnoValue() == ESHUTDOWN);
	}
	SECTION("a short transfer")
	{
		test::SpidevRig r;
		r.faults.shortBy = 16;
		const ecmxf::Error e = thrown([&] { r.dev->command(simple(kSlvCntGet)); });
		CHECK_THAT(e.what(), Equals("ECAT_SLV_CNT_GET: spidev /dev/spidev-fake: short SPI transfer: 128 of 144 bytes moved"));
		CHECK(e.errnoValue() == EIO);
	}
	SECTION("INT0 cannot be read")
	{
		test::SpidevRig r;
		r.faults.lineErrno = ENODEV;
		const ecmxf::Error e = thrown([&] { r.dev->command(simple(kSlvCntGet)); });
		CHECK_THAT(e.what(), Equals(std::string("ECAT_SLV_CNT_GET: spidev /dev/spidev-fake: cannot read the INT0 (ready) line: ") +
					    std::strerror(ENODEV)));
		CHECK(e.errnoValue() == ENODEV);
	}
	SECTION("the edge wait fails")
	{
		test::SpidevRig r;
		r.chip.faults().int0StuckBusy = true;
		r.faults.edgeErrno = EINTR;
		const ecmxf::Error e = thrown([&] { (void)r.transport->waitReady(1ms); });
		CHECK_THAT(e.what(), Contains("spidev /dev/spidev-fake: waiting for an edge on the INT0 (ready) line "
					      "failed: "));
		CHECK(e.errnoValue() == EINTR);
	}
	SECTION("MOSI and MISO of different sizes")
	{
		test::SpidevRig r;
		std::vector<std::uint8_t> a(144), b(64);
		const ecmxf::Error e = thrown([&] { r.transport->exchange(a, b); });
		CHECK_THAT(e.what(), Contains("MOSI and MISO buffers differ in size (144 and 64 bytes)"));
		CHECK(e.errnoValue() == EINVAL);
	}
}

TEST_CASE("the device stays usable after a failed transfer", "[transport][spidev]")
{
	test::SpidevRig r;
	r.faults.transferErrno = EIO;
	CHECK_THROWS_AS(r.dev->command(simple(kSlvCntGet)), ecmxf::Error);
	r.faults.transferErrno = 0;
	CHECK(r.dev->command(simple(kFwVersionGet)).ret == ecmxf::sim::ChipConfig{}.fwVersion);
}

TEST_CASE("a chip left in CRC-32 by another driver: assumeFormat() makes it reachable, without it the "
	  "power-on guess fails",
	  "[transport][spidev]")
{
	test::SpidevRig r;
	// another owner (e.g. ecmxf.ko at probe) switches the chip to CRC-32
	r.dev->chip().setCheckType(ecmxf::CheckType::Crc32);
	CHECK(r.dev->chip().firmwareVersion().version == 0x30);

	// a new Device over the same chip assumes the power-on format (fixed
	// check word): the chip rejects its packets, the retry bound runs out
	{
		auto fake = std::make_unique<test::FakeSpidev>(r.chip, true, false, r.faults);
		ecmxf::SpidevOptions o;
		o.device = "/dev/spidev-fake";
		ecmxf::Device fresh(std::make_unique<ecmxf::SpidevChannel>(std::move(fake), o));
		CHECK(fresh.checkType() == ecmxf::CheckType::Fixed);
		const ecmxf::Error e = thrown([&] { (void)fresh.chip().firmwareVersion(); });
		CHECK((e.errnoValue() == EBADMSG || e.errnoValue() == EPROTO));
	}
	// told the format, it talks
	auto fake = std::make_unique<test::FakeSpidev>(r.chip, true, false, r.faults);
	ecmxf::SpidevOptions o;
	o.device = "/dev/spidev-fake";
	ecmxf::Device told(std::make_unique<ecmxf::SpidevChannel>(std::move(fake), o));
	told.assumeFormat(112, ecmxf::CheckType::Crc32);
	CHECK(told.checkType() == ecmxf::CheckType::Crc32);
	CHECK(told.dataSize() == 112);
	CHECK(told.chip().firmwareVersion().version == 0x30);
	CHECK(told.chip().queryDataSize() == 112);

	const ecmxf::Error bad = thrown([&] { told.assumeFormat(31, ecmxf::CheckType::Crc32); });
	CHECK(bad.errnoValue() == EINVAL);
	CHECK_THAT(bad.what(), Equals("spidev:/dev/spidev-fake: data section size 31 or check type 3 is out of "
				      "range (32..1408 bytes; 0 fixed .. 3 CRC-32)"));
	CHECK(told.checkType() == ecmxf::CheckType::Crc32); // unchanged
}
