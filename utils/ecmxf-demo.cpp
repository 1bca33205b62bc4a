// SPDX-License-Identifier: MIT
/*
 * ecmxf-demo - what the stack does, on the in-process simulator (the
 * default network: 2 x EST-584 stepper drive + 1 digital I/O terminal):
 *
 *   1. the bring-up to OP with ecmxf::Master, step by step
 *   2. the slaves found
 *   3. SDO: read, write and read back, and a real abort from the drive
 *   4. both drives enabled through CiA-402 (the state walk)
 *   5. a synchronized CSP move of both axes with live positions, and a
 *      running light on the I/O terminal's outputs
 *   6. a summary; exit code 1 if anything failed
 *
 * Paced in real time so a person can watch (~2 s); --fast runs at the
 * simulator's speed. --plot DIR records the move of each axis
 * (ecmxf::Recorder) and writes DIR/axisN.csv and DIR/axisN.svg
 * (ecmxf-demo-plot.cpp).
 */
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <ecmxf/model/cia402.hpp>
#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/bus/master.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/slaves.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/model/types_bus.hpp>
#include <ecmxf/scope/recorder.hpp>

#include "ecmxf-demo-plot.hpp"
#include "ecmxf-demo-sk.hpp"

namespace {

using namespace std::chrono_literals;
using std::chrono::nanoseconds;

const char *const kHelp = "Usage: ecmxf-demo [--fast] [--board ecm-xf|ecm-sk] [--plot DIR] [--help]\n"
			  "\n"
			  "A tour of the ecmxf stack on the in-process ECM-XF simulator (2 x EST-584\n"
			  "stepper drive + digital I/O): bring-up to OP, the slaves, SDO access with a\n"
			  "real abort, CiA-402 enable, a synchronized CSP move of both axes with live\n"
			  "positions, and a summary. Exit code 0 when everything worked.\n"
			  "\n"
			  "  --fast   do not pace the move in real time\n"
			  "  --board ecm-sk  the tour on the simulated ECM-SK starter kit\n"
			  "  --plot DIR  record the CSP move of each axis and write DIR/axis0.csv,\n"
			  "           DIR/axis0.svg, DIR/axis1.csv, DIR/axis1.svg (target position,\n"
			  "           position actual value, following error, statusword); DIR\n"
			  "           is made when missing (its parent must exist)\n"
			  "  --help   show this help\n";

constexpr std::uint32_t kEst584Vendor = 0x00000E5C;
constexpr std::uint32_t kEst584Product = 0x00000584;

void heading(int n, const char *title)
{
	std::printf("\n== %d. %s ==\n", n, title);
	std::fflush(stdout);
}

std::string hex(std::uint32_t v, int digits)
{
	char b[16];
	std::snprintf(b, sizeof b, "0x%0*X", digits, v);
	return b;
}

std::string stateText(std::optional<ecmxf::Cia402State> s)
{
	return s ? std::string(ecmxf::cia402StateName(*s)) : std::string("no CiA-402 state");
}

std::string lights(std::uint8_t v)
{
	std::string s;
	for (int i = 0; i < 8; i++)
		s += (v >> i) & 1 ? '*' : '.';
	return s;
}

struct Demo {
	bool fast = false;
	bool sk = false; // --board ecm-sk
	std::string plotDir; // --plot DIR; empty: no plots
	ecmxf::SimChannel *sim = nullptr;
	std::unique_ptr<ecmxf::Device> dev;
	unsigned sdoCount = 0;
	std::vector<std::string> failures;

	void fail(std::string what)
	{
		std::printf("   FAILED: %s\n", what.c_str());
		failures.push_back(std::move(what));
	}
};

int run(Demo &d)
{
	const auto wall0 = std::chrono::steady_clock::now();
	auto transport = std::make_unique<ecmxf::SimChannel>(); // the default network
	d.sim = transport.get();
	d.dev = std::make_unique<ecmxf::Device>(std::move(transport));
	ecmxf::Device &dev = *d.dev;
	std::printf("ecmxf-demo: the ECM-XF simulator, network \"%s\" (%zu slaves)\n",
		    d.sim->chip().network().name().c_str(), d.sim->chip().network().size());

	// ---------------------------------------------------------------- 1
	heading(1, "Bring-up: the network to OP (ecmxf::Master)");
	ecmxf::Master master(dev);
	{
		// a first scan to find the EST-584s, which then get the motion PDOs
		ecmxf::MasterConfig scan;
		scan.target = ecmxf::State::PreOp;
		scan.enableFifo = false;
		scan.readPdoMapping = false;
		master.bringUp(scan);
	}
	ecmxf::MasterConfig mc;
	mc.init.dc.sync0Ns = 1'000'000; // the EST-584 takes 250..4000 us
	mc.expectedSlaves = 3;
	for (const ecmxf::SlaveInfo &s : master.slaves())
		if (s.vendorId == kEst584Vendor && s.productCode == kEst584Product)
			mc.pdoAssignments.push_back(ecmxf::est584MotionPdos(s.position));
	mc.onStep = [&](std::string_view step) {
		std::printf("   %-20s t = %8.3f ms (bus time)\n", std::string(step).c_str(),
			    std::chrono::duration<double, std::milli>(d.sim->now()).count());
		std::fflush(stdout);
	};
	master.bringUp(mc);
	std::printf("   network in OP, DC SYNC0 1 ms, FIFO on: %u RxPDO / %u TxPDO bytes per cycle\n",
		    master.rxPdoSize(), master.txPdoSize());

	// ---------------------------------------------------------------- 2
	heading(2, "The slaves");
	std::printf("   %-3s %-28s %-21s %-7s %4s %4s\n", "pos", "name", "vendor:product", "state", "out", "in");
	for (const ecmxf::SlaveInfo &s : master.slaves()) {
		const ecmxf::SlaveInfo live = dev.bus().slaveInfo(s.position);
		std::printf("   %-3u %-28s %s:%s %-7s %4u %4u\n", unsigned{ s.position }, s.name.c_str(),
			    hex(s.vendorId, 8).c_str(), hex(s.productCode, 8).c_str(), ecmxf::stateName(live.state).c_str(),
			    unsigned{ live.outputBytes }, unsigned{ live.inputBytes });
		if (live.state != ecmxf::State::Op)
			d.fail("slave " + std::to_string(s.position) + " is not in OP");
	}

	// ---------------------------------------------------------------- 3
	heading(3, "SDO (CoE mailbox) on slave 0");
	const auto vendor = dev.sdo().read<std::uint32_t>(0, 0x1018, 1);
	const auto product = dev.sdo().read<std::uint32_t>(0, 0x1018, 2);
	const auto serial = dev.sdo().read<std::uint32_t>(0, 0x1018, 4);
	d.sdoCount += 3;
	std::printf("   read  0x1018 identity: vendor %s, product %s, serial %u\n", hex(vendor, 8).c_str(),
		    hex(product, 8).c_str(), serial);
	const auto pv0 = dev.sdo().read<std::uint32_t>(0, 0x6081, 0);
	dev.sdo().write<std::uint32_t>(0, 0x6081, 0, 120000);
	const auto pv1 = dev.sdo().read<std::uint32_t>(0, 0x6081, 0);
	d.sdoCount += 3;
	std::printf("   0x6081 profile velocity: read %u, wrote 120000, read back %u\n", pv0, pv1);
	if (pv1 != 120000)
		d.fail("0x6081 read back " + std::to_string(pv1));
	try {
		d.sdoCount++;
		(void)dev.sdo().read<std::uint32_t>(0, 0x2FFF, 0);
		d.fail("reading 0x2FFF did not abort");
	} catch (const ecmxf::SdoError &e) {
		std::printf("   read  0x2FFF (no such object): abort %s \"%s\"\n", hex(e.abortCode(), 8).c_str(),
			    std::string(ecmxf::sdoAbortText(e.abortCode())).c_str());
		std::printf("         the library says: %s\n", e.what());
		if (e.abortCode() != 0x06020000)
			d.fail("abort code " + hex(e.abortCode(), 8) + ", expected 0x06020000");
	}
	try {
		d.sdoCount++;
		dev.sdo().write<std::int32_t>(0, 0x6064, 0, 5);
		d.fail("writing 0x6064 did not abort");
	} catch (const ecmxf::SdoError &e) {
		std::printf("   write 0x6064 (read-only):   abort %s \"%s\"\n", hex(e.abortCode(), 8).c_str(),
			    std::string(ecmxf::sdoAbortText(e.abortCode())).c_str());
		if (e.abortCode() != 0x06010002)
			d.fail("abort code " + hex(e.abortCode(), 8) + ", expected 0x06010002");
	}

	// ---------------------------------------------------------------- 4
	heading(4, "CiA-402: enable both drives (cyclic exchange, 1 ms)");
	ecmxf::ProcessImage image(master.pdos());
	ecmxf::CyclicConfig cc;
	cc.period = 1ms;
	cc.busCycle = 1ms;
	cc.rxFill = 2; // outputs reach the drives ~2 bus cycles after cycle()
	ecmxf::Cyclic cyc(dev, image, cc);
	ecmxf::Cia402AxisConfig ac;
	ac.modes = { ecmxf::cia402::kModeCsp };
	ecmxf::Cia402Axis ax0(dev, image, 0, ac), ax1(dev, image, 1, ac);
	std::array<ecmxf::Cia402Axis *, 2> axes{ &ax0, &ax1 };
	auto lamp = image.output<std::uint8_t>(2, 0x7000, 1);
	cyc.start();
	int warm = 0;
	(void)ecmxf::runUntil(cyc, axes, [&] { return ++warm >= 10; }, 1s, "the first inputs");
	for (auto *a : axes)
		a->setMode(ecmxf::cia402::kModeCsp, d.sim->now());
	(void)ecmxf::runUntilDone(cyc, axes, 1s, "mode 8 (CSP)");
	std::printf("   mode of operation: 8 (cyclic synchronous position), by PDO\n");
	for (auto *a : axes)
		a->enable(d.sim->now());
	std::array<std::vector<std::string>, 2> walk;
	(void)ecmxf::runUntil(
		cyc, axes,
		[&] {
			for (std::size_t i = 0; i < 2; i++) {
				const std::string s = stateText(axes[i]->state());
				if (walk[i].empty() || walk[i].back() != s)
					walk[i].push_back(s);
			}
			return ax0.done() && ax1.done();
		},
		2s, "OPERATION ENABLED");
	for (std::size_t i = 0; i < 2; i++) {
		std::string line;
		for (const std::string &s : walk[i])
			line.append(line.empty() ? "" : " -> ").append(s);
		std::printf("   slave %zu: %s\n", i, line.c_str());
	}

	// ---------------------------------------------------------------- 5
	heading(5, "Synchronized CSP move: both axes, different distances, 1 s");
	for (auto *a : axes)
		a->startCsp(d.sim->now());
	const std::array<std::int32_t, 2> from{ ax0.position(), ax1.position() };
	const std::array<std::int32_t, 2> to{ from[0] + 200000, from[1] - 75000 }; // 4 and -1.5 revolutions
	const ecmxf::CspTrajectory traj(from, to, 1s);
	std::printf("   slave 0: %d -> %d, slave 1: %d -> %d (cosine profile, peak %.0f / %.0f units/s)\n",
		    from[0], to[0], from[1], to[1], traj.peakVelocity(0), traj.peakVelocity(1));
	std::printf("   %8s %10s %10s %10s %10s %9s  %s\n", "t [ms]", "target 0", "actual 0", "target 1", "actual 1",
		    "max |fe|", "I/O outputs");
	auto &dio = dynamic_cast<ecmxf::sim::DioModel &>(d.sim->chip().network().at(2));
	// --plot: each axis's target, actual position, following error and
	// statusword, every cycle of the move and the settling (~1100)
	std::array<std::unique_ptr<ecmxf::Recorder>, 2> recs;
	if (!d.plotDir.empty())
		for (std::size_t i = 0; i < 2; i++) {
			recs[i] = std::make_unique<ecmxf::Recorder>(4000);
			for (const char *e : { ":0x607A:0", ":0x6064:0", ":0x60F4:0", ":0x6041:0" })
				(void)recs[i]->add(image, std::to_string(i) + e);
			recs[i]->arm();
		}
	const nanoseconds m0 = d.sim->now();
	const auto wallMove = std::chrono::steady_clock::now();
	std::int32_t maxFe = 0;
	std::uint64_t rxEmpty = 0;
	nanoseconds nextRow = 0ms;
	const nanoseconds runFor = traj.duration() + 100ms; // and settle
	(void)ecmxf::runUntil(
		cyc, axes,
		[&] {
			const nanoseconds t = d.sim->now() - m0;
			if (cyc.lastResult().rxFifoCount == 0)
				rxEmpty++;
			for (auto &r : recs) // the targets this cycle sent, the inputs it brought
				if (r)
					(void)r->sample(d.sim->now(), cyc.lastResult());
			for (auto *a : axes)
				maxFe = std::max(maxFe, std::abs(a->followingError().value_or(0)));
			traj.apply(axes, t + 1ms); // the targets of the next cycle
			lamp.set(static_cast<std::uint8_t>(1u << ((t / 125ms) % 8)));
			if (t >= nextRow) {
				nextRow += 100ms;
				std::printf("   %8.0f %10d %10d %10d %10d %9d  %s\n",
					    std::chrono::duration<double, std::milli>(t).count(), ax0.cspTarget(),
					    ax0.position(), ax1.cspTarget(), ax1.position(), maxFe,
					    lights(dio.outputs()[0]).c_str());
				std::fflush(stdout);
				if (!d.fast)
					std::this_thread::sleep_until(wallMove + t);
			}
			return t >= runFor;
		},
		runFor + 1s, "the CSP move");
	lamp.set(0);
	for (auto &r : recs)
		if (r)
			r->finish();

	// ---------------------------------------------------------------- 6
	heading(6, "Summary");
	for (auto *a : axes)
		a->disable(d.sim->now());
	(void)ecmxf::runUntilDone(cyc, axes, 2s, "SWITCH ON DISABLED");
	const ecmxf::CyclicStats st = cyc.stats();
	const ecmxf::CycleResult &last = cyc.lastResult();
	cyc.stop();
	for (std::size_t i = 0; i < 2; i++) {
		const std::int32_t p = axes[i]->position();
		std::printf("   slave %zu final position %d, target %d: %s\n", i, p, to[i], p == to[i] ? "reached" : "MISSED");
		if (p != to[i])
			d.fail("slave " + std::to_string(i) + " ended at " + std::to_string(p));
	}
	std::printf("   drives disabled: %s, %s\n", stateText(ax0.state()).c_str(), stateText(ax1.state()).c_str());
	std::printf("   %llu cycles, %llu failed, %llu WKC errors (%llu WKC reads; chip's WKC error counter %u)\n",
		    static_cast<unsigned long long>(st.cycles), static_cast<unsigned long long>(st.failedCycles),
		    static_cast<unsigned long long>(st.wkcMismatches), static_cast<unsigned long long>(st.wkcReads),
		    unsigned{ last.wkcErrorCount });
	std::printf("   FIFO: %llu RxPDO frames pushed, %llu TxPDO popped, %llu RxFIFO overruns (refused), "
		    "%llu RxFIFO found empty, %llu TxFIFO overflows\n",
		    static_cast<unsigned long long>(st.framesPushed), static_cast<unsigned long long>(st.framesPopped),
		    static_cast<unsigned long long>(st.rxRefusals), static_cast<unsigned long long>(rxEmpty),
		    static_cast<unsigned long long>(st.txOverflows));
	std::printf("   max following error (0x60F4) during the move: %d units (the table's target - actual is\n"
		    "   the pipeline: a target reaches the drive a few cycles after it is written)\n",
		    maxFe);
	std::printf("   %u SDO transfers (2 of them aborted on purpose)\n", d.sdoCount);
	std::printf("   bus time %.1f ms, wall time %.1f ms\n",
		    std::chrono::duration<double, std::milli>(d.sim->now()).count(),
		    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count());
	if (st.failedCycles)
		d.fail(std::to_string(st.failedCycles) + " failed cycles");
	if (st.wkcMismatches)
		d.fail(std::to_string(st.wkcMismatches) + " WKC errors");
	if (st.rxRefusals || st.txOverflows)
		d.fail("FIFO overruns");
	if (!d.plotDir.empty()) {
		std::vector<DemoAxisPlot> plots;
		for (std::size_t i = 0; i < 2; i++)
			plots.push_back({ recs[i].get(), "ecmxf-demo: CSP move of slave " + std::to_string(i) + " (EST-584), " +
								 std::to_string(from[i]) + " to " + std::to_string(to[i]) });
		std::printf("   plots:");
		for (const std::string &f : writeDemoPlots(d.plotDir, plots))
			std::printf(" %s", f.c_str());
		std::printf("\n");
	}
	if (!d.failures.empty()) {
		std::printf("\necmxf-demo: %zu check(s) FAILED\n", d.failures.size());
		return 1;
	}
	std::printf("\necmxf-demo: all steps OK\n");
	return 0;
}

} // namespace

int main(int argc, char **argv)
{
	Demo d;
	for (int i = 1; i < argc; i++) {
		const std::string_view a = argv[i];
		if (a == "--fast") {
			d.fast = true;
		} else if (a == "--board" && i + 1 < argc) {
			const std::string_view board = argv[++i];
			if (board != "ecm-xf" && board != "ecm-sk") {
				std::fprintf(stderr, "ecmxf-demo: --board %s: ecm-xf or ecm-sk\n", argv[i]);
				return 2;
			}
			d.sk = board == "ecm-sk";
		} else if (a == "--plot" || a.starts_with("--plot=")) {
			if (a == "--plot" && i + 1 >= argc) {
				std::fprintf(stderr, "ecmxf-demo: --plot needs a directory\n");
				return 2;
			}
			d.plotDir = a == "--plot" ? argv[++i] : std::string(a.substr(7));
			if (d.plotDir.empty()) {
				std::fprintf(stderr, "ecmxf-demo: --plot: an empty directory name\n");
				return 2;
			}
		} else if (a == "-h" || a == "--help") {
			std::fputs(kHelp, stdout);
			return 0;
		} else {
			std::fprintf(stderr, "ecmxf-demo: unknown argument '%s' (try --help)\n", argv[i]);
			return 2;
		}
	}
	try {
		if (!d.plotDir.empty())
			demoPlotDir(d.plotDir); // before the tour: a bad DIR wastes none of it
		if (d.sk) // utils/ecmxf-demo-sk.cpp
			return ecmxfDemoSk(d.fast, d.plotDir);
		return run(d);
	} catch (const std::exception &e) {
		std::fflush(stdout);
		std::fprintf(stderr, "ecmxf-demo: %s\n", e.what());
		return 1;
	}
}
