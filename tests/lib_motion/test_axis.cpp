// SPDX-License-Identifier: MIT
// Cia402Axis against the simulator's EST-584 and servo models: the state
// walk, PP absolute and relative with the set-point handshake, PV, homing,
// synchronized CSP, faults and timeouts, and the constructor's refusals.
// Expected values come from the EST-584 manual (modes, objects) and the
// models' documented behaviour (Documentation/sim-slaves.rst).

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <vector>

#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/error.hpp>

#include "bench.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using Catch::Matchers::StartsWith;
using ecmxf::Cia402Axis;
using ecmxf::Cia402State;
using ecmxf::Error;
namespace cia402 = ecmxf::cia402;
using motiontest::Bench;

namespace {

/// setMode() then enable(), each run to done; returns the states seen on
/// the way to OPERATION ENABLED, in order, without repeats.
std::vector<Cia402State> modeAndEnable(Bench &b, std::vector<Cia402Axis *> axes, std::int8_t mode)
{
	for (Cia402Axis *a : axes)
		a->setMode(mode, b.now());
	ecmxf::runUntilDone(*b.cyc, axes, 1s, "the mode");
	for (Cia402Axis *a : axes)
		a->enable(b.now());
	std::vector<Cia402State> seen;
	ecmxf::runUntil(
		*b.cyc, axes,
		[&] {
			const auto s = axes[0]->state();
			if (s && (seen.empty() || seen.back() != *s))
				seen.push_back(*s);
			return std::all_of(axes.begin(), axes.end(), [](Cia402Axis *a) { return a->done(); });
		},
		2s, "OPERATION ENABLED");
	return seen;
}

} // namespace

TEST_CASE("axis: enable walks SWITCH ON DISABLED to OPERATION ENABLED and disable back", "[axis]")
{
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 0);
	const auto seen = modeAndEnable(b, { &a }, cia402::kModePp);
	const std::vector<Cia402State> want{ Cia402State::SwitchOnDisabled, Cia402State::ReadyToSwitchOn,
					     Cia402State::SwitchedOn, Cia402State::OperationEnabled };
	CHECK(seen == want);
	CHECK(a.enabled());
	// 0x27 OPERATION ENABLED + bit 4 voltage + bit 9 remote + bit 10 target
	// reached (at rest) + bit 15 trigger response (= NOT bit 12, manual 2.1.4)
	CHECK(b.drive(0).statusword() == 0x8637);
	CHECK(a.statusword() == 0x8637);
	a.disable(b.now());
	std::vector<Cia402Axis *> v{ &a };
	ecmxf::runUntilDone(*b.cyc, v, 1s);
	CHECK(a.state() == Cia402State::SwitchOnDisabled);
	CHECK(b.drive(0).controlword() == 0x0000);
}

TEST_CASE("axis: PP absolute move with the set-point handshake reaches the target", "[axis][pp]")
{
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 0, { .modes = { cia402::kModePp } });
	CHECK(a.modeByPdo());
	modeAndEnable(b, { &a }, cia402::kModePp);
	CHECK(a.modeDisplay() == 1);
	ecmxf::PpMove m;
	m.velocity = 100000;
	a.moveTo(60000, m, b.now());
	bool sawAck = false, sawMoving = false;
	std::vector<Cia402Axis *> v{ &a };
	ecmxf::runUntil(
		*b.cyc, v,
		[&] {
			sawAck |= (a.statusword() & cia402::kSwSetPointAck) != 0;
			sawMoving |= !a.targetReached();
			return a.done();
		},
		5s, "target reached");
	CHECK(sawAck);
	CHECK(a.setPointAcknowledged());
	CHECK(sawMoving);
	CHECK(a.targetReached());
	CHECK(a.position() == 60000);
	CHECK(b.drive(0).positionActual() == 60000);
	// 0x6081 went by SDO (not mapped)
	CHECK(b.dev->sdo().read<std::uint32_t>(0, 0x6081, 0) == 100000u);
	// the other drive did not move
	CHECK(b.drive(1).positionActual() == 0);
}

TEST_CASE("axis: PP relative move adds to the previous target", "[axis][pp]")
{
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 1);
	modeAndEnable(b, { &a }, cia402::kModePp);
	std::vector<Cia402Axis *> v{ &a };
	ecmxf::PpMove m;
	m.velocity = 200000;
	a.moveTo(-30000, m, b.now());
	ecmxf::runUntilDone(*b.cyc, v, 5s);
	CHECK(a.position() == -30000);
	m.relative = true;
	a.moveTo(45000, m, b.now());
	ecmxf::runUntilDone(*b.cyc, v, 5s);
	CHECK(a.setPointAcknowledged());
	CHECK(a.position() == 15000);
	CHECK(b.drive(1).positionActual() == 15000);
}

TEST_CASE("axis: PP on the default mapping sets the mode by SDO", "[axis][pp]")
{
	Bench b("est584x2-io.net", false);
	Cia402Axis a(*b.dev, *b.image, 0);
	CHECK_FALSE(a.modeByPdo());
	modeAndEnable(b, { &a }, cia402::kModePp);
	CHECK(b.dev->sdo().read<std::int8_t>(0, 0x6060, 0) == 1);
	CHECK(a.modeDisplay() == 1); // 0x6061 is in the default TxPDO
	a.moveTo(5000, {}, b.now());
	std::vector<Cia402Axis *> v{ &a };
	ecmxf::runUntilDone(*b.cyc, v, 5s);
	CHECK(a.position() == 5000);
}

TEST_CASE("axis: PV reaches the target velocity", "[axis][pv]")
{
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 0, { .modes = { cia402::kModePv } });
	modeAndEnable(b, { &a }, cia402::kModePv);
	a.setVelocity(40000, b.now(), 400000u, 400000u);
	std::vector<Cia402Axis *> v{ &a };
	ecmxf::runUntilDone(*b.cyc, v, 2s, "velocity reached");
	CHECK(a.velocity() == 40000);
	CHECK(b.drive(0).velocityActual() == 40000);
	CHECK(b.dev->sdo().read<std::uint32_t>(0, 0x6083, 0) == 400000u);
	// and back to 0
	a.setVelocity(0, b.now());
	ecmxf::runUntilDone(*b.cyc, v, 2s, "standstill");
	CHECK(a.velocity() == 0);
	CHECK((a.statusword() & cia402::kSwSpeedZero) != 0);
}

TEST_CASE("axis: homing on the current position (method 37) attains homing at the home offset", "[axis][hm]")
{
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 0);
	b.drive(0).setPositionActual(12345);
	modeAndEnable(b, { &a }, cia402::kModeHm);
	ecmxf::HomingParams h;
	h.method = 37;
	a.home(h, b.now());
	std::vector<Cia402Axis *> v{ &a };
	ecmxf::runUntilDone(*b.cyc, v, 2s, "homing attained");
	CHECK(ecmxf::homingStatus(a.statusword()) == ecmxf::HomingStatus::Completed);
	CHECK(a.position() == 0); // 0x607C = 0
	CHECK(b.dev->sdo().read<std::int8_t>(0, 0x6098, 0) == 37);
}

TEST_CASE("axis: homing on the home switch (method 19) ends near the edge", "[axis][hm]")
{
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 1);
	b.est(1).setHomeSwitch(20000);
	modeAndEnable(b, { &a }, cia402::kModeHm);
	ecmxf::HomingParams h;
	h.method = 19;
	h.speedSearch = 40000;
	h.speedZero = 2000;
	a.home(h, b.now());
	std::vector<Cia402Axis *> v{ &a };
	ecmxf::runUntilDone(*b.cyc, v, 10s, "homing attained");
	CHECK(ecmxf::homingStatus(a.statusword()) == ecmxf::HomingStatus::Completed);
	// the edge became 0 (0x607C); the motor stops with 0x609A a few
	// units past it: 2000 units/s at 200000 units/s^2 brake in 10 units
	CHECK(a.position() >= 0);
	CHECK(a.position() <= 10);
}

TEST_CASE("axis: homing with a method the drive refuses is an SDO abort", "[axis][hm]")
{
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 0);
	modeAndEnable(b, { &a }, cia402::kModeHm);
	ecmxf::HomingParams h;
	h.method = 1;
	REQUIRE_THROWS_AS(a.home(h, b.now()), ecmxf::SdoError);
	try {
		a.home(h, b.now());
	} catch (const ecmxf::SdoError &e) {
		CHECK_THAT(e.what(), Contains("0x6098"));
		CHECK_THAT(e.what(), Contains("0x06090030"));
	}
}

TEST_CASE("axis: synchronized CSP move, both axes end at their targets in the same cycle", "[axis][csp]")
{
	Bench b;
	Cia402Axis a0(*b.dev, *b.image, 0, { .modes = { cia402::kModeCsp } });
	Cia402Axis a1(*b.dev, *b.image, 1, { .modes = { cia402::kModeCsp } });
	b.drive(1).setPositionActual(-7000);
	std::vector<Cia402Axis *> v{ &a0, &a1 };
	modeAndEnable(b, v, cia402::kModeCsp);
	// enabling did not move them (the target followed the actual position)
	CHECK(a0.position() == 0);
	CHECK(a1.position() == -7000);
	for (Cia402Axis *a : v)
		a->startCsp(b.now());
	const std::array<std::int32_t, 2> from{ a0.position(), a1.position() };
	const std::array<std::int32_t, 2> to{ 150000, -57000 };
	const ecmxf::CspTrajectory traj(from, to, 1s);
	const auto t0 = b.now();
	// per cycle: the targets written (for the next frame) and the positions read
	std::vector<std::array<std::int32_t, 2>> cmd, pos;
	std::int32_t maxFe = 0;
	ecmxf::runUntil(
		*b.cyc, v,
		[&] {
			pos.push_back({ a0.position(), a1.position() });
			maxFe = std::max({ maxFe, std::abs(*a0.followingError()), std::abs(*a1.followingError()) });
			traj.apply(v, b.now() - t0 + 1ms); // the next cycle's target
			cmd.push_back({ a0.cspTarget(), a1.cspTarget() });
			return b.now() - t0 > traj.duration() + 20ms;
		},
		3s, "the CSP move");
	REQUIRE(pos.size() > 1000);
	// the drives follow the targets with one latency, the same for both
	// axes: their targets travel in the same frame
	std::optional<std::size_t> lag;
	for (std::size_t l = 1; l < 10 && !lag; l++) {
		bool all = true;
		for (std::size_t k = l; k < pos.size(); k++)
			all = all && pos[k][0] == cmd[k - l][0];
		if (all)
			lag = l;
	}
	REQUIRE(lag);
	for (std::size_t k = *lag; k < pos.size(); k++) {
		INFO("cycle " << k);
		REQUIRE(pos[k][1] == cmd[k - *lag][1]);
	}
	// the trajectory's last sample (t = 1 s, cycle 999) gives both targets
	CHECK(cmd[999][0] == 150000);
	CHECK(cmd[999][1] == -57000);
	CHECK(pos[999 + *lag][0] == 150000);
	CHECK(pos[999 + *lag][1] == -57000);
	// and half way (t = 0.5 s) both are half way: the same fraction
	CHECK(cmd[499][0] == 75000);
	CHECK(cmd[499][1] == -32000);
	std::int32_t lo0 = 0, hi0 = 0;
	for (const auto &p : pos) {
		lo0 = std::min(lo0, p[0]);
		hi0 = std::max(hi0, p[0]);
	}
	CHECK(lo0 == 0);      // no move backwards
	CHECK(hi0 == 150000); // no overshoot
	// the drive follows each step (no speed limit hit): following error 0
	CHECK(maxFe == 0);
	CHECK(a0.done());
	CHECK(b.cyc->stats().wkcMismatches == 0);
}

TEST_CASE("axis: CSP on the servo network", "[axis][csp][servo]")
{
	Bench b("servo-io.net");
	Cia402Axis a0(*b.dev, *b.image, 0, { .modes = { cia402::kModeCsp } });
	Cia402Axis a1(*b.dev, *b.image, 1, { .modes = { cia402::kModeCsp } });
	std::vector<Cia402Axis *> v{ &a0, &a1 };
	modeAndEnable(b, v, cia402::kModeCsp);
	for (Cia402Axis *a : v)
		a->startCsp(b.now());
	const std::array<std::int32_t, 2> from{ a0.position(), a1.position() };
	const std::array<std::int32_t, 2> to{ 1 << 20, -(1 << 19) }; // one turn, half a turn back
	const ecmxf::CspTrajectory traj(from, to, 500ms);
	const auto t0 = b.now();
	ecmxf::runUntil(
		*b.cyc, v,
		[&] {
			traj.apply(v, b.now() - t0 + 1ms);
			return a0.position() == to[0] && a1.position() == to[1];
		},
		2s, "the CSP move");
	CHECK(b.drive(0).positionActual() == 1 << 20);
	CHECK(b.drive(1).positionActual() == -(1 << 19));
}

TEST_CASE("axis: a fault during a PP move fails it with the drive's state", "[axis][fault]")
{
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 0);
	modeAndEnable(b, { &a }, cia402::kModePp);
	ecmxf::PpMove m;
	m.velocity = 50000;
	a.moveTo(100000, m, b.now());
	std::vector<Cia402Axis *> v{ &a };
	int n = 0;
	try {
		ecmxf::runUntil(
			*b.cyc, v,
			[&] {
				if (++n == 100)
					b.drive(0).injectFault(0x7500);
				return a.done();
			},
			5s);
		FAIL("no failure");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EIO);
		CHECK_THAT(e.what(), Contains("slave 0: CiA-402 drive left OPERATION ENABLED: now FAULT"));
	}
	CHECK(a.failed());
	CHECK(a.position() > 0);
	CHECK(a.position() < 100000);
	// enable again resets the fault (rising edge of bit 7)
	a.enable(b.now());
	ecmxf::runUntilDone(*b.cyc, v, 2s);
	CHECK(a.enabled());
	CHECK(b.drive(0).errorCode() == 0);
}

TEST_CASE("axis: enable times out when the drive does not follow (slave in SAFE-OP)", "[axis][timeout]")
{
	Bench b;
	ecmxf::Cia402AxisConfig cfg;
	cfg.state.timeout = 200ms;
	Cia402Axis a(*b.dev, *b.image, 0, cfg);
	b.dev->bus().stateSet(0, ecmxf::State::SafeOp); // outputs are no longer applied
	a.enable(b.now());
	const auto t0 = b.now();
	while (!a.failed() && b.now() - t0 < 1s) {
		(void)b.cyc->cycle();
		a.update(b.now());
		(void)b.cyc->waitNextCycle();
	}
	REQUIRE(a.failed());
	CHECK_THAT(a.failureMessage(),
		   Equals("slave 0: CiA-402 timed out after 200 ms waiting for READY TO SWITCH ON on the way to "
			  "OPERATION ENABLED: stays in SWITCH ON DISABLED (statusword 0x0250)"));
	try {
		a.throwIfFailed();
		FAIL("no throw");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == ETIMEDOUT);
	}
}

TEST_CASE("axis: runUntil names the slave that left OP", "[axis][timeout]")
{
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 0);
	b.dev->bus().stateSet(1, ecmxf::State::SafeOp);
	a.enable(b.now());
	std::vector<Cia402Axis *> v{ &a };
	try {
		ecmxf::runUntilDone(*b.cyc, v, 1s);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EIO);
		// 2 x EST-584 (3 each) + dio (3) = 9; slave 1 in SAFE-OP takes no
		// outputs (-2)
		CHECK_THAT(e.what(), Equals("runUntil: working counter 7, expected 9 (bus state 0x04); slave 1 in "
					    "SAFE-OP, AL status code 0x0000 No error"));
	}
}

TEST_CASE("axis: runUntil times out naming what it waited for", "[axis][timeout]")
{
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 0);
	std::vector<Cia402Axis *> v{ &a };
	try {
		ecmxf::runUntil(*b.cyc, v, [] { return false; }, 50ms, "Godot");
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == ETIMEDOUT);
		CHECK_THAT(e.what(), Equals("runUntil: timed out after 50 ms waiting for Godot"));
	}
}

TEST_CASE("axis: the constructor names what is not mapped, for which mode", "[axis][errors]")
{
	Bench b("est584x2-io.net", false);
	try {
		Cia402Axis a(*b.dev, *b.image, 0, { .modes = { cia402::kModePp, cia402::kModePv } });
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("slave 0: Cia402Axis: not mapped: 0x60FF:00 (target velocity) as an output "
					    "for mode 3 (profile velocity). Mapped outputs: 0x6040, 0x607A, 0x60B0, "
					    "0x60B8; inputs: 0x6041, 0x6061, 0x6064, 0x60B9, 0x60BA, 0x60FD"));
	}
	try {
		Cia402Axis a(*b.dev, *b.image, 2);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK_THAT(e.what(), Equals("slave 2: Cia402Axis: not mapped: 0x6040:00 (controlword) as an output, "
					    "0x6041:00 (statusword) as an input, 0x6064:00 (position actual value) as "
					    "an input (every mode). Mapped outputs: 0x7000:1; inputs: 0x6000:1"));
	}
	Cia402Axis a(*b.dev, *b.image, 0);
	try {
		a.setVelocity(100, b.now());
		FAIL("no error");
	} catch (const Error &e) {
		CHECK_THAT(e.what(), Equals("slave 0: PV needs 0x60FF:00 (target velocity) mapped as an output; mapped "
					    "outputs: 0x6040, 0x607A, 0x60B0, 0x60B8"));
	}
	// a move before the mode and the enable (after the inputs came in)
	std::vector<Cia402Axis *> v{ &a };
	int n = 0;
	ecmxf::runUntil(*b.cyc, v, [&] { return ++n == 10; }, 1s);
	try {
		a.moveTo(100, {}, b.now());
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("slave 0: PP move needs mode 1 (profile position); the drive is in mode 8 "
					    "(cyclic synchronous position) (setMode() first)"));
	}
}

TEST_CASE("axis: the requests without now run on the link's clock (issue 15)", "[axis][pp]")
{
	// the same walk and move as above, with no time kept by the caller
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 0, { .modes = { cia402::kModePp } });
	std::vector<Cia402Axis *> v{ &a };
	a.setMode(cia402::kModePp);
	ecmxf::runUntilDone(*b.cyc, v, 1s, "the mode");
	a.enable();
	ecmxf::runUntilDone(*b.cyc, v, 2s, "OPERATION ENABLED");
	CHECK(a.state() == Cia402State::OperationEnabled);
	ecmxf::PpMove m;
	m.velocity = 100000;
	a.moveTo(30000, m);
	ecmxf::runUntilDone(*b.cyc, v, 5s, "target reached");
	CHECK(b.drive(0).positionActual() == 30000);
	a.requestState(Cia402State::SwitchedOn);
	ecmxf::runUntilDone(*b.cyc, v, 1s, "SWITCHED ON");
	CHECK(a.state() == Cia402State::SwitchedOn);
	a.disable();
	ecmxf::runUntilDone(*b.cyc, v, 1s, "SWITCH ON DISABLED");
	CHECK(a.state() == Cia402State::SwitchOnDisabled);
	// a request that is not allowed throws as its timed form does
	CHECK_THROWS_AS(a.startCsp(), Error);
}

// ---- the safe stop (issue 29): stopAxes() and stop on scope exit

namespace {

/// A PV axis of @p b at velocity 40000 (the drive moving).
void spinUp(Bench &b, Cia402Axis &a)
{
	modeAndEnable(b, { &a }, cia402::kModePv);
	a.setVelocity(40000, b.now(), 400000u, 400000u);
	std::vector<Cia402Axis *> v{ &a };
	ecmxf::runUntilDone(*b.cyc, v, 2s, "velocity reached");
	REQUIRE(b.drive(0).velocityActual() == 40000);
}

std::optional<Cia402State> simState(Bench &b)
{
	return ecmxf::cia402StateFrom(b.drive(0).statusword());
}

} // namespace

TEST_CASE("axis: stopAxes() quick-stops a moving drive to standstill, then disables it", "[axis][stop]")
{
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 0, { .modes = { cia402::kModePv } });
	spinUp(b, a);
	std::vector<Cia402Axis *> v{ &a };
	const auto out = ecmxf::stopAxes(*b.cyc, v);
	REQUIRE(out.size() == 1);
	CHECK(out[0].wasEnabled);
	CHECK(out[0].halted);
	CHECK(out[0].velocity == 0);
	CHECK(simState(b) == Cia402State::SwitchOnDisabled);
	CHECK(b.drive(0).velocityActual() == 0);
	CHECK(b.drive(0).controlword() == 0x0000); // Disable Voltage, by PDO
	CHECK_THAT(out[0].text, Contains("slave 0: quick stop, then disabled: SWITCH ON DISABLED (statusword 0x"));
	CHECK_THAT(out[0].text, Contains(", velocity 0"));
	// a drive already disabled: nothing to do, said so
	const auto again = ecmxf::stopAxes(*b.cyc, v);
	REQUIRE(again.size() == 1);
	CHECK_FALSE(again[0].wasEnabled);
	CHECK(again[0].halted);
	CHECK_THAT(again[0].text, Contains("slave 0: not enabled: SWITCH ON DISABLED"));
}

TEST_CASE("axis: an exception out of the application's loop halts the drive on scope exit", "[axis][stop]")
{
	Bench b;
	{
		Cia402Axis a(*b.dev, *b.image, 0, { .modes = { cia402::kModePv } });
		spinUp(b, a);
		std::vector<Cia402Axis *> v{ &a };
		CHECK_THROWS_WITH(ecmxf::runUntil(
					  *b.cyc, v, []() -> bool { throw std::runtime_error("the application failed"); },
					  1s),
				  "the application failed");
		// still moving: the chip keeps sending the last outputs
		CHECK(simState(b) == Cia402State::OperationEnabled);
	} // the axis goes: runUntil() set stop-on-exit
	CHECK(simState(b) == Cia402State::SwitchOnDisabled);
	CHECK(b.drive(0).velocityActual() == 0);
}

TEST_CASE("axis: the Cyclic going first halts the drive, and the axis outlives it safely", "[axis][stop]")
{
	Bench b;
	Cia402Axis a(*b.dev, *b.image, 0, { .modes = { cia402::kModePv } });
	spinUp(b, a);
	CHECK(a.stopsVia() == b.cyc.get());
	b.cyc.reset();
	CHECK(a.stopsVia() == nullptr);
	CHECK(simState(b) == Cia402State::SwitchOnDisabled);
	CHECK(b.drive(0).velocityActual() == 0);
}

TEST_CASE("axis: stopOnExit(nullptr) leaves the drive as it is", "[axis][stop]")
{
	Bench b;
	{
		Cia402Axis a(*b.dev, *b.image, 0, { .modes = { cia402::kModePv } });
		spinUp(b, a);
		a.stopOnExit(nullptr);
	}
	CHECK(simState(b) == Cia402State::OperationEnabled);
}

TEST_CASE("axis: a following-error fault names the drive's error code (0x603F)", "[axis][csp][fault]")
{
	// the servo maps 0x603F; a CSP target far beyond its following
	// window faults it with 0x8611
	Bench b("servo-io.net");
	Cia402Axis a(*b.dev, *b.image, 0, { .modes = { cia402::kModeCsp } });
	std::vector<Cia402Axis *> v{ &a };
	modeAndEnable(b, v, cia402::kModeCsp);
	a.startCsp(b.now());
	a.setCspTarget(a.position() + (1 << 28));
	try {
		ecmxf::runUntil(*b.cyc, v, [] { return false; }, 2s, "the jump");
		FAIL("no failure");
	} catch (const Error &e) {
		INFO(e.what());
		CHECK_THAT(e.what(), StartsWith("slave 0: "));
		CHECK_THAT(e.what(), Contains(", error code 0x8611 (0x603F)"));
	}
	CHECK(a.failed());
	CHECK_THAT(a.failureMessage(), Contains("error code 0x8611"));
}
