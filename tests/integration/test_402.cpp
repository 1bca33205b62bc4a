// SPDX-License-Identifier: MIT
// CiA-402 on the device of ECMXF_TEST_URI: the chip's own 402 engine
// (402_CONFIG_SET/STATE_SET/STATE_GET/CTL_SET/CTL_GET/GET_STATUSWORD), and
// the host's Cia402Axis over Cyclic (enable, a PP move, a CSP move).
//
// Expected values: the state codes of the manuals' appendix (SWITCH ON
// DISABLED 0x40, OPERATION ENABLED 0x27, SWITCHED ON 0x23) and the
// EST-584's statuswords (sim-slaves.rst: pattern | bit 4 voltage | bit 9
// remote; in CSP, the models' default mode, OPERATION ENABLED adds bit 12:
// 0x1237; SWITCHED ON 0x0233); positions the moves were given.

#include <catch2/catch.hpp>

#include <array>
#include <cerrno>
#include <cstdint>
#include <vector>

#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/chip/chip402.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>

#include "integration.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using ecmxf::Cia402State;
using ecmxf::kAllSlaves;
using ecmxf::State;
using integ::Rig;
namespace cia402 = ecmxf::cia402;

TEST_CASE("CiA-402 chip engine: both drives enabled and walked back", "[402][chip402]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	// to OP with the outputs written directly (FIFO off): the engine
	// writes the controlword into the image the chip sends every cycle
	integ::initBus(d);
	struct EngineOff {
		ecmxf::Device &d;
		~EngineOff()
		{
			try {
				integ::engineOff(d);
			} catch (...) {
			}
		}
	} off{ d };
	d.pdo().fifoEnable(false);
	d.bus().stateSet(kAllSlaves, State::PreOp);
	d.bus().stateSet(kAllSlaves, State::SafeOp);
	// outputs: controlword 0, the CSP target (0x607A, bytes 2..5 of each
	// drive's 12) = where the drive stands (0x6064, bytes 3..6 of its 17
	// inputs), so that enabling moves nothing
	const std::vector<std::uint8_t> in = d.pdo().read();
	REQUIRE(in.size() == 35);
	std::vector<std::uint8_t> out(25, 0);
	for (std::size_t drive = 0; drive < 2; drive++)
		for (std::size_t b = 0; b < 4; b++)
			out[drive * 12 + 2 + b] = in[drive * 17 + 3 + b];
	d.pdo().write(out);
	d.bus().stateSet(kAllSlaves, State::Op);

	const ecmxf::Chip402Flags engine{ true, false, false };
	// controlword at byte 0 of each drive's outputs, statusword at byte 0
	// of its inputs (0x1600 / 0x1A00, manual 5.4.1)
	d.chip402().configure(0, ecmxf::Chip402Config{ 0, 0, 0, engine });
	d.chip402().configure(1, ecmxf::Chip402Config{ 1, 0, 0, engine });
	d.chip402().setControl(1, ecmxf::Chip402Control{ engine, 2, 1 });
	CHECK(d.chip402().control(0) == engine);
	CHECK(d.chip402().control(1) == engine);
	const ecmxf::Chip402State st = d.chip402().state(0);
	CHECK(st.code == 0x40);
	CHECK(st.state == Cia402State::SwitchOnDisabled);

	d.chip402().requestState(0, Cia402State::OperationEnabled);
	d.chip402().requestState(1, Cia402State::OperationEnabled);
	CHECK(d.chip402().awaitState(0, Cia402State::OperationEnabled, 2s) == Cia402State::OperationEnabled);
	CHECK(d.chip402().awaitState(1, Cia402State::OperationEnabled, 2s) == Cia402State::OperationEnabled);
	const ecmxf::Chip402State oe = d.chip402().state(1);
	CHECK(oe.code == 0x27);
	CHECK(d.chip402().statusword(0) == 0x1237);
	CHECK(d.chip402().statusword(1) == 0x1237);

	d.chip402().requestState(1, Cia402State::SwitchedOn);
	CHECK(d.chip402().awaitState(1, Cia402State::SwitchedOn, 2s) == Cia402State::SwitchedOn);
	CHECK(d.chip402().statusword(1) == 0x0233);
	d.chip402().requestState(0, Cia402State::SwitchOnDisabled);
	d.chip402().requestState(1, Cia402State::SwitchOnDisabled);
	CHECK(d.chip402().awaitState(0, Cia402State::SwitchOnDisabled, 2s) == Cia402State::SwitchOnDisabled);
	CHECK(d.chip402().awaitState(1, Cia402State::SwitchOnDisabled, 2s) == Cia402State::SwitchOnDisabled);

	// FAULT cannot be requested; motor 128 does not exist
	ecmxf::Error e = integ::thrown([&] { d.chip402().requestState(0, Cia402State::Fault); });
	CHECK(e.errnoValue() == EINVAL);
	e = integ::thrown([&] { (void)d.chip402().state(128); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Contains("motor 128 is out of range 0..127"));
}

TEST_CASE("CiA-402 host axis: enable, a PP move and a CSP move end where they were sent", "[402][motion]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	ecmxf::Master m(d);
	ecmxf::MasterConfig mc = integ::masterConfig(d);
	// every mode by PDO (controlword, target position and velocity, mode;
	// statusword, mode display, positions, following error)
	mc.pdoAssignments = { ecmxf::est584MotionPdos(0), ecmxf::est584MotionPdos(1) };
	m.bringUp(mc);
	CHECK(m.rxPdoSize() == 11 + 11 + 1);
	CHECK(m.txPdoSize() == 15 + 15 + 1);
	ecmxf::ProcessImage image(m.pdos());
	ecmxf::CyclicConfig cc = integ::cyclicConfig(r.u);
	ecmxf::Cyclic cyc(d, image, cc);
	cyc.start();

	ecmxf::Cia402Axis a0(d, image, 0, integ::axisConfig(r.u, { cia402::kModePp }));
	ecmxf::Cia402Axis a1(d, image, 1, integ::axisConfig(r.u, { cia402::kModeCsp }));
	CHECK(a0.modeByPdo());
	std::vector<ecmxf::Cia402Axis *> both{ &a0, &a1 };
	// one exchange first: the modes start from positions actually read
	ecmxf::runUntil(cyc, both, [&] { return cyc.lastResult().inputsUpdated; }, integ::patience(r.u, 5s), "the first inputs");
	a0.setMode(cia402::kModePp, d.link().now());
	a1.setMode(cia402::kModeCsp, d.link().now());
	ecmxf::runUntilDone(cyc, both, integ::patience(r.u, 5s), "the modes");
	CHECK(a0.modeDisplay() == 1);
	CHECK(a1.modeDisplay() == 8);
	for (auto *a : both)
		a->enable(d.link().now());
	ecmxf::runUntilDone(cyc, both, integ::patience(r.u, 5s), "OPERATION ENABLED");
	CHECK(a0.enabled());
	CHECK(a1.enabled());
	// PP at rest: 0x27 | voltage | remote | bit 10 target reached | bit 15
	// (= NOT bit 12, EST-584 manual 2.1.4)
	CHECK(a0.statusword() == 0x8637);

	// PP: an absolute move with the set-point handshake
	const std::int32_t p0 = a0.position();
	ecmxf::PpMove pp;
	pp.velocity = 200000;
	a0.moveTo(p0 + 20000, pp, d.link().now());
	std::vector<ecmxf::Cia402Axis *> one{ &a0 };
	ecmxf::runUntilDone(cyc, one, integ::patience(r.u, 10s), "the PP move");
	CHECK(a0.setPointAcknowledged());
	CHECK(a0.targetReached());
	CHECK(a0.position() == p0 + 20000);

	// CSP: a 1 s cosine trajectory over 2000 units (peak 3142 units/s),
	// then held until the drive is there. Slow on purpose: in the QEMU
	// guest a host cycle can take tens of ms while the bus runs at 1 ms,
	// and one step of the target must stay inside the EST-584's following
	// window (0x6065, 1000 by default)
	a1.startCsp(d.link().now());
	const std::array<std::int32_t, 1> from{ a1.position() };
	const std::array<std::int32_t, 1> to{ from[0] - 2000 };
	// (over a real transport stretched by patience(): cycles can take
	// hundreds of ms on a loaded host)
	const ecmxf::CspTrajectory traj(from, to, std::chrono::duration_cast<std::chrono::nanoseconds>(integ::patience(r.u, 1s)));
	std::vector<ecmxf::Cia402Axis *> csp{ &a1 };
	const auto t0 = d.link().now();
	ecmxf::runUntil(
		cyc, csp,
		[&] {
			const auto t = d.link().now() - t0 + 1ms;
			traj.apply(csp, t);
			return traj.finished(t) && a1.position() == to[0];
		},
		integ::patience(r.u, 10s), "the CSP move");
	CHECK(a1.position() == to[0]);
	CHECK(a1.cspTarget() == to[0]);
	CHECK_FALSE(a1.failed());

	// and both off again
	for (auto *a : both)
		a->disable(d.link().now());
	ecmxf::runUntilDone(cyc, both, integ::patience(r.u, 5s), "SWITCH ON DISABLED");
	CHECK(a0.state() == Cia402State::SwitchOnDisabled);
	CHECK(a1.state() == Cia402State::SwitchOnDisabled);
	cyc.stop();
}
