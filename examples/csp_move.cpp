// SPDX-License-Identifier: MIT
/*
 * Enable a CiA-402 drive and move it in CSP mode with ecmxf::Cyclic; the
 * drive is disabled again however the move ends (done, error, exception).
 *
 *   ecmxf-example-csp-move [URI]    (default "sim:"; slave 0 is an EST-584)
 */
#include <chrono>
#include <cstdio>
#include <exception>

#include <ecmxf/ecmxf.hpp>

using namespace std::chrono_literals;

int main(int argc, char **argv)
{
	if (argc > 2) {
		std::fprintf(stderr, "usage: %s [URI]\n", argv[0]);
		return 2;
	}
	try {
		auto dev = ecmxf::Device::open(argc > 1 ? argv[1] : "sim:");
		ecmxf::Master master(*dev); // the bus to OP, DC at 1 ms, PDOs for every mode on slave 0
		ecmxf::MasterConfig mc;
		mc.pdoAssignments = { ecmxf::est584MotionPdos(0) };
		master.bringUp(mc);

		ecmxf::ProcessImage image(master.pdos());
		ecmxf::Cyclic cyc(*dev, image, ecmxf::CyclicConfig::motion(1ms));
		ecmxf::Cia402AxisConfig ac;
		ac.modes = { ecmxf::cia402::kModeCsp };
		ecmxf::Cia402Axis axis(*dev, image, 0, ac);
		ecmxf::Cia402Axis *axes[] = { &axis };
		cyc.start(); // runUntil() runs the cycles: cycle(), axis.update(), waitNextCycle()

		axis.setMode(ecmxf::cia402::kModeCsp);
		(void)ecmxf::runUntilDone(cyc, axes, 1s, "mode CSP");
		struct DisableOnExit { // on every way out: back to SWITCH ON DISABLED
			ecmxf::Cyclic &cyc;
			ecmxf::Cia402Axis &axis;
			~DisableOnExit()
			{
				try {
					ecmxf::Cia402Axis *axes[] = { &axis };
					axis.disable();
					(void)ecmxf::runUntilDone(cyc, axes, 1s, "SWITCH ON DISABLED");
				} catch (const std::exception &e) {
					std::fprintf(stderr, "csp-move: disabling: %s\n", e.what());
				}
			}
		} const guard{ cyc, axis };
		axis.enable();
		(void)ecmxf::runUntilDone(cyc, axes, 2s, "OPERATION ENABLED");

		axis.startCsp(); // 50000 counts in 500 ms, one target per cycle
		const std::int32_t from[] = { axis.position() }, to[] = { from[0] + 50000 };
		const ecmxf::CspTrajectory traj(from, to, 500ms);
		const auto t0 = dev->link().now();
		(void)ecmxf::runUntil(cyc, axes, [&] {
			const auto t = dev->link().now() - t0;
			traj.apply(axes, t + 1ms); // the next cycle's target
			return traj.finished(t - 50ms); // and 50 ms to settle
		}, 2s, "the move");
		std::printf("slave 0: moved from %d to %d (target %d)\n", from[0], axis.position(), to[0]);
	} catch (const std::exception &e) {
		std::fprintf(stderr, "csp-move: %s\n", e.what());
		return 1;
	}
	return 0;
}
