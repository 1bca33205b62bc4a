// SPDX-License-Identifier: MIT
// Device URIs: parseDeviceUri() on good and bad URIs (exact messages), and
// Device::open() failures of the real transports that can be provoked
// without hardware: a missing node, a node that is not a spidev or ecmxf
// device (/dev/null: the real open() and ioctl() paths run and fail), a
// GPIO chip that does not exist.

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>

#include <ecmxf/device.hpp>
#include <ecmxf/device_uri.hpp>
#include <ecmxf/error.hpp>
#include "../common/thrown.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using Catch::Matchers::StartsWith;
using Kind = ecmxf::DeviceUri::Kind;

namespace {

using ecmxftest::thrown;

/// The message parseDeviceUri() gives for @p uri and @p what.
std::string badUri(const std::string &uri, const std::string &what)
{
	return "cannot open \"" + uri + "\": " + what + "; accepted: " + std::string(ecmxf::kDeviceUriForms);
}

void checkBad(const std::string &uri, const std::string &what)
{
	INFO("URI " << uri);
	const ecmxf::Error e = thrown([&] { (void)ecmxf::parseDeviceUri(uri); });
	CHECK_THAT(e.what(), Equals(badUri(uri, what)));
	CHECK(e.errnoValue() == EINVAL);
}

} // namespace

TEST_CASE("the accepted URI forms are listed in every URI error", "[transport][uri]")
{
	const std::string forms(ecmxf::kDeviceUriForms);
	CHECK_THAT(forms, Contains("\"sim:\""));
	CHECK_THAT(forms, Contains("\"sim:<network file>\""));
	CHECK_THAT(forms, Contains("\"/dev/ecmxfN\""));
	CHECK_THAT(forms, Contains("spidev:/dev/spidevB.C[?int0=<chip>:<line>][&int1=<chip>:<line>][&speed=<Hz>]"
				   "[&mode=0..3][&ready=high|low][&size=<bytes>][&check=fixed|crc8|ccitt|crc32]"));
	CHECK_THAT(forms, Contains("trace=<file>"));
}

TEST_CASE("sim URIs: default network, a network file, and a trace option", "[transport][uri]")
{
	auto u = ecmxf::parseDeviceUri("sim:");
	CHECK(u.kind == Kind::Sim);
	CHECK(u.path.empty());
	CHECK(u.trace.empty());
	u = ecmxf::parseDeviceUri("sim:/x/servo-io.net");
	CHECK(u.kind == Kind::Sim);
	CHECK(u.path == "/x/servo-io.net");
	u = ecmxf::parseDeviceUri("sim:?trace=/tmp/a.trace");
	CHECK(u.path.empty());
	CHECK(u.trace == "/tmp/a.trace");
}

TEST_CASE("kernel URIs: any absolute path is a kernel device node", "[transport][uri]")
{
	auto u = ecmxf::parseDeviceUri("/dev/ecmxf0");
	CHECK(u.kind == Kind::Kernel);
	CHECK(u.path == "/dev/ecmxf0");
	u = ecmxf::parseDeviceUri("/dev/ecmxf1?trace=t.trace");
	CHECK(u.path == "/dev/ecmxf1");
	CHECK(u.trace == "t.trace");
}

TEST_CASE("spidev URIs: defaults from the chip manual", "[transport][uri]")
{
	const auto u = ecmxf::parseDeviceUri("spidev:/dev/spidev0.0");
	CHECK(u.kind == Kind::Spidev);
	CHECK(u.path == "/dev/spidev0.0");
	CHECK(u.spidev.device == "/dev/spidev0.0");
	CHECK(u.spidev.mode == 0);               // manual: POL=0 PHA=0 (mode 0)
	CHECK(u.spidev.speedHz == 48'000'000u);  // half the 96 Mbit/s maximum
	CHECK_FALSE(u.spidev.int0.has_value());  // the 150 us fallback
	CHECK_FALSE(u.spidev.int1.has_value());
	CHECK(u.spidev.readyHigh);               // ver. 050: INT0 high = ready
	CHECK(ecmxf::SpidevOptions::kMaxSpeedHz == 96'000'000u);
	CHECK(ecmxf::SpidevOptions::kFallbackWait == std::chrono::microseconds(150));
}

TEST_CASE("spidev URIs: every option", "[transport][uri]")
{
	const auto u = ecmxf::parseDeviceUri(
		"spidev:/dev/spidev1.2?int0=gpiochip0:17&int1=pinctrl-bcm2711:27&speed=24000000&mode=3&ready=low"
		"&trace=/tmp/x.trace");
	CHECK(u.kind == Kind::Spidev);
	CHECK(u.spidev.device == "/dev/spidev1.2");
	REQUIRE(u.spidev.int0.has_value());
	CHECK(u.spidev.int0->chip == "gpiochip0");
	CHECK(u.spidev.int0->line == 17);
	REQUIRE(u.spidev.int1.has_value());
	CHECK(u.spidev.int1->chip == "pinctrl-bcm2711");
	CHECK(u.spidev.int1->line == 27);
	CHECK(u.spidev.speedHz == 24'000'000u);
	CHECK(u.spidev.mode == 3);
	CHECK_FALSE(u.spidev.readyHigh);
	CHECK(u.trace == "/tmp/x.trace");

	// a chip given by path keeps its colons but the last
	const auto p = ecmxf::parseDeviceUri("spidev:/dev/spidev0.0?int0=/dev/gpiochip4:3&speed=96000000&mode=0");
	CHECK(p.spidev.int0->chip == "/dev/gpiochip4");
	CHECK(p.spidev.int0->line == 3);
	CHECK(p.spidev.speedHz == 96'000'000u);
}

TEST_CASE("bad URIs throw EINVAL naming the bad part and the accepted forms", "[transport][uri]")
{
	checkBad("", "empty device URI");
	checkBad("bogus:", "unknown device URI");
	checkBad("dev/ecmxf0", "unknown device URI");
	checkBad("spidev:", "no spidev node after \"spidev:\" (e.g. spidev:/dev/spidev0.0)");
	checkBad("spidev:?int0=gpiochip0:1", "no spidev node after \"spidev:\" (e.g. spidev:/dev/spidev0.0)");
	checkBad("spidev:/dev/spidev0.0?int0=gpiochip0",
		 "bad int0 value \"gpiochip0\": expected <chip>:<line>, e.g. int0=gpiochip0:17");
	checkBad("spidev:/dev/spidev0.0?int1=:5", "bad int1 value \":5\": expected <chip>:<line>, e.g. int1=gpiochip0:17");
	checkBad("spidev:/dev/spidev0.0?int0=gpiochip0:x",
		 "bad int0 value \"gpiochip0:x\": expected <chip>:<line>, e.g. int0=gpiochip0:17");
	checkBad("spidev:/dev/spidev0.0?speed=0",
		 "bad speed value \"0\": expected 1..96000000 (Hz; the chip's maximum is 96 MHz)");
	checkBad("spidev:/dev/spidev0.0?speed=96000001",
		 "bad speed value \"96000001\": expected 1..96000000 (Hz; the chip's maximum is 96 MHz)");
	checkBad("spidev:/dev/spidev0.0?speed=10M",
		 "bad speed value \"10M\": expected 1..96000000 (Hz; the chip's maximum is 96 MHz)");
	checkBad("spidev:/dev/spidev0.0?mode=4", "bad mode value \"4\": expected 0..3 (the chip uses mode 0)");
	checkBad("spidev:/dev/spidev0.0?ready=up",
		 "bad ready value \"up\": expected high or low (the INT0 level that means ready; high by default)");
	checkBad("spidev:/dev/spidev0.0?speed=1&speed=2", "option \"speed\" given twice");
	checkBad("spidev:/dev/spidev0.0?mode", "option \"mode\" is not key=value");
	checkBad("spidev:/dev/spidev0.0?mode=0&", "empty option (options are key=value, separated by '&')");
	checkBad("spidev:/dev/spidev0.0?cs=1",
		 "unknown option \"cs\" (spidev: takes int0, int1, speed, mode, ready, size, check, trace)");
	checkBad("sim:?speed=1",
		 "option \"speed\" applies to spidev: URIs only (sim: takes check=<type> and trace=<file>)");
	checkBad("/dev/ecmxf0?int0=gpiochip0:1",
		 "option \"int0\" applies to spidev: URIs only (the kernel device takes only trace=<file>)");
	checkBad("/dev/ecmxf0?foo=1", "unknown option \"foo\" (only trace=<file> is accepted here)");
	checkBad("sim:?trace=", "option \"trace\" needs a file name (trace=<file>)");
	checkBad("spidev:/dev/spidev0.0?size=31",
		 "bad size value \"31\": expected 32..1408 (the data section the chip uses now, in bytes)");
	checkBad("spidev:/dev/spidev0.0?size=1409",
		 "bad size value \"1409\": expected 32..1408 (the data section the chip uses now, in bytes)");
	checkBad("spidev:/dev/spidev0.0?check=crc16",
		 "bad check value \"crc16\": expected fixed, crc8, ccitt or crc32 (the check word the chip uses now)");
	checkBad("sim:?check=crc16", "bad check value \"crc16\": expected fixed, crc8, ccitt or crc32 (the check "
				     "word to switch the chip to)");
	checkBad("sim:?check=", "bad check value \"\": expected fixed, crc8, ccitt or crc32 (the check word to "
				"switch the chip to)");
	checkBad("sim:?check=CRC32", "bad check value \"CRC32\": expected fixed, crc8, ccitt or crc32 (the check "
				     "word to switch the chip to)");
	checkBad("sim:?check=crc32&check=fixed", "option \"check\" given twice");
	checkBad("sim:?foo=1", "unknown option \"foo\" (check=<type> and trace=<file> are accepted here)");
	checkBad("/dev/ecmxf0?check=crc32",
		 "option \"check\" applies to spidev: URIs only (the kernel device takes only trace=<file>)");
	checkBad("/dev/ecmxf0?size=112",
		 "option \"size\" applies to spidev: URIs only (the kernel device takes only trace=<file>)");
}

TEST_CASE("sim and unix URIs: check= names the check word to switch the chip to", "[transport][uri]")
{
	auto u = ecmxf::parseDeviceUri("sim:?check=crc32");
	CHECK(u.kind == ecmxf::DeviceUri::Kind::Sim);
	CHECK(u.path.empty());
	CHECK(u.checkType == std::optional<ecmxf::CheckType>(ecmxf::CheckType::Crc32));
	u = ecmxf::parseDeviceUri("sim:/tmp/n.net?trace=/tmp/t&check=ccitt");
	CHECK(u.path == "/tmp/n.net");
	CHECK(u.checkType == std::optional<ecmxf::CheckType>(ecmxf::CheckType::Ccitt));
	CHECK(ecmxf::parseDeviceUri("unix:/tmp/s?check=fixed").checkType == ecmxf::CheckType::Fixed);
	CHECK(ecmxf::parseDeviceUri("unix:/tmp/s?check=crc8").checkType == ecmxf::CheckType::Crc8);
	CHECK_FALSE(ecmxf::parseDeviceUri("sim:").checkType);
}

TEST_CASE("spidev URIs: size= and check= give the format the chip speaks now", "[transport][uri]")
{
	auto u = ecmxf::parseDeviceUri("spidev:/dev/spidev1.0?int0=gpiochip2:0&check=crc32");
	CHECK_FALSE(u.dataSize);
	REQUIRE(u.checkType);
	CHECK(*u.checkType == ecmxf::CheckType::Crc32);
	u = ecmxf::parseDeviceUri("spidev:/dev/spidev1.0?size=256&check=fixed");
	CHECK(u.dataSize == std::optional<std::uint16_t>(256));
	CHECK(u.checkType == std::optional<ecmxf::CheckType>(ecmxf::CheckType::Fixed));
	CHECK(ecmxf::parseDeviceUri("spidev:/dev/spidev1.0?check=crc8").checkType == ecmxf::CheckType::Crc8);
	CHECK(ecmxf::parseDeviceUri("spidev:/dev/spidev1.0?check=ccitt").checkType == ecmxf::CheckType::Ccitt);
	u = ecmxf::parseDeviceUri("spidev:/dev/spidev1.0");
	CHECK_FALSE(u.dataSize);
	CHECK_FALSE(u.checkType);
}

TEST_CASE("Device::open of a missing kernel node names the path and the reason", "[transport][uri][kernel]")
{
	const ecmxf::Error e = thrown([] { (void)ecmxf::Device::open("/nonexistent/ecmxf0"); });
	CHECK_THAT(e.what(), Equals(std::string("cannot open \"/nonexistent/ecmxf0\": ") + std::strerror(ENOENT) +
				    " (is the ecmxf kernel module loaded and the chip bound?)"));
	CHECK(e.errnoValue() == ENOENT);
}

TEST_CASE("Device::open of a node that is not an ecmxf device fails at ECMXF_IOC_GET_VERSION",
	  "[transport][uri][kernel]")
{
	// /dev/null opens, but the real ioctl() answers ENOTTY
	const ecmxf::Error e = thrown([] { (void)ecmxf::Device::open("/dev/null"); });
	CHECK_THAT(e.what(), Equals(std::string("/dev/null: ECMXF_IOC_GET_VERSION failed: ") + std::strerror(ENOTTY) +
				    " (not an ecmxf device?)"));
	CHECK(e.errnoValue() == ENOTTY);
}

TEST_CASE("Device::open of a missing spidev node names the path and the reason", "[transport][uri][spidev]")
{
	const ecmxf::Error e = thrown([] { (void)ecmxf::Device::open("spidev:/nonexistent/spidev0.0"); });
	CHECK_THAT(e.what(), Equals(std::string("cannot open \"/nonexistent/spidev0.0\": ") + std::strerror(ENOENT)));
	CHECK(e.errnoValue() == ENOENT);
}

TEST_CASE("Device::open of a node that is not a spidev device fails at SPI_IOC_WR_MODE",
	  "[transport][uri][spidev]")
{
	const ecmxf::Error e = thrown([] { (void)ecmxf::Device::open("spidev:/dev/null?mode=0"); });
	CHECK_THAT(e.what(), Equals(std::string("/dev/null: cannot set SPI mode 0 (SPI_IOC_WR_MODE): ") +
				    std::strerror(ENOTTY) + " (not a spidev device?)"));
	CHECK(e.errnoValue() == ENOTTY);
}

TEST_CASE("Device::open with an INT0 on a GPIO chip that does not exist names chip and line",
	  "[transport][uri][spidev]")
{
	// the lines are opened before the SPI node is touched
	const ecmxf::Error e =
		thrown([] { (void)ecmxf::Device::open("spidev:/dev/null?int0=nosuchgpiochip:3"); });
	CHECK_THAT(e.what(), StartsWith("cannot open the GPIO chip \"nosuchgpiochip\" of the INT0 (ready) line "
					"\"nosuchgpiochip:3\": "));
	CHECK(e.errnoValue() != 0);
}

TEST_CASE("openSpidevBackend checks the options it is given directly", "[transport][spidev]")
{
	ecmxf::SpidevOptions o;
	o.device = "/dev/null";
	o.mode = 7;
	ecmxf::Error e = thrown([&] { (void)ecmxf::openSpidevBackend(o); });
	CHECK_THAT(e.what(), Equals("spidev /dev/null: SPI mode 7 outside 0..3"));
	CHECK(e.errnoValue() == EINVAL);
	o.mode = 0;
	o.speedHz = 100'000'000;
	e = thrown([&] { (void)ecmxf::openSpidevBackend(o); });
	CHECK_THAT(e.what(), Equals("spidev /dev/null: SPI clock 100000000 Hz outside 1..96000000 Hz (the chip's "
				    "maximum is 96 MHz)"));
	o.device.clear();
	e = thrown([&] { (void)ecmxf::openSpidevBackend(o); });
	CHECK_THAT(e.what(), Equals("spidev: no spidev node given (e.g. /dev/spidev0.0)"));
}
