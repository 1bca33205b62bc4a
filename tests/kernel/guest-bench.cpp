// SPDX-License-Identifier: MIT
// ecmxf-guest-bench: inside the QEMU guest, the synchronous round trip of
// one cheap, read-only immediate command (FW_VERSION_GET) through
// /dev/ecmxf0 and through spidev, on the same virtual controller and the
// same simulated chip (Documentation/kernel-testing.rst, "Benchmarks").
//
//   ecmxf-guest-bench <N> <blocks> <spi device> <gpiochip>
//   ecmxf-guest-bench kernel <N> [/dev/ecmxfN]
//
// The second form times only A and B (10 interleaved blocks), on the
// device given, without handing the SPI device over (figures for
// steps/check/72-integration.sh).
//
// Three paths, each N commands in <blocks> interleaved blocks (after 20
// unmeasured rounds whenever a path starts again):
//   A  library Device::transact() over KernelLink (/dev/ecmxf0)
//   B  the bare ECMXF_IOC_CMD ioctl on the same file
//   C  library Device::transact() over SpidevChannel (INT0 by libgpiod)
// and an SDO upload (2 bytes, 0x2001:00 of slave 0, the bus in PRE-OP) over
// both devices in the same blocks, N / 5 per block:
//   D  Sdo::read() over /dev/ecmxf0 (ECAT_SDO_REQ with its ECAT_SDO_GET
//      in one ECMXF_IOC_CMD, ECMXF_CMD_F_FETCH)
//   E  Sdo::read() over spidev (the library's engine pairs them)
//   F  the same upload as two bare ECMXF_IOC_CMD, ECAT_SDO_REQ and then
//      ECAT_SDO_GET (no fetch: what /dev/ecmxf0 cost before uAPI 3)
// The SPI device (e.g. spi0.0) is handed from ecmxf to spidev and back
// between the blocks through sysfs (unbind, driver_override, bind), in the
// order A B | C, C | B A, A B | C, ... so that every path sees the same
// host load; ecmxf is bound at the start and at the end. Each path's
// figure is the median of its block means, the ratios are ratios of
// medians (and the median of the per-block ratios), so a host that slows
// down for a while moves the spread, not the ratio.
//
// In the first block, every path (and Device::command(), and transact()
// after dataSize() and checkType(), over /dev/ecmxf0) also runs 50 commands in a child traced with
// ptrace(PTRACE_SYSCALL): the system calls per command, counted exactly
// (spidev's after its timed block: the child moves the chip's link state
// on without the parent's protocol engine, so that Device is not used
// again).
//
// Every line starts with "bench:". Timings under QEMU TCG are emulated:
// only ratios within one run mean something. CPU time is this process's
// user + system time (getrusage), and for /dev/ecmxf0 also the kernel
// worker's (/proc/PID/schedstat of the kthread ecmxf0); the bridge
// process (the chip) is in neither.

#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/engine_link.hpp>
#include <ecmxf/link/kernel_link.hpp>
#include <ecmxf/link/spidev_channel.hpp>

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/ptrace.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/user.h>
#include <sys/utsname.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <uapi/linux/ecmxf.h>

#include "bench-proc.hpp"

namespace {

constexpr std::uint8_t kFwVersionGet = 56; // FW_VERSION_GET, immediate, read-only
constexpr std::uint8_t kFwVersion = 0x30;  // the simulated chip's (sim.hpp ChipConfig)
constexpr unsigned kWarmup = 20;
constexpr unsigned kTraced = 50;
// every path's commands may take this long: the guest can stall beyond the
// 100 ms FW_VERSION_GET allows (a loaded host, ptrace; the debug kernel)
constexpr std::chrono::microseconds kTimeout{ 5'000'000 };

std::string gKernel;
bool gPinned = true; ///< the bench, the worker (CPU 0) and the bridge (CPU 1) are pinned
std::string gWhy; ///< what the last failed command returned

[[noreturn]] void die(const std::string &why)
{
	std::printf("bench: FAIL %s\n", why.c_str());
	std::exit(1);
}

using ecmxf::ktest::cpuUs;
using ecmxf::ktest::taskCpuUs;
using ecmxf::ktest::workerPid;

using ecmxf::ktest::countSyscalls;

/// One FW_VERSION_GET; false on a wrong answer.
using Once = std::function<bool()>;

void traced(const char *path, const Once &once)
{
	std::string which;
	int failed = 0;
	const long calls = countSyscalls(
		[&] {
			int f = 0;
			for (unsigned i = 0; i < kTraced; i++)
				if (!once())
					f++;
			return f;
		},
		which, failed);
	if (calls < 0) {
		std::printf("bench: %s %s: system calls per command not counted (no ptrace count here; child "
			    "status %d)\n",
			    gKernel.c_str(), path, failed);
		return;
	}
	std::printf("bench: %s %s: %.2f system calls per command (ptrace, %u commands:%s)%s\n", gKernel.c_str(),
		    path, static_cast<double>(calls) / kTraced, kTraced, which.c_str(),
		    failed ? (" - " + std::to_string(failed) + " FAILED").c_str() : "");
	std::fflush(stdout);
}

/// A path's blocks.
struct Path {
	const char *name;
	std::vector<double> blockUs; ///< mean per command of each block
	double cpuUs = 0;            ///< this process, summed over the blocks
	double workerUs = 0;         ///< the kernel worker, summed
	unsigned commands = 0;
};

void warmup(const char *name, const Once &once)
{
	for (unsigned i = 0; i < kWarmup; i++)
		if (!once())
			die(std::string(name) + ": wrong answer in the warm-up: " + gWhy);
}

void block(Path &p, unsigned n, const Once &once, long worker)
{
	const double c0 = cpuUs(), w0 = taskCpuUs(worker);
	const auto t0 = std::chrono::steady_clock::now();
	for (unsigned i = 0; i < n; i++)
		if (!once())
			die(std::string(p.name) + ": wrong answer in round " + std::to_string(p.commands + i) + ": " +
			    gWhy);
	const auto t1 = std::chrono::steady_clock::now();
	p.cpuUs += cpuUs() - c0;
	p.workerUs += taskCpuUs(worker) - w0;
	p.blockUs.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count() / n);
	p.commands += n;
}

double median(std::vector<double> v)
{
	if (v.empty())
		return 0;
	std::sort(v.begin(), v.end());
	const std::size_t m = v.size() / 2;
	return v.size() % 2 ? v[m] : (v[m - 1] + v[m]) / 2;
}

void report(const Path &p)
{
	const double med = median(p.blockUs);
	const auto [lo, hi] = std::minmax_element(p.blockUs.begin(), p.blockUs.end());
	std::printf("bench: %s %s: %.1f us per command (median of %zu blocks; blocks %.1f .. %.1f us), %.1f us cpu "
		    "(user+sys) per command",
		    gKernel.c_str(), p.name, med, p.blockUs.size(), *lo, *hi, p.cpuUs / p.commands);
	if (p.workerUs > 0)
		std::printf(" + %.1f us in the kernel worker", p.workerUs / p.commands);
	std::printf(" (%u commands)\n", p.commands);
}

/// Median over the blocks of @p a's block time / @p b's same block.
double pairedRatio(const Path &a, const Path &b)
{
	std::vector<double> r;
	for (std::size_t i = 0; i < a.blockUs.size() && i < b.blockUs.size(); i++)
		r.push_back(a.blockUs[i] / b.blockUs[i]);
	return median(r);
}

void ratio(const char *what, const Path &a, const Path &b, const char *note)
{
	std::vector<double> r;
	for (std::size_t i = 0; i < a.blockUs.size() && i < b.blockUs.size(); i++)
		r.push_back(a.blockUs[i] / b.blockUs[i]);
	std::sort(r.begin(), r.end());
	std::printf("bench: %s: %.2f (ratio of the medians; per block: median %.2f, %.2f .. %.2f)%s\n", what,
		    median(a.blockUs) / median(b.blockUs), pairedRatio(a, b), r.front(), r.back(), note);
}

// ---- handing the SPI device between ecmxf and spidev (sysfs)

void sysfsWrite(const std::string &file, const std::string &value)
{
	const int fd = ::open(file.c_str(), O_WRONLY | O_CLOEXEC);
	if (fd < 0)
		die("open " + file + ": " + std::strerror(errno));
	const ssize_t n = ::write(fd, value.data(), value.size());
	const int err = errno;
	::close(fd);
	if (n != static_cast<ssize_t>(value.size()))
		die("write \"" + value + "\" to " + file + ": " + std::strerror(err));
}

void waitNode(const std::string &node, bool present)
{
	struct stat sb {};
	for (int i = 0; i < 500; i++) {
		if ((::stat(node.c_str(), &sb) == 0) == present)
			return;
		::usleep(10'000);
	}
	die(node + (present ? " did not appear" : " did not go away"));
}

struct Spi {
	std::string dev;   ///< e.g. spi0.0
	std::string node;  ///< /dev/spidev0.0
	std::string uri;   ///< the spidev: URI
};

void toSpidev(const Spi &s)
{
	sysfsWrite("/sys/bus/spi/drivers/ecmxf/unbind", s.dev);
	waitNode("/dev/ecmxf0", false);
	sysfsWrite("/sys/bus/spi/devices/" + s.dev + "/driver_override", "spidev");
	sysfsWrite("/sys/bus/spi/drivers/spidev/bind", s.dev);
	waitNode(s.node, true);
}

void toEcmxf(const Spi &s)
{
	sysfsWrite("/sys/bus/spi/drivers/spidev/unbind", s.dev);
	waitNode(s.node, false);
	sysfsWrite("/sys/bus/spi/devices/" + s.dev + "/driver_override", "\n");
	sysfsWrite("/sys/bus/spi/drivers/ecmxf/bind", s.dev);
	waitNode("/dev/ecmxf0", true);
}

// ---- the paths

/// A command's outcome: @p err (0 or an errno value) and the return value.
bool check(int err, std::uint8_t ret)
{
	if (err == 0 && ret == kFwVersion)
		return true;
	gWhy = err ? std::strerror(err) : "FW_VERSION_GET returned " + std::to_string(ret);
	return false;
}

constexpr std::uint16_t kSdoValue = 50000; // EST-584 manual 3.5: 0x2001:00 pulses per revolution

/// One SDO upload of 0x2001:00 of slave 0; false on a wrong answer.
bool sdoUpload(ecmxf::Device &dev)
{
	try {
		const auto v = dev.sdo().read<std::uint16_t>(0, 0x2001, 0);
		if (v == kSdoValue)
			return true;
		gWhy = "SDO 0x2001:00 read " + std::to_string(v);
	} catch (const ecmxf::Error &e) {
		gWhy = e.what();
	}
	return false;
}

struct Kernel {
	std::unique_ptr<ecmxf::Device> dev;
	ecmxf::KernelLink *k = nullptr;
	ecmxf::RawCommand c;
	std::array<std::uint8_t, 1408> rx{};
	ecmxf::ResponseHeader h;
	long worker = 0;

	explicit Kernel(const std::string &node = "/dev/ecmxf0")
	{
		dev = ecmxf::Device::open(node);
		k = &dynamic_cast<ecmxf::KernelLink &>(dev->link());
		dev->setMinimumTimeout(kTimeout);
		c.code = kFwVersionGet;
		worker = workerPid();
		// the worker on the caller's CPU (run() pins the caller): see run()
		if (worker && ecmxf::ktest::pinToCpu(worker, 0))
			gPinned = false;
	}
	bool lib()
	{
		const int err = dev->transact(c, {}, rx, h);
		return check(err, h.ret);
	}
	bool command()
	{
		ecmxf::Command cmd;
		cmd.code = kFwVersionGet;
		try {
			return check(0, dev->command(cmd).ret);
		} catch (const ecmxf::Error &e) {
			gWhy = e.what();
			return false;
		}
	}
	bool sdo() { return sdoUpload(*dev); }
	/// The upload as two ioctls: ECAT_SDO_REQ, then ECAT_SDO_GET.
	bool sdoUnpaired()
	{
		// upload, slave 0, 0x2001:00, 2 bytes, the chip's SDO timeout
		const std::array<std::uint8_t, 12> req{ 1, 0, 0x01, 0x20, 0, 0, 2, 0, 0, 0, 0, 0 };
		ecmxf_cmd cmd{};
		cmd.hdr.code = ECMXF_CMD_ECAT_SDO_REQ;
		cmd.tx_ptr = reinterpret_cast<std::uintptr_t>(req.data());
		cmd.tx_len = static_cast<std::uint32_t>(req.size());
		cmd.timeout_us = static_cast<std::uint32_t>(kTimeout.count());
		if (::ioctl(k->fd(), ECMXF_IOC_CMD, &cmd) < 0 || cmd.status) {
			gWhy = std::string("ECAT_SDO_REQ: ") + std::strerror(cmd.status ? -cmd.status : errno);
			return false;
		}
		cmd = ecmxf_cmd{};
		cmd.hdr.code = ECMXF_CMD_ECAT_SDO_GET;
		cmd.rx_ptr = reinterpret_cast<std::uintptr_t>(rx.data());
		cmd.rx_size = static_cast<std::uint32_t>(rx.size());
		cmd.timeout_us = static_cast<std::uint32_t>(kTimeout.count());
		if (::ioctl(k->fd(), ECMXF_IOC_CMD, &cmd) < 0 || cmd.status || cmd.rx_len != 2) {
			gWhy = std::string("ECAT_SDO_GET: ") + std::strerror(cmd.status ? -cmd.status : errno);
			return false;
		}
		const unsigned v = rx[0] | rx[1] << 8;
		if (v == kSdoValue)
			return true;
		gWhy = "SDO 0x2001:00 read " + std::to_string(v);
		return false;
	}
	bool raw()
	{
		ecmxf_cmd cmd{};
		cmd.hdr.code = kFwVersionGet;
		cmd.rx_ptr = reinterpret_cast<std::uintptr_t>(rx.data());
		cmd.rx_size = static_cast<std::uint32_t>(rx.size());
		cmd.timeout_us = static_cast<std::uint32_t>(kTimeout.count());
		if (::ioctl(k->fd(), ECMXF_IOC_CMD, &cmd) < 0)
			return check(errno, 0);
		return check(-cmd.status, cmd.rsp.ret);
	}
};

struct Spidev {
	std::unique_ptr<ecmxf::Device> dev;
	ecmxf::SpidevChannel *sp = nullptr;
	ecmxf::RawCommand c;
	std::array<std::uint8_t, 1408> rx{};
	ecmxf::ResponseHeader h;

	explicit Spidev(const std::string &uri)
	{
		dev = ecmxf::Device::open(uri);
		sp = &dynamic_cast<ecmxf::SpidevChannel &>(dynamic_cast<ecmxf::EngineLink &>(dev->link()).channel());
		dev->setMinimumTimeout(kTimeout);
		c.code = kFwVersionGet;
	}
	bool lib()
	{
		const int err = dev->transact(c, {}, rx, h);
		return check(err, h.ret);
	}
	bool sdo() { return sdoUpload(*dev); }
};

int run(unsigned n, unsigned blocks, const Spi &spi)
{
	// TCG runs each of the guest's two vCPUs as a host thread: a wake-up
	// of a task on the other vCPU can wait milliseconds for the host to
	// schedule that thread, a cost real hardware does not have. So the
	// bench and the ecmxf0 worker share CPU 0 (the worker is woken where
	// the caller runs, as spidev's transfer runs in the caller), and the
	// bridge, the chip, runs on CPU 1 for both paths alike.
	const long bridgePid = ecmxf::ktest::pidOf("ecmxf-bridge");
	if (ecmxf::ktest::pinToCpu(0, 0) || !bridgePid || ecmxf::ktest::pinToCpu(bridgePid, 1))
		gPinned = false;
	const unsigned per = n / blocks ? n / blocks : 1;
	Path a{ "/dev/ecmxf0 library (KernelLink)", {}, 0, 0, 0 };
	Path b{ "/dev/ecmxf0 raw ECMXF_IOC_CMD", {}, 0, 0, 0 };
	Path c{ "spidev library (SpidevChannel, INT0 by libgpiod)", {}, 0, 0, 0 };
	Path d{ "/dev/ecmxf0 SDO upload (KernelLink, ECMXF_CMD_F_FETCH)", {}, 0, 0, 0 };
	Path e{ "spidev SDO upload (SpidevChannel)", {}, 0, 0, 0 };
	Path f{ "/dev/ecmxf0 SDO upload as SDO_REQ + SDO_GET (two ioctls, no fetch)", {}, 0, 0, 0 };
	const unsigned perSdo = std::max(per / 5, 5u);
	std::uint64_t kExchanges = 0, kInt0 = 0, kCommands = 0;
	std::uint64_t sExchanges = 0, sEdges = 0, sTimeouts = 0, sCommands = 0;
	std::uint64_t kSdoExchanges = 0, sSdoExchanges = 0, kUnpairedExchanges = 0;
	{
		// the mailboxes answer from PRE-OP on (the same chip for both)
		Kernel k;
		k.dev->bus().initNetwork();
		k.dev->bus().stateSet(ecmxf::kAllSlaves, ecmxf::State::PreOp);
	}

	const auto kernelPhase = [&](bool first, bool reversed) {
		Kernel k;
		const Once lib = [&] { return k.lib(); };
		const Once raw = [&] { return k.raw(); };
		if (first) {
			traced("/dev/ecmxf0 library Device::transact()", lib);
			traced("/dev/ecmxf0 library Device::command()", [&] { return k.command(); });
			// as the typed commands that check a size first (FoE, PDO
			// frames, mailbox reads): the format is kept, not asked
			traced("/dev/ecmxf0 library Device::dataSize() + checkType() + transact()", [&] {
				const ecmxf::KernelDevInfo &at = k.k->openInfo();
				if (k.dev->dataSize() != at.dataSize ||
				    static_cast<unsigned>(k.dev->checkType()) != at.checkType) {
					gWhy = "dataSize() " + std::to_string(k.dev->dataSize()) + ", checkType() " +
					       std::to_string(static_cast<unsigned>(k.dev->checkType()));
					return false;
				}
				return k.lib();
			});
			traced("/dev/ecmxf0 raw ECMXF_IOC_CMD", raw);
		}
		const ecmxf::LinkCounters c0 = k.k->counters();
		for (int i = 0; i < 2; i++) {
			const bool libNow = (i == 0) != reversed;
			Path &p = libNow ? a : b;
			const Once &once = libNow ? lib : raw;
			warmup(p.name, once);
			block(p, per, once, k.worker);
		}
		const ecmxf::LinkCounters c1 = k.k->counters();
		kExchanges += c1.exchanges - c0.exchanges;
		kInt0 += c1.int0Irqs - c0.int0Irqs;
		kCommands += 2 * (kWarmup + per);
		const Once sdo = [&] { return k.sdo(); };
		warmup(d.name, sdo);
		const ecmxf::LinkCounters c2 = k.k->counters();
		block(d, perSdo, sdo, k.worker);
		kSdoExchanges += k.k->counters().exchanges - c2.exchanges;
		const Once unpaired = [&] { return k.sdoUnpaired(); };
		warmup(f.name, unpaired);
		const ecmxf::LinkCounters c3 = k.k->counters();
		block(f, perSdo, unpaired, k.worker);
		kUnpairedExchanges += k.k->counters().exchanges - c3.exchanges;
	};
	const auto spidevPhase = [&](bool first) {
		Spidev s(spi.uri);
		const Once lib = [&] { return s.lib(); };
		const ecmxf::SpidevStats s0 = s.sp->stats();
		warmup(c.name, lib);
		block(c, per, lib, 0);
		const ecmxf::SpidevStats s1 = s.sp->stats();
		sExchanges += s1.exchanges - s0.exchanges;
		sEdges += s1.int0Edges - s0.int0Edges;
		sTimeouts += s1.int0Timeouts - s0.int0Timeouts;
		sCommands += kWarmup + per;
		const Once sdo = [&] { return s.sdo(); };
		warmup(e.name, sdo);
		const std::uint64_t x0 = s.sp->stats().exchanges;
		block(e, perSdo, sdo, 0);
		sSdoExchanges += s.sp->stats().exchanges - x0;
		// last: the traced child moves the chip's link state on without
		// this process's engine (s is not used again)
		if (first)
			traced("spidev library Device::transact()", lib);
	};

	// A B | C, C | B A, A B | C, ...: one hand-over per block
	for (unsigned i = 0; i < blocks; i++) {
		if (i % 2 == 0) {
			kernelPhase(i == 0, false);
			toSpidev(spi);
			spidevPhase(i == 0);
		} else {
			spidevPhase(false);
			toEcmxf(spi);
			kernelPhase(false, true);
		}
	}
	if (blocks % 2)
		toEcmxf(spi);

	std::printf("bench: %s round trip of FW_VERSION_GET, %u blocks of %u commands per path, interleaved "
		    "(A B | C, C | B A, ...)\n",
		    gKernel.c_str(), blocks, per);
	std::printf("bench: %s CPUs: %s\n", gKernel.c_str(),
		    gPinned ? "the bench and the ecmxf0 worker pinned to CPU 0, the bridge (the chip) to CPU 1"
			    : "not pinned (sched_setaffinity failed, or no bridge found): cross-vCPU wake-ups included");
	report(a);
	report(b);
	report(c);
	std::printf("bench: %s /dev/ecmxf0: %.2f SPI exchanges, %.2f INT0 interrupts per command\n", gKernel.c_str(),
		    static_cast<double>(kExchanges) / static_cast<double>(kCommands),
		    static_cast<double>(kInt0) / static_cast<double>(kCommands));
	std::printf("bench: %s spidev: %.2f SPI exchanges, %.2f INT0 edges, %llu INT0 timeouts per %llu commands\n",
		    gKernel.c_str(), static_cast<double>(sExchanges) / static_cast<double>(sCommands),
		    static_cast<double>(sEdges) / static_cast<double>(sCommands),
		    static_cast<unsigned long long>(sTimeouts), static_cast<unsigned long long>(sCommands));
	ratio("kernel/spidev round-trip ratio", a, c,
	      " (library over /dev/ecmxf0 vs library over spidev; < 1: the kernel path is cheaper)");
	ratio("kernel/spidev round-trip ratio, raw ECMXF_IOC_CMD", b, c, "");
	ratio("library/raw round-trip ratio over /dev/ecmxf0", a, b, "");
	report(d);
	report(e);
	report(f);
	std::printf("bench: %s SDO upload: %.2f SPI exchanges per upload over /dev/ecmxf0 (with the fetch), %.2f "
		    "over spidev, %.2f over /dev/ecmxf0 as two ioctls\n",
		    gKernel.c_str(), static_cast<double>(kSdoExchanges) / std::max(d.commands, 1u),
		    static_cast<double>(sSdoExchanges) / std::max(e.commands, 1u),
		    static_cast<double>(kUnpairedExchanges) / std::max(f.commands, 1u));
	ratio("kernel/spidev SDO upload round-trip ratio", d, e,
	      " (Sdo::read() over /dev/ecmxf0 vs over spidev; < 1: the kernel path is faster)");
	ratio("kernel SDO upload with the fetch / as two ioctls", d, f, " (< 1: the fetch saves time)");
	std::printf("bench: kernel/spidev cpu ratio (this process only): %.2f; with the kernel worker: %.2f\n",
		    c.cpuUs > 0 ? (a.cpuUs / a.commands) / (c.cpuUs / c.commands) : 0.0,
		    c.cpuUs > 0 ? ((a.cpuUs + a.workerUs) / a.commands) / (c.cpuUs / c.commands) : 0.0);
	std::printf("bench: (QEMU TCG: the times above are emulated; only the ratios within this run mean "
		    "something)\n");
	return 0;
}

/// A and B only, on @p node, 10 interleaved blocks.
int runKernelOnly(unsigned n, const std::string &node)
{
	const unsigned blocks = n >= 10 ? 10 : 1;
	const unsigned per = n / blocks;
	Path a{ "/dev/ecmxf0 library (KernelLink)", {}, 0, 0, 0 };
	Path b{ "/dev/ecmxf0 raw ECMXF_IOC_CMD", {}, 0, 0, 0 };
	Kernel k(node);
	const Once lib = [&] { return k.lib(); };
	const Once raw = [&] { return k.raw(); };
	warmup(a.name, lib);
	warmup(b.name, raw);
	for (unsigned i = 0; i < blocks; i++) {
		block(i % 2 ? b : a, per, i % 2 ? raw : lib, k.worker);
		block(i % 2 ? a : b, per, i % 2 ? lib : raw, k.worker);
	}
	report(a);
	report(b);
	ratio("library/raw round-trip ratio over /dev/ecmxf0", a, b, "");
	return 0;
}

} // namespace

int main(int argc, char **argv)
{
	utsname u{};
	gKernel = ::uname(&u) == 0 ? u.release : "?";
	try {
		if (argc >= 3 && std::string(argv[1]) == "kernel") {
			const auto n = static_cast<unsigned>(std::strtoul(argv[2], nullptr, 10));
			if (n == 0) {
				std::fprintf(stderr, "ecmxf-guest-bench: N must be positive\n");
				return 2;
			}
			return runKernelOnly(n, argc > 3 ? argv[3] : "/dev/ecmxf0");
		}
	} catch (const std::exception &e) {
		std::printf("bench: FAIL kernel: %s\n", e.what());
		return 1;
	}
	if (argc != 5) {
		std::fprintf(stderr, "usage: ecmxf-guest-bench <N> <blocks> <spi device> <gpiochip> | kernel <N> [/dev/ecmxfN]\n");
		return 2;
	}
	const auto n = static_cast<unsigned>(std::strtoul(argv[1], nullptr, 10));
	const auto blocks = static_cast<unsigned>(std::strtoul(argv[2], nullptr, 10));
	if (n == 0 || blocks == 0 || blocks > n) {
		std::fprintf(stderr, "ecmxf-guest-bench: N and blocks must be positive, blocks <= N\n");
		return 2;
	}
	Spi spi;
	spi.dev = argv[3];
	spi.node = "/dev/spidev" + spi.dev.substr(spi.dev.find_first_of("0123456789"));
	const std::string chip = argv[4];
	spi.uri = "spidev:" + spi.node + "?int0=" + chip + ":0&int1=" + chip + ":1&check=crc32";
	try {
		return run(n, blocks, spi);
	} catch (const std::exception &e) {
		std::printf("bench: FAIL %s\n", e.what());
		return 1;
	}
}
