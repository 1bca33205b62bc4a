// SPDX-License-Identifier: MIT
// The ECM-SK device URIs, kinds of ecmxf::DeviceUri parsed by
// ecmxf::parseDeviceUri(): every option, and bad values of each.

#include <catch2/catch.hpp>

#include <cerrno>

#include <ecmxf/error.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/device_uri.hpp>

using namespace ecmxf::sk;
using ecmxf::kSkMaxSpeedHz;
using ecmxf::parseDeviceUri;
using Kind = ecmxf::DeviceUri::Kind;

namespace {
int errnoOf(const char *uri)
{
	try {
		(void)parseDeviceUri(uri);
	} catch (const ecmxf::Error &e) {
		return e.errnoValue();
	}
	return 0;
}
} // namespace

TEST_CASE("sk uri: sk-sim with a network file and board settings")
{
	auto u = parseDeviceUri("sk-sim:");
	CHECK(u.kind == Kind::SkSim);
	CHECK(u.path.empty());
	CHECK(u.skSlotSize == 12);
	u = parseDeviceUri("sk-sim:/tmp/x.net?slot=16&test=1&abandon=0&ex=3&fifo=300&busy_us=5&spi_hz=6000000&lio=7");
	CHECK(u.path == "/tmp/x.net");
	CHECK(u.skSlotSize == 16);
	CHECK(u.skExtensions == 3u);
	CHECK(u.skBoard.testMode);
	CHECK_FALSE(u.skBoard.fifoAbandon);
	CHECK(u.skBoard.fifoDepth == 300u);
	CHECK(u.skBoard.lioInputs == 7u);
}

TEST_CASE("sk uri: sk-unix and sk-spidev with their options")
{
	auto u = parseDeviceUri("sk-unix:/run/sk.sock?slot=16&ex=2");
	CHECK(u.kind == Kind::SkUnix);
	CHECK(u.path == "/run/sk.sock");
	CHECK(u.skSlotSize == 16);
	CHECK(u.skExtensions == 2u);
	u = parseDeviceUri("sk-spidev:/dev/spidev0.1?busy=gpiochip0:25&slot=12&speed=6000000&mode=0&ex=1");
	CHECK(u.kind == Kind::SkSpidev);
	CHECK(u.spidev.device == "/dev/spidev0.1");
	REQUIRE(u.spidev.int0);
	CHECK(u.spidev.int0->chip == "gpiochip0");
	CHECK(u.spidev.int0->line == 25u);
	CHECK_FALSE(u.spidev.readyHigh);
	CHECK(u.spidev.speedHz == 6000000u);
	CHECK(u.skExtensions == 1u);
	u = parseDeviceUri("sk-spidev:/dev/spidev0.0?busy=/dev/gpiochip4:3");
	CHECK(u.spidev.speedHz == kSkMaxSpeedHz);
	CHECK(u.spidev.int0->chip == "/dev/gpiochip4");
	CHECK(Board::isSkUri("sk-sim:"));
	CHECK_FALSE(Board::isSkUri("sim:"));
}

TEST_CASE("sk uri: bad schemes, paths, options and values are EINVAL")
{
	for (const char *bad : {
		     "sk-sim:?slot=14", "sk-sim:?slot=", "sk-sim:?test=2", "sk-sim:?fifo=100", "sk-sim:?ex=9",
		     "sk-sim:?colour=red", "sk-sim:?slot", "sk-unix:", "sk-unix:/s?slot=13", "sk-unix:/s?ex=4",
		     "sk-unix:/s?speed=1", "sk-spidev:/dev/spidev0.0", "sk-spidev:spidev0.0?busy=gpiochip0:1",
		     "sk-spidev:/dev/spidev0.0?busy=gpiochip0", "sk-spidev:/dev/spidev0.0?busy=:3",
		     "sk-spidev:/dev/spidev0.0?busy=gpiochip0:x", "sk-spidev:/dev/spidev0.0?busy=c:1&speed=24000001",
		     "sk-spidev:/dev/spidev0.0?busy=c:1&speed=0", "sk-spidev:/dev/spidev0.0?busy=c:1&mode=4",
		     "sk-spidev:/dev/spidev0.0?busy=c:1&slot=8", "sk-spidev:/dev/spidev0.0?busy=c:1&turbo=1",
		     "sk-can:", "sk", "sk-sim:?=1", "sk-unix:/s?trace=", "sk-sim:?trace=", "sk-sim:?trace=a&trace=b",
		     "sk-spidev:/dev/spidev0.0?busy=c:1&int0=c:2", "sk-spidev:/dev/spidev0.0?busy=c:1&busy=c:2",
		     "sk-unix:/s?slot=12&slot=16", "sk-unix:/s?ex=x", "sk-spidev:?busy=c:1" }) {
		INFO(bad);
		CHECK(errnoOf(bad) == EINVAL);
	}
}

TEST_CASE("sk uri: every ECM-SK form takes trace=<file>, after the other options too")
{
	auto u = parseDeviceUri("sk-sim:?trace=/tmp/t.trace");
	CHECK(u.kind == Kind::SkSim);
	CHECK(u.trace == "/tmp/t.trace");
	u = parseDeviceUri("sk-sim:?ex=3&slot=16&trace=/tmp/t.pcapng");
	CHECK(u.trace == "/tmp/t.pcapng");
	CHECK(u.skExtensions == 3u);
	CHECK(u.skSlotSize == 16);
	u = parseDeviceUri("sk-unix:/s?trace=x&ex=1");
	CHECK(u.kind == Kind::SkUnix);
	CHECK(u.trace == "x");
	CHECK(u.skExtensions == 1u);
	u = parseDeviceUri("sk-spidev:/dev/spidev0.0?busy=c:1&trace=y");
	CHECK(u.kind == Kind::SkSpidev);
	CHECK(u.trace == "y");
	CHECK(parseDeviceUri("sk-sim:").trace.empty());
	try {
		(void)parseDeviceUri("sk-sim:?ex=3&trace=");
		FAIL("parsed");
	} catch (const ecmxf::Error &e) {
		CHECK(std::string(e.what()).find("option \"trace\" needs a file name (trace=<file>)") != std::string::npos);
		CHECK(std::string(e.what()).find("each may add \"trace=<file>\"") != std::string::npos);
	}
}

TEST_CASE("sk uri: opening a network file that does not exist fails with the reason")
{
	try {
		(void)Board::open("sk-sim:/nonexistent/net.net");
		FAIL("opened");
	} catch (const ecmxf::Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK(std::string(e.what()).find("/nonexistent/net.net") != std::string::npos);
	}
}

TEST_CASE("sk uri: errors name the bad part and list the ECM-SK's forms, an ECM-XF URI is not a board")
{
	const auto msg = [](const char *uri) {
		try {
			(void)parseDeviceUri(uri);
		} catch (const ecmxf::Error &e) {
			return std::string(e.what());
		}
		return std::string();
	};
	CHECK_THAT(msg("sk-sim:?slot=14"), Catch::Contains("slot=14") && Catch::Contains(std::string(ecmxf::kSkUriForms)));
	CHECK_THAT(msg("sk-spidev:/dev/spidev0.0"), Catch::Contains("busy=<chip>:<line> is required"));
	CHECK_THAT(msg("sk-spidev:/dev/spidev0.0?busy=c:1&speed=24000001"), Catch::Contains("24000001"));
	CHECK_THAT(msg("sk-unix:/s?colour=red"), Catch::Contains("unknown option \"colour\""));
	CHECK_THAT(msg("sk-can:"), Catch::Contains("unknown ECM-SK device URI"));
	CHECK(parseDeviceUri("sk-sim:?&slot=16&").skSlotSize == 16); // empty options skipped, as before
	CHECK(parseDeviceUri("sk-unix:/s").isSk());
	CHECK_FALSE(parseDeviceUri("unix:/s").isSk());
	try {
		(void)Board::open("sim:");
		FAIL("opened");
	} catch (const ecmxf::Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Catch::Contains("ECM-XF"));
	}
	try {
		(void)ecmxf::Device::open("sk-sim:");
		FAIL("opened");
	} catch (const ecmxf::Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Catch::Contains("sk::Board::open()"));
	}
}
