// SPDX-License-Identifier: MIT
// ecmxf-guest-cyclic-bench: inside the QEMU guest, system calls and CPU
// time per cycle of the cyclic process-data exchange over three paths
// (Documentation/kernel-testing.rst, "Benchmarks"):
//
//   ecmxf-guest-cyclic-bench kernel <N> [/dev/ecmxfN]
//       1. rings: the library's Cyclic over /dev/ecmxf0 (the kernel's PDO
//          rings; the pump in the kernel's worker sends the commands);
//       2. ioctl: a loop of synchronous ECMXF_IOC_CMD ECAT_PDO_DATA_FIFO_OP
//          (one output frame pushed, the inputs popped) per cycle;
//       writes the figures to /tmp/ecmxf-cbench-kernel; then the
//       kernel's SPI exchanges per cycle over the rings, with no working
//       counter read and with one every cycle, the pump's answers fetched
//       within its cycle or by its next FIFO command
//       (ECMXF_RING_F_FIFO_NEXT, ECMXF_RING_F_WKC_NEXT)
//   ecmxf-guest-cyclic-bench spidev <N> <spidev URI>
//       first its system calls with each FIFO command's answer fetched
//       within its cycle (two exchanges a cycle); then
//       3. spidev: the library's Cyclic over SpidevChannel (the same
//          FIFO commands, from userspace, each cycle's answer fetched by
//          the next cycle's exchange: CyclicConfig::fifoAnswerNextCycle);
//          prints the ratios
//
// The process runs as an RT application would (ecmxf::applyRealtime():
// memory locked, SCHED_FIFO 49, below the kernel worker's 50), on CPU 0
// with the kernel's worker, the bridge (at SCHED_FIFO 48: the chip is no
// process that the guest's other tasks delay) and the interrupts of INT0
// and INT1 with their threads (/proc/irq/N/smp_affinity, as the PREEMPT_RT
// recipe of process-data.rst): no path pays TCG's cross-vCPU wake-ups.
// Each path:
// the bus up (2 x EST-584 + digital I/O, 1 ms SYNC0), 100
// cycles of warm-up, N cycles at a 1 ms period measured (this process's
// CPU time from getrusage(), the kernel worker's from its
// /proc/PID/schedstat), then 1400 cycles in a child process of which
// every 7th (200) is traced with ptrace(PTRACE_SYSCALL): every system
// call of those is counted, by name and by call site (the innermost two project functions
// on the caller's stack, bench-proc.hpp). The spidev run ends with the
// three paths' call-site tables side by side (the kernel run leaves its
// tables in /tmp/ecmxf-cbench-sites) and the late cycles of rings and
// spidev. Those are counted over a run of their own (from start() again,
// 100 cycles of warm-up, ECMXF_BENCH_LATE_N cycles, default 10 000: a
// thousand have too few to compare), by cause (woke a period or more
// late, or cycle() ran past the next boundary), each listed. Every line
// starts with "bench:". Timings under TCG are emulated: only ratios within
// one run mean something.

#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/engine_link.hpp>
#include <ecmxf/link/kernel_link.hpp>
#include <ecmxf/link/spidev_channel.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/bus/master.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/pdo/realtime.hpp>

#include <dirent.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/ptrace.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/user.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <sstream>
#include <functional>
#include <map>
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include <uapi/linux/ecmxf.h>

#include "bench-proc.hpp"

using namespace std::chrono_literals;

namespace {

constexpr const char *kResultFile = "/tmp/ecmxf-cbench-kernel";
/// the kernel paths' system calls by call site, for the side-by-side table
constexpr const char *kSitesFile = "/tmp/ecmxf-cbench-sites";
constexpr unsigned kWarmup = 100;
/// the cycles whose late ones are counted (ECMXF_BENCH_LATE_N)
constexpr unsigned kLateCycles = 10000;
constexpr unsigned kTraced = 200;
/// one traced cycle in this many (the others bring the exchange back to
/// its steady state; 7: every phase of a working counter read every 10)
constexpr unsigned kStride = 7;
/// the bench's SCHED_FIFO priority: below the ecmxf0 worker's 50
constexpr int kPriority = 49;
/// the bridge's (the chip's): below this process
constexpr int kBridgePriority = 48;

using ecmxf::ktest::cpuUs;
using ecmxf::ktest::taskCpuUs;
using ecmxf::ktest::workerPid;

struct Figures {
	double syscalls = -1; ///< per cycle
	double appCpuUs = 0;  ///< this process, per cycle
	double workerCpuUs = 0; ///< the kernel's worker, per cycle
	double wallUs = 0;    ///< per cycle
	long late = -1;       ///< late cycles (lateRun()), -1: not counted
	long lateWoke = 0;    ///< of those, the ones that woke a period or more late
	/// the traced cycles' system calls by call site
	ecmxf::ktest::SiteCounts sites;
};

/// @p once runs one cycle (exchange and wait).
Figures measure(const char *name, unsigned n, const std::function<void()> &once)
{
	for (unsigned i = 0; i < kWarmup; i++)
		once();
	const long wpid = workerPid();
	const double c0 = cpuUs(), w0 = taskCpuUs(wpid);
	const auto t0 = std::chrono::steady_clock::now();
	for (unsigned i = 0; i < n; i++)
		once();
	const auto t1 = std::chrono::steady_clock::now();
	Figures f;
	f.appCpuUs = (cpuUs() - c0) / n;
	f.workerCpuUs = (taskCpuUs(wpid) - w0) / n;
	f.wallUs = std::chrono::duration<double, std::micro>(t1 - t0).count() / n;
	std::string which;
	const long calls = ecmxf::ktest::countCycleSyscalls(once, kTraced, kStride, which, &f.sites);
	f.syscalls = calls < 0 ? -1 : static_cast<double>(calls) / kTraced;
	std::printf("bench: cyclic %s: system calls in %u traced cycles (x86-64):%s\n", name, kTraced,
		    which.c_str());
	for (const auto &[site, count] : f.sites)
		std::printf("bench: cyclic %s: %8.2f per cycle  %s\n", name, static_cast<double>(count) / kTraced,
			    site.c_str());
	std::printf("bench: cyclic %s: %.2f syscalls per cycle, CPU %.1f us per cycle in the application + %.1f us in "
		    "the kernel worker, %.0f us wall per cycle (%u cycles, 1 ms period)\n",
		    name, f.syscalls, f.appCpuUs, f.workerCpuUs, f.wallUs, n);
	return f;
}

/// One cycle of this process as the bench saw it.
struct CycleMark {
	double wakeUs; ///< cycle() began this long after its boundary
	double workUs; ///< cycle() took this long
	bool late;     ///< waitNextCycle() found the next boundary past
};

/// The late cycles of @p cyc over @p n cycles after the warm-up, from
/// start() again (no bench work between its cycles), by cause: woke a
/// period or more after its boundary (the process was not run: the same
/// for every path), or cycle() ran past the next boundary (the path's own
/// time). Prints the percentiles of both times and each late cycle.
void lateRun(ecmxf::Cyclic &cyc, ecmxf::Link &link, const char *name, unsigned n, Figures &f)
{
	cyc.stop();
	cyc.start();
	const auto us = [](std::chrono::nanoseconds d) { return static_cast<double>(d.count()) / 1000.0; };
	std::vector<CycleMark> marks;
	marks.reserve(kWarmup + n);
	for (unsigned i = 0; i < kWarmup + n; i++) {
		// the link's clock is the one Cyclic paces on
		const auto t0 = link.now();
		const std::uint64_t late0 = cyc.stats().lateCycles;
		(void)cyc.cycle();
		const auto t1 = link.now();
		marks.push_back({ us(t0 - cyc.boundary()), us(t1 - t0), false });
		(void)cyc.waitNextCycle();
		marks.back().late = cyc.stats().lateCycles != late0;
	}
	std::vector<double> wake, work;
	f.late = f.lateWoke = 0;
	for (std::size_t i = kWarmup; i < marks.size(); i++) {
		const CycleMark &m = marks[i];
		wake.push_back(m.wakeUs);
		work.push_back(m.workUs);
		if (!m.late)
			continue;
		f.late++;
		if (m.wakeUs >= 1000.0)
			f.lateWoke++;
		std::printf("bench: cyclic %s: late cycle %zu: woke %.0f us after its boundary, cycle() %.0f us\n", name,
			    i - kWarmup, m.wakeUs, m.workUs);
	}
	if (wake.empty())
		return;
	std::sort(wake.begin(), wake.end());
	std::sort(work.begin(), work.end());
	const auto pct = [](const std::vector<double> &v, double p) {
		return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
	};
	std::printf("bench: cyclic %s: wake-up after the boundary p50 %.0f p99 %.0f max %.0f us; cycle() p50 %.0f "
		    "p99 %.0f max %.0f us (%u cycles)\n",
		    name, pct(wake, 0.5), pct(wake, 0.99), wake.back(), pct(work, 0.5), pct(work, 0.99), work.back(), n);
	std::printf("bench: cyclic %s: %ld late of %u cycles: %ld woke a period or more late, %ld ran cycle() past the "
		    "next boundary\n",
		    name, f.late, n, f.lateWoke, f.late - f.lateWoke);
}

/// Routes every interrupt of the virtual controller's lines (INT0/INT1:
/// /proc/interrupts rows naming ecmxf) to CPU @p cpu, as the PREEMPT_RT
/// recipe does on a board (process-data.rst, "Real time"): their threads
/// (gpiolib's edge thread for a spidev application's line request) then
/// run beside the application. Returns the interrupts routed, as text.
std::string routeIrqs(unsigned cpu)
{
	std::ifstream f("/proc/interrupts");
	std::string routed;
	for (std::string line; std::getline(f, line);) {
		if (line.find("ecmxf") == std::string::npos)
			continue;
		const long irq = std::strtol(line.c_str(), nullptr, 10);
		if (irq <= 0)
			continue;
		std::ofstream a("/proc/irq/" + std::to_string(irq) + "/smp_affinity");
		a << std::hex << (1u << cpu) << '\n';
		a.flush();
		routed += " " + std::to_string(irq) + (a ? "" : " (refused)");
	}
	return routed.empty() ? " none" : routed;
}

/// The CPU each interrupt thread last ran on (/proc/PID/stat field 39) and
/// the CPUs it may run on.
std::string irqThreadCpus()
{
	std::string out;
	ecmxf::ktest::forEachTask([&](long pid, const std::string &comm) {
		if (comm.rfind("irq/", 0) != 0)
			return false;
		const std::string dir = "/proc/" + std::to_string(pid);
		std::ifstream f(dir + "/stat");
		std::string st;
		std::getline(f, st);
		const std::size_t b = st.rfind(')'); // after the comm, which may hold any byte
		if (b == std::string::npos)
			return false;
		std::istringstream rest(st.substr(b + 2));
		std::string field;
		for (int i = 3; i <= 39 && rest >> field; i++) {
		}
		std::ifstream ps(dir + "/status");
		std::string allowed;
		for (std::string l; std::getline(ps, l);)
			if (l.rfind("Cpus_allowed_list:", 0) == 0)
				allowed = l.substr(l.find_first_not_of(" \t", 18));
		out += " " + comm + " on CPU " + field + " (allowed " + allowed + ");";
		return false;
	});
	return out.empty() ? " none" : out;
}

/// The bus up on the default network, 1 ms SYNC0; the process image.
ecmxf::ProcessImage bringUp(ecmxf::Device &dev)
{
	ecmxf::Master m(dev);
	ecmxf::MasterConfig mc;
	mc.init.dc.sync0Ns = 1'000'000;
	m.bringUp(mc);
	return ecmxf::ProcessImage(m.pdos());
}

ecmxf::CyclicConfig config(bool fifoNext = true)
{
	ecmxf::CyclicConfig cc;
	cc.period = 1ms;
	cc.busCycle = 1ms;
	cc.rxFill = 4;
	cc.wkcEvery = 10;
	cc.commandTimeout = 1s;
	// the FIFO command's answer comes with the next cycle's exchange, one
	// exchange per cycle (spidev: the library's; the rings: the kernel
	// pump's, ECMXF_RING_F_FIFO_NEXT)
	cc.fifoAnswerNextCycle = fifoNext;
	return cc;
}

/// The library's Cyclic; one cycle = cycle() + waitNextCycle().
Figures cyclicPath(ecmxf::Device &dev, ecmxf::ProcessImage &image, const char *name, unsigned n, unsigned lateN,
		   bool wantRings, bool fifoNext = true)
{
	ecmxf::Cyclic cyc(dev, image, config(fifoNext));
	if (cyc.usesKernelRings() != wantRings) {
		std::printf("bench: FAIL %s: the Cyclic %s the kernel rings\n", name, wantRings ? "does not use" : "uses");
		std::exit(1);
	}
	// over spidev: its INT0 counters, from here
	auto *const el = dynamic_cast<ecmxf::EngineLink *>(&dev.link());
	auto *const sc = el ? dynamic_cast<ecmxf::SpidevChannel *>(&el->channel()) : nullptr;
	const ecmxf::SpidevStats st0 = sc ? sc->stats() : ecmxf::SpidevStats{};
	cyc.start();
	unsigned errors = 0;
	const ecmxf::LinkCounters k0 = dev.link().counters();
	Figures f = measure(name, n, [&] {
		errors += cyc.cycle().error != 0;
		(void)cyc.waitNextCycle();
	});
	const ecmxf::CyclicStats &s = cyc.stats();
	// what the link (the kernel's, for the rings: its pump's) exchanged
	// per cycle, in this process's cycles (not the traced child's)
	const ecmxf::LinkCounters k1 = dev.link().counters();
	const auto per = [&](std::uint64_t a, std::uint64_t b) {
		return s.cycles ? static_cast<double>(b - a) / static_cast<double>(s.cycles) : 0.0;
	};
	std::printf("bench: cyclic %s: per cycle %.2f SPI exchanges, %.2f polls, %.2f retries, %.2f not-ready answers "
		    "(the link's counters)\n",
		    name, per(k0.exchanges, k1.exchanges), per(k0.polls, k1.polls), per(k0.retries, k1.retries),
		    per(k0.badNotReady, k1.badNotReady));
	// over spidev: how INT0 was waited for
	if (sc) {
		const ecmxf::SpidevStats &st = sc->stats();
		const auto d = [](std::uint64_t a, std::uint64_t b) { return static_cast<unsigned long long>(b - a); };
		std::printf("bench: cyclic %s: INT0 in this process's cycles (warm-up and measured): %llu exchanges, "
			    "%llu ready edges, %llu level reads (%llu found ready with no edge), %llu timeouts\n",
			    name, d(st0.exchanges, st.exchanges), d(st0.int0Edges, st.int0Edges),
			    d(st0.int0LevelReads, st.int0LevelReads), d(st0.int0Unsignalled, st.int0Unsignalled),
			    d(st0.int0Timeouts, st.int0Timeouts));
	}
	std::printf("bench: cyclic %s: %llu cycles, %.2f commands per cycle (%s), %u failed, %llu late\n", name,
		    static_cast<unsigned long long>(s.cycles),
		    s.cycles ? static_cast<double>(s.commands) / static_cast<double>(s.cycles) : 0.0,
		    wantRings ? "the kernel pump's" : "from userspace", errors,
		    static_cast<unsigned long long>(s.lateCycles));
	if (lateN)
		lateRun(cyc, dev.link(), name, lateN, f);
	cyc.stop();
	return f;
}

/// One ECMXF_IOC_CMD ECAT_PDO_DATA_FIFO_OP per cycle (push one frame,
/// pop the inputs), then a sleep to the next 1 ms boundary.
Figures ioctlPath(ecmxf::Device &dev, ecmxf::ProcessImage &image, unsigned n)
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
	unsigned errors = 0;
	const Figures f = measure("ioctl (sync PDO_DATA_FIFO_OP)", n, [&] {
		ecmxf_cmd c = ecmxf::ktest::fifoOpCmd(out, in);
		if (::ioctl(fd, ECMXF_IOC_CMD, &c) < 0 || c.status)
			errors++;
		next.tv_nsec += 1'000'000;
		if (next.tv_nsec >= 1'000'000'000) {
			next.tv_nsec -= 1'000'000'000;
			next.tv_sec++;
		}
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
	});
	std::printf("bench: cyclic ioctl: %u failed commands\n", errors);
	dev.pdo().fifoEnable(false);
	return f;
}

/// The kernel's SPI exchanges per cycle over the rings: no working counter
/// read or one every cycle, the pump's answers fetched within its cycle or
/// by its next FIFO command (fifoAnswerNextCycle: ECMXF_RING_F_FIFO_NEXT,
/// wkcAnswerNextCycle: ECMXF_RING_F_WKC_NEXT).
void ringsExchanges(ecmxf::Device &dev, ecmxf::ProcessImage &image, unsigned n)
{
	struct Mode {
		unsigned wkcEvery;
		bool wkcNext, fifoNext;
		const char *name;
	};
	static constexpr Mode kModes[] = {
		{ 0, false, false, "no WKC read, FIFO answer within the pump's cycle" },
		{ 0, false, true, "no WKC read, FIFO answer by the next FIFO command (ECMXF_RING_F_FIFO_NEXT)" },
		{ 1, false, false, "WKC read every cycle, answers within the pump's cycle" },
		{ 1, true, false, "WKC read every cycle, its answer by the next FIFO command (ECMXF_RING_F_WKC_NEXT)" },
		{ 1, true, true, "WKC read every cycle, both answers by the next FIFO command (both flags)" },
	};
	for (const Mode &mode : kModes) {
		ecmxf::CyclicConfig cc = config();
		cc.wkcEvery = mode.wkcEvery;
		cc.wkcAnswerNextCycle = mode.wkcNext;
		cc.fifoAnswerNextCycle = mode.fifoNext;
		ecmxf::Cyclic cyc(dev, image, cc);
		cyc.start();
		const auto once = [&] {
			(void)cyc.cycle();
			(void)cyc.waitNextCycle();
		};
		for (unsigned i = 0; i < kWarmup; i++)
			once();
		const ecmxf::LinkCounters k0 = dev.link().counters();
		const ecmxf::CyclicStats s0 = cyc.stats();
		for (unsigned i = 0; i < n; i++)
			once();
		const ecmxf::LinkCounters k1 = dev.link().counters();
		const ecmxf::CyclicStats s1 = cyc.stats();
		const double cycles = static_cast<double>(s1.cycles - s0.cycles);
		const auto per = [&](std::uint64_t v) { return cycles > 0 ? static_cast<double>(v) / cycles : 0.0; };
		const std::uint64_t sent = k1.exchanges - k0.exchanges;
		const std::uint64_t cmds = s1.commands - s0.commands;
		// polls: packets sent again, to fetch an answer (a repeat runs as
		// INFO_UPDATE) or because the guest's chip had not answered yet
		// (the bridge is slower than a chip under TCG)
		std::printf("bench: cyclic rings, %s: %.2f SPI exchanges per cycle (the kernel's counters), %.2f of "
			    "them polls; %.2f pump commands per cycle, %.2f exchanges per command; %llu WKC reads, %llu "
			    "not the expected count, %llu failed cycles, %llu late\n",
			    mode.name, per(sent), per(k1.polls - k0.polls), per(cmds),
			    cmds ? static_cast<double>(sent) / static_cast<double>(cmds) : 0.0,
			    static_cast<unsigned long long>(s1.wkcReads - s0.wkcReads),
			    static_cast<unsigned long long>(s1.wkcMismatches - s0.wkcMismatches),
			    static_cast<unsigned long long>(s1.failedCycles - s0.failedCycles),
			    static_cast<unsigned long long>(s1.lateCycles - s0.lateCycles));
		cyc.stop();
	}
}

void save(const Figures &ring, const Figures &ioc)
{
	std::FILE *f = std::fopen(kResultFile, "w");
	if (!f)
		return;
	std::fprintf(f, "%f %f %f %f %f %f %ld %ld\n", ring.syscalls, ring.appCpuUs, ring.workerCpuUs, ioc.syscalls,
		     ioc.appCpuUs, ioc.workerCpuUs, ring.late, ring.lateWoke);
	std::fclose(f);
	std::FILE *t = std::fopen(kSitesFile, "w");
	if (!t)
		return;
	for (const auto &[site, count] : ring.sites)
		std::fprintf(t, "0\t%ld\t%s\n", count, site.c_str());
	for (const auto &[site, count] : ioc.sites)
		std::fprintf(t, "1\t%ld\t%s\n", count, site.c_str());
	std::fclose(t);
}

/// The kernel paths' call sites (save()) and @p sp's side by side, per
/// cycle: one row per system call and call site.
void printSites(const Figures &sp)
{
	std::map<std::string, std::array<long, 3>> rows;
	std::ifstream t(kSitesFile);
	for (std::string line; std::getline(t, line);) {
		const std::size_t a = line.find('\t'), b = line.find('\t', a + 1);
		if (a == std::string::npos || b == std::string::npos)
			continue;
		const unsigned col = line[0] == '1' ? 1 : 0;
		rows[line.substr(b + 1)][col] += std::strtol(line.c_str() + a + 1, nullptr, 10);
	}
	for (const auto &[site, count] : sp.sites)
		rows[site][2] += count;
	std::printf("bench: cyclic call sites, system calls per cycle (%u traced cycles each):\n", kTraced);
	std::printf("bench:    rings    ioctl   spidev  system call @ call site < its caller\n");
	std::array<long, 3> sum{};
	for (const auto &[site, c] : rows) {
		std::printf("bench: %8.2f %8.2f %8.2f  %s\n", static_cast<double>(c[0]) / kTraced,
			    static_cast<double>(c[1]) / kTraced, static_cast<double>(c[2]) / kTraced, site.c_str());
		for (std::size_t i = 0; i < 3; i++)
			sum[i] += c[i];
	}
	std::printf("bench: %8.2f %8.2f %8.2f  all\n", static_cast<double>(sum[0]) / kTraced,
		    static_cast<double>(sum[1]) / kTraced, static_cast<double>(sum[2]) / kTraced);
}

double ratio(double a, double b)
{
	return b > 0 ? a / b : 0;
}

} // namespace

int main(int argc, char **argv)
{
	try {
		if (argc < 4) {
			std::fprintf(stderr, "usage: ecmxf-guest-cyclic-bench kernel N DEV | spidev N URI\n");
			return 2;
		}
		const std::string_view mode = argv[1];
		const auto n = static_cast<unsigned>(std::strtoul(argv[2], nullptr, 10));
		// the late cycles: few in 1000, too few to compare two paths
		const char *ln = std::getenv("ECMXF_BENCH_LATE_N");
		const auto lateN = ln ? static_cast<unsigned>(std::strtoul(ln, nullptr, 10)) : kLateCycles;
		// what an RT application does (CyclicConfig::realtime): memory
		// locked, SCHED_FIFO just below the kernel's link worker (50),
		// for all three paths alike
		ecmxf::RealtimeConfig rt;
		rt.lockMemory = true;
		rt.priority = kPriority;
		rt.prefaultStack = 256 * 1024;
		ecmxf::applyRealtime(rt);
		std::printf("bench: cyclic: memory locked, SCHED_FIFO %d\n", kPriority);
		// TCG runs each vCPU as a host thread: a wake-up across vCPUs can
		// wait milliseconds for the host, a cost real hardware does not
		// have (and the bridge, the chip, is no process there). So this
		// process, the kernel's worker and the bridge share CPU 0, for
		// every path alike.
		const long bridge = ecmxf::ktest::pidOf("ecmxf-bridge");
		const long worker = workerPid();
		const bool pinned = !ecmxf::ktest::pinToCpu(0, 0) && bridge && !ecmxf::ktest::pinToCpu(bridge, 0) &&
				    (!worker || !ecmxf::ktest::pinToCpu(worker, 0));
		std::printf("bench: cyclic: %s\n", pinned ? "this process, the ecmxf0 worker and the bridge on CPU 0"
							  : "not pinned (sched_setaffinity failed, or no bridge found)");
		// the chip answers and raises INT0 in its own time, whatever
		// else the host runs: the bridge that stands in for it runs
		// at SCHED_FIFO, below this process and the worker (they
		// preempt it, it waits for nothing of theirs), above the
		// guest's CFS tasks, which otherwise delay an answer or a
		// ready edge by milliseconds (that cost only the path whose
		// application thread waits for the chip: spidev's)
		sched_param bsp{};
		bsp.sched_priority = kBridgePriority;
		const bool bridgeRt = bridge && !::sched_setscheduler(static_cast<pid_t>(bridge), SCHED_FIFO, &bsp);
		std::printf("bench: cyclic: the bridge %s SCHED_FIFO %d\n", bridgeRt ? "at" : "could not be set to",
			    kBridgePriority);
		auto dev = ecmxf::Device::open(argv[3]);
		// after the open: a spidev Device requests INT0/INT1 in it
		std::printf("bench: cyclic: interrupts of INT0/INT1 routed to CPU 0:%s\n", routeIrqs(0).c_str());
		ecmxf::ProcessImage image = bringUp(*dev);
		if (mode == "kernel") {
			const Figures ring = cyclicPath(*dev, image, "rings", n, lateN, true);
			const Figures ioc = ioctlPath(*dev, image, n);
			save(ring, ioc);
			std::printf("bench: cyclic: interrupt threads:%s\n", irqThreadCpus().c_str());
			ringsExchanges(*dev, image, n);
			std::printf("bench: cyclic rings/ioctl: syscalls per cycle %.2f, CPU per cycle %.2f (application "
				    "only), %.2f (with the kernel worker)\n",
				    ratio(ring.syscalls, ioc.syscalls), ratio(ring.appCpuUs, ioc.appCpuUs),
				    ratio(ring.appCpuUs + ring.workerCpuUs, ioc.appCpuUs + ioc.workerCpuUs));
			return 0;
		}
		if (mode == "spidev") {
			// the pipelined engine without fifoAnswerNextCycle: the FIFO
			// command's answer within its cycle, two exchanges a cycle
			// (system calls only)
			(void)cyclicPath(*dev, image, "spidev (answers within the cycle)", n, 0, false, false);
			const Figures sp = cyclicPath(*dev, image, "spidev (library, FIFO commands)", n, lateN, false);
			std::FILE *f = std::fopen(kResultFile, "r");
			Figures ring, ioc;
			if (!f || std::fscanf(f, "%lf %lf %lf %lf %lf %lf %ld %ld", &ring.syscalls, &ring.appCpuUs,
					      &ring.workerCpuUs, &ioc.syscalls, &ioc.appCpuUs, &ioc.workerCpuUs,
					      &ring.late, &ring.lateWoke) != 8) {
				std::printf("bench: no kernel figures in %s: no ratios\n", kResultFile);
				return 0;
			}
			std::fclose(f);
			printSites(sp);
			std::printf("bench: cyclic: interrupt threads:%s\n", irqThreadCpus().c_str());
			std::printf("bench: cyclic late cycles of %u: rings %ld (%ld woke a period or more late), spidev %ld "
				    "(%ld woke a period or more late)\n",
				    lateN, ring.late, ring.lateWoke, sp.late, sp.lateWoke);
			std::printf("bench: cyclic rings/spidev: syscalls per cycle %.2f, CPU per cycle %.2f (with the "
				    "kernel worker)\n",
				    ratio(ring.syscalls, sp.syscalls),
				    ratio(ring.appCpuUs + ring.workerCpuUs, sp.appCpuUs + sp.workerCpuUs));
			std::printf("bench: cyclic ioctl/spidev: syscalls per cycle %.2f, CPU per cycle %.2f (with the "
				    "kernel worker)\n",
				    ratio(ioc.syscalls, sp.syscalls),
				    ratio(ioc.appCpuUs + ioc.workerCpuUs, sp.appCpuUs + sp.workerCpuUs));
			return 0;
		}
		std::fprintf(stderr, "unknown mode %s\n", argv[1]);
		return 2;
	} catch (const std::exception &e) {
		std::printf("bench: FAIL exception: %s\n", e.what());
		return 1;
	}
}
