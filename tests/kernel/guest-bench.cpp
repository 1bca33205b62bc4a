// SPDX-License-Identifier: MIT
// ecmxf-guest-bench: inside the QEMU guest, the synchronous round trip of
// one cheap, read-only immediate command (FW_VERSION_GET) through
// /dev/ecmxf0 and through spidev, on the same virtual controller and the
// same simulated chip (Documentation/kernel-testing.rst, "Benchmarks").
//
//   ecmxf-guest-bench kernel <N> [/dev/ecmxfN]
//       library Device over KernelTransport (Device::transact()), and the
//       bare ECMXF_IOC_CMD ioctl; writes the means to /tmp/ecmxf-bench-kernel
//   ecmxf-guest-bench spidev <N> <spidev URI>
//       library Device over SpidevTransport (INT0 by libgpiod), the same
//       Device::transact(); with /tmp/ecmxf-bench-kernel present, prints
//       the kernel/spidev ratios
//
// Every line starts with "bench:". Timings under QEMU TCG are emulated:
// only ratios within one run mean something. CPU time is this process's
// user + system time (getrusage): the driver's worker thread and the
// bridge process are not in it.

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/kernel_transport.hpp>
#include <ecmxf/spidev_transport.hpp>

#include <fcntl.h>
#include <sys/ioctl.h>
#include <sys/resource.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <string_view>

#include <uapi/linux/ecmxf.h>

namespace {

constexpr std::uint8_t kFwVersionGet = 56; // FW_VERSION_GET, immediate, read-only
constexpr std::uint8_t kFwVersion = 0x30;  // the simulated chip's (sim.hpp ChipConfig)
constexpr const char *kResultFile = "/tmp/ecmxf-bench-kernel";
// the time allowed per command: generous, the bench measures, it does not
// judge time limits
constexpr std::chrono::seconds kPatience{ 5 };

std::string gKernel;

double cpuUs()
{
	rusage ru{};
	getrusage(RUSAGE_SELF, &ru);
	const auto us = [](const timeval &t) {
		return static_cast<double>(t.tv_sec) * 1e6 + static_cast<double>(t.tv_usec);
	};
	return us(ru.ru_utime) + us(ru.ru_stime);
}

struct Result {
	double meanUs = 0;
	double cpuUs = 0;
};

/// Runs @p once @p n times (after 20 unmeasured warm-up rounds); @p once
/// returns false on a wrong answer, which ends the program.
template <typename F>
Result measure(const char *path, unsigned n, F &&once)
{
	for (unsigned i = 0; i < 20; i++)
		if (!once()) {
			std::printf("bench: FAIL %s: wrong answer in the warm-up\n", path);
			std::exit(1);
		}
	const double c0 = cpuUs();
	const auto t0 = std::chrono::steady_clock::now();
	// the first and the last tenth on their own: a path that slows down
	// as commands accumulate shows here
	const unsigned tenth = n / 10 ? n / 10 : 1;
	auto tFirst = t0, tLast = t0;
	for (unsigned i = 0; i < n; i++) {
		if (i == tenth)
			tFirst = std::chrono::steady_clock::now();
		if (i == n - tenth)
			tLast = std::chrono::steady_clock::now();
		if (!once()) {
			std::printf("bench: FAIL %s: wrong answer in round %u\n", path, i);
			std::exit(1);
		}
	}
	const auto t1 = std::chrono::steady_clock::now();
	const double c1 = cpuUs();
	Result r;
	r.meanUs = std::chrono::duration<double, std::micro>(t1 - t0).count() / n;
	r.cpuUs = (c1 - c0) / n;
	std::printf("bench: %s %s: %.1f us per command, %.1f us cpu (user+sys) per command (%u commands; first "
		    "tenth %.1f us, last tenth %.1f us per command)\n",
		    gKernel.c_str(), path, r.meanUs, r.cpuUs, n,
		    std::chrono::duration<double, std::micro>(tFirst - t0).count() / tenth,
		    std::chrono::duration<double, std::micro>(t1 - tLast).count() / tenth);
	std::fflush(stdout);
	return r;
}

/// Device::transact() of FW_VERSION_GET: allocation-free, the same call
/// over either transport.
Result libraryPath(ecmxf::Device &dev, const char *path, unsigned n)
{
	ecmxf::RawCommand c;
	c.code = kFwVersionGet;
	std::array<std::uint8_t, 1408> rx{};
	ecmxf::ResponseHeader h;
	return measure(path, n, [&] { return dev.transact(c, {}, rx, h) == 0 && h.ret == kFwVersion; });
}

int runKernel(unsigned n, const std::string &node)
{
	auto dev = ecmxf::Device::open(node);
	// a round trip is measured, not judged: the table's 100 ms was raced
	// by a loaded debug-kernel guest (a timed-out warm-up command)
	dev->setMinimumTimeout(kPatience);
	auto &k = dynamic_cast<ecmxf::KernelTransport &>(dev->transport());
	const ecmxf::KernelCounters c0 = k.counters();
	const Result lib = libraryPath(*dev, "/dev/ecmxf0 library (KernelTransport)", n);
	const ecmxf::KernelCounters c1 = k.counters();
	std::printf("bench: %s /dev/ecmxf0: %.2f SPI exchanges, %.2f INT0 interrupts per command\n", gKernel.c_str(),
		    static_cast<double>(c1.exchanges - c0.exchanges) / (n + 20),
		    static_cast<double>(c1.int0Irqs - c0.int0Irqs) / (n + 20));

	// the bare ioctl, as a C program would make it
	const int fd = k.fd();
	std::array<std::uint8_t, 1408> rx{};
	const Result raw = measure("/dev/ecmxf0 raw ECMXF_IOC_CMD", n, [&] {
		ecmxf_cmd cmd{};
		cmd.hdr.code = kFwVersionGet;
		cmd.rx_ptr = reinterpret_cast<std::uintptr_t>(rx.data());
		cmd.rx_size = static_cast<std::uint32_t>(rx.size());
		cmd.timeout_us = static_cast<std::uint32_t>(std::chrono::microseconds(kPatience).count());
		return ::ioctl(fd, ECMXF_IOC_CMD, &cmd) == 0 && cmd.status == 0 && cmd.rsp.ret == kFwVersion;
	});

	FILE *f = std::fopen(kResultFile, "w");
	if (!f) {
		std::printf("bench: FAIL cannot write %s: %s\n", kResultFile, std::strerror(errno));
		return 1;
	}
	std::fprintf(f, "%f %f %f %f\n", lib.meanUs, lib.cpuUs, raw.meanUs, raw.cpuUs);
	std::fclose(f);
	return 0;
}

int runSpidev(unsigned n, const std::string &uri)
{
	auto dev = ecmxf::Device::open(uri);
	dev->setMinimumTimeout(kPatience);
	auto &sp = dynamic_cast<ecmxf::SpidevTransport &>(dev->transport());
	const ecmxf::SpidevStats s0 = sp.stats();
	const Result lib = libraryPath(*dev, "spidev library (SpidevTransport, INT0 by libgpiod)", n);
	const ecmxf::SpidevStats s1 = sp.stats();
	std::printf("bench: %s spidev: %.2f SPI exchanges, %.2f INT0 edges, %llu INT0 timeouts per %u commands\n",
		    gKernel.c_str(), static_cast<double>(s1.exchanges - s0.exchanges) / (n + 20),
		    static_cast<double>(s1.int0Edges - s0.int0Edges) / (n + 20),
		    static_cast<unsigned long long>(s1.int0Timeouts - s0.int0Timeouts), n + 20);

	FILE *f = std::fopen(kResultFile, "r");
	double kLib = 0, kLibCpu = 0, kRaw = 0, kRawCpu = 0;
	if (!f || std::fscanf(f, "%lf %lf %lf %lf", &kLib, &kLibCpu, &kRaw, &kRawCpu) != 4) {
		std::printf("bench: FAIL no kernel figures in %s (run \"kernel\" first)\n", kResultFile);
		return 1;
	}
	std::fclose(f);
	std::printf("bench: kernel/spidev round-trip ratio: %.2f (library over /dev/ecmxf0 vs library over "
		    "spidev; < 1: the kernel path is cheaper)\n",
		    kLib / lib.meanUs);
	std::printf("bench: kernel/spidev round-trip ratio, raw ECMXF_IOC_CMD: %.2f\n", kRaw / lib.meanUs);
	std::printf("bench: kernel/spidev cpu ratio (this process only): %.2f\n",
		    lib.cpuUs > 0 ? kLibCpu / lib.cpuUs : 0.0);
	std::printf("bench: (QEMU TCG: the times above are emulated; only the ratios within this run mean "
		    "something)\n");
	return 0;
}

} // namespace

int main(int argc, char **argv)
{
	utsname u{};
	gKernel = ::uname(&u) == 0 ? u.release : "?";
	if (argc < 3) {
		std::fprintf(stderr, "usage: ecmxf-guest-bench kernel <N> [/dev/ecmxfN] | spidev <N> <URI>\n");
		return 2;
	}
	const std::string_view mode = argv[1];
	const auto n = static_cast<unsigned>(std::strtoul(argv[2], nullptr, 10));
	if (n == 0) {
		std::fprintf(stderr, "ecmxf-guest-bench: N must be positive\n");
		return 2;
	}
	try {
		if (mode == "kernel")
			return runKernel(n, argc > 3 ? argv[3] : "/dev/ecmxf0");
		if (mode == "spidev" && argc > 3)
			return runSpidev(n, argv[3]);
	} catch (const std::exception &e) {
		std::printf("bench: FAIL %s: %s\n", std::string(mode).c_str(), e.what());
		return 1;
	}
	std::fprintf(stderr, "usage: ecmxf-guest-bench kernel <N> [/dev/ecmxfN] | spidev <N> <URI>\n");
	return 2;
}
