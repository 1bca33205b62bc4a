// SPDX-License-Identifier: MIT
//
// bench-cyclic: the cost of one application cycle of ecmxf::Cyclic through
// the in-process simulator transport.
//
// For 2, 16 and 128 slaves: bring the network to OP with raw commands
// (1 ms SYNC0 cycle, 1408-byte SPI data section at 96 Mbit/s), set up a ProcessImage and
// a Cyclic (1 ms period, bus cycle 1 ms, WKC read every cycle or every
// 10th), warm up for 200 cycles, then run 2000 cycles paced with
// waitNextCycle() in virtual time, in each mode of the engine and of
// CyclicConfig (see main()). Reported: cycles per second of wall time, thread CPU time per
// cycle, commands and SPI exchanges per cycle, allocations per cycle
// (global operator new is counted in this program), and failed cycles /
// WKC mismatches so that a broken run cannot look fast. The CPU time
// includes the simulated chip and slave models that answer the exchanges.
//
// Then the scope's cost (ecmxf::Recorder, Documentation/scope.rst) at 128
// slaves: 8 signals (target position, position actual value and statusword
// of the first and the last EST-584, the WKC and the RxFIFO level) sampled
// once per cycle, printed beside the cyclic path's CPU time per cycle: the
// cyclic loop alone, the same loop with Recorder::sample() after each
// cycle(), and sample() alone (many calls on the live image, the ring
// wrapping), with its allocations. The target is 2 % of the cyclic path.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include <time.h>

#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/scope/recorder.hpp>

#include "../common/alloc_counter.hpp"

namespace {

using namespace std::chrono_literals;

double threadCpuSeconds()
{
	timespec ts{};
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
	return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

ecmxf::Response cmd(ecmxf::Device &d, std::uint8_t code, std::uint8_t param = 0, std::uint8_t d0 = 0)
{
	ecmxf::Command c;
	c.code = code;
	c.param = param;
	c.data[0] = d0;
	return d.command(c);
}

std::uint16_t le16(const ecmxf::Response &r)
{
	return static_cast<std::uint16_t>(r.data.at(0) | r.data.at(1) << 8);
}

/// INIT_OP (SYNC0 1 ms), PRE-OP, SAFE-OP, OP; 1408-byte data section.
void bringUp(ecmxf::Device &d)
{
	ecmxf::Command init;
	init.code = 1; // ECAT_INIT_OP
	init.payload = { 0xFF, 0x81, 0x00, 0x03 };
	const std::uint32_t sync0 = 1'000'000;
	for (int i = 0; i < 4; i++)
		init.payload.push_back(static_cast<std::uint8_t>(sync0 >> (8 * i)));
	init.payload.resize(16, 0);
	(void)d.command(init);
	for (int st : { 2, 4, 8 })
		(void)cmd(d, 12, 0xFF, static_cast<std::uint8_t>(st)); // ECAT_STATE_SET
	ecmxf::Command reconfig;
	reconfig.code = 23; // SPI_RECONFIG_OP
	reconfig.len = 1408;
	(void)d.command(reconfig);
}

/// One SlavePdos per slave with its byte counts (ECAT_SLV_INFO_GET 8/9);
/// the bench touches the frames only as bytes.
std::vector<ecmxf::SlavePdos> sizes(ecmxf::Device &d);

/// The EST-584's default mapping (lib/sim/slaves/est584.cpp: 0x1600 and
/// 0x1A00) as entries, on each slave of its byte counts (12 / 17): what
/// the recorder's N:INDEX:SUB signals find.
void est584Entries(std::vector<ecmxf::SlavePdos> &pdos)
{
	struct E {
		std::uint16_t index;
		std::uint8_t bits;
	};
	static constexpr E kOut[] = { { 0x6040, 16 }, { 0x607A, 32 }, { 0x60B0, 32 }, { 0x60B8, 16 } };
	static constexpr E kIn[] = { { 0x6041, 16 }, { 0x6061, 8 },  { 0x6064, 32 },
				     { 0x60B9, 16 }, { 0x60BA, 32 }, { 0x60FD, 32 } };
	const auto fill = [](std::vector<ecmxf::PdoEntryInfo> &v, std::uint16_t pdo, const auto &table) {
		std::uint32_t bit = 0;
		for (const E &e : table) {
			ecmxf::PdoEntryInfo i;
			i.pdo = pdo;
			i.index = e.index;
			i.bitLength = e.bits;
			i.bitOffset = bit;
			bit += e.bits;
			v.push_back(i);
		}
	};
	for (ecmxf::SlavePdos &p : pdos)
		if (p.outputBytes == 12 && p.inputBytes == 17) {
			fill(p.outputs, 0x1600, kOut);
			fill(p.inputs, 0x1A00, kIn);
		}
}

std::vector<ecmxf::SlavePdos> sizes(ecmxf::Device &d)
{
	const unsigned n = cmd(d, 16).ret; // ECAT_SLV_CNT_GET
	std::vector<ecmxf::SlavePdos> v(n);
	for (unsigned i = 0; i < n; i++) {
		v[i].outputBytes = le16(cmd(d, 15, static_cast<std::uint8_t>(i), 8));
		v[i].inputBytes = le16(cmd(d, 15, static_cast<std::uint8_t>(i), 9));
	}
	return v;
}

struct Row {
	std::size_t slaves = 0, rxBytes = 0, txBytes = 0;
	double cyclesPerSecond = 0, cpuUsPerCycle = 0, commandsPerCycle = 0, exchangesPerCycle = 0;
	double allocsPerCycle = 0;
	std::uint64_t failed = 0, wkcBad = 0;
};

/// How a run sends its commands.
struct Mode {
	const char *name;
	bool pipeline;
	bool wkcNext;  ///< CyclicConfig::wkcAnswerNextCycle
	bool fifoNext; ///< CyclicConfig::fifoAnswerNextCycle
	unsigned wkcEvery;
};

Row run(const std::string &network, const Mode &mode)
{
	constexpr int kWarmup = 200;
	constexpr int kCycles = 2000;
	ecmxf::sim::ChipConfig chip;
	chip.spiClockHz = 96'000'000; // the chip's maximum
	auto t = std::make_unique<ecmxf::SimChannel>(network, chip);
	ecmxf::SimChannel &sim = *t;
	ecmxf::Device dev(std::move(t));
	dev.link().setPipelining(mode.pipeline);
	bringUp(dev);
	ecmxf::ProcessImage image(sizes(dev));
	ecmxf::CyclicConfig cfg;
	cfg.period = 1ms;
	cfg.busCycle = 1ms;
	cfg.wkcAnswerNextCycle = mode.wkcNext;
	cfg.fifoAnswerNextCycle = mode.fifoNext;
	cfg.wkcEvery = mode.wkcEvery;
	ecmxf::Cyclic cyc(dev, image, cfg);
	cyc.start();
	for (int i = 0; i < kWarmup; i++) {
		(void)cyc.cycle();
		(void)cyc.waitNextCycle();
	}

	const auto stats0 = cyc.stats();
	const auto exchanges0 = sim.chip().stats().exchanges;
	const auto allocs0 = ecmxf_test::allocations();
	const double cpu0 = threadCpuSeconds();
	const auto wall0 = std::chrono::steady_clock::now();
	for (int i = 0; i < kCycles; i++) {
		image.outputs()[0] = static_cast<std::uint8_t>(i);
		(void)cyc.cycle();
		(void)cyc.waitNextCycle();
	}
	const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
	const double cpu = threadCpuSeconds() - cpu0;
	const auto allocs = ecmxf_test::allocations() - allocs0;

	Row r;
	r.slaves = image.slaveCount();
	r.rxBytes = image.outputs().size();
	r.txBytes = image.inputs().size();
	r.cyclesPerSecond = kCycles / wall;
	r.cpuUsPerCycle = cpu / kCycles * 1e6;
	r.commandsPerCycle = static_cast<double>(cyc.stats().commands - stats0.commands) / kCycles;
	r.exchangesPerCycle = static_cast<double>(sim.chip().stats().exchanges - exchanges0) / kCycles;
	r.allocsPerCycle = static_cast<double>(allocs) / kCycles;
	r.failed = cyc.stats().failedCycles - stats0.failedCycles;
	r.wkcBad = cyc.stats().wkcMismatches - stats0.wkcMismatches;
	return r;
}

/// The recorder beside the cyclic path (file comment).
struct ScopeRow {
	std::size_t slaves = 0, signals = 0;
	double cyclicUs = 0, withSampleUs = 0, sampleUs = 0;
	std::uint64_t sampleAllocs = 0, failed = 0;
};

ScopeRow runScope(const std::string &network)
{
	constexpr int kWarmup = 200;
	constexpr int kCycles = 2000;
	constexpr int kSamples = 200'000;
	ecmxf::sim::ChipConfig chip;
	chip.spiClockHz = 96'000'000;
	auto t = std::make_unique<ecmxf::SimChannel>(network, chip);
	ecmxf::Device dev(std::move(t));
	dev.link().setPipelining(true);
	bringUp(dev);
	std::vector<ecmxf::SlavePdos> pdos = sizes(dev);
	est584Entries(pdos);
	ecmxf::ProcessImage image(pdos);
	ecmxf::CyclicConfig cfg;
	cfg.period = 1ms;
	cfg.busCycle = 1ms;
	ecmxf::Cyclic cyc(dev, image, cfg);
	ecmxf::Recorder rec(1000); // the ring wraps: the recorder's steady state
	for (const char *s : { "0:0x607A:0", "0:0x6064:0", "0:0x6041:0", "63:0x607A:0", "63:0x6064:0", "63:0x6041:0",
			       "wkc", "rx_fifo" })
		(void)rec.add(image, s);
	ecmxf::RecorderTrigger never; // a rising edge that never comes: armed, the ring wrapping
	never.edge = ecmxf::TriggerEdge::Rising;
	never.signal = "0:0x6064:0";
	never.level = 1e12;
	never.preSamples = 999;
	rec.arm(never);
	cyc.start();
	for (int i = 0; i < kWarmup; i++) {
		(void)rec.sample(dev.link().now(), cyc.cycle());
		(void)cyc.waitNextCycle();
	}
	const auto failed0 = cyc.stats().failedCycles;
	ScopeRow r;
	r.slaves = image.slaveCount();
	r.signals = rec.signals().size();
	double cpu0 = threadCpuSeconds();
	for (int i = 0; i < kCycles; i++) {
		(void)cyc.cycle();
		(void)cyc.waitNextCycle();
	}
	r.cyclicUs = (threadCpuSeconds() - cpu0) / kCycles * 1e6;
	cpu0 = threadCpuSeconds();
	for (int i = 0; i < kCycles; i++) {
		(void)rec.sample(dev.link().now(), cyc.cycle());
		(void)cyc.waitNextCycle();
	}
	r.withSampleUs = (threadCpuSeconds() - cpu0) / kCycles * 1e6;
	const ecmxf::CycleResult last = cyc.lastResult();
	const auto now = dev.link().now();
	const auto allocs0 = ecmxf_test::allocations();
	cpu0 = threadCpuSeconds();
	for (int i = 0; i < kSamples; i++)
		(void)rec.sample(now + std::chrono::microseconds(i), last);
	r.sampleUs = (threadCpuSeconds() - cpu0) / kSamples * 1e6;
	r.sampleAllocs = ecmxf_test::allocations() - allocs0;
	r.failed = cyc.stats().failedCycles - failed0 + (rec.state() != ecmxf::RecorderState::Armed);
	cyc.stop();
	return r;
}

} // namespace

int main()
{
	const std::string own = ECMXF_BENCH_OWN_NETWORK_DIR;
	const std::string bundled = ECMXF_BENCH_NETWORK_DIR;
	const std::string nets[] = { own + "/est584x2.net", own + "/slaves16.net", bundled + "/slaves128.net" };
	std::printf("bench-cyclic: ecmxf::Cyclic through the simulator transport, 1 ms cycle, 1408-byte SPI data\n"
		    "at 96 Mbit/s, "
		    "2000 cycles after 200 of warm-up; CPU = this thread (library + simulated chip and slaves)\n\n");
	std::printf("mode: 'off' = engine without pipelining (one command per two exchanges), 'on' = pipelined,\n"
		    "'next' = pipelined with CyclicConfig::wkcAnswerNextCycle (the WKC read's answer comes with the\n"
		    "next cycle's first exchange), 'fifo' = pipelined with CyclicConfig::fifoAnswerNextCycle (the FIFO\n"
		    "command's answer comes with the next cycle's exchange, which sends the next one), 'fifo+next' =\n"
		    "both; WKC = the read every this many cycles (0: never). All in this run, on the same machine:\n"
		    "'on'/'next' are before, 'fifo' after\n\n");
	static constexpr Mode kModes[] = {
		{ "off", false, false, false, 1 },	 { "on", true, false, false, 1 },
		{ "next", true, true, false, 1 },	 { "fifo", true, false, true, 1 },
		{ "fifo+next", true, true, true, 1 },	 { "on", true, false, false, 10 },
		{ "next", true, true, false, 10 },	 { "fifo", true, false, true, 10 },
		{ "fifo+next", true, true, true, 10 }, { "on", true, false, false, 0 },
		{ "fifo", true, false, true, 0 },
	};
	std::printf("%7s %10s %4s %7s %7s %10s %11s %9s %10s %11s %7s %8s\n", "slaves", "mode", "WKC", "out B", "in B",
		    "cycles/s", "CPU us/cyc", "cmds/cyc", "xfers/cyc", "allocs/cyc", "failed", "WKC bad");
	int rc = 0;
	for (const std::string &n : nets)
		for (const Mode &mode : kModes) {
			try {
				const Row r = run(n, mode);
				std::printf("%7zu %10s %4u %7zu %7zu %10.0f %11.2f %9.2f %10.2f %11.3f %7llu %8llu\n",
					    r.slaves, mode.name, mode.wkcEvery, r.rxBytes, r.txBytes, r.cyclesPerSecond,
					    r.cpuUsPerCycle, r.commandsPerCycle, r.exchangesPerCycle, r.allocsPerCycle,
					    static_cast<unsigned long long>(r.failed),
					    static_cast<unsigned long long>(r.wkcBad));
				if (r.failed || r.wkcBad || r.allocsPerCycle != 0.0)
					rc = 1;
			} catch (const std::exception &e) {
				std::fprintf(stderr, "bench-cyclic: %s: %s\n", n.c_str(), e.what());
				rc = 1;
			}
		}
	std::printf("\nscope: ecmxf::Recorder::sample() once per cycle, pipelined, WKC every cycle; 'cyclic' =\n"
		    "cycle() + waitNextCycle() alone, '+sample' = the same with sample() after each cycle(),\n"
		    "'sample' = sample() alone (%d calls, the 1000-sample ring wrapping); share = sample / cyclic\n"
		    "(target: at most 2 %%)\n\n",
		    200'000);
	std::printf("%7s %8s %11s %11s %11s %8s %11s %7s\n", "slaves", "signals", "cyclic us", "+sample us",
		    "sample us", "share", "allocs", "failed");
	try {
		const ScopeRow s = runScope(bundled + "/slaves128.net");
		const double share = s.sampleUs / s.cyclicUs * 100;
		std::printf("%7zu %8zu %11.2f %11.2f %11.4f %7.2f%% %11llu %7llu\n", s.slaves, s.signals, s.cyclicUs,
			    s.withSampleUs, s.sampleUs, share, static_cast<unsigned long long>(s.sampleAllocs),
			    static_cast<unsigned long long>(s.failed));
		if (s.sampleAllocs || s.failed || s.signals != 8)
			rc = 1;
		if (share > 2.0)
			std::printf("scope: the recorder costs more than 2 %% of the cyclic path\n");
	} catch (const std::exception &e) {
		std::fprintf(stderr, "bench-cyclic: scope: %s\n", e.what());
		rc = 1;
	}
	return rc;
}
