// SPDX-License-Identifier: MIT
// Device::open() and Device::command() over the in-process simulator: the
// raw command path end to end (immediate and async commands, an SDO read),
// and every failure turned into an ecmxf::Error that names the command and
// what happened.

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include "../common/thrown.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Contains;

namespace {

// command codes (manual ver. 050)
constexpr std::uint8_t kInitOp = 1;
constexpr std::uint8_t kSdoReq = 10;
constexpr std::uint8_t kSdoGet = 11;
constexpr std::uint8_t kStateSet = 12;
constexpr std::uint8_t kSlvCntGet = 16;
constexpr std::uint8_t kFwVersionGet = 56;

constexpr std::uint8_t kPreOp = 2;

void put16(std::vector<std::uint8_t> &d, std::uint16_t v)
{
	d.push_back(static_cast<std::uint8_t>(v));
	d.push_back(static_cast<std::uint8_t>(v >> 8));
}

void put32(std::vector<std::uint8_t> &d, std::uint32_t v)
{
	for (unsigned i = 0; i < 4; i++)
		d.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

std::uint32_t le32(const std::vector<std::uint8_t> &d)
{
	REQUIRE(d.size() >= 4);
	return static_cast<std::uint32_t>(d[0]) | static_cast<std::uint32_t>(d[1]) << 8 |
	       static_cast<std::uint32_t>(d[2]) << 16 | static_cast<std::uint32_t>(d[3]) << 24;
}

ecmxf::Command simple(std::uint8_t code, std::uint8_t param = 0)
{
	ecmxf::Command c;
	c.code = code;
	c.param = param;
	return c;
}

/// INIT_OP for all slaves: 0xFF, 0x81, AssignActivate 0x0300, SYNC0 1 ms,
/// SYNC1 0, shift 0; data length field 16.
ecmxf::Command initOp()
{
	ecmxf::Command c = simple(kInitOp);
	c.payload = { 0xFF, 0x81 };
	put16(c.payload, 0x0300);
	put32(c.payload, 1'000'000);
	put32(c.payload, 0);
	put32(c.payload, 0);
	c.len = 16;
	return c;
}

ecmxf::Command stateSet(std::uint8_t state)
{
	ecmxf::Command c = simple(kStateSet, 0xFF);
	c.data[0] = state;
	return c;
}

/// SDO_REQ upload: op 1, slave, index, sub, reserved, length, timeout µs.
ecmxf::Command sdoRead(std::uint8_t slave, std::uint16_t index, std::uint8_t sub, std::uint16_t len)
{
	ecmxf::Command c = simple(kSdoReq);
	c.payload = { 1, slave };
	put16(c.payload, index);
	c.payload.push_back(sub);
	c.payload.push_back(0);
	put16(c.payload, len);
	put32(c.payload, 100'000);
	return c;
}

struct SimDevice {
	std::unique_ptr<ecmxf::Device> dev = ecmxf::Device::open("sim:");
	ecmxf::sim::Chip &chip = *dev->link().simulator();

	/// INIT_OP, then all slaves to PRE-OP (mailboxes running).
	void toPreOp()
	{
		dev->command(initOp());
		dev->command(stateSet(kPreOp));
		REQUIRE(dev->lastHeader().ecatState == kPreOp);
	}
};

using ecmxftest::thrown;

} // namespace

TEST_CASE("FW_VERSION_GET over sim: returns the simulator's configured firmware version",
	  "[lib][device]")
{
	SimDevice s;
	const ecmxf::Response r = s.dev->command(simple(kFwVersionGet));
	CHECK(r.ret == ecmxf::sim::ChipConfig{}.fwVersion);
	CHECK(r.header.code == kFwVersionGet);
	REQUIRE(r.data.size() == 20);
	CHECK(std::string(r.data.begin() + 4, r.data.begin() + 19) == "ecmxf-simulator");
}

TEST_CASE("SLV_CNT_GET before INIT_OP counts no slaves, after the async INIT_OP all three",
	  "[lib][device]")
{
	SimDevice s;
	CHECK(s.dev->command(simple(kSlvCntGet)).ret == 0);

	const auto t0 = s.chip.now();
	const ecmxf::Response init = s.dev->command(initOp());
	// the command returned only after the busy bit cleared
	CHECK((init.header.ecmStatus & 0x80) == 0);
	CHECK((s.dev->lastHeader().ecmStatus & 0x80) == 0);
	CHECK((init.header.errStatus & 0x08) == 0);
	CHECK(s.chip.now() - t0 > 1ms); // the scan took bus time, not one exchange
	CHECK(s.dev->lastHeader().ecatState == 1);

	CHECK(s.dev->command(simple(kSlvCntGet)).ret == 3);
	CHECK(s.chip.network().size() == 3);
}

TEST_CASE("STATE_SET PRE-OP for all slaves completes and the last header shows ECAT state 2",
	  "[lib][device]")
{
	SimDevice s;
	s.dev->command(initOp());
	REQUIRE(s.dev->lastHeader().ecatState == 1);
	const ecmxf::Response r = s.dev->command(stateSet(kPreOp));
	CHECK(r.header.ecatState == kPreOp);
	CHECK(s.dev->lastHeader().ecatState == kPreOp);
	for (std::size_t i = 0; i < s.chip.network().size(); i++)
		CHECK((s.chip.network().at(i).alStatus() & 0x0F) == kPreOp);
}

TEST_CASE("SDO read of 0x1018:01 then SDO_GET returns the vendor id of slave 0", "[lib][device]")
{
	SimDevice s;
	s.toPreOp();
	s.dev->command(sdoRead(0, 0x1018, 1, 4));
	const ecmxf::Response r = s.dev->command(simple(kSdoGet));
	REQUIRE(r.data.size() == 4);
	const std::uint32_t vendor = s.chip.network().at(0).identity().vendorId;
	CHECK(vendor != 0);
	CHECK(le32(r.data) == vendor);
}

TEST_CASE("a failing SDO read throws an Error naming ECAT_SDO_REQ and the async failure",
	  "[lib][device]")
{
	SimDevice s;
	s.toPreOp();
	const ecmxf::Error e = thrown([&] { s.dev->command(sdoRead(0, 0x5FFF, 0, 4)); });
	CHECK_THAT(e.what(), Contains("ECAT_SDO_REQ: the async command failed (error status bit 3)"));
	CHECK(e.errnoValue() == EREMOTEIO);
	REQUIRE(e.errorStatus().has_value());
	CHECK((*e.errorStatus() & 0x08) != 0);

	// the engine cleared the async error bit: the next SDO read works
	s.dev->command(sdoRead(0, 0x1018, 1, 4));
	CHECK(le32(s.dev->command(simple(kSdoGet)).data) == s.chip.network().at(0).identity().vendorId);
}

TEST_CASE("an async command that never completes throws 'timed out' after the command's timeout",
	  "[lib][device]")
{
	SimDevice s;
	s.chip.faults().asyncStuckBusy = true;
	ecmxf::Command c = initOp();
	c.timeout = 20ms;
	const auto t0 = s.chip.now();
	const ecmxf::Error e = thrown([&] { s.dev->command(c); });
	CHECK_THAT(e.what(),
		   Contains("ECAT_INIT_OP: timed out after 20 ms waiting for the async command to complete"));
	CHECK(e.errnoValue() == ETIMEDOUT);
	CHECK_FALSE(e.errorStatus().has_value());
	const auto waited = s.chip.now() - t0;
	CHECK(waited >= 20ms);
	CHECK(waited < 21ms);
}

TEST_CASE("setMinimumTimeout raises shorter timeouts and the table's default, never longer ones",
	  "[lib][device]")
{
	SimDevice s;
	s.chip.faults().asyncStuckBusy = true;
	CHECK(s.dev->minimumTimeout() == 0us);
	s.dev->setMinimumTimeout(50ms);
	CHECK(s.dev->minimumTimeout() == 50ms);

	// its own 20 ms is raised to 50 ms
	ecmxf::Command c = initOp();
	c.timeout = 20ms;
	auto t0 = s.chip.now();
	ecmxf::Error e = thrown([&] { s.dev->command(c); });
	CHECK_THAT(e.what(),
		   Contains("ECAT_INIT_OP: timed out after 50 ms waiting for the async command to complete"));
	CHECK(s.chip.now() - t0 >= 50ms);
	CHECK(s.chip.now() - t0 < 51ms);

	// a longer one stays (a fresh chip: the stuck command still runs)
	SimDevice s2;
	s2.chip.faults().asyncStuckBusy = true;
	s2.dev->setMinimumTimeout(5ms);
	c.timeout = 30ms;
	e = thrown([&] { s2.dev->command(c); });
	CHECK_THAT(e.what(), Contains("ECAT_INIT_OP: timed out after 30 ms"));

	// through transact() as well: ECAT_INIT_OP's 10 s table default
	// (the manual's) becomes 12 s
	SimDevice s3;
	s3.chip.faults().asyncStuckBusy = true;
	s3.dev->setMinimumTimeout(12s);
	const ecmxf::Command ic = initOp();
	ecmxf::RawCommand rc;
	rc.code = ic.code;
	rc.len = static_cast<std::int32_t>(ic.payload.size());
	ecmxf::ResponseHeader h;
	t0 = s3.chip.now();
	CHECK(s3.dev->transact(rc, ic.payload, {}, h) == ETIMEDOUT);
	CHECK(s3.chip.now() - t0 >= 12s);
	CHECK(s3.chip.now() - t0 < 12100ms);

	s.dev->setMinimumTimeout(-1ms);
	CHECK(s.dev->minimumTimeout() == 0us);
}

TEST_CASE("bit errors on every response throw an Error naming the bad packets and the fault",
	  "[lib][device]")
{
	SimDevice s;
	s.chip.faults().misoBitErrors = 20;
	const ecmxf::Error e = thrown([&] { s.dev->command(simple(kFwVersionGet)); });
	CHECK_THAT(e.what(), Contains("FW_VERSION_GET: 9 bad packets in a row (check word mismatch)"));
	CHECK(e.errnoValue() == EBADMSG);

	// once the line is clean again, the device works
	s.chip.faults().misoBitErrors = 0;
	CHECK(s.dev->command(simple(kFwVersionGet)).ret == ecmxf::sim::ChipConfig{}.fwVersion);
}

TEST_CASE("a few bit errors are retried and the command still succeeds", "[lib][device]")
{
	SimDevice s;
	s.chip.faults().misoBitErrors = 3;
	CHECK(s.dev->command(simple(kFwVersionGet)).ret == ecmxf::sim::ChipConfig{}.fwVersion);
	CHECK(s.chip.faults().misoBitErrors == 0);
}

TEST_CASE("Device::open with an unknown URI throws naming the URI and what is supported",
	  "[lib][device]")
{
	const ecmxf::Error e = thrown([] { (void)ecmxf::Device::open("bogus:"); });
	CHECK_THAT(e.what(), Contains("\"bogus:\": unknown device URI"));
	CHECK_THAT(e.what(), Contains("sim:"));
	CHECK(e.errnoValue() == EINVAL);

	// the kernel transport (tests/transport): no module here, so no node
	const ecmxf::Error dev = thrown([] { (void)ecmxf::Device::open("/dev/ecmxf-none0"); });
	CHECK_THAT(dev.what(), Contains("\"/dev/ecmxf-none0\""));
	CHECK(dev.errnoValue() == ENOENT);
}

TEST_CASE("Device::open of sim:<network file> uses that network, a missing file throws",
	  "[lib][device]")
{
	const std::string file = ECMXF_TEST_NETWORK_DIR "/servo-io.net";
	auto dev = ecmxf::Device::open("sim:" + file);
	auto &chip = *dev->link().simulator();
	dev->command(initOp());
	CHECK(dev->command(simple(kSlvCntGet)).ret == chip.network().size());

	const ecmxf::Error e = thrown([] { (void)ecmxf::Device::open("sim:/nonexistent/x.net"); });
	CHECK_THAT(e.what(), Contains("\"sim:/nonexistent/x.net\""));
}

TEST_CASE("a payload larger than the data section throws EMSGSIZE before anything is sent",
	  "[lib][device]")
{
	SimDevice s;
	ecmxf::Command c = simple(kSdoReq);
	c.payload.resize(113);
	const auto exchanges = s.chip.stats().exchanges;
	const ecmxf::Error e = thrown([&] { s.dev->command(c); });
	CHECK_THAT(e.what(), Contains("ECAT_SDO_REQ: payload of 113 bytes"));
	CHECK(e.errnoValue() == EMSGSIZE);
	CHECK(s.chip.stats().exchanges == exchanges);
}
