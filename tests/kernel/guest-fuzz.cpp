// SPDX-License-Identifier: MIT
// ecmxf-guest-fuzz: a seeded, time-bounded system-call fuzzer of
// /dev/ecmxfN, run inside the QEMU guest (Documentation/kernel-testing.rst,
// "The interface fuzzer"). Several threads pick random actions on a small
// table of open files:
//  - open() in every mode (O_RDONLY, O_WRONLY, O_RDWR, O_NONBLOCK, ...),
//    close(), fcntl(F_SETFL) of O_NONBLOCK, and write()/lseek()/pread(),
//    which the device does not support;
//  - every ioctl of <linux/ecmxf.h> with structures that are well formed
//    (command codes and flags from the protocol core's command table,
//    lib/core/ecmxf-cmds.c, with random parameters), lightly mutated,
//    boundary values in every field (reserved and padding included) or
//    random bytes; user pointers that are valid, NULL, unmapped, straddle
//    the end of a page, point into read-only memory, at kernel or
//    non-canonical addresses; unknown ioctl numbers, known numbers with
//    wrong sizes or directions, a few generic VFS ioctls;
//  - CLAIM + RING_SETUP, mmap() of the rings at odd offsets, lengths and
//    protections, reads and writes of the mapped memory (head, tail and
//    the kernel-owned words too), partial munmap(), mremap(), mprotect(),
//    fork() with the rings mapped;
//  - read() with short, exact, long and bad buffers, poll() of one or all
//    files;
//  - unbind and bind again of the SPI device through sysfs (as
//    tests/kernel/steps/check/80-rebind.sh), while the others go on.
// A watchdog thread interrupts (SIGUSR1, no SA_RESTART) any system call
// that blocks longer than --stall-ms; one that stays blocked for
// --hang-s seconds in spite of the signals is a hang: the program prints
// the thread's kernel stack, asks the kernel for its blocked tasks
// (sysrq w) and exits 2.
//
// After --seconds: every thread stops, every mapping and file is closed,
// and the device must still work: a fresh descriptor sees open_count 1,
// FW_VERSION_GET and ECAT_SLV_CNT_GET succeed (after ECMXF_IOC_RESET's
// documented recoveries: async reset, link reset, warm reset, in that
// order, each only if the previous did not suffice), the rings' vmalloc
// memory is freed (/proc/vmallocinfo). Invariants checked on the way
// (documented in include/uapi/linux/ecmxf.h): reserved output fields are
// zero, read() returns whole records, a successful CMD's rx_len is at most
// rx_size, a mapping the kernel accepted is readable over its whole
// length. The run prints how many calls of each kind it made, how many
// succeeded and their errnos. Exit 0 when no check failed.
//
//   ecmxf-guest-fuzz [--seconds N] [--seed S] [--threads T]
//                    [--stall-ms MS] [--hang-s S] [--no-rebind]
//                    [--no-bringup] [--format-changes] [/dev/ecmxfN]
//
// --format-changes: send SPI_RECONFIG_OP and CRC_TYPE_SET too (by default
// they become harmless reads: a chip left in another packet format is not
// found again by the probe after an unbind, a known limit)
//
// The seed (printed first) fixes each thread's sequence of actions
// (thread i draws from seed + i); the interleaving of the threads, the
// chip's answers and what the watchdog interrupts are not reproducible,
// so a replay with --seed repeats the same actions in about the same order.

#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/bus/master.hpp>

#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cinttypes>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "../../lib/core/ecmxf-proto.h"
#include "uapi/linux/ecmxf.h"

namespace {

// ---------------------------------------------------------------------
// random numbers: xoshiro256** seeded by splitmix64

std::uint64_t splitmix(std::uint64_t &x)
{
	std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
	return z ^ (z >> 31);
}

class Rng {
public:
	explicit Rng(std::uint64_t seed)
	{
		for (auto &w : s_)
			w = splitmix(seed);
	}
	std::uint64_t next()
	{
		const std::uint64_t r = rotl(s_[1] * 5, 7) * 9;
		const std::uint64_t t = s_[1] << 17;
		s_[2] ^= s_[0];
		s_[3] ^= s_[1];
		s_[1] ^= s_[2];
		s_[0] ^= s_[3];
		s_[2] ^= t;
		s_[3] = rotl(s_[3], 45);
		return r;
	}
	// uniform in [0, n), n > 0
	std::uint64_t below(std::uint64_t n) { return next() % n; }
	std::uint32_t u32() { return static_cast<std::uint32_t>(next()); }
	std::uint8_t u8() { return static_cast<std::uint8_t>(next()); }
	// true with probability permille / 1000
	bool chance(unsigned permille) { return below(1000) < permille; }
	void fill(void *p, std::size_t n)
	{
		auto *b = static_cast<unsigned char *>(p);
		for (std::size_t i = 0; i < n; i++)
			b[i] = u8();
	}

private:
	static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
	std::uint64_t s_[4];
};

// a value at or next to a boundary of the field's type, or random
template <typename T>
T boundary(Rng &r)
{
	static constexpr std::uint64_t kVals[] = {
		0, 1, 2, 3, 4, 7, 8, 16, 31, 32, 63, 64, 0x7f, 0x80, 0xff, 0x100, 0x3ff, 0x400, 0x57f, 0x580,
		0x581, 0xfff, 0x1000, 0x1001, 0x7fff, 0x8000, 0xffff, 0x10000, 0x7fffffff, 0x80000000,
		0xffffffff, 0x100000000ULL, 0x7fffffffffffffffULL, 0x8000000000000000ULL, ~0ULL,
	};
	std::uint64_t v;
	switch (r.below(4)) {
	case 0:
		v = r.next();
		break;
	case 1:
		v = kVals[r.below(std::size(kVals))] - 1;
		break;
	default:
		v = kVals[r.below(std::size(kVals))];
		break;
	}
	return static_cast<T>(v);
}

template <typename T>
void mut(Rng &r, T &f, unsigned permille)
{
	if (r.chance(permille))
		f = boundary<T>(r);
}

template <typename T, std::size_t N>
void mut(Rng &r, T (&a)[N], unsigned permille)
{
	for (auto &e : a)
		mut(r, e, permille);
}

// ---------------------------------------------------------------------
// what the run counts: calls, successes and errnos per kind of call

enum Kind : unsigned {
	kOpen, kClose, kFcntl, kMisc, kIocVersion, kIocDevinfo, kIocCmd, kIocSubmit, kIocCounters, kIocReset,
	kIocClaim, kIocRelease, kIocRingSetup, kIocUnknown, kIocWrongSize, kIocVfs, kRead, kPoll, kMmap,
	kMunmap, kMremap, kMprotect, kTouch, kFork, kUnbind, kBind, kBringUp, kKinds
};

constexpr const char *kKindName[kKinds] = {
	"open", "close", "fcntl", "write/lseek/pread", "ioctl GET_VERSION", "ioctl DEVINFO", "ioctl CMD",
	"ioctl SUBMIT", "ioctl COUNTERS", "ioctl RESET", "ioctl CLAIM", "ioctl RELEASE", "ioctl RING_SETUP",
	"ioctl unknown number", "ioctl wrong size/dir", "ioctl generic (VFS)", "read", "poll", "mmap",
	"munmap", "mremap", "mprotect", "ring memory access", "fork", "sysfs unbind", "sysfs bind",
	"bus bring-up (library)",
};

constexpr int kErrMax = 140;

struct Stats {
	std::atomic<std::uint64_t> calls[kKinds];
	std::atomic<std::uint64_t> ok[kKinds];
	std::atomic<std::uint64_t> err[kKinds][kErrMax];
};

Stats gStats;
std::atomic<unsigned> gFailures{0};

void failure(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void failure(const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	std::printf("guest-test: FAIL fuzz: ");
	std::vprintf(fmt, ap);
	std::printf("\n");
	std::fflush(stdout);
	va_end(ap);
	gFailures++;
}

// ---------------------------------------------------------------------
// threads, the watchdog and the hang check

std::int64_t nowNs()
{
	timespec ts{};
	::clock_gettime(CLOCK_MONOTONIC, &ts);
	return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

struct ThreadState {
	std::atomic<std::int64_t> since{0}; // start of the current system call, 0 when none
	std::atomic<unsigned> kind{0};
	std::atomic<std::int64_t> lastSignal{0};
	std::atomic<bool> interruptible{true};
	std::atomic<pid_t> tid{0};
	pthread_t self{};
	std::atomic<bool> running{false};
};

constexpr unsigned kMaxThreads = 16;
ThreadState gThreads[kMaxThreads + 1]; // + the main thread's end checks
std::atomic<std::uint64_t> gInterrupts{0};
std::atomic<bool> gStop{false};

struct Options {
	unsigned seconds = 20;
	std::uint64_t seed = 0;
	bool seedGiven = false;
	unsigned threads = 4;
	unsigned stallMs = 2000;
	unsigned hangS = 60;
	bool rebind = true;
	bool bringup = true;
	bool formatChanges = false;
	std::string path = "/dev/ecmxf0";
};
Options gOpt;

void onSignal(int) {}

// a mapping the kernel accepted must be memory over its whole length, as
// long as it is mapped: a fault there is the kernel's
void onFault(int sig, siginfo_t *si, void *)
{
	char m[128];
	const int n = std::snprintf(m, sizeof(m), "guest-test: FAIL fuzz: signal %d at address %p\n", sig, si->si_addr);
	if (n > 0)
		(void)!::write(1, m, static_cast<std::size_t>(n));
	::_exit(3);
}

// run f() as a system call of kind k in thread slot ts: counted, watched
template <typename F>
long sys(ThreadState &ts, Kind k, F f, int *errOut = nullptr)
{
	ts.kind = k;
	ts.since = nowNs();
	errno = 0;
	const long r = static_cast<long>(f());
	const int e = errno;
	ts.since = 0;
	gStats.calls[k]++;
	if (r >= 0) {
		gStats.ok[k]++;
	} else {
		gStats.err[k][e > 0 && e < kErrMax ? e : 0]++;
	}
	if (errOut)
		*errOut = r < 0 ? e : 0;
	return r;
}

void dumpThread(pid_t tid)
{
	for (const char *f : { "wchan", "stack" }) {
		const std::string p = "/proc/self/task/" + std::to_string(tid) + "/" + f;
		FILE *fp = std::fopen(p.c_str(), "r");
		if (!fp) {
			std::printf("fuzz: %s: %s\n", p.c_str(), std::strerror(errno));
			continue;
		}
		char line[256];
		while (std::fgets(line, sizeof(line), fp))
			std::printf("fuzz: %s: %s%s", f, line, std::strchr(line, '\n') ? "" : "\n");
		std::fclose(fp);
	}
}

[[noreturn]] void declareHang(unsigned i, double secs)
{
	const unsigned k = gThreads[i].kind;
	std::printf("guest-test: FAIL fuzz: thread %u stuck in %s for %.1f s in spite of %s: a hang\n", i,
		    kKindName[k], secs, gThreads[i].interruptible ? "signals" : "(uninterruptible by design)");
	dumpThread(gThreads[i].tid);
	std::fflush(stdout);
	if (FILE *s = std::fopen("/proc/sysrq-trigger", "w")) {
		std::fputs("w", s);
		std::fclose(s);
	}
	std::fflush(stdout);
	::_exit(2);
}

void watchdog()
{
	const std::int64_t stall = static_cast<std::int64_t>(gOpt.stallMs) * 1'000'000;
	const std::int64_t hang = static_cast<std::int64_t>(gOpt.hangS) * 1'000'000'000;
	for (;;) {
		::usleep(50'000);
		const std::int64_t now = nowNs();
		for (unsigned i = 0; i <= kMaxThreads; i++) {
			ThreadState &t = gThreads[i];
			if (!t.running)
				continue;
			const std::int64_t s = t.since;
			if (!s)
				continue;
			// blocking reads and polls are cut short sooner
			const unsigned k = t.kind;
			const std::int64_t lim = (k == kRead || k == kPoll) ? stall / 8 : stall;
			if (now - s > hang)
				declareHang(i, static_cast<double>(now - s) / 1e9);
			if (t.interruptible && now - s > lim && now - t.lastSignal > lim / 2) {
				t.lastSignal = now;
				gInterrupts++;
				::syscall(SYS_tgkill, ::getpid(), t.tid.load(), SIGUSR1);
			}
		}
	}
}

// ---------------------------------------------------------------------
// memory: per thread an arena with RW, guard (PROT_NONE) and read-only
// pages, so that pointers can be valid, straddle a page end, point into
// nothing or into memory the kernel may read but not write

long gPage = 4096;

struct Arena {
	unsigned char *base = nullptr;
	unsigned char *rw = nullptr;    // 4 pages RW
	unsigned char *guard = nullptr; // 1 page PROT_NONE
	unsigned char *ro = nullptr;    // 1 page PROT_READ
	std::size_t rwLen = 0;
};

// offsets inside the read-only page of well-formed arguments
constexpr std::size_t kRoCmd = 0, kRoSubmit = 512, kRoRing = 1024, kRoReset = 1536;

Arena makeArena(Rng &r)
{
	const std::size_t pg = static_cast<std::size_t>(gPage);
	void *p = ::mmap(nullptr, 8 * pg, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
	if (p == MAP_FAILED) {
		std::perror("mmap arena");
		std::exit(1);
	}
	Arena a;
	a.base = static_cast<unsigned char *>(p);
	a.rw = a.base;
	a.rwLen = 4 * pg;
	a.guard = a.base + 4 * pg;
	a.ro = a.base + 5 * pg;
	r.fill(a.rw, a.rwLen);
	r.fill(a.ro, pg);
	// well-formed arguments in the read-only page: the kernel reads them,
	// runs them, and fails writing the answer back
	ecmxf_cmd c{};
	c.hdr.code = ECMXF_CMD_FW_VERSION_GET;
	std::memcpy(a.ro + kRoCmd, &c, sizeof(c));
	ecmxf_submit s{};
	s.hdr.code = ECMXF_CMD_ECAT_SLV_CNT_GET;
	std::memcpy(a.ro + kRoSubmit, &s, sizeof(s));
	ecmxf_ring_setup rs{};
	rs.out_entries = 4;
	rs.in_entries = 4;
	std::memcpy(a.ro + kRoRing, &rs, sizeof(rs));
	ecmxf_reset rr{};
	rr.flags = ECMXF_RESET_F_LINK;
	std::memcpy(a.ro + kRoReset, &rr, sizeof(rr));
	::mprotect(a.guard, pg, PROT_NONE);
	::mprotect(a.ro, pg, PROT_READ);
	::mprotect(a.base + 6 * pg, 2 * pg, PROT_NONE);
	return a;
}

// a user pointer for a buffer of len bytes that the kernel reads or writes
std::uint64_t genPtr(Rng &r, const Arena &a, std::size_t len, std::size_t roOff = 0)
{
	const std::size_t pg = static_cast<std::size_t>(gPage);
	const std::size_t n = std::min(len, a.rwLen);
	auto u = [](const void *p) { return static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(p)); };
	const unsigned w = static_cast<unsigned>(r.below(100));
	if (w < 55) // valid, somewhere in the RW pages
		return u(a.rw + r.below(a.rwLen - n + 1));
	if (w < 62)
		return 0;
	if (w < 68) // nothing mapped there
		return u(a.guard + r.below(pg));
	if (w < 76) // the first bytes fit, the rest is in the guard page
		return u(a.guard - (n > 1 ? 1 + r.below(n - 1) : 0));
	if (w < 84) // readable, not writable
		return u(a.ro + (roOff ? roOff : r.below(pg - std::min(n, pg) + 1)));
	if (w < 88)
		return 0xffff888000000000ULL + (r.below(1 << 20) << 12); // the kernel's direct map
	if (w < 91)
		return 0x8000000000000000ULL; // not canonical
	if (w < 93)
		return ~0ULL - r.below(64);
	if (w < 96)
		return u(reinterpret_cast<const void *>(&onSignal)); // text: read-only
	return boundary<std::uint64_t>(r);
}

// ---------------------------------------------------------------------
// the files: slots at fixed high descriptor numbers, so that no other
// open() of the process (sysfs, /proc) ever gets a number a thread still
// uses for the device

constexpr int kSlots = 6;
constexpr int kSlotBase = 200;

struct SlotInfo {
	ecmxf_ring_offsets out{}, in{}; // of the slot's last successful RING_SETUP
	bool rings = false;
};

std::mutex gMu; // protects gSlotInfo, gMaps, gChildren
SlotInfo gSlotInfo[kSlots];

struct Mapping {
	unsigned char *addr;
	std::size_t len;
	int prot;
	bool ringStart;          // starts at the ring's offset 0
	ecmxf_ring_offsets offs; // valid when ringStart
};
std::vector<Mapping> gMaps;
std::vector<pid_t> gChildren;

std::string gSpidev;    // the SPI device's name for sysfs bind/unbind
std::atomic<bool> gRebinding{false};
std::atomic<std::int64_t> gNextRebind{0};

// The device node: after a bind it may have another number (the old
// device keeps its number while files of it are open).
std::mutex gPathMu;
std::string gPath;

std::string devPath()
{
	std::lock_guard<std::mutex> l(gPathMu);
	return gPath;
}

// the node that sysfs names for the SPI device now, or "" when unbound
std::string findNode()
{
	const std::string dir = "/sys/bus/spi/devices/" + gSpidev + "/ecmxf";
	DIR *d = ::opendir(dir.c_str());
	if (!d)
		return "";
	std::string node;
	while (dirent *e = ::readdir(d)) {
		if (std::string_view(e->d_name).substr(0, 5) == "ecmxf") {
			node = std::string("/dev/") + e->d_name;
			break;
		}
	}
	::closedir(d);
	return node;
}

int slotFd(Rng &r) { return kSlotBase + static_cast<int>(r.below(kSlots)); }

// ---------------------------------------------------------------------
// the command table of the protocol core

std::vector<const ecmxf_cmd_info *> gSafeCmds, gBadCmds;

void loadTable()
{
	std::size_t n = 0;
	const ecmxf_cmd_info *t = ecmxf_cmd_table(&n);
	for (std::size_t i = 0; i < n; i++) {
		if (t[i].flags & ECMXF_CMDF_DESTRUCTIVE)
			gBadCmds.push_back(&t[i]);
		else
			gSafeCmds.push_back(&t[i]);
	}
}

// how a structure is made: well formed, a few fields mutated, boundary
// values in many fields, or random bytes
enum class Shape { Good, Mutated, Boundary, Random };

Shape pickShape(Rng &r)
{
	const auto w = r.below(100);
	return w < 50 ? Shape::Good : w < 80 ? Shape::Mutated : w < 94 ? Shape::Boundary : Shape::Random;
}

unsigned mutRate(Shape s) { return s == Shape::Mutated ? 80 : s == Shape::Boundary ? 500 : 0; }

void genHeader(Rng &r, ecmxf_cmd_header &h, Shape s)
{
	std::memset(&h, 0, sizeof(h));
	const ecmxf_cmd_info *ci;
	if (r.chance(15) && !gBadCmds.empty())
		ci = gBadCmds[r.below(gBadCmds.size())];
	else
		ci = gSafeCmds[r.below(gSafeCmds.size())];
	h.code = ci->code;
	if (r.chance(30))
		h.code = r.u8(); // not in the table: the driver treats it as destructive
	h.param = r.chance(700) ? static_cast<std::uint8_t>(r.below(4)) : r.u8();
	for (auto &d : h.data)
		d = r.chance(600) ? static_cast<std::uint8_t>(r.below(4)) : r.u8();
	if (r.chance(100))
		h.rsv_word = static_cast<std::uint16_t>(r.below(2) << 15 | r.below(2) << 11 | r.below(2) << 12);
	if (r.chance(150))
		h.control = r.u8();
	h.len = static_cast<std::uint16_t>(r.chance(500) ? r.below(64) : r.below(ECMXF_DATA_MAX + 2));
	if (h.code == ECMXF_CMD_SPI_RECONFIG_OP && r.chance(800))
		h.len = static_cast<std::uint16_t>(32 + 8 * r.below(10)); // valid sizes mostly
	if (r.chance(50))
		h.int_clear = r.u32();
	if (r.chance(50))
		r.fill(h.gpio_int_clear, sizeof(h.gpio_int_clear));
	if (r.chance(50))
		r.fill(h.gpio_out, sizeof(h.gpio_out));
	const unsigned m = mutRate(s);
	mut(r, h.data, m);
	mut(r, h.rsv_word, m);
	mut(r, h.control, m);
	mut(r, h.padding, m);
	mut(r, h.code, m);
	mut(r, h.param, m);
	mut(r, h.len, m);
	mut(r, h.int_clear, m);
	mut(r, h.gpio_int_clear, m);
	mut(r, h.gpio_out, m);
	mut(r, h.reserved, m);
}

// SPI_RECONFIG_OP and CRC_TYPE_SET change the packet format; a chip left
// in a format other than the power-on one and the module's is not found
// again by the probe after an unbind (kernel-testing.rst, "The interface
// fuzzer": a known limit), so without --format-changes they are not sent
void keepFormat(Rng &r, ecmxf_cmd_header &h)
{
	if (gOpt.formatChanges)
		return;
	if (h.code == ECMXF_CMD_SPI_RECONFIG_OP || h.code == ECMXF_CMD_CRC_TYPE_SET)
		h.code = r.chance(500) ? ECMXF_CMD_SPI_PACK_SIZE_GET : ECMXF_CMD_FW_VERSION_GET;
}

std::uint32_t genTimeout(Rng &r)
{
	const auto w = r.below(100);
	if (w < 40)
		return 0; // the command's default
	if (w < 90)
		return static_cast<std::uint32_t>(1 + r.below(500'000));
	if (w < 98)
		return static_cast<std::uint32_t>(r.below(5));
	return boundary<std::uint32_t>(r); // up to 71 minutes: the watchdog interrupts
}

std::uint32_t genFlags(Rng &r, Shape s)
{
	std::uint32_t f = r.chance(200) ? ECMXF_CMD_F_NO_AUTO_CLEAR : 0;
	mut(r, f, mutRate(s));
	return f;
}

// ---------------------------------------------------------------------
// the actions

struct Ctx {
	unsigned idx;
	Rng rng;
	Arena arena;
	ThreadState &ts;
	std::vector<unsigned char> big = std::vector<unsigned char>(16 * sizeof(ecmxf_completion)); // long read()s
};

bool zero(const void *p, std::size_t n)
{
	const auto *b = static_cast<const unsigned char *>(p);
	return std::all_of(b, b + n, [](unsigned char c) { return c == 0; });
}

void actOpen(Ctx &c)
{
	Rng &r = c.rng;
	static constexpr int kModes[] = { O_RDONLY, O_WRONLY, O_RDWR };
	int flags = kModes[r.below(3)];
	if (r.chance(400))
		flags |= O_NONBLOCK;
	if (r.chance(100))
		flags |= O_CLOEXEC;
	if (r.chance(30))
		flags |= O_APPEND;
	if (r.chance(20))
		flags |= O_TRUNC;
	if (r.chance(20))
		flags |= O_NOCTTY;
	const std::string path = devPath();
	int err = 0;
	const int fd = static_cast<int>(sys(c.ts, kOpen, [&] { return ::open(path.c_str(), flags); }, &err));
	if (fd < 0) {
		// unbound for the moment: no point in spinning on it
		if (err == ENOENT)
			::usleep(1000);
		return;
	}
	if (r.chance(100)) { // opened and closed again at once
		sys(c.ts, kClose, [&] { return ::close(fd); });
		return;
	}
	// into a slot: dup3 closes (releases) what the slot held
	const int slot = slotFd(r);
	if (::dup3(fd, slot, O_CLOEXEC) < 0)
		std::printf("fuzz: dup3: %s\n", std::strerror(errno));
	::close(fd);
	std::lock_guard<std::mutex> l(gMu);
	gSlotInfo[slot - kSlotBase] = SlotInfo{};
}

void actClose(Ctx &c)
{
	const int fd = slotFd(c.rng);
	sys(c.ts, kClose, [&] { return ::close(fd); });
}

void actFcntl(Ctx &c)
{
	const int fd = slotFd(c.rng);
	const int fl = ::fcntl(fd, F_GETFL);
	if (fl < 0)
		return;
	sys(c.ts, kFcntl, [&] { return ::fcntl(fd, F_SETFL, fl ^ O_NONBLOCK); });
}

void actMisc(Ctx &c)
{
	Rng &r = c.rng;
	const int fd = slotFd(r);
	const std::size_t n = r.below(256);
	switch (r.below(3)) {
	case 0:
		sys(c.ts, kMisc, [&] { return ::write(fd, c.arena.rw, n); });
		break;
	case 1:
		sys(c.ts, kMisc, [&] { return ::lseek(fd, static_cast<off_t>(r.below(4096)), SEEK_SET); });
		break;
	default:
		sys(c.ts, kMisc, [&] { return ::pread(fd, c.arena.rw, n, 0); });
		break;
	}
}

// the ioctl argument: the structure in the RW pages, or a bad pointer
void *argPtr(Ctx &c, const void *s, std::size_t n, std::size_t roOff)
{
	Rng &r = c.rng;
	unsigned char *rw = c.arena.rw + r.below(c.arena.rwLen - n + 1) / 8 * 8;
	std::memcpy(rw, s, n);
	if (r.chance(850))
		return rw;
	if (r.chance(300))
		return c.arena.ro + roOff; // a well-formed one, read-only
	const std::uint64_t p = genPtr(r, c.arena, n);
	// a straddling argument gets the structure's first bytes
	auto *q = reinterpret_cast<unsigned char *>(static_cast<std::uintptr_t>(p));
	if (q >= c.arena.rw && q < c.arena.guard)
		std::memcpy(q, s, std::min(n, static_cast<std::size_t>(c.arena.guard - q)));
	return q;
}

/// Sometimes a result fetch (ECMXF_CMD_F_FETCH) for @p hdr: the *_GET
/// partner of an async *_REQ is its code plus one; any code otherwise.
void genFetch(Rng &r, const ecmxf_cmd_header &hdr, ecmxf_cmd_header &fetch, std::uint32_t &flags, Shape s)
{
	if (!r.chance(60))
		return;
	flags |= ECMXF_CMD_F_FETCH;
	genHeader(r, fetch, s);
	fetch.code = static_cast<std::uint8_t>(r.chance(700) ? hdr.code + 1 : r.below(256));
}

void actCmd(Ctx &c)
{
	Rng &r = c.rng;
	const Shape s = pickShape(r);
	ecmxf_cmd cmd;
	if (s == Shape::Random) {
		r.fill(&cmd, sizeof(cmd));
	} else {
		std::memset(&cmd, 0, sizeof(cmd));
		genHeader(r, cmd.hdr, s);
		cmd.tx_len = static_cast<std::uint32_t>(r.chance(600) ? r.below(113) : r.below(ECMXF_DATA_MAX + 16));
		cmd.rx_size = static_cast<std::uint32_t>(r.chance(600) ? r.below(200) : r.below(0x20000));
		cmd.tx_ptr = cmd.tx_len || r.chance(500) ? genPtr(r, c.arena, cmd.tx_len) : 0;
		cmd.rx_ptr = cmd.rx_size || r.chance(500) ? genPtr(r, c.arena, cmd.rx_size) : 0;
		cmd.timeout_us = genTimeout(r);
		cmd.flags = genFlags(r, s);
		genFetch(r, cmd.hdr, cmd.fetch, cmd.flags, s);
		if (r.chance(100))
			r.fill(&cmd.rsp, sizeof(cmd.rsp)); // output fields: ignored
		const unsigned m = mutRate(s);
		mut(r, cmd.tx_len, m);
		mut(r, cmd.rx_size, m);
		mut(r, cmd.tx_ptr, m / 4);
		mut(r, cmd.rx_ptr, m / 4);
	}
	keepFormat(r, cmd.hdr);
	const int fd = slotFd(r);
	void *arg = argPtr(c, &cmd, sizeof(cmd), kRoCmd);
	const long ret = sys(c.ts, kIocCmd, [&] { return ::ioctl(fd, ECMXF_IOC_CMD, arg); });
	if (ret == 0 && arg != c.arena.ro + kRoCmd) {
		ecmxf_cmd out;
		std::memcpy(&out, arg, sizeof(out));
		if (out.rsp.padding)
			failure("CMD code %u: reserved output fields not zero", out.hdr.code);
		if (!(out.flags & ECMXF_CMD_F_FETCH) && !zero(&out.fetch, sizeof(out.fetch)))
			failure("CMD code %u: accepted with a fetch header but no ECMXF_CMD_F_FETCH", out.hdr.code);
		if ((out.flags & ECMXF_CMD_F_FETCHED) && !(out.flags & ECMXF_CMD_F_FETCH))
			failure("CMD code %u: ECMXF_CMD_F_FETCHED without ECMXF_CMD_F_FETCH", out.hdr.code);
		if (out.rx_len > out.rx_size)
			failure("CMD code %u: rx_len %u > rx_size %u", out.hdr.code, out.rx_len, out.rx_size);
	}
}

void actSubmit(Ctx &c)
{
	Rng &r = c.rng;
	const Shape s = pickShape(r);
	ecmxf_submit sub;
	if (s == Shape::Random) {
		r.fill(&sub, sizeof(sub));
	} else {
		std::memset(&sub, 0, sizeof(sub));
		genHeader(r, sub.hdr, s);
		sub.tx_len = static_cast<std::uint32_t>(r.chance(600) ? r.below(113) : r.below(ECMXF_DATA_MAX + 16));
		sub.rx_size = static_cast<std::uint32_t>(r.chance(600) ? r.below(200) : r.below(0x20000));
		sub.tx_ptr = sub.tx_len || r.chance(500) ? genPtr(r, c.arena, sub.tx_len) : 0;
		// must be zero since uAPI 2 (the answer is in the record)
		sub.reserved_ptr = r.chance(950) ? 0 : genPtr(r, c.arena, sub.rx_size);
		sub.timeout_us = genTimeout(r);
		sub.flags = genFlags(r, s);
		genFetch(r, sub.hdr, sub.fetch, sub.flags, s);
		sub.cookie = r.next();
		const unsigned m = mutRate(s);
		mut(r, sub.tx_len, m);
		mut(r, sub.rx_size, m);
		mut(r, sub.tx_ptr, m / 4);
		mut(r, sub.reserved_ptr, m / 4);
		// the fetch header's words that must be zero
		mut(r, sub.fetch.padding, m);
		mut(r, sub.fetch.reserved, m);
		mut(r, sub.fetch.len, m);
	}
	keepFormat(r, sub.hdr);
	const int fd = slotFd(r);
	void *arg = argPtr(c, &sub, sizeof(sub), kRoSubmit);
	sys(c.ts, kIocSubmit, [&] { return ::ioctl(fd, ECMXF_IOC_SUBMIT, arg); });
}

void actInfo(Ctx &c)
{
	Rng &r = c.rng;
	const int fd = slotFd(r);
	unsigned char *buf = c.arena.rw + 8 * r.below(64);
	const bool good = r.chance(850);
	void *arg = good ? static_cast<void *>(buf)
			 : reinterpret_cast<void *>(static_cast<std::uintptr_t>(genPtr(r, c.arena, 256)));
	switch (r.below(3)) {
	case 0:
		if (sys(c.ts, kIocVersion, [&] { return ::ioctl(fd, ECMXF_IOC_GET_VERSION, arg); }) == 0 && good) {
			std::uint32_t v;
			std::memcpy(&v, buf, sizeof(v));
			if (v != ECMXF_UAPI_VERSION)
				failure("GET_VERSION gave %u, the header says %u", v, ECMXF_UAPI_VERSION);
		}
		break;
	case 1:
		if (sys(c.ts, kIocDevinfo, [&] { return ::ioctl(fd, ECMXF_IOC_DEVINFO, arg); }) == 0 && good) {
			ecmxf_devinfo d;
			std::memcpy(&d, buf, sizeof(d));
			if (d.uapi_version != ECMXF_UAPI_VERSION || !zero(d.reserved, sizeof(d.reserved)))
				failure("DEVINFO: uapi_version %u or reserved fields not zero", d.uapi_version);
			if (d.open_count > d.max_open)
				failure("DEVINFO: open_count %u > max_open %u", d.open_count, d.max_open);
		}
		break;
	default:
		if (sys(c.ts, kIocCounters, [&] { return ::ioctl(fd, ECMXF_IOC_COUNTERS, arg); }) == 0 && good) {
			ecmxf_counters k;
			std::memcpy(&k, buf, sizeof(k));
			if (!zero(k.reserved, sizeof(k.reserved)))
				failure("COUNTERS: reserved fields not zero");
		}
		break;
	}
}

void actReset(Ctx &c)
{
	Rng &r = c.rng;
	const Shape s = pickShape(r);
	ecmxf_reset rr;
	if (s == Shape::Random) {
		r.fill(&rr, sizeof(rr));
	} else {
		std::memset(&rr, 0, sizeof(rr));
		const auto w = r.below(100);
		if (w < 55) {
			rr.flags = ECMXF_RESET_F_ASYNC_CMD;
			rr.param = static_cast<std::uint32_t>(1 + r.below(7));
		} else if (w < 92) {
			rr.flags = ECMXF_RESET_F_LINK;
		} else {
			rr.flags = ECMXF_RESET_F_WARM;
		}
		rr.timeout_us = genTimeout(r);
		const unsigned m = mutRate(s);
		mut(r, rr.flags, m);
		mut(r, rr.param, m);
		mut(r, rr.reserved, m);
	}
	const int fd = slotFd(r);
	void *arg = argPtr(c, &rr, sizeof(rr), kRoReset);
	sys(c.ts, kIocReset, [&] { return ::ioctl(fd, ECMXF_IOC_RESET, arg); });
}

void actClaim(Ctx &c)
{
	Rng &r = c.rng;
	const int fd = slotFd(r);
	const unsigned long junk = r.chance(800) ? 0 : static_cast<unsigned long>(r.next());
	if (r.chance(650)) {
		sys(c.ts, kIocClaim, [&] { return ::ioctl(fd, ECMXF_IOC_CLAIM, junk); });
	} else {
		if (sys(c.ts, kIocRelease, [&] { return ::ioctl(fd, ECMXF_IOC_RELEASE, junk); }) == 0) {
			std::lock_guard<std::mutex> l(gMu);
			gSlotInfo[fd - kSlotBase].rings = false;
		}
	}
}

void genRingSetup(Rng &r, ecmxf_ring_setup &rs, Shape s)
{
	if (s == Shape::Random) {
		r.fill(&rs, sizeof(rs));
		return;
	}
	std::memset(&rs, 0, sizeof(rs));
	rs.out_entries = 1u << (1 + r.below(r.chance(900) ? 6 : 12));
	rs.in_entries = 1u << (1 + r.below(r.chance(900) ? 6 : 12));
	rs.flags = static_cast<std::uint32_t>(r.below(16)); // POLL_OUT, POLL_IN, WKC_NEXT, FIFO_NEXT
	rs.poll_us = r.chance(300) ? 0 : static_cast<std::uint32_t>(r.chance(900) ? 500 + r.below(5000) : 50 + r.below(100'000));
	rs.rx_fill = static_cast<std::uint32_t>(r.below(8));
	rs.wkc_us = r.chance(500) ? 0 : static_cast<std::uint32_t>(r.below(1'000'000));
	if (r.chance(50))
		r.fill(&rs.out, sizeof(rs.out) + sizeof(rs.in)); // outputs: ignored
	const unsigned m = mutRate(s);
	mut(r, rs.out_entries, m);
	mut(r, rs.in_entries, m);
	mut(r, rs.flags, m);
	mut(r, rs.poll_us, m);
	mut(r, rs.rx_fill, m);
	mut(r, rs.wkc_us, m);
	mut(r, rs.reserved, m);
}

bool ringSetup(Ctx &c, int fd, Shape s)
{
	ecmxf_ring_setup rs;
	genRingSetup(c.rng, rs, s);
	void *arg = argPtr(c, &rs, sizeof(rs), kRoRing);
	if (sys(c.ts, kIocRingSetup, [&] { return ::ioctl(fd, ECMXF_IOC_RING_SETUP, arg); }) != 0)
		return false;
	if (arg == c.arena.ro + kRoRing)
		return false;
	std::memcpy(&rs, arg, sizeof(rs));
	if (!zero(rs.reserved, sizeof(rs.reserved)) || rs.out.reserved || rs.in.reserved)
		failure("RING_SETUP: reserved output fields not zero");
	if (rs.out.mmap_size % gPage || rs.in.mmap_size % gPage)
		failure("RING_SETUP: mmap_size %u/%u not a multiple of the page size", rs.out.mmap_size,
			rs.in.mmap_size);
	std::lock_guard<std::mutex> l(gMu);
	SlotInfo &si = gSlotInfo[fd - kSlotBase];
	si.out = rs.out;
	si.in = rs.in;
	si.rings = true;
	return true;
}

void actRingSetup(Ctx &c) { ringSetup(c, slotFd(c.rng), pickShape(c.rng)); }

void doMmap(Ctx &c, int fd, bool good)
{
	Rng &r = c.rng;
	SlotInfo si;
	{
		std::lock_guard<std::mutex> l(gMu);
		si = gSlotInfo[fd - kSlotBase];
	}
	const std::size_t pg = static_cast<std::size_t>(gPage);
	const bool in = r.chance(500);
	const ecmxf_ring_offsets &o = in ? si.in : si.out;
	std::uint64_t off = in ? ECMXF_RING_OFF_IN : ECMXF_RING_OFF_OUT;
	std::size_t len = si.rings ? o.mmap_size : pg;
	int prot = PROT_READ | PROT_WRITE;
	int flags = MAP_SHARED;
	if (!good) {
		switch (r.below(8)) {
		case 0:
			off += pg * (1 + r.below(4));
			break;
		case 1:
			off = (off ? off - pg : 0x20000000ULL);
			break;
		case 2:
			off = (r.next() & ~(pg - 1)) & 0x7fffffffffffULL;
			break;
		case 3:
			off += 1 + r.below(pg - 1); // not page aligned
			break;
		default:
			break;
		}
		switch (r.below(7)) {
		case 0:
			len += pg;
			break;
		case 1:
			len = len > pg ? len - pg : len;
			break;
		case 2:
			len = 1 + r.below(3 * pg);
			break;
		case 3:
			len = 0;
			break;
		case 4:
			len = static_cast<std::size_t>(r.below(1 << 24));
			break;
		default:
			break;
		}
		static constexpr int kProts[] = { PROT_READ, PROT_WRITE, PROT_NONE, PROT_READ | PROT_WRITE | PROT_EXEC,
						  PROT_READ | PROT_WRITE };
		prot = kProts[r.below(std::size(kProts))];
		if (r.chance(250))
			flags = MAP_PRIVATE;
		if (r.chance(150))
			flags |= MAP_POPULATE;
		if (r.chance(100))
			flags |= MAP_LOCKED;
	}
	void *p = MAP_FAILED;
	sys(c.ts, kMmap, [&] {
		p = ::mmap(nullptr, len, prot, flags, fd, static_cast<off_t>(off));
		return p == MAP_FAILED ? -1L : 0L;
	});
	if (p == MAP_FAILED)
		return;
	Mapping m{ static_cast<unsigned char *>(p), len, prot, false, {} };
	// the kernel accepted it: where does it start in the ring?
	if ((off == ECMXF_RING_OFF_IN || off == ECMXF_RING_OFF_OUT) && si.rings) {
		m.ringStart = true;
		m.offs = o;
	}
	std::lock_guard<std::mutex> l(gMu);
	gMaps.push_back(m);
	// the whole accepted length must be memory (else SIGBUS below)
	if (prot & PROT_READ) {
		volatile unsigned char sum = 0;
		for (std::size_t i = 0; i < len; i += pg)
			sum = static_cast<unsigned char>(sum + m.addr[i]);
		sum = static_cast<unsigned char>(sum + m.addr[len - 1]);
	}
}

void actMmap(Ctx &c) { doMmap(c, slotFd(c.rng), c.rng.chance(400)); }

// a claim, rings and both mappings in a row on one file: the deep path
void actCycle(Ctx &c)
{
	Rng &r = c.rng;
	const int fd = slotFd(r);
	if (r.chance(500)) {
		const std::string path = devPath();
		const int nfd = static_cast<int>(sys(c.ts, kOpen, [&] { return ::open(path.c_str(), O_RDWR); }));
		if (nfd >= 0) {
			::dup3(nfd, fd, O_CLOEXEC);
			::close(nfd);
			std::lock_guard<std::mutex> l(gMu);
			gSlotInfo[fd - kSlotBase] = SlotInfo{};
		}
	}
	sys(c.ts, kIocClaim, [&] { return ::ioctl(fd, ECMXF_IOC_CLAIM, 0); });
	if (!ringSetup(c, fd, r.chance(800) ? Shape::Good : Shape::Mutated))
		return;
	doMmap(c, fd, true);
	doMmap(c, fd, r.chance(700));
}

void actMunmap(Ctx &c)
{
	Rng &r = c.rng;
	const std::size_t pg = static_cast<std::size_t>(gPage);
	std::lock_guard<std::mutex> l(gMu);
	if (gMaps.empty())
		return;
	const std::size_t i = r.below(gMaps.size());
	Mapping m = gMaps[i];
	const std::size_t pages = (m.len + pg - 1) / pg;
	switch (r.below(9)) {
	case 0:
	case 1:
	case 2: { // the whole mapping
		if (sys(c.ts, kMunmap, [&] { return ::munmap(m.addr, m.len); }) == 0)
			gMaps.erase(gMaps.begin() + static_cast<long>(i));
		break;
	}
	case 3: { // one page of it: up to two pieces remain
		const std::size_t pgI = r.below(pages);
		if (sys(c.ts, kMunmap, [&] { return ::munmap(m.addr + pgI * pg, pg); }) != 0)
			break;
		gMaps.erase(gMaps.begin() + static_cast<long>(i));
		if (pgI > 0)
			gMaps.push_back({ m.addr, pgI * pg, m.prot, m.ringStart, m.offs });
		if (pgI + 1 < pages)
			gMaps.push_back({ m.addr + (pgI + 1) * pg, pages * pg - (pgI + 1) * pg, m.prot, false, {} });
		break;
	}
	case 4: // not page aligned: EINVAL, nothing unmapped
		sys(c.ts, kMunmap, [&] { return ::munmap(m.addr + 1 + r.below(pg - 1), pg); });
		break;
	case 5: // length 0: EINVAL
		sys(c.ts, kMunmap, [&] { return ::munmap(m.addr, 0); });
		break;
	case 6: { // mremap: shrink in place, or grow (VM_DONTEXPAND: refused)
		const std::size_t nl = r.chance(500) ? pg : m.len + pg;
		void *q = MAP_FAILED;
		sys(c.ts, kMremap, [&] {
			q = ::mremap(m.addr, m.len, nl, r.chance(500) ? MREMAP_MAYMOVE : 0);
			return q == MAP_FAILED ? -1L : 0L;
		});
		if (q != MAP_FAILED) {
			gMaps[i].addr = static_cast<unsigned char *>(q);
			gMaps[i].len = std::min(nl, pages * pg);
			if (nl > m.len)
				gMaps[i].len = nl;
		}
		break;
	}
	case 7: { // move it elsewhere
		void *q = MAP_FAILED;
		sys(c.ts, kMremap, [&] {
			void *tmp = ::mmap(nullptr, m.len, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
			if (tmp == MAP_FAILED)
				return -1L;
			q = ::mremap(m.addr, m.len, m.len, MREMAP_MAYMOVE | MREMAP_FIXED, tmp);
			if (q == MAP_FAILED)
				::munmap(tmp, m.len);
			return q == MAP_FAILED ? -1L : 0L;
		});
		if (q != MAP_FAILED)
			gMaps[i].addr = static_cast<unsigned char *>(q);
		break;
	}
	default: { // mprotect: add or drop write, or none
		static constexpr int kProts[] = { PROT_READ, PROT_READ | PROT_WRITE, PROT_NONE, PROT_WRITE };
		const int np = kProts[r.below(std::size(kProts))];
		if (sys(c.ts, kMprotect, [&] { return ::mprotect(m.addr, pages * pg, np); }) == 0)
			gMaps[i].prot = np;
		break;
	}
	}
}

// reads and writes of mapped ring memory, the kernel-owned words too
void actTouch(Ctx &c)
{
	Rng &r = c.rng;
	std::lock_guard<std::mutex> l(gMu);
	if (gMaps.empty())
		return;
	Mapping &m = gMaps[r.below(gMaps.size())];
	gStats.calls[kTouch]++;
	if (!(m.prot & PROT_READ) && !(m.prot & PROT_WRITE))
		return;
	auto word = [&](std::uint32_t off) -> volatile std::uint32_t * {
		if (off + 4 > m.len || off % 4)
			return nullptr;
		return reinterpret_cast<volatile std::uint32_t *>(m.addr + off);
	};
	const bool canWrite = m.prot & PROT_WRITE;
	for (int n = 0; n < 8; n++) {
		const auto w = r.below(10);
		volatile std::uint32_t *p;
		if (m.ringStart && w < 4) {
			// the indices: the producer's tail, the consumer's head
			const std::uint32_t offs[] = { m.offs.head, m.offs.tail, m.offs.flags, m.offs.dropped, m.offs.mask,
						       m.offs.entries };
			p = word(offs[r.below(std::size(offs))]);
			if (!p)
				continue;
			if (canWrite && (m.prot & PROT_READ) && r.chance(600)) {
				const std::uint32_t v = *p;
				*p = r.chance(700) ? v + static_cast<std::uint32_t>(r.below(8)) : boundary<std::uint32_t>(r);
			} else if (m.prot & PROT_READ) {
				(void)*p;
			} else if (canWrite) {
				*p = r.u32();
			}
		} else {
			p = word(static_cast<std::uint32_t>(r.below(m.len / 4) * 4));
			if (!p)
				continue;
			if (canWrite && r.chance(300))
				*p = r.u32();
			else if (m.prot & PROT_READ)
				(void)*p;
		}
	}
	gStats.ok[kTouch]++;
}

void actRead(Ctx &c)
{
	Rng &r = c.rng;
	const int fd = slotFd(r);
	const std::size_t rec = sizeof(ecmxf_completion);
	std::size_t n;
	switch (r.below(6)) {
	case 0:
		n = r.below(rec); // short: EINVAL
		break;
	case 1:
		n = rec;
		break;
	case 2:
		n = rec * (1 + r.below(8)) + r.below(2) * r.below(rec);
		break;
	case 3:
		n = c.big.size();
		break;
	case 4:
		n = static_cast<std::size_t>(boundary<std::uint32_t>(r));
		break;
	default:
		n = rec + 1;
		break;
	}
	void *buf;
	if (n <= c.big.size() && r.chance(800))
		buf = c.big.data();
	else
		buf = reinterpret_cast<void *>(static_cast<std::uintptr_t>(genPtr(r, c.arena, n)));
	// blocking reads of a file with nothing submitted wait for the
	// watchdog's signal: fewer of them
	if (!(::fcntl(fd, F_GETFL) & O_NONBLOCK) && r.chance(700)) {
		pollfd pfd{ fd, POLLIN, 0 };
		if (::poll(&pfd, 1, 0) != 1)
			return;
	}
	const long got = sys(c.ts, kRead, [&] { return ::read(fd, buf, n); });
	if (got > 0 && static_cast<std::size_t>(got) % rec)
		failure("read() returned %ld bytes, not whole %zu-byte records", got, rec);
	if (got > 0 && buf == c.big.data()) {
		for (long o = 0; o + static_cast<long>(rec) <= got; o += static_cast<long>(rec)) {
			ecmxf_completion cp;
			std::memcpy(&cp, c.big.data() + o, rec);
			if (!zero(cp.reserved, sizeof(cp.reserved)) || cp.rsp.padding)
				failure("completion record: reserved fields not zero");
			if (cp.flags & ~ECMXF_CMD_F_FETCHED)
				failure("completion record: flags 0x%x (only ECMXF_CMD_F_FETCHED is defined)", cp.flags);
		}
	}
}

void actPoll(Ctx &c)
{
	Rng &r = c.rng;
	pollfd p[kSlots];
	const nfds_t n = r.chance(300) ? kSlots : 1;
	for (nfds_t i = 0; i < n; i++) {
		p[i].fd = n == 1 ? slotFd(r) : kSlotBase + static_cast<int>(i);
		p[i].events = static_cast<short>(r.chance(500) ? POLLIN | POLLOUT | POLLRDBAND | POLLPRI : r.u32());
		p[i].revents = 0;
	}
	const int tmo = static_cast<int>(r.chance(300) ? 0 : r.below(100));
	sys(c.ts, kPoll, [&] { return ::poll(p, n, tmo); });
}

// generic VFS ioctls that are harmless on any file (FIONBIO toggles
// O_NONBLOCK; the others are passed on or answered by the VFS). The fuzzer
// never sends FIFREEZE and its kin: freezing devtmpfs would block binds.
void actVfsIoctl(Ctx &c)
{
	Rng &r = c.rng;
	const int fd = slotFd(r);
	int v = static_cast<int>(r.below(2));
	static constexpr unsigned long kCmds[] = { FIONBIO, FIOASYNC, FIONREAD, FIOCLEX, FIONCLEX, FIOQSIZE };
	const unsigned long cmd = kCmds[r.below(std::size(kCmds))];
	sys(c.ts, kIocVfs, [&] { return ::ioctl(fd, cmd, &v); });
}

void actBadIoctl(Ctx &c)
{
	Rng &r = c.rng;
	const int fd = slotFd(r);
	static constexpr unsigned long kKnown[] = {
		ECMXF_IOC_GET_VERSION, ECMXF_IOC_DEVINFO, ECMXF_IOC_CMD, ECMXF_IOC_SUBMIT, ECMXF_IOC_COUNTERS,
		ECMXF_IOC_RESET, ECMXF_IOC_CLAIM, ECMXF_IOC_RELEASE, ECMXF_IOC_RING_SETUP, ECMXF_IOC_CLAIM_BREAK,
	};
	unsigned long cmd;
	Kind k = kIocUnknown;
	const auto w = r.below(10);
	static constexpr unsigned kDirs[] = { _IOC_NONE, _IOC_READ, _IOC_WRITE, _IOC_READ | _IOC_WRITE };
	if (w < 5) { // a known number, another size or direction
		const unsigned long base = kKnown[r.below(std::size(kKnown))];
		unsigned size = _IOC_SIZE(base);
		unsigned dir = _IOC_DIR(base);
		if (r.chance(600)) {
			static constexpr int kDelta[] = { -8, -4, -1, 1, 4, 8 };
			size = static_cast<unsigned>(static_cast<int>(size) + kDelta[r.below(std::size(kDelta))]) & 0x3fff;
		} else if (r.chance(500)) {
			size = static_cast<unsigned>(r.below(0x4000));
		}
		if (r.chance(400))
			dir = kDirs[r.below(4)];
		cmd = _IOC(dir, ECMXF_IOC_MAGIC, _IOC_NR(base), size);
		k = kIocWrongSize;
		if (cmd == base)
			k = kIocUnknown; // drawn back onto the real one: still counted here
	} else if (w < 8) { // our type, unknown numbers
		cmd = _IOC(kDirs[r.below(4)], ECMXF_IOC_MAGIC, 9 + r.below(0xff - 8), r.below(0x4000));
	} else { // another type (not the VFS's: 0x00 'T' 'X' 'f' 0x94 0x12)
		unsigned type;
		do
			type = r.u8();
		while (type == 0 || type == 'T' || type == 'X' || type == 'f' || type == 0x94 || type == 0x12 ||
		       type == ECMXF_IOC_MAGIC);
		cmd = _IOC(kDirs[r.below(4)], type, r.below(256), r.below(0x4000));
	}
	void *arg = r.chance(800) ? static_cast<void *>(c.arena.rw)
				  : reinterpret_cast<void *>(static_cast<std::uintptr_t>(genPtr(r, c.arena, 64)));
	sys(c.ts, k, [&] { return ::ioctl(fd, cmd, arg); });
}

void actFork(Ctx &c)
{
	Rng &r = c.rng;
	const int fd = slotFd(r);
	std::lock_guard<std::mutex> l(gMu);
	if (gChildren.size() > 16)
		return;
	pid_t pid = -1;
	sys(c.ts, kFork, [&] {
		pid = ::fork();
		return static_cast<long>(pid);
	});
	if (pid == 0) {
		// the child: its copies of the mappings hold the rings, its
		// copies of the files keep them open until it exits
		volatile unsigned char s = 0;
		for (const Mapping &m : gMaps)
			if (m.prot & PROT_READ)
				s = static_cast<unsigned char>(s + m.addr[0]);
		ecmxf_devinfo d;
		::ioctl(fd, ECMXF_IOC_DEVINFO, &d);
		::ioctl(fd, ECMXF_IOC_RELEASE, 0);
		::_exit(0);
	}
	if (pid > 0)
		gChildren.push_back(pid);
}

void reapChildren(bool wait)
{
	std::lock_guard<std::mutex> l(gMu);
	for (auto it = gChildren.begin(); it != gChildren.end();) {
		int st = 0;
		const pid_t p = ::waitpid(*it, &st, wait ? 0 : WNOHANG);
		if (p == 0) {
			++it;
			continue;
		}
		if (p == *it && !(WIFEXITED(st) && WEXITSTATUS(st) == 0))
			failure("a forked child ended with status 0x%x", st);
		it = gChildren.erase(it);
	}
}

bool writeSysfs(const std::string &file, const std::string &v, int *err)
{
	const int fd = ::open(file.c_str(), O_WRONLY | O_CLOEXEC);
	if (fd < 0) {
		*err = errno;
		return false;
	}
	const bool ok = ::write(fd, v.data(), v.size()) == static_cast<ssize_t>(v.size());
	*err = ok ? 0 : errno;
	::close(fd);
	return ok;
}

// unbind the SPI device and bind it again; the others go on meanwhile
void actRebind(Ctx &c)
{
	// at most one every five seconds: the device is there most of the time
	if (!gOpt.rebind || gSpidev.empty() || nowNs() < gNextRebind || gRebinding.exchange(true))
		return;
	Rng &r = c.rng;
	const std::string drv = "/sys/bus/spi/drivers/ecmxf/";
	int err = 0;
	c.ts.interruptible = false;
	const std::int64_t t0 = nowNs();
	if (sys(c.ts, kUnbind, [&] { return writeSysfs(drv + "unbind", gSpidev, &err) ? 0L : (errno = err, -1L); }) == 0)
		::usleep(static_cast<useconds_t>(r.below(300'000)));
	// bind again (the probe talks to the chip; a chip left in a strange
	// state by the commands above may need a few tries)
	bool bound = false;
	for (int i = 0; i < 10 && !bound; i++) {
		bound = sys(c.ts, kBind, [&] { return writeSysfs(drv + "bind", gSpidev, &err) ? 0L : (errno = err, -1L); }) == 0;
		if (!bound && !findNode().empty())
			bound = true; // it was never unbound
		if (!bound)
			::usleep(200'000);
	}
	c.ts.interruptible = true;
	if (bound) {
		const std::string node = findNode();
		if (node.empty()) {
			failure("%s bound, but no ecmxf device under it in sysfs", gSpidev.c_str());
		} else {
			std::lock_guard<std::mutex> l(gPathMu);
			gPath = node;
		}
		std::printf("fuzz: unbind + bind took %.2f s, now %s\n", static_cast<double>(nowNs() - t0) / 1e9,
			    node.c_str());
	}
	gNextRebind = nowNs() + 5'000'000'000;
	if (!bound) {
		failure("binding %s again failed 10 times (last errno %d %s)", gSpidev.c_str(), err, std::strerror(err));
		gStop = true;
	}
	gRebinding = false;
}

// A bus with process data (the default network, the EST-584 motion PDOs),
// so that RING_SETUP finds frame sizes: before the run, and again now and
// then during it (the random commands reconfigure and reset the chip).
// The library's commands have their own time limits; only the hang check
// watches them.
bool bringUp(ThreadState &ts)
{
	ts.interruptible = false;
	ts.kind = kBringUp;
	ts.since = nowNs();
	bool ok = false;
	try {
		auto dev = ecmxf::Device::open(devPath());
		dev->setMinimumTimeout(std::chrono::seconds(5));
		ecmxf::Master master(*dev);
		ecmxf::MasterConfig mc;
		mc.pdoAssignments = { ecmxf::est584MotionPdos(0), ecmxf::est584MotionPdos(1) };
		master.bringUp(mc);
		ok = true;
	} catch (const std::exception &e) {
		std::printf("fuzz: bus bring-up failed: %s\n", e.what());
	}
	ts.since = 0;
	ts.interruptible = true;
	gStats.calls[kBringUp]++;
	if (ok)
		gStats.ok[kBringUp]++;
	return ok;
}

std::atomic<bool> gBringingUp{false};
std::atomic<std::int64_t> gNextBringUp{0};

void actBringUp(Ctx &c)
{
	if (nowNs() < gNextBringUp || gBringingUp.exchange(true))
		return;
	bringUp(c.ts);
	gNextBringUp = nowNs() + 8'000'000'000;
	gBringingUp = false;
}

// ---------------------------------------------------------------------

struct Action {
	void (*fn)(Ctx &);
	unsigned weight;
};

constexpr Action kActions[] = {
	{ actOpen, 80 },      { actClose, 20 },    { actFcntl, 10 },  { actMisc, 10 },       { actCmd, 200 },
	{ actSubmit, 120 },   { actInfo, 60 },     { actReset, 15 },  { actClaim, 50 },      { actRingSetup, 35 },
	{ actCycle, 40 },     { actMmap, 40 },     { actMunmap, 45 }, { actTouch, 70 },      { actRead, 90 },
	{ actPoll, 60 },      { actBadIoctl, 60 }, { actVfsIoctl, 8 }, { actFork, 3 },       { actRebind, 2 },
	{ actBringUp, 2 },
};

void fuzzThread(unsigned idx)
{
	ThreadState &ts = gThreads[idx];
	ts.self = ::pthread_self();
	ts.tid = static_cast<pid_t>(::syscall(SYS_gettid));
	std::uint64_t seed = gOpt.seed + idx;
	Ctx c{ idx, Rng(splitmix(seed)), {}, ts, std::vector<unsigned char>(64 * 1024) };
	c.arena = makeArena(c.rng);
	unsigned total = 0;
	for (const auto &a : kActions)
		total += a.weight;
	ts.running = true;
	while (!gStop) {
		auto w = static_cast<unsigned>(c.rng.below(total));
		for (const auto &a : kActions) {
			if (w < a.weight) {
				a.fn(c);
				break;
			}
			w -= a.weight;
		}
		if (idx == 0 && c.rng.chance(20))
			reapChildren(false);
	}
	ts.running = false;
}

// ---------------------------------------------------------------------
// before and after

// the rings' vmalloc areas (their caller is in ecmxf.ko)
long ringAreas()
{
	FILE *f = std::fopen("/proc/vmallocinfo", "r");
	if (!f)
		return -1;
	long n = 0;
	char line[512];
	while (std::fgets(line, sizeof(line), f))
		if (std::strstr(line, "[ecmxf]"))
			n++;
	std::fclose(f);
	return n;
}

struct CmdResult {
	long ret;
	int err;
	ecmxf_cmd cmd;
};

CmdResult simpleCmd(int fd, std::uint8_t code)
{
	static unsigned char rx[ECMXF_DATA_MAX];
	CmdResult r{};
	r.cmd.hdr.code = code;
	r.cmd.timeout_us = 5'000'000;
	r.cmd.rx_ptr = reinterpret_cast<std::uintptr_t>(rx);
	r.cmd.rx_size = sizeof(rx);
	r.ret = ::ioctl(fd, ECMXF_IOC_CMD, &r.cmd);
	r.err = r.ret < 0 ? errno : 0;
	return r;
}

bool works(int fd, const char *after)
{
	const CmdResult fw = simpleCmd(fd, ECMXF_CMD_FW_VERSION_GET);
	const CmdResult sc = simpleCmd(fd, ECMXF_CMD_ECAT_SLV_CNT_GET);
	const bool ok = fw.ret == 0 && fw.cmd.status == 0 && sc.ret == 0 && sc.cmd.status == 0;
	std::printf("fuzz: after %s: FW_VERSION_GET ioctl %ld errno %d status %d ret 0x%02x; "
		    "ECAT_SLV_CNT_GET ioctl %ld errno %d status %d ret %u: %s\n",
		    after, fw.ret, fw.err, fw.cmd.status, fw.cmd.rsp.ret, sc.ret, sc.err, sc.cmd.status, sc.cmd.rsp.ret,
		    ok ? "works" : "does not work");
	return ok;
}

int reset(int fd, std::uint32_t flags, std::uint32_t param)
{
	ecmxf_reset r{};
	r.flags = flags;
	r.param = param;
	r.timeout_us = 10'000'000;
	return ::ioctl(fd, ECMXF_IOC_RESET, &r) < 0 ? -errno : 0;
}

void endChecks(long areasBefore)
{
	ThreadState &ts = gThreads[kMaxThreads];
	ts.self = ::pthread_self();
	ts.tid = static_cast<pid_t>(::syscall(SYS_gettid));
	ts.interruptible = false; // these must not block at all: the hang check only
	ts.running = true;

	reapChildren(true);
	{
		std::lock_guard<std::mutex> l(gMu);
		for (const Mapping &m : gMaps)
			::munmap(m.addr, m.len);
		gMaps.clear();
	}
	for (int i = 0; i < kSlots; i++)
		::close(kSlotBase + i);

	ts.since = nowNs();
	ts.kind = kOpen;
	const std::string path = devPath();
	const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
	ts.since = 0;
	if (fd < 0) {
		failure("%s after the run: %s", path.c_str(), std::strerror(errno));
		ts.running = false;
		return;
	}
	ecmxf_devinfo d{};
	ts.since = nowNs();
	ts.kind = kIocDevinfo;
	if (::ioctl(fd, ECMXF_IOC_DEVINFO, &d) != 0)
		failure("DEVINFO after the run: %s", std::strerror(errno));
	else if (d.open_count != 1)
		failure("open_count %u after every other file was closed, want 1", d.open_count);
	else if (d.flags & (ECMXF_DEVINFO_F_CLAIMED | ECMXF_DEVINFO_F_RINGS))
		failure("devinfo flags 0x%x: a claim or rings survive every file closed", d.flags);
	else
		std::printf("fuzz: open_count 1, no claim, no rings after the run\n");

	// the device works, after the documented recoveries if need be
	ts.kind = kIocCmd;
	bool ok = works(fd, "the run");
	if (!ok) {
		std::printf("fuzz: RESET async (abandon, clear busy): %d\n",
			    reset(fd, ECMXF_RESET_F_ASYNC_CMD, ECMXF_RESET_ASYNC_ABANDON | ECMXF_RESET_ASYNC_CLEAR_BUSY));
		ok = works(fd, "the async reset");
	}
	if (!ok) {
		std::printf("fuzz: RESET link: %d\n", reset(fd, ECMXF_RESET_F_LINK, 0));
		ok = works(fd, "the link reset");
	}
	if (!ok) {
		std::printf("fuzz: RESET warm: %d\n", reset(fd, ECMXF_RESET_F_WARM, 0));
		ok = works(fd, "the warm reset");
	}
	if (!ok)
		failure("the device does not work after the run, not even after the warm reset");
	// the commands may have changed the chip's own configuration, which
	// outlives a rebind (ECAT_INT_SET_ENABLE's parameter sets the INT0/INT1
	// polarity: with INT1 inverted the driver sees no INT1 edge): a warm
	// reset, the documented way back to the power-on configuration, and
	// the device works after it too
	if (ok) {
		std::printf("fuzz: RESET warm (the chip's power-on configuration): %d\n",
			    reset(fd, ECMXF_RESET_F_WARM, 0));
		if (!works(fd, "the final warm reset"))
			failure("the device does not work after the final warm reset");
	}
	::close(fd);
	ts.since = 0;
	ts.running = false;

	// the rings' memory: freed once no file and no mapping holds it
	long after = ringAreas();
	for (int i = 0; i < 50 && after > areasBefore; i++) {
		::usleep(100'000);
		after = ringAreas();
	}
	if (areasBefore < 0)
		std::printf("fuzz: /proc/vmallocinfo not readable: ring memory not checked\n");
	else if (after != areasBefore)
		failure("%ld vmalloc areas of ecmxf.ko after the run, %ld before: ring memory leaked", after,
			areasBefore);
	else
		std::printf("fuzz: vmalloc areas of ecmxf.ko: %ld before, %ld after\n", areasBefore, after);
}

void printStats(double secs)
{
	std::uint64_t total = 0;
	for (unsigned k = 0; k < kKinds; k++)
		total += gStats.calls[k];
	std::printf("fuzz: %" PRIu64 " calls in %.1f s (%.0f/s), %" PRIu64 " interrupted by the watchdog\n", total,
		    secs, static_cast<double>(total) / secs, gInterrupts.load());
	for (unsigned k = 0; k < kKinds; k++) {
		std::string errs;
		for (int e = 0; e < kErrMax; e++) {
			const std::uint64_t n = gStats.err[k][e];
			if (!n)
				continue;
			const char *name = e ? strerrorname_np(e) : "?";
			errs += " " + std::string(name ? name : std::to_string(e).c_str()) + "=" + std::to_string(n);
		}
		std::printf("fuzz: %-22s %8" PRIu64 " calls %8" PRIu64 " ok%s\n", kKindName[k], gStats.calls[k].load(),
			    gStats.ok[k].load(), errs.c_str());
	}
}

std::uint64_t parseU64(const char *s) { return std::strtoull(s, nullptr, 0); }

} // namespace

int main(int argc, char **argv)
{
	for (int i = 1; i < argc; i++) {
		const std::string_view a = argv[i];
		const bool more = i + 1 < argc;
		if (a == "--seconds" && more)
			gOpt.seconds = static_cast<unsigned>(parseU64(argv[++i]));
		else if (a == "--seed" && more)
			gOpt.seed = parseU64(argv[++i]), gOpt.seedGiven = true;
		else if (a == "--threads" && more)
			gOpt.threads = std::clamp(static_cast<unsigned>(parseU64(argv[++i])), 1u, kMaxThreads);
		else if (a == "--stall-ms" && more)
			gOpt.stallMs = static_cast<unsigned>(parseU64(argv[++i]));
		else if (a == "--hang-s" && more)
			gOpt.hangS = static_cast<unsigned>(parseU64(argv[++i]));
		else if (a == "--no-rebind")
			gOpt.rebind = false;
		else if (a == "--no-bringup")
			gOpt.bringup = false;
		else if (a == "--format-changes")
			gOpt.formatChanges = true;
		else if (!a.empty() && a[0] != '-')
			gOpt.path = std::string(a);
		else {
			std::fprintf(stderr, "usage: ecmxf-guest-fuzz [--seconds N] [--seed S] [--threads T] "
					     "[--stall-ms MS] [--hang-s S] [--no-rebind] [--no-bringup] [--format-changes] [/dev/ecmxfN]\n");
			return 64;
		}
	}
	if (!gOpt.seedGiven) {
		std::uint64_t s = static_cast<std::uint64_t>(nowNs()) ^ (static_cast<std::uint64_t>(::getpid()) << 32);
		gOpt.seed = splitmix(s);
	}
	std::setvbuf(stdout, nullptr, _IOLBF, 0);
	std::printf("fuzz: seed 0x%016" PRIx64 " (replay: --seed 0x%016" PRIx64 "), %u s, %u threads, %s\n", gOpt.seed,
		    gOpt.seed, gOpt.seconds, gOpt.threads, gOpt.path.c_str());
	gPage = ::sysconf(_SC_PAGESIZE);
	gPath = gOpt.path;
	loadTable();

	// the SPI device behind /dev/ecmxfN, for unbind and bind
	const std::string node = gOpt.path.substr(gOpt.path.rfind('/') + 1);
	char link[256];
	const ssize_t ln = ::readlink(("/sys/class/ecmxf/" + node + "/device").c_str(), link, sizeof(link) - 1);
	if (ln > 0) {
		link[ln] = 0;
		const std::string_view l(link);
		gSpidev = std::string(l.substr(l.rfind('/') + 1));
		std::printf("fuzz: %s is %s's\n", gOpt.path.c_str(), gSpidev.c_str());
	} else {
		std::printf("fuzz: no /sys/class/ecmxf/%s/device: no unbind/bind\n", node.c_str());
	}

	// signals: SIGUSR1 interrupts blocking calls (no SA_RESTART);
	// SIGPIPE and the children's SIGCHLD are nothing to us
	struct sigaction sa {};
	sa.sa_handler = onSignal;
	::sigemptyset(&sa.sa_mask);
	::sigaction(SIGUSR1, &sa, nullptr);
	::signal(SIGPIPE, SIG_IGN);
	struct sigaction fa {};
	fa.sa_sigaction = onFault;
	fa.sa_flags = SA_SIGINFO;
	::sigemptyset(&fa.sa_mask);
	::sigaction(SIGSEGV, &fa, nullptr);
	::sigaction(SIGBUS, &fa, nullptr);

	if (gOpt.bringup) {
		gThreads[kMaxThreads].tid = static_cast<pid_t>(::syscall(SYS_gettid));
		gThreads[kMaxThreads].running = true;
		std::thread(watchdog).detach();
		if (bringUp(gThreads[kMaxThreads]))
			std::printf("fuzz: bus brought up to OP with process data\n");
		gThreads[kMaxThreads].running = false;
		gNextBringUp = nowNs() + 8'000'000'000;
	} else {
		std::thread(watchdog).detach();
	}
	const long areasBefore = ringAreas();

	const std::int64_t t0 = nowNs();
	std::vector<std::thread> threads;
	for (unsigned i = 0; i < gOpt.threads; i++)
		threads.emplace_back(fuzzThread, i);
	long areasMax = areasBefore;
	while (!gStop && nowNs() - t0 < static_cast<std::int64_t>(gOpt.seconds) * 1'000'000'000) {
		::usleep(100'000);
		areasMax = std::max(areasMax, ringAreas());
	}
	gStop = true;
	// a thread blocked in a system call gets the watchdog's signals; one
	// that never returns is the watchdog's hang
	for (auto &t : threads)
		t.join();
	const double secs = static_cast<double>(nowNs() - t0) / 1e9;

	std::printf("fuzz: at most %ld vmalloc areas of ecmxf.ko seen during the run (sampled every 100 ms)\n",
		    areasMax);
	endChecks(areasBefore);
	printStats(secs);
	std::printf("guest-test: %s fuzz: seed 0x%016" PRIx64 ", %.1f s, %u failure(s)\n",
		    gFailures ? "FAIL" : "ok  ", gOpt.seed, secs, gFailures.load());
	return gFailures ? 1 : 0;
}
