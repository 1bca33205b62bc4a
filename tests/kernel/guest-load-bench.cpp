// SPDX-License-Identifier: MIT
// ecmxf-guest-load-bench: inside the QEMU guest, one cyclic path under
// load (Documentation/kernel-testing.rst, "Benchmarks", "Under load"):
//
//   ecmxf-guest-load-bench rings  HZ N K DEV        the library's Cyclic
//                                                   over the kernel's rings
//   ecmxf-guest-load-bench ioctl  HZ N K DEV        a loop of synchronous
//                                                   ECMXF_IOC_CMD FIFO_OPs
//   ecmxf-guest-load-bench spidev HZ N K URI        the library's Cyclic
//                                                   over spidev
//
// HZ is the bus rate in the chip's time; the bridge runs the chip's clock
// K times slower than the guest's (bridge --time-scale K, as the ratio
// runs of 66-rings.sh), so the application's period is K/HZ of guest
// time. make bench runs it with K 1 on one vCPU whose clock counts
// instructions (QEMU -icount shift=1: 2 ns each); on plain TCG, whose
// guest time is the host's, K 4.
//
// The step (tests/kernel/steps/bench/30-load.sh) runs stress-ng in the
// guest meanwhile (CPU, context switches, pipes, memory). Each path: the
// bus up (2 x EST-584 + digital I/O, SYNC0 = 1/HZ), 200 cycles of
// warm-up, then N cycles at K/HZ. The process runs as an RT application
// would (memory locked, SCHED_FIFO 49, below the kernel worker's 50), the
// bridge (the chip) at SCHED_FIFO 48; nothing is pinned: the load runs on
// every vCPU the guest has. Per cycle it records how long after its boundary the
// process woke (into a buffer sized up front), whether the cycle was late
// (the next boundary already past when it was done), and the output
// frames lost: refused by the RxFIFO, skipped by the pump, or in a failed
// command. It prints one line
//
//   bench: load PATH HZ Hz (K k) N cycles: late L, ... p99.9 P us, max M us, ... lost F
//
// and appends "PATH HZ N L P M F" to /tmp/ecmxf-load-results (the step
// prints the table). Timings under TCG are emulated: only the paths side
// by side in one run mean something.

#include <ecmxf/bus/master.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/kernel_link.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/pdo/realtime.hpp>

#include <sched.h>
#include <sys/ioctl.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include <uapi/linux/ecmxf.h>

#include "bench-proc.hpp"

namespace {

constexpr unsigned kWarmup = 200;
constexpr int kPriority = 49;       ///< below the ecmxf0 worker's 50
constexpr int kBridgePriority = 48; ///< the chip: below this process

struct Result {
	std::uint64_t late = 0;
	std::uint64_t lost = 0;    ///< the three below
	std::uint64_t skipped = 0; ///< skipped by the pump (a backlog)
	std::uint64_t refused = 0; ///< cycles whose frame the RxFIFO refused
	std::uint64_t failed = 0;  ///< cycles (commands) that failed
	std::vector<double> wakeUs; ///< sized before the run
};

double nowUs()
{
	timespec t{};
	clock_gettime(CLOCK_MONOTONIC, &t);
	return static_cast<double>(t.tv_sec) * 1e6 + static_cast<double>(t.tv_nsec) / 1e3;
}

ecmxf::ProcessImage bringUp(ecmxf::Device &dev, std::chrono::nanoseconds bus)
{
	ecmxf::Master m(dev);
	ecmxf::MasterConfig mc;
	mc.init.dc.sync0Ns = static_cast<std::uint32_t>(bus.count());
	m.bringUp(mc);
	return ecmxf::ProcessImage(m.pdos());
}

/// rings or spidev: the library's Cyclic
void cyclicRun(ecmxf::Device &dev, ecmxf::ProcessImage &image, std::chrono::nanoseconds period, unsigned n,
	       bool wantRings, Result &r)
{
	ecmxf::CyclicConfig cc;
	cc.period = period;
	cc.busCycle = std::chrono::nanoseconds(0); // the chip's clock is scaled: no estimate
	cc.rxFill = 4;
	cc.wkcEvery = 10;
	cc.commandTimeout = std::chrono::seconds(1);
	cc.fifoAnswerNextCycle = true;
	ecmxf::Cyclic cyc(dev, image, cc);
	if (cyc.usesKernelRings() != wantRings) {
		std::printf("bench: FAIL load: the Cyclic %s the kernel rings\n", wantRings ? "does not use" : "uses");
		std::exit(1);
	}
	cyc.start();
	for (unsigned i = 0; i < kWarmup; i++) {
		(void)cyc.cycle();
		(void)cyc.waitNextCycle();
	}
	const ecmxf::CyclicStats s0 = cyc.stats();
	for (unsigned i = 0; i < n; i++) {
		const auto woke = dev.link().now() - cyc.boundary();
		r.wakeUs.push_back(static_cast<double>(woke.count()) / 1000.0);
		(void)cyc.cycle();
		(void)cyc.waitNextCycle();
	}
	const ecmxf::CyclicStats &s1 = cyc.stats();
	r.late = s1.lateCycles - s0.lateCycles;
	r.skipped = s1.outputsSkipped - s0.outputsSkipped;
	r.refused = s1.rxRefusals - s0.rxRefusals;
	r.failed = s1.failedCycles - s0.failedCycles;
	r.lost = r.skipped + r.refused + r.failed;
	cyc.stop();
}

/// a loop of synchronous FIFO commands, one per period, clock_nanosleep
void ioctlRun(ecmxf::Device &dev, ecmxf::ProcessImage &image, std::chrono::nanoseconds period, unsigned n,
	      Result &r)
{
	auto &kt = dynamic_cast<ecmxf::KernelLink &>(dev.link());
	const int fd = kt.fd();
	dev.pdo().write(image.outputs());
	dev.pdo().fifoClear(ecmxf::FifoSelect::Both);
	dev.pdo().fifoEnable(true);
	std::vector<std::uint8_t> out(image.outputs().begin(), image.outputs().end());
	std::vector<std::uint8_t> in(1408);
	timespec next{};
	clock_gettime(CLOCK_MONOTONIC, &next);
	for (unsigned i = 0; i < kWarmup + n; i++) {
		const double boundary = static_cast<double>(next.tv_sec) * 1e6 + static_cast<double>(next.tv_nsec) / 1e3;
		if (i >= kWarmup)
			r.wakeUs.push_back(nowUs() - boundary);
		ecmxf_cmd c = ecmxf::ktest::fifoOpCmd(out, in);
		const bool failed = ::ioctl(fd, ECMXF_IOC_CMD, &c) < 0 || c.status;
		// return value bit 0 clear: the RxFIFO refused the frame
		if (i >= kWarmup && failed)
			r.failed++;
		else if (i >= kWarmup && !(c.rsp.ret & 1))
			r.refused++;
		r.lost = r.failed + r.refused;
		next.tv_nsec += period.count();
		while (next.tv_nsec >= 1'000'000'000) {
			next.tv_nsec -= 1'000'000'000;
			next.tv_sec++;
		}
		// late: the next boundary already past; then the first one still
		// ahead, as Cyclic::waitNextCycle() does
		bool late = false;
		for (;;) {
			const double due =
				static_cast<double>(next.tv_sec) * 1e6 + static_cast<double>(next.tv_nsec) / 1e3;
			if (nowUs() < due)
				break;
			late = true;
			next.tv_nsec += period.count();
			while (next.tv_nsec >= 1'000'000'000) {
				next.tv_nsec -= 1'000'000'000;
				next.tv_sec++;
			}
		}
		if (i >= kWarmup && late)
			r.late++;
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
	}
	dev.pdo().fifoEnable(false);
}

} // namespace

int main(int argc, char **argv)
{
	if (argc != 6) {
		std::fprintf(stderr, "usage: ecmxf-guest-load-bench rings|ioctl|spidev HZ N K DEV|URI\n");
		return 2;
	}
	const std::string_view path = argv[1];
	const unsigned long hz = std::strtoul(argv[2], nullptr, 10);
	const auto n = static_cast<unsigned>(std::strtoul(argv[3], nullptr, 10));
	const unsigned long scale = std::strtoul(argv[4], nullptr, 10);
	if ((path != "rings" && path != "ioctl" && path != "spidev") || hz < 100 || hz > 20000 || n == 0 ||
	    scale < 1 || scale > 1000) {
		std::fprintf(stderr, "ecmxf-guest-load-bench: bad arguments (path rings|ioctl|spidev, HZ 100..20000, "
				     "N > 0, K 1..1000)\n");
		return 2;
	}
	try {
		const auto bus = std::chrono::nanoseconds(1'000'000'000LL / static_cast<long long>(hz));
		const auto period = bus * static_cast<long long>(scale);
		ecmxf::RealtimeConfig rt;
		rt.lockMemory = true;
		rt.priority = kPriority;
		rt.prefaultStack = 256 * 1024;
		ecmxf::applyRealtime(rt);
		const long bridge = ecmxf::ktest::pidOf("ecmxf-bridge");
		sched_param bsp{};
		bsp.sched_priority = kBridgePriority;
		if (!bridge || ::sched_setscheduler(static_cast<pid_t>(bridge), SCHED_FIFO, &bsp))
			std::printf("bench: load: the bridge could not be set to SCHED_FIFO %d\n", kBridgePriority);
		auto dev = ecmxf::Device::open(argv[5]);
		dev->setMinimumTimeout(std::chrono::seconds(2));
		ecmxf::ProcessImage image = bringUp(*dev, bus);
		Result r;
		r.wakeUs.reserve(n);
		if (path == "ioctl")
			ioctlRun(*dev, image, period, n, r);
		else
			cyclicRun(*dev, image, period, n, path == "rings", r);
		std::sort(r.wakeUs.begin(), r.wakeUs.end());
		const double p999 =
			r.wakeUs[std::min(r.wakeUs.size() - 1, static_cast<std::size_t>(0.999 * static_cast<double>(n)))];
		const double worst = r.wakeUs.back();
		std::printf("bench: load %s %lu Hz (K %lu) %u cycles: late %llu, wake-up after the boundary p99.9 %.0f us, max "
			    "%.0f us, output frames lost %llu (skipped by the pump %llu, refused by a full RxFIFO %llu, "
			    "failed %llu)\n",
			    argv[1], hz, scale, n, static_cast<unsigned long long>(r.late), p999, worst,
			    static_cast<unsigned long long>(r.lost), static_cast<unsigned long long>(r.skipped),
			    static_cast<unsigned long long>(r.refused), static_cast<unsigned long long>(r.failed));
		if (std::FILE *f = std::fopen("/tmp/ecmxf-load-results", "a")) {
			std::fprintf(f, "%s %lu %u %llu %.0f %.0f %llu\n", argv[1], hz, n,
				     static_cast<unsigned long long>(r.late), p999, worst,
				     static_cast<unsigned long long>(r.lost));
			std::fclose(f);
		}
		return 0;
	} catch (const std::exception &e) {
		std::printf("bench: FAIL load %s: %s\n", argv[1], e.what());
		return 1;
	}
}
