// SPDX-License-Identifier: MIT
// The CiA-402 state machine against the simulator: the host-side stepper
// driving the EST-584 and servo models (controlword written into the
// outputs with raw PDO_DATA_OP, statusword and controlword read through
// the models' sim_slaves.hpp hooks), and the chip's internal 402 engine
// through the typed Device calls, on networks brought to OP with raw
// Device::command() calls.
//
// Expected statuswords are built by hand from Documentation/sim-slaves.rst:
// the appendix pattern | bit 4 (voltage enabled) | bit 9 (remote); in CSP
// (the models' default mode) OPERATION ENABLED adds bit 12 (following the
// command value): 0x0027 | 0x0010 | 0x0200 | 0x1000 = 0x1237.

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/model/cia402.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/chip/chip402.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/slaves.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include "../common/thrown.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Equals;
using ecmxf::Cia402Progress;
using ecmxf::Cia402State;
using ecmxf::Cia402Stepper;

namespace {

// command codes (manual ver. 050)
constexpr std::uint8_t kInitOp = 1;
constexpr std::uint8_t kPdoDataOp = 6;
constexpr std::uint8_t kStateSet = 12;
constexpr std::uint8_t kFifoPackSizeGet = 19;

constexpr std::uint16_t kSod = 0x0250;
constexpr std::uint16_t kOeCsp = 0x1237;
constexpr std::uint16_t kFault = 0x0218;

ecmxf::Command simple(std::uint8_t code, std::uint8_t param = 0)
{
	ecmxf::Command c;
	c.code = code;
	c.param = param;
	return c;
}

void put16(std::vector<std::uint8_t> &d, std::size_t at, std::uint16_t v)
{
	d.at(at) = static_cast<std::uint8_t>(v);
	d.at(at + 1) = static_cast<std::uint8_t>(v >> 8);
}

void put32(std::vector<std::uint8_t> &d, std::uint32_t v)
{
	for (unsigned i = 0; i < 4; i++)
		d.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

/// A simulated chip brought up with raw commands, as the manuals describe:
/// INIT_OP, PRE-OP, SAFE-OP, initial outputs, OP.
struct Bus {
	std::unique_ptr<ecmxf::Device> dev;
	ecmxf::sim::Chip &chip;
	std::vector<std::uint8_t> out; // the outputs of every slave (RxPDO image)

	explicit Bus(const std::string &uri = "sim:")
		: dev(ecmxf::Device::open(uri)), chip(*dev->link().simulator())
	{
	}

	void stateSet(std::uint8_t state)
	{
		ecmxf::Command c = simple(kStateSet, 0xFF);
		c.data[0] = state;
		dev->command(c);
		REQUIRE(dev->lastHeader().ecatState == state);
	}

	/// INIT_OP with DC: AssignActivate 0x0300, SYNC0 1 ms.
	void init()
	{
		ecmxf::Command c = simple(kInitOp);
		c.payload = { 0xFF, 0x81, 0x00, 0x03 };
		put32(c.payload, 1'000'000);
		put32(c.payload, 0);
		put32(c.payload, 0);
		c.len = 16;
		dev->command(c);
	}

	void toSafeOp()
	{
		init();
		stateSet(2);
		stateSet(4);
		const ecmxf::Response r = dev->command(simple(kFifoPackSizeGet, 0));
		REQUIRE(r.data.size() == 2);
		out.assign(static_cast<std::size_t>(r.data[0] | r.data[1] << 8), 0);
		write();
	}

	void toOp()
	{
		toSafeOp();
		stateSet(8);
	}

	/// PDO_DATA_OP: write the outputs (bit 2: bits 0/1 valid, bit 0 write).
	void write()
	{
		ecmxf::Command c = simple(kPdoDataOp);
		c.data[0] = 0x05;
		c.payload = out;
		dev->command(c);
	}

	ecmxf::sim::Cia402Model &drive(std::size_t pos)
	{
		auto *m = dynamic_cast<ecmxf::sim::Cia402Model *>(&chip.network().at(pos));
		REQUIRE(m != nullptr);
		return *m;
	}

	std::chrono::nanoseconds now() { return dev->link().now(); }
	void sleep(std::chrono::nanoseconds d) { dev->link().sleepFor(d); }

	/// Runs @p s on the drive at @p pos (controlword at byte @p cwOff of
	/// the outputs) until it is no longer busy, 2 ms per step; returns the
	/// controlwords written, runs of equal words collapsed.
	std::vector<std::uint16_t> run(Cia402Stepper &s, std::size_t pos, std::size_t cwOff)
	{
		std::vector<std::uint16_t> written;
		for (int i = 0; i < 500; i++) {
			const ecmxf::Cia402Step r = s.step(drive(pos).statusword(), now(), 0);
			put16(out, cwOff, r.controlword);
			write();
			if (written.empty() || written.back() != r.controlword)
				written.push_back(r.controlword);
			if (r.progress != Cia402Progress::Busy)
				break;
			sleep(2ms);
		}
		return written;
	}
};

std::string networkUri(const char *file)
{
	return std::string("sim:") + ECMXF_TEST_NETWORK_DIR + "/" + file;
}

using ecmxftest::thrown;

} // namespace

TEST_CASE("cia402 sim: the stepper enables an EST-584 from SWITCH ON DISABLED to OPERATION ENABLED",
	  "[402][sim]")
{
	Bus b;
	b.toOp();
	b.sleep(5ms);
	REQUIRE(b.drive(1).statusword() == kSod);
	Cia402Stepper s(1);
	s.request(Cia402State::OperationEnabled, b.now());
	// slave 1's controlword: after slave 0's 12 output bytes (0x1600:
	// 0x6040 16 bits, 0x607A 32, 0x60B0 32, 0x60B8 16)
	const std::vector<std::uint16_t> cws = b.run(s, 1, 12);
	CHECK(s.progress() == Cia402Progress::Done);
	CHECK(cws == std::vector<std::uint16_t>{ 0x0006, 0x0007, 0x000F });
	b.sleep(2ms);
	CHECK(b.drive(1).controlword() == 0x000F);
	CHECK(b.drive(1).statusword() == kOeCsp);
	// the other drive saw nothing
	CHECK(b.drive(0).controlword() == 0x0000);
	CHECK(b.drive(0).statusword() == kSod);
}

TEST_CASE("cia402 sim: the stepper enables a servo (servo-io.net, DC) and walks it back down", "[402][sim]")
{
	Bus b(networkUri("servo-io.net"));
	b.toOp();
	b.sleep(5ms);
	// slave 1's controlword: after slave 0's 13 output bytes (0x1600:
	// 0x6040 16 bits, 0x607A 32, 0x60FF 32, 0x6071 16, 0x6060 8)
	Cia402Stepper s(1);
	s.request(Cia402State::OperationEnabled, b.now());
	CHECK(b.run(s, 1, 13) == std::vector<std::uint16_t>{ 0x0006, 0x0007, 0x000F });
	CHECK(s.progress() == Cia402Progress::Done);
	b.sleep(2ms);
	CHECK(b.drive(1).statusword() == kOeCsp);
	// down: 5 (disable operation), then 6 (shutdown), then 7 (disable voltage)
	s.request(Cia402State::SwitchedOn, b.now());
	CHECK(b.run(s, 1, 13) == std::vector<std::uint16_t>{ 0x0007 });
	b.sleep(2ms);
	CHECK(b.drive(1).statusword() == 0x0233);
	s.request(Cia402State::SwitchOnDisabled, b.now());
	CHECK(b.run(s, 1, 13) == std::vector<std::uint16_t>{ 0x0000 });
	b.sleep(2ms);
	CHECK(b.drive(1).statusword() == kSod);
}

TEST_CASE("cia402 sim: a level-high bit 7 does not reset a fault, the stepper's rising edge does",
	  "[402][sim]")
{
	Bus b;
	b.toOp();
	b.sleep(5ms);
	Cia402Stepper s(0);
	s.request(Cia402State::OperationEnabled, b.now());
	REQUIRE(b.run(s, 0, 0) == std::vector<std::uint16_t>{ 0x0006, 0x0007, 0x000F });

	// bit 7 high before the fault: no command is decoded, the drive stays
	put16(b.out, 0, 0x008F);
	b.write();
	b.sleep(5ms);
	CHECK(b.drive(0).statusword() == kOeCsp);
	b.drive(0).injectFault(0x3210);
	b.sleep(20ms);
	CHECK(b.drive(0).controlword() == 0x008F);
	CHECK(b.drive(0).statusword() == kFault); // a level is no reset
	CHECK(b.drive(0).errorCode() == 0x3210);

	// the stepper: bit 7 = 0, then 1; then on to OPERATION ENABLED
	s.request(Cia402State::OperationEnabled, b.now());
	CHECK(b.run(s, 0, 0) == std::vector<std::uint16_t>{ 0x0000, 0x0080, 0x0006, 0x0007, 0x000F });
	CHECK(s.progress() == Cia402Progress::Done);
	b.sleep(2ms);
	CHECK(b.drive(0).statusword() == kOeCsp);
	CHECK(b.drive(0).errorCode() == 0x0000);
}

TEST_CASE("cia402 sim: a fault while enabled fails the walk, naming the state and statusword", "[402][sim]")
{
	Bus b;
	b.toOp();
	b.sleep(5ms);
	Cia402Stepper s(0);
	s.request(Cia402State::OperationEnabled, b.now());
	REQUIRE(b.run(s, 0, 0).back() == 0x000F);
	b.drive(0).injectFault(0x3210);
	b.sleep(5ms);
	const ecmxf::Cia402Step r = s.step(b.drive(0).statusword(), b.now(), 0);
	CHECK(r.progress == Cia402Progress::Failed);
	CHECK(s.failureMessage() == "slave 0: CiA-402 drive left OPERATION ENABLED: now FAULT (statusword 0x0218)");
	const ecmxf::Error e = thrown([&] { s.throwIfFailed(); });
	CHECK(e.errnoValue() == EIO);
}

TEST_CASE("cia402 sim: outputs not applied in SAFE-OP: the walk times out", "[402][sim]")
{
	Bus b;
	b.toSafeOp();
	b.sleep(5ms);
	Cia402Stepper s(0, Cia402Stepper::Options{ 100ms, true });
	s.request(Cia402State::OperationEnabled, b.now());
	b.run(s, 0, 0);
	CHECK(s.progress() == Cia402Progress::Failed);
	CHECK(b.drive(0).controlword() == 0x0000);
	const ecmxf::Error e = thrown([&] { s.throwIfFailed(); });
	CHECK(e.errnoValue() == ETIMEDOUT);
	CHECK_THAT(e.what(), Equals("slave 0: CiA-402 timed out after 100 ms waiting for READY TO SWITCH ON on the "
				    "way to OPERATION ENABLED: stays in SWITCH ON DISABLED (statusword 0x0250)"));
}

// ---------------------------------------------------------------- the chip's engine

TEST_CASE("cia402 chip engine: enable two drives, read states and statuswords", "[402][sim][chip402]")
{
	Bus b;
	b.toOp();
	b.sleep(5ms);
	ecmxf::Device &d = *b.dev;
	const ecmxf::Chip402Flags engine{ true, false, false };
	d.chip402().configure(0, ecmxf::Chip402Config{ 0, 0, 0, engine });
	d.chip402().configure(1, ecmxf::Chip402Config{ 1, 0, 0, engine });
	CHECK(d.chip402().control(0) == engine);
	const ecmxf::Chip402State st = d.chip402().state(0);
	CHECK(st.code == 0x40);
	CHECK(st.state == Cia402State::SwitchOnDisabled);
	// the engine starts with SWITCH ON DISABLED requested: nothing moves
	b.sleep(10ms);
	CHECK(d.chip402().state(1).state == Cia402State::SwitchOnDisabled);

	d.chip402().requestState(0, Cia402State::OperationEnabled);
	d.chip402().requestState(1, Cia402State::OperationEnabled);
	CHECK(d.chip402().awaitState(0, Cia402State::OperationEnabled, 100ms) == Cia402State::OperationEnabled);
	CHECK(d.chip402().awaitState(1, Cia402State::OperationEnabled, 100ms) == Cia402State::OperationEnabled);
	const ecmxf::Chip402State oe = d.chip402().state(0);
	CHECK(oe.code == 0x27);
	CHECK(oe.state == Cia402State::OperationEnabled);
	CHECK(d.chip402().statusword(0) == kOeCsp);
	CHECK(d.chip402().statusword(1) == kOeCsp);
	CHECK(b.drive(0).statusword() == kOeCsp);
	CHECK((b.drive(0).controlword() & 0x8F) == 0x0F);

	// and down to SWITCHED ON
	d.chip402().requestState(1, Cia402State::SwitchedOn);
	d.chip402().awaitState(1, Cia402State::SwitchedOn, 100ms);
	CHECK(d.chip402().statusword(1) == 0x0233);
	CHECK((b.drive(1).controlword() & 0x8F) == 0x07);
}

TEST_CASE("cia402 chip engine: a fault stays without reset flags, single and automatic fault reset",
	  "[402][sim][chip402]")
{
	Bus b;
	b.toOp();
	b.sleep(5ms);
	ecmxf::Device &d = *b.dev;
	d.chip402().configure(0, ecmxf::Chip402Config{ 0, 0, 0, { true, false, false } });
	d.chip402().requestState(0, Cia402State::OperationEnabled);
	d.chip402().awaitState(0, Cia402State::OperationEnabled, 100ms);

	b.drive(0).injectFault(0x3210);
	b.sleep(10ms);
	const ecmxf::Chip402State f = d.chip402().state(0);
	CHECK(f.code == 0x08);
	CHECK(f.state == Cia402State::Fault);
	CHECK(d.chip402().statusword(0) == kFault);
	const ecmxf::Error e = thrown([&] { d.chip402().awaitState(0, Cia402State::OperationEnabled, 50ms); });
	CHECK(e.errnoValue() == ETIMEDOUT);
	CHECK_THAT(e.what(), Equals("motor 0: the chip's CiA-402 engine timed out after 50 ms waiting for OPERATION "
				    "ENABLED: stays in FAULT (statusword 0x0218)"));

	// one fault reset: bit 3 reads 0 again once the drive has left FAULT
	d.chip402().setControl(0, ecmxf::Chip402Control{ { true, true, false }, 2, 0 });
	d.chip402().awaitState(0, Cia402State::OperationEnabled, 100ms);
	CHECK(d.chip402().control(0) == ecmxf::Chip402Flags{ true, false, false });
	CHECK(b.drive(0).errorCode() == 0x0000);
	b.drive(0).injectFault(0x3210);
	b.sleep(20ms);
	CHECK(d.chip402().state(0).state == Cia402State::Fault); // only once

	// automatic fault reset: every fault
	d.chip402().setControl(0, ecmxf::Chip402Control{ { true, false, true }, 2, 0 });
	d.chip402().awaitState(0, Cia402State::OperationEnabled, 100ms);
	b.drive(0).injectFault(0x3210);
	b.sleep(2ms);
	d.chip402().awaitState(0, Cia402State::OperationEnabled, 100ms);
	CHECK(d.chip402().control(0) == ecmxf::Chip402Flags{ true, false, true });
	CHECK(d.chip402().statusword(0) == kOeCsp);
}

TEST_CASE("cia402 chip engine: refused commands and bad arguments name the reason", "[402][sim][chip402]")
{
	Bus b;
	ecmxf::Device &d = *b.dev;
	// before INIT_OP
	ecmxf::Error e = thrown([&] { d.chip402().configure(0, ecmxf::Chip402Config{ 0, 0, 0, {} }); });
	CHECK(e.errnoValue() == EREMOTEIO);
	REQUIRE(e.errorStatus().has_value());
	CHECK((*e.errorStatus() & 0x80) == 0x80);
	CHECK_THAT(e.what(), Equals("402_CONFIG_SET (motor 0): the chip refused the command (error status bit 7, command "
				    "error: the bus is not initialized (ECAT_INIT_OP), slave 0 does not exist, or the "
				    "controlword (offset 0) or statusword (offset 0) is not inside that slave's process "
				    "data)"));

	b.toOp();
	// EST-584: 12 output bytes, so a controlword at 11 does not fit
	e = thrown([&] { d.chip402().configure(0, ecmxf::Chip402Config{ 0, 11, 0, {} }); });
	CHECK_THAT(e.what(), Equals("402_CONFIG_SET (motor 0): the chip refused the command (error status bit 7, command "
				    "error: the bus is not initialized (ECAT_INIT_OP), slave 0 does not exist, or the "
				    "controlword (offset 11) or statusword (offset 0) is not inside that slave's process "
				    "data)"));
	e = thrown([&] { (void)d.chip402().state(5); });
	CHECK(e.errnoValue() == EREMOTEIO);
	CHECK_THAT(e.what(), Equals("402_STATE_GET (motor 5): the chip refused the command (error status bit 7, command "
				    "error: motor 5 is not configured (402_CONFIG_SET first))"));
	e = thrown([&] { (void)d.chip402().statusword(5); });
	CHECK_THAT(e.what(), Equals("402_GET_STATUSWORD (motor 5): the chip refused the command (error status bit 7, "
				    "command error: motor 5 is not configured (402_CONFIG_SET first)); the command "
				    "exists only in firmware of manual ver. 050"));
	e = thrown([&] { (void)d.chip402().control(5); });
	CHECK_THAT(e.what(), Equals("402_CTL_GET (motor 5): the chip refused the command (error status bit 7, command "
				    "error: motor 5 is not configured (402_CONFIG_SET first))"));
	e = thrown([&] { d.chip402().requestState(5, Cia402State::OperationEnabled); });
	CHECK_THAT(e.what(), Equals("402_STATE_SET (motor 5): the chip refused the command (error status bit 7, command "
				    "error: motor 5 is not configured (402_CONFIG_SET first))"));

	// the next command starts clean
	d.chip402().configure(0, ecmxf::Chip402Config{ 0, 0, 0, {} });
	CHECK(d.chip402().state(0).state == Cia402State::SwitchOnDisabled);
	e = thrown([&] { d.chip402().setControl(0, ecmxf::Chip402Control{ { true, false, false }, 1, 3 }); });
	CHECK_THAT(e.what(), Equals("402_CTL_SET (motor 0): the chip refused the command (error status bit 7, command "
				    "error: motor 0 is not configured (402_CONFIG_SET first), or slave 3 does not "
				    "exist)"));

	// arguments
	e = thrown([&] { d.chip402().requestState(0, Cia402State::Fault); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("402_STATE_SET (motor 0): FAULT (code 0x08) cannot be requested: SWITCH ON "
				    "DISABLED 0x40, READY TO SWITCH ON 0x21, SWITCHED ON 0x23, OPERATION ENABLED 0x27 "
				    "or QUICK STOP ACTIVE 0x07"));
	e = thrown([&] { (void)d.chip402().state(128); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("402_STATE_GET: motor 128 is out of range 0..127"));
	e = thrown([&] { d.chip402().setControl(0, ecmxf::Chip402Control{ {}, 0, 0 }); });
	CHECK_THAT(e.what(), Equals("402_CTL_SET: motor count 0 is out of range 1..128 (motor 0)"));
	e = thrown([&] { d.chip402().configure(1, ecmxf::Chip402Config{ 128, 0, 0, {} }); });
	CHECK_THAT(e.what(), Equals("402_CONFIG_SET: slave 128 is out of range 0..127 (motor 1)"));
	e = thrown([&] { d.chip402().configure(1, ecmxf::Chip402Config{ 0, 256, 0, {} }); });
	CHECK_THAT(e.what(), Equals("402_CONFIG_SET: controlword offset 256 is out of range 0..255 (motor 1)"));
}

TEST_CASE("cia402 chip engine: with the engine off the host's controlword passes, on it takes over",
	  "[402][sim][chip402]")
{
	Bus b;
	b.toOp();
	b.sleep(5ms);
	ecmxf::Device &d = *b.dev;
	d.chip402().configure(0, ecmxf::Chip402Config{ 0, 0, 0, {} });
	d.chip402().requestState(0, Cia402State::OperationEnabled);
	put16(b.out, 0, 0x0106); // shutdown, with halt (bit 8)
	b.write();
	b.sleep(5ms);
	CHECK(b.drive(0).controlword() == 0x0106);
	CHECK(d.chip402().state(0).state == Cia402State::ReadyToSwitchOn);
	d.chip402().setControl(0, ecmxf::Chip402Control{ { true, false, false }, 1, 0 });
	d.chip402().awaitState(0, Cia402State::OperationEnabled, 100ms);
	// the engine owns bits 0-3 and 7; the host's bit 8 stays
	CHECK(b.drive(0).controlword() == 0x010F);
}
