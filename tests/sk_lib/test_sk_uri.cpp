// SPDX-License-Identifier: MIT
// The ECM-SK device URIs: every option, and bad values of each.

#include <catch2/catch.hpp>

#include <cerrno>

#include <ecmxf/error.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/sk/uri.hpp>

using namespace ecmxf::sk;

namespace {
int errnoOf(const char *uri)
{
	try {
		(void)parseSkUri(uri);
	} catch (const ecmxf::Error &e) {
		return e.errnoValue();
	}
	return 0;
}
} // namespace

TEST_CASE("sk uri: sk-sim with a network file and board settings")
{
	auto u = parseSkUri("sk-sim:");
	CHECK(u.kind == SkUri::Kind::Sim);
	CHECK(u.path.empty());
	CHECK(u.slotSize == 12);
	u = parseSkUri("sk-sim:/tmp/x.net?slot=16&test=1&abandon=0&ex=3&fifo=300&busy_us=5&spi_hz=6000000&lio=7");
	CHECK(u.path == "/tmp/x.net");
	CHECK(u.slotSize == 16);
	CHECK(u.extensions == 3u);
	CHECK(u.board.testMode);
	CHECK_FALSE(u.board.fifoAbandon);
	CHECK(u.board.fifoDepth == 300u);
	CHECK(u.board.lioInputs == 7u);
}

TEST_CASE("sk uri: sk-unix and sk-spidev with their options")
{
	auto u = parseSkUri("sk-unix:/run/sk.sock?slot=16&ex=2");
	CHECK(u.kind == SkUri::Kind::Unix);
	CHECK(u.path == "/run/sk.sock");
	CHECK(u.slotSize == 16);
	CHECK(u.extensions == 2u);
	u = parseSkUri("sk-spidev:/dev/spidev0.1?busy=gpiochip0:25&slot=12&speed=6000000&mode=0&ex=1");
	CHECK(u.kind == SkUri::Kind::Spidev);
	CHECK(u.spidev.device == "/dev/spidev0.1");
	REQUIRE(u.spidev.int0);
	CHECK(u.spidev.int0->chip == "gpiochip0");
	CHECK(u.spidev.int0->line == 25u);
	CHECK_FALSE(u.spidev.readyHigh);
	CHECK(u.spidev.speedHz == 6000000u);
	CHECK(u.extensions == 1u);
	u = parseSkUri("sk-spidev:/dev/spidev0.0?busy=/dev/gpiochip4:3");
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
		     "sk-usb:", "sk", "sk-sim:?=1" }) {
		INFO(bad);
		CHECK(errnoOf(bad) == EINVAL);
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
