// SPDX-License-Identifier: MIT
// ecmxf-bridge: the guest-side half of the QEMU kernel tests
// (Documentation/kernel-testing.rst). Answers every transfer of the virtual
// SPI controller (tests/kernel/modules/ecmxf-vspi.c) from an in-process
// simulated chip, and drives the INT0/INT1 GPIO lines from the chip's lines.
//
//   ecmxf-bridge [--time-scale K] [--lockstep] [network-file]   (no file: the default network)
//   ecmxf-bridge ctl COMMAND [ARG]   send one control command, print the reply
//
// Time: by default the chip runs in Paced mode (its clock is the guest's
// monotonic clock). With --time-scale K (1..1000) its clock is virtual and
// the bridge moves it to (guest time since start) / K: the bus runs K times
// slower than on hardware, so that a guest under TCG can keep up with a
// 1 kHz or 8 kHz bus (the cyclic tests scale the application's period and
// the kernel pump's timer by the same K: every ratio between bus,
// application and pump stays as on hardware). In this mode the SPI wire
// and processing times are not modelled (an exchange under TCG takes far
// longer than on hardware already): exchanges do not move the clock.
//
// --lockstep (with or without --time-scale; K = 1 without): the chip's
// lock-step bus (sim::ChipConfig::lockstep): with the PDO FIFO on, a bus
// cycle runs only when the RxFIFO holds its frame and the TxFIFO has room,
// so a slow guest can lose no frame, and any loss is a bug. The clock is
// virtual as with --time-scale, and besides following the guest's clock
// it jumps ahead to each bus cycle that can run (Chip::nextLockstepCycle())
// right after every transfer: the bus runs as fast as the driver brings
// frames and takes them away, not at the guest's pace. With the FIFO off
// (bring-up, SDOs, states) time runs as with --time-scale K.
//
// Runs until SIGTERM/SIGINT; then prints the chip's counters to stderr.
//
// Control channel (fault injection)
// ---------------------------------
// The bridge creates the FIFO /tmp/bridge.ctl and reads command lines from
// it, so steps can simply `echo "miso-bit-errors 3" >/tmp/bridge.ctl`. A
// line may end in " @/path/of/a/fifo": the bridge then writes its one-line
// reply there ("ok ..." or "error ..."). `ecmxf-bridge ctl ...` (the shell
// helper bridge_ctl of guest-init.sh) and the guest programs
// (tests/kernel/bridge-ctl.hpp) do that and wait for the reply; every
// command and reply is also logged to stderr (/tmp/bridge.log).
// Commands are applied before the next transfer is read: a command whose
// write returned is in force for every transfer the driver starts later.
//
//   mosi-bit-errors N   corrupt the check word of the next N command packets
//                       (the chip counts them: header crc_err_cnt, error
//                       status bit 6, and does not execute them)
//   miso-bit-errors N   corrupt the check word of the next N response packets
//   not-ready N         answer the next N exchanges "not ready" (0x87654321)
//   int0-stuck 0|1      INT0 never signals "ready"
//   async-stuck 0|1     the next async command never completes (busy stays
//                       set until ASYNCCMD_RESET or WARM_RESET)
//   link-lost 0|1       all slaves gone: WKC errors, EtherCAT state ERROR
//   slave-dropped POS   the slave at POS stops answering (-1: none)
//   sdo-abort CODE      the next SDO fails with this abort code (0: none)
//   silent 0|1          stop answering transfers: ecmxf-vspi fails each one
//                       after its timeout_ms module parameter (-ETIMEDOUT)
//   clear               all of the above off
//   state               reply with the fault plan and the chip's counters
//
// Counts are "the next N" and are replaced, not added to. sim::FaultPlan
// (include/ecmxf/sim/chip.hpp) documents the faults themselves.

#include <ecmxf/sim/chip.hpp>

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <exception>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "bridge-ctl.hpp"
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

/// The bridge's side of the control channel.
class Control
{
public:
	Control(ecmxf::sim::Chip &chip) : chip_(chip)
	{
		::unlink(ecmxf::ktest::kBridgeCtlPath);
		if (::mkfifo(ecmxf::ktest::kBridgeCtlPath, 0666) < 0)
			die("mkfifo /tmp/bridge.ctl");
		// read-write: a writer closing the FIFO is no end of file
		fd_ = ::open(ecmxf::ktest::kBridgeCtlPath, O_RDWR | O_NONBLOCK | O_CLOEXEC);
		if (fd_ < 0)
			die("open /tmp/bridge.ctl");
	}
	~Control()
	{
		::close(fd_);
		::unlink(ecmxf::ktest::kBridgeCtlPath);
	}
	Control(const Control &) = delete;
	Control &operator=(const Control &) = delete;

	[[nodiscard]] int fd() const { return fd_; }
	[[nodiscard]] bool silent() const { return silent_; }
	void countTransfer() { transfers_++; }
	[[nodiscard]] std::uint64_t transfers() const { return transfers_; }

	/// Reads and applies every complete line that is there.
	void drain()
	{
		char buf[1024];
		for (;;) {
			const ssize_t n = ::read(fd_, buf, sizeof(buf));
			if (n <= 0)
				break;
			pending_.append(buf, static_cast<std::size_t>(n));
		}
		std::size_t nl;
		while ((nl = pending_.find('\n')) != std::string::npos) {
			std::string line = pending_.substr(0, nl);
			pending_.erase(0, nl + 1);
			handle(line);
		}
	}

private:
	void handle(std::string line)
	{
		std::string replyPath;
		const auto at = line.rfind(" @");
		if (at != std::string::npos) {
			replyPath = line.substr(at + 2);
			line.erase(at);
		}
		const std::string reply = apply(line);
		std::fprintf(stderr, "ecmxf-bridge: ctl: %s -> %s\n", line.c_str(), reply.c_str());
		if (replyPath.empty())
			return;
		const int rfd = ::open(replyPath.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
		if (rfd < 0) {
			std::fprintf(stderr, "ecmxf-bridge: ctl: reply to %s: %s\n", replyPath.c_str(),
				     std::strerror(errno));
			return;
		}
		const std::string out = reply + "\n";
		if (::write(rfd, out.data(), out.size()) < 0)
			std::fprintf(stderr, "ecmxf-bridge: ctl: reply: %s\n", std::strerror(errno));
		::close(rfd);
	}

	static bool number(const std::string &s, long long &v)
	{
		if (s.empty())
			return false;
		char *end = nullptr;
		errno = 0;
		v = std::strtoll(s.c_str(), &end, 0);
		return errno == 0 && end && *end == '\0';
	}

	std::string apply(const std::string &line)
	{
		std::istringstream in(line);
		std::string cmd, arg, extra;
		in >> cmd >> arg >> extra;
		if (cmd.empty())
			return "error: empty command";
		if (!extra.empty())
			return "error " + cmd + ": too many arguments";
		ecmxf::sim::FaultPlan &f = chip_.faults();
		if (cmd == "state") {
			const auto &s = chip_.stats();
			char b[1024];
			std::snprintf(b, sizeof(b),
				      "ok state mosi-bit-errors=%u miso-bit-errors=%u not-ready=%u int0-stuck=%d async-stuck=%d link-lost=%d slave-dropped=%d sdo-abort=0x%x silent=%d transfers=%llu chip-exchanges=%llu chip-bad-packets=%llu chip-not-ready=%llu bus-cycles=%llu rx-underruns=%llu rx-refused=%llu tx-dropped=%llu wkc-errors=%llu bus-waits=%llu chip-time-us=%llu",
				      f.mosiBitErrors, f.misoBitErrors, f.notReady, f.int0StuckBusy ? 1 : 0,
				      f.asyncStuckBusy ? 1 : 0, f.linkLost ? 1 : 0, f.slaveDropped,
				      static_cast<unsigned>(f.forcedSdoAbort), silent_ ? 1 : 0,
				      static_cast<unsigned long long>(transfers_),
				      static_cast<unsigned long long>(s.exchanges),
				      static_cast<unsigned long long>(s.badPackets),
				      static_cast<unsigned long long>(s.notReady),
				      static_cast<unsigned long long>(s.busCycles),
				      static_cast<unsigned long long>(s.rxUnderruns),
				      static_cast<unsigned long long>(s.rxRefused),
				      static_cast<unsigned long long>(s.txDropped),
				      static_cast<unsigned long long>(s.wkcErrors),
				      static_cast<unsigned long long>(s.busWaits),
				      static_cast<unsigned long long>(chip_.now().count() / 1000));
			return b;
		}
		if (cmd == "clear") {
			if (!arg.empty())
				return "error clear: no argument expected";
			f = ecmxf::sim::FaultPlan{};
			silent_ = false;
			return "ok clear";
		}
		long long v = 0;
		if (!number(arg, v))
			return "error " + cmd + ": a number is needed";
		const bool flag = v == 0 || v == 1;
		const std::string done = "ok " + cmd + " " + arg;
		if (cmd == "mosi-bit-errors" && v >= 0 && v <= 1000000) {
			f.mosiBitErrors = static_cast<unsigned>(v);
		} else if (cmd == "miso-bit-errors" && v >= 0 && v <= 1000000) {
			f.misoBitErrors = static_cast<unsigned>(v);
		} else if (cmd == "not-ready" && v >= 0 && v <= 1000000) {
			f.notReady = static_cast<unsigned>(v);
		} else if (cmd == "int0-stuck" && flag) {
			f.int0StuckBusy = v == 1;
		} else if (cmd == "async-stuck" && flag) {
			f.asyncStuckBusy = v == 1;
		} else if (cmd == "link-lost" && flag) {
			f.linkLost = v == 1;
		} else if (cmd == "slave-dropped" && v >= -1 && v <= 65535) {
			f.slaveDropped = static_cast<int>(v);
		} else if (cmd == "sdo-abort" && v >= 0 && v <= 0xFFFFFFFFLL) {
			f.forcedSdoAbort = static_cast<std::uint32_t>(v);
		} else if (cmd == "silent" && flag) {
			silent_ = v == 1;
		} else {
			return "error " + cmd + " " + arg + ": unknown command or value out of range";
		}
		return done;
	}

	ecmxf::sim::Chip &chip_;
	int fd_ = -1;
	std::string pending_;
	bool silent_ = false;
	std::uint64_t transfers_ = 0;
};

int ctlClient(int argc, char **argv)
{
	std::string cmd;
	for (int i = 2; i < argc; i++) {
		if (!cmd.empty())
			cmd += ' ';
		cmd += argv[i];
	}
	std::string reply;
	const bool ok = ecmxf::ktest::bridgeCtl(cmd, reply);
	std::printf("%s\n", reply.c_str());
	return ok ? 0 : 1;
}

} // namespace

int main(int argc, char **argv)
{
	if (argc > 1 && std::strcmp(argv[1], "ctl") == 0)
		return ctlClient(argc, argv);
	try {
		long scale = 0;
		bool lockstep = false;
		int arg = 1;
		for (;;) {
			if (argc > arg + 1 && std::strcmp(argv[arg], "--time-scale") == 0) {
				char *end = nullptr;
				scale = std::strtol(argv[arg + 1], &end, 10);
				if (!end || *end || scale < 1 || scale > 1000) {
					std::fprintf(stderr, "ecmxf-bridge: --time-scale wants 1..1000\n");
					return 2;
				}
				arg += 2;
			} else if (argc > arg && std::strcmp(argv[arg], "--lockstep") == 0) {
				lockstep = true;
				arg++;
			} else {
				break;
			}
		}
		if (lockstep && !scale)
			scale = 1;
		ecmxf::sim::ChipConfig cfg;
		cfg.lockstep = lockstep;
		if (scale) {
			// virtual time, moved by the loop below; exchanges cost none
			cfg.timeMode = ecmxf::sim::TimeMode::Virtual;
			cfg.processingTime = std::chrono::nanoseconds(0);
			cfg.spiClockHz = 4'000'000'000u;
		} else {
			cfg.timeMode = ecmxf::sim::TimeMode::Paced; // guest wall clock
		}
		ecmxf::sim::Chip chip(argc > arg ? std::string(argv[arg]) : std::string(), cfg);
		timespec t0{};
		clock_gettime(CLOCK_MONOTONIC, &t0);
		const std::chrono::nanoseconds v0 = chip.now();
		// scaled mode: the chip's clock follows the guest's, K times slower
		auto follow = [&] {
			if (!scale)
				return;
			timespec t{};
			clock_gettime(CLOCK_MONOTONIC, &t);
			const std::int64_t wall = (t.tv_sec - t0.tv_sec) * 1'000'000'000LL + (t.tv_nsec - t0.tv_nsec);
			const std::chrono::nanoseconds target = v0 + std::chrono::nanoseconds(wall / scale);
			if (target > chip.now())
				chip.advance(target - chip.now());
		};

		// lock-step: every bus cycle that can run, now (each takes its
		// RxPDO frame, so this ends when the frames do)
		auto runBus = [&] {
			if (!lockstep)
				return;
			for (;;) {
				const std::chrono::nanoseconds due = chip.nextLockstepCycle();
				if (due == std::chrono::nanoseconds::max())
					return;
				const std::chrono::nanoseconds now = chip.now();
				chip.advance(due > now ? due - now : std::chrono::nanoseconds(1));
			}
		};

		struct sigaction sa {};
		sa.sa_handler = onSignal;
		sigaction(SIGTERM, &sa, nullptr);
		sigaction(SIGINT, &sa, nullptr);

		const int fd = ::open(ECMXF_VSPI_DEV, O_RDWR | O_CLOEXEC);
		if (fd < 0)
			die("open " ECMXF_VSPI_DEV);
		Control ctl(chip);

		std::uint32_t lines = linesOf(chip);
		if (::ioctl(fd, ECMXF_VSPI_IOC_SET_LINES, &lines) < 0)
			die("ECMXF_VSPI_IOC_SET_LINES");
		std::fprintf(stderr, "ecmxf-bridge: ready (%zu-byte packets, control FIFO %s, time %s%ld%s)\n",
			     chip.packetSize(), ecmxf::ktest::kBridgeCtlPath, scale ? "virtual, scale 1/" : "paced",
			     scale ? scale : 1L, lockstep ? ", lock-step bus" : "");

		std::vector<std::uint8_t> mosi(ECMXF_VSPI_MAX_XFER), miso(ECMXF_VSPI_MAX_XFER);
		while (!gStop) {
			// while the chip is busy, look again soon: INT0 must go ready
			const bool busy = !chip.ready();
			timespec ts{ 0, busy ? 20'000L : 1'000'000L };
			// silent: leave the transfers unread, ecmxf-vspi times them out
			pollfd p[2] = { { ctl.fd(), POLLIN, 0 }, { fd, POLLIN, 0 } };
			const nfds_t np = ctl.silent() ? 1 : 2;
			const int n = ::ppoll(p, np, &ts, nullptr);
			if (n < 0 && errno != EINTR)
				die("poll");
			// commands first: one written before a transfer started
			// applies to that transfer
			ctl.drain();
			follow();
			runBus();
			if (n > 0 && np == 2 && (p[1].revents & POLLIN) && !ctl.silent()) {
				const ssize_t len = ::read(fd, mosi.data(), mosi.size());
				if (len < 0) {
					if (errno == EINTR || errno == EAGAIN)
						continue;
					die("read");
				}
				const auto ulen = static_cast<std::size_t>(len);
				chip.exchange(std::span<const std::uint8_t>(mosi.data(), ulen),
					      std::span<std::uint8_t>(miso.data(), ulen));
				ctl.countTransfer();
				// the frames it brought go out on the bus before the
				// answer returns (an INT1 for their inputs follows it)
				runBus();
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
			     static_cast<unsigned long long>(ctl.transfers()),
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
