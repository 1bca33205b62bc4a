// SPDX-License-Identifier: MIT
// ecmxf-bridge: the guest-side half of the QEMU kernel tests
// (Documentation/kernel-testing.rst). Answers every transfer of the virtual
// SPI controller (tests/kernel/modules/ecmxf-vspi.c) from an in-process
// simulated chip, and drives the INT0/INT1 GPIO lines from the chip's lines.
//
//   ecmxf-bridge [network-file]      (no file: the default network)
//
// Runs until SIGTERM/SIGINT; then prints the chip's counters to stderr.

#include <ecmxf/sim.hpp>

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <exception>
#include <span>
#include <string>
#include <vector>

#include "modules/ecmxf-vspi.h"

namespace {

volatile std::sig_atomic_t gStop = 0;

void onSignal(int)
{
	gStop = 1;
}

std::uint32_t linesOf(ecmxf::sim::Chip &chip)
{
	std::uint32_t v = 0;
	if (chip.int0())
		v |= ECMXF_VSPI_LINE_INT0;
	if (chip.int1())
		v |= ECMXF_VSPI_LINE_INT1;
	return v;
}

[[noreturn]] void die(const char *what)
{
	std::fprintf(stderr, "ecmxf-bridge: %s: %s\n", what, std::strerror(errno));
	std::exit(1);
}

} // namespace

int main(int argc, char **argv)
{
	try {
		ecmxf::sim::ChipConfig cfg;
		cfg.timeMode = ecmxf::sim::TimeMode::Paced; // guest wall clock
		ecmxf::sim::Chip chip(argc > 1 ? std::string(argv[1]) : std::string(), cfg);

		struct sigaction sa {};
		sa.sa_handler = onSignal;
		sigaction(SIGTERM, &sa, nullptr);
		sigaction(SIGINT, &sa, nullptr);

		const int fd = ::open(ECMXF_VSPI_DEV, O_RDWR | O_CLOEXEC);
		if (fd < 0)
			die("open " ECMXF_VSPI_DEV);

		std::uint32_t lines = linesOf(chip);
		if (::ioctl(fd, ECMXF_VSPI_IOC_SET_LINES, &lines) < 0)
			die("ECMXF_VSPI_IOC_SET_LINES");
		std::fprintf(stderr, "ecmxf-bridge: ready (%zu-byte packets)\n", chip.packetSize());

		std::vector<std::uint8_t> mosi(ECMXF_VSPI_MAX_XFER), miso(ECMXF_VSPI_MAX_XFER);
		std::uint64_t transfers = 0;
		while (!gStop) {
			// while the chip is busy, look again soon: INT0 must go ready
			const bool busy = !chip.ready();
			timespec ts{ 0, busy ? 20'000L : 1'000'000L };
			pollfd p{ fd, POLLIN, 0 };
			const int n = ::ppoll(&p, 1, &ts, nullptr);
			if (n < 0 && errno != EINTR)
				die("poll");
			if (n > 0 && (p.revents & POLLIN)) {
				const ssize_t len = ::read(fd, mosi.data(), mosi.size());
				if (len < 0) {
					if (errno == EINTR || errno == EAGAIN)
						continue;
					die("read");
				}
				const auto ulen = static_cast<std::size_t>(len);
				chip.exchange(std::span<const std::uint8_t>(mosi.data(), ulen),
					      std::span<std::uint8_t>(miso.data(), ulen));
				transfers++;
				// the chip is busy now: INT0 drops before the answer
				// returns, and rises (an interrupt) when it is ready
				const std::uint32_t l = linesOf(chip);
				if (l != lines) {
					lines = l;
					if (::ioctl(fd, ECMXF_VSPI_IOC_SET_LINES, &lines) < 0)
						die("ECMXF_VSPI_IOC_SET_LINES");
				}
				if (::write(fd, miso.data(), ulen) != len && errno != ETIMEDOUT)
					die("write");
			}
			const std::uint32_t l = linesOf(chip);
			if (l != lines) {
				lines = l;
				if (::ioctl(fd, ECMXF_VSPI_IOC_SET_LINES, &lines) < 0)
					die("ECMXF_VSPI_IOC_SET_LINES");
			}
		}
		const auto &s = chip.stats();
		std::fprintf(stderr,
			     "ecmxf-bridge: %llu transfers; chip: %llu exchanges, %llu bad packets, %llu busy exchanges\n",
			     static_cast<unsigned long long>(transfers),
			     static_cast<unsigned long long>(s.exchanges),
			     static_cast<unsigned long long>(s.badPackets),
			     static_cast<unsigned long long>(s.busyExchanges));
		::close(fd);
		return 0;
	} catch (const std::exception &e) {
		std::fprintf(stderr, "ecmxf-bridge: %s\n", e.what());
		return 1;
	}
}
