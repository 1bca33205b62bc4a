// SPDX-License-Identifier: MIT
// The motion layer's cyclic path allocates nothing and throws nothing.
// This binary replaces the global operator new/delete with counting
// versions (as tests/lib_pdo/test_alloc.cpp does for Cyclic alone) and
// runs the default network (2 x EST-584 + I/O) in OP with the motion PDOs
// (est584MotionPdos()). The counted windows hold everything a motion
// application does per cycle: Cyclic::cycle(), Cia402Axis::update() of both
// axes, CspTrajectory::apply() / setCspTarget(), ProcessImage accessors,
// Cyclic::waitNextCycle(); and the requests that go by PDO only (moveTo()
// without SDO parameters, setMode() with 0x6060 mapped, enable(),
// disable(), startCsp()). The count covers the whole process, the
// simulated chip and drive models included. Nothing inside a counted
// window uses Catch (its macros allocate): results are gathered in plain
// variables and checked afterwards.
//
// Expected positions: the trajectories' end points and the PP targets set
// here; the EST-584 model stops exactly at a PP target and follows a CSP
// target within one cycle's 0x607F limit (Documentation/sim-slaves.rst).

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>

#include "../common/alloc_counter.hpp"
#include "../lib_motion/bench.hpp"

using namespace std::chrono_literals;
using std::chrono::nanoseconds;
using ecmxf::Cia402Axis;
using ecmxf::Cia402Progress;
using ecmxf::Cia402State;
namespace cia402 = ecmxf::cia402;
using motiontest::Bench;

// "Throws nothing": the cyclic calls are noexcept, so no exception can
// leave them (one thrown inside would end the program, not unwind into
// the loop). A change that drops noexcept fails to compile here.
static_assert(noexcept(std::declval<ecmxf::Cyclic &>().cycle()));
static_assert(noexcept(std::declval<ecmxf::Cyclic &>().waitNextCycle()));
static_assert(noexcept(std::declval<Cia402Axis &>().update(nanoseconds{})));
static_assert(noexcept(std::declval<Cia402Axis &>().update()));
static_assert(noexcept(std::declval<Cia402Axis &>().setCspTarget(0)));
static_assert(noexcept(std::declval<Cia402Axis &>().setHalt(false)));
static_assert(noexcept(std::declval<const Cia402Axis &>().position()));
static_assert(noexcept(std::declval<const Cia402Axis &>().statusword()));
static_assert(noexcept(std::declval<const Cia402Axis &>().progress()));
static_assert(noexcept(std::declval<const Cia402Axis &>().followingError()));
static_assert(noexcept(std::declval<const Cia402Axis &>().velocity()));
static_assert(noexcept(std::declval<const ecmxf::CspTrajectory &>().position(0, nanoseconds{})));
static_assert(noexcept(std::declval<const ecmxf::CspTrajectory &>().apply(
	std::span<Cia402Axis *const>{}, nanoseconds{})));
static_assert(noexcept(std::declval<const ecmxf::InputVar<std::int32_t> &>().get()));
static_assert(noexcept(std::declval<ecmxf::OutputVar<std::uint8_t> &>().set(0)));

namespace {

/// setMode() then enable() for @p axes, run to done (set-up, not counted).
void modeAndEnable(Bench &b, std::vector<Cia402Axis *> axes, std::int8_t mode)
{
	for (Cia402Axis *a : axes)
		a->setMode(mode, b.now());
	ecmxf::runUntilDone(*b.cyc, axes, 1s, "the mode");
	for (Cia402Axis *a : axes)
		a->enable(b.now());
	ecmxf::runUntilDone(*b.cyc, axes, 2s, "OPERATION ENABLED");
}

} // namespace

TEST_CASE("motion alloc: the counter counts", "[lib][motion][alloc]")
{
	const auto before = ecmxf_test::allocations();
	{
		std::vector<int> v(3);
		(void)v;
	}
	REQUIRE(ecmxf_test::allocations() == before + 1);
}

TEST_CASE("motion alloc: 2000 CSP cycles of two axes allocate nothing", "[lib][motion][alloc][csp]")
{
	Bench b;
	Cia402Axis a0(*b.dev, *b.image, 0, { .modes = { cia402::kModeCsp } });
	Cia402Axis a1(*b.dev, *b.image, 1, { .modes = { cia402::kModeCsp } });
	b.drive(1).setPositionActual(-7000);
	modeAndEnable(b, { &a0, &a1 }, cia402::kModeCsp);
	REQUIRE(a0.enabled());
	REQUIRE(a1.enabled());
	REQUIRE(a0.position() == 0);
	REQUIRE(a1.position() == -7000);
	a0.startCsp(b.now());
	a1.startCsp(b.now());
	const std::array<Cia402Axis *, 2> axes{ &a0, &a1 };
	const std::array<std::int32_t, 2> from{ 0, -7000 };
	const std::array<std::int32_t, 2> to{ 150000, -57000 };
	const ecmxf::CspTrajectory traj(from, to, 1s); // cycles 0..999
	// the I/O terminal's outputs and the drives' inputs by plain handles
	auto dio = b.image->output<std::uint8_t>(2, 0x7000, 1);
	auto pos1 = b.image->input<std::int32_t>(1, 0x6064, 0);

	// warm-up: the same loop body, the targets standing still
	for (int i = 0; i < 50; i++) {
		(void)b.cyc->cycle();
		a0.update(b.now());
		a1.update();
		(void)b.cyc->waitNextCycle();
	}
	REQUIRE(a0.done());
	REQUIRE(a1.done());

	int errors = 0, failed = 0;
	std::int32_t hi0 = 0, lo1 = 0;
	std::int32_t at1100[2]{}, at1999[2]{};
	std::int32_t fe = 0;
	int moved0 = 0;
	std::int32_t last0 = a0.position();
	const nanoseconds t0 = b.now();

	const auto start = ecmxf_test::allocations();
	for (int i = 0; i < 2000; i++) {
		const ecmxf::CycleResult &r = b.cyc->cycle();
		errors += r.error != 0 || !r.wkcOk;
		const nanoseconds now = b.now();
		a0.update(now);
		a1.update(); // the transport's clock
		failed += a0.failed() + a1.failed();
		if (i < 1000) {
			// the next cycle's targets, both axes on one profile
			traj.apply(axes, now - t0 + 1ms);
		} else {
			// back to the start on a straight line over 800 cycles
			const int k = std::min(i - 999, 800);
			a0.setCspTarget(to[0] + (from[0] - to[0]) * k / 800);
			a1.setCspTarget(to[1] + (from[1] - to[1]) * k / 800);
		}
		dio.set(static_cast<std::uint8_t>(i));
		const std::int32_t p0 = a0.position();
		moved0 += p0 != last0;
		last0 = p0;
		hi0 = std::max(hi0, p0);
		lo1 = std::min(lo1, pos1.get());
		fe = std::max({ fe, std::abs(a0.followingError().value_or(0)), std::abs(a1.followingError().value_or(0)) });
		if (i == 1100) {
			at1100[0] = p0;
			at1100[1] = a1.position();
		}
		if (i == 1999) {
			at1999[0] = p0;
			at1999[1] = a1.position();
		}
		(void)b.cyc->waitNextCycle();
	}
	const auto allocs = ecmxf_test::allocations() - start;

	CHECK(allocs == 0);
	CHECK(errors == 0);
	CHECK(failed == 0);
	// the window really moved the drives: out to the trajectory's end
	// (reached 1000 cycles + the latency after t0, before cycle 1100: the
	// return ramp has taken 100 / 800 of the way back by then at most)
	CHECK(hi0 == 150000);
	CHECK(lo1 == -57000);
	CHECK(at1100[0] < 150000);
	CHECK(at1100[0] >= 150000 - 150000 * 101 / 800);
	// and back to the start, in (nearly) every cycle a new position
	CHECK(at1999[0] == 0);
	CHECK(at1999[1] == -7000);
	CHECK(b.drive(0).positionActual() == 0);
	CHECK(b.drive(1).positionActual() == -7000);
	CHECK(moved0 >= 1700);
	CHECK(fe == 0); // within 0x607F: the drive follows each step
	CHECK(a0.done());
	CHECK(a1.done());
	CHECK(b.cyc->stats().failedCycles == 0);
	CHECK(b.cyc->stats().wkcMismatches == 0);
}

TEST_CASE("motion alloc: PP moves issued and run inside the window allocate nothing", "[lib][motion][alloc][pp]")
{
	Bench b;
	Cia402Axis a0(*b.dev, *b.image, 0, { .modes = { cia402::kModePp } });
	Cia402Axis a1(*b.dev, *b.image, 1, { .modes = { cia402::kModePp } });
	modeAndEnable(b, { &a0, &a1 }, cia402::kModePp);
	REQUIRE(a0.enabled());
	REQUIRE(a1.enabled());
	for (int i = 0; i < 20; i++) {
		(void)b.cyc->cycle();
		a0.update(b.now());
		a1.update(b.now());
		(void)b.cyc->waitNextCycle();
	}

	// phase 0: issue the first moves; 1: running; 2: second moves issued
	// (relative, change immediately); 3: done
	int phase = 0, errors = 0, failed = 0, cycles = 0, acks = 0;
	std::int32_t after1[2]{};
	ecmxf::PpMove rel;
	rel.relative = true;
	ecmxf::PpMove now2;
	now2.changeImmediately = true;
	bool moving0 = false;

	const auto start = ecmxf_test::allocations();
	for (; cycles < 4000 && phase < 3; cycles++) {
		const ecmxf::CycleResult &r = b.cyc->cycle();
		errors += r.error != 0 || !r.wkcOk;
		const nanoseconds now = b.now();
		a0.update(now);
		a1.update(now);
		failed += a0.failed() + a1.failed();
		moving0 |= !a0.targetReached();
		if (phase == 0) {
			a0.moveTo(40000, {}, now);
			a1.moveTo(-25000, {}, now);
			phase = 1;
		} else if (phase == 1 && a0.done() && a1.done()) {
			acks += a0.setPointAcknowledged() + a1.setPointAcknowledged();
			after1[0] = a0.position();
			after1[1] = a1.position();
			a0.moveTo(-10000, rel, now);
			a1.moveTo(5000, now2, now);
			phase = 2;
		} else if (phase == 2 && a0.done() && a1.done()) {
			acks += a0.setPointAcknowledged() + a1.setPointAcknowledged();
			phase = 3;
		}
		(void)b.cyc->waitNextCycle();
	}
	const auto allocs = ecmxf_test::allocations() - start;

	CHECK(allocs == 0);
	REQUIRE(phase == 3);
	CHECK(errors == 0);
	CHECK(failed == 0);
	CHECK(acks == 4);
	CHECK(moving0);
	CHECK(after1[0] == 40000);
	CHECK(after1[1] == -25000);
	CHECK(a0.position() == 30000); // 40000 - 10000 (relative)
	CHECK(a1.position() == 5000);
	CHECK(b.drive(0).positionActual() == 30000);
	CHECK(b.drive(1).positionActual() == 5000);
	// 0x6081 = 50000 units/s (the EST-584 default): 40000 units take
	// at least 800 cycles
	CHECK(cycles > 800);
}

TEST_CASE("motion alloc: mode, enable, CSP start and disable by PDO allocate nothing", "[lib][motion][alloc]")
{
	Bench b;
	Cia402Axis a0(*b.dev, *b.image, 0);
	Cia402Axis a1(*b.dev, *b.image, 1);
	REQUIRE(a0.modeByPdo());
	for (int i = 0; i < 20; i++) {
		(void)b.cyc->cycle();
		a0.update(b.now());
		a1.update(b.now());
		(void)b.cyc->waitNextCycle();
	}
	REQUIRE(a0.state() == Cia402State::SwitchOnDisabled);

	// each step: a request for both axes, then cycles until both are done
	int step = 0, errors = 0, failed = 0, cycles = 0;
	bool issued = false;
	std::array<std::int8_t, 2> ppSeen{}, modeSeen{};
	std::array<bool, 2> enabledSeen{};
	std::int32_t csp0 = 0;

	const auto start = ecmxf_test::allocations();
	for (; cycles < 3000 && step < 6; cycles++) {
		const ecmxf::CycleResult &r = b.cyc->cycle();
		errors += r.error != 0 || !r.wkcOk;
		const nanoseconds now = b.now();
		a0.update(now);
		a1.update(now);
		failed += a0.failed() + a1.failed();
		if (step == 4) {
			// CSP steps of 50 units a cycle (startCsp() is done at
			// once): wait on the position
			if (a0.position() >= 5000) {
				csp0 = a0.position();
				step = 5;
				issued = false;
			} else {
				a0.setCspTarget(a0.cspTarget() + 50);
			}
		} else if (issued && a0.done() && a1.done()) {
			if (step == 0)
				ppSeen = { a0.modeDisplay(), a1.modeDisplay() };
			else if (step == 1)
				modeSeen = { a0.modeDisplay(), a1.modeDisplay() };
			else if (step == 2)
				enabledSeen = { a0.enabled(), a1.enabled() };
			step++;
			issued = false;
		}
		if (!issued && step != 4) {
			issued = true;
			switch (step) {
			case 0:
				// 0x6060 defaults to 8: PP first, then CSP
				a0.setMode(cia402::kModePp, now);
				a1.setMode(cia402::kModePp, now);
				break;
			case 1:
				a0.setMode(cia402::kModeCsp, now);
				a1.setMode(cia402::kModeCsp, now);
				break;
			case 2:
				a0.enable(now);
				a1.enable(now);
				break;
			case 3:
				a0.startCsp(now);
				a1.startCsp(now);
				break;
			case 5:
				a0.disable(now);
				a1.disable(now);
				break;
			default:
				break;
			}
		}
		(void)b.cyc->waitNextCycle();
	}
	const auto allocs = ecmxf_test::allocations() - start;

	CHECK(allocs == 0);
	REQUIRE(step == 6);
	CHECK(errors == 0);
	CHECK(failed == 0);
	CHECK(ppSeen == std::array<std::int8_t, 2>{ 1, 1 });
	CHECK(modeSeen == std::array<std::int8_t, 2>{ 8, 8 });
	CHECK(enabledSeen == std::array<bool, 2>{ true, true });
	CHECK(csp0 >= 5000);
	CHECK(a0.state() == Cia402State::SwitchOnDisabled);
	CHECK(a1.state() == Cia402State::SwitchOnDisabled);
	CHECK(b.drive(0).controlword() == 0x0000);
}

TEST_CASE("motion alloc: PV and homing requests without SDO parameters allocate nothing",
	  "[lib][motion][alloc][pv][hm]")
{
	Bench b;
	Cia402Axis a0(*b.dev, *b.image, 0, { .modes = { cia402::kModePv } });
	Cia402Axis a1(*b.dev, *b.image, 1, { .modes = { cia402::kModeHm } });
	b.drive(1).setPositionActual(12345);
	// set-up: homing on the current position (0x6098 is not mapped: an
	// SDO write, so before the window)
	b.dev->sdo().write<std::int8_t>(1, 0x6098, 0, 37);
	modeAndEnable(b, { &a0 }, cia402::kModePv);
	modeAndEnable(b, { &a1 }, cia402::kModeHm);
	REQUIRE(a0.enabled());
	REQUIRE(a1.enabled());
	REQUIRE(a1.position() == 12345);

	int step = 0, errors = 0, failed = 0, cycles = 0;
	bool issued = false;
	std::optional<std::int32_t> vReached;
	std::int32_t homed = -1;
	ecmxf::HomingStatus hs = ecmxf::HomingStatus::InProgress;

	const auto start = ecmxf_test::allocations();
	for (; cycles < 3000 && step < 2; cycles++) {
		const ecmxf::CycleResult &r = b.cyc->cycle();
		errors += r.error != 0 || !r.wkcOk;
		const nanoseconds now = b.now();
		a0.update(now);
		a1.update(now);
		failed += a0.failed() + a1.failed();
		if (issued && a0.done() && (step > 0 || a1.done())) {
			if (step == 0) {
				vReached = a0.velocity();
				homed = a1.position();
				hs = ecmxf::homingStatus(a1.statusword());
			}
			step++;
			issued = false;
		}
		if (!issued && step < 2) {
			issued = true;
			if (step == 0) {
				a0.setVelocity(30000, now); // 0x60FF by PDO
				a1.home({}, now);           // no parameters: nothing to write
			} else {
				a0.setVelocity(0, now);
			}
		}
		(void)b.cyc->waitNextCycle();
	}
	const auto allocs = ecmxf_test::allocations() - start;

	CHECK(allocs == 0);
	REQUIRE(step == 2);
	CHECK(errors == 0);
	CHECK(failed == 0);
	CHECK(vReached == 30000);
	CHECK(homed == 0); // 0x607C = 0
	CHECK(hs == ecmxf::HomingStatus::Completed);
	CHECK(a0.velocity() == 0);
	CHECK(b.drive(0).velocityActual() == 0);
	CHECK(a0.position() > 0); // it ran forward in between
}
