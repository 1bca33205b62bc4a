// SPDX-License-Identifier: MIT
// ecmxf-guest-unbind: the chip unbound under its users, inside the QEMU
// guest (Documentation/kernel-testing.rst, "Unbind under load"; the
// behaviour checked is the one Documentation/uapi.rst, "When the chip goes
// away", documents).
//
//   ecmxf-guest-unbind DEV SPIDEV     SPIDEV: the SPI device's name (spi0.0)
//
// Phase 1, the chip bound: close() with the rings still mapped. The claim
// holder sets the rings up, maps both and closes its descriptor: the
// mappings hold the file, so the claim stays (devinfo of another
// descriptor: claimed, rings, the holder's pid; CLAIM there: EBUSY), the
// pump goes on filling the input ring, and the module is held. Only the
// last munmap() releases the file: the claim and the rings go, and the
// module's reference count is back where it was.
//
// Phase 2: the program unbinds the chip itself (the driver's sysfs
// "unbind") while
//  (a) a cyclic loop runs on the mapped rings, clocked by its input frames
//      (consume them, push one output frame per cycle) and making no
//      system call at all: it must see ECMXF_RING_S_ERROR in a flags word,
//      and it must see it in the cycle that runs when the unbind returns
//      or the next one (the kernel sets the flag before remove() goes on);
//      the status block's error is ENODEV;
//  (b) a thread blocks in ECMXF_IOC_CMD with an async command the chip
//      runs (the bridge's async-stuck fault), a second one in a CMD queued
//      behind it, both on the claim holder's open file: both return
//      -1/ENODEV;
//  (c) a thread sleeps in poll() for POLLIN: it wakes with POLLERR |
//      POLLHUP, and read() then gives ENODEV; another sleeps in read():
//      ENODEV; a descriptor with a SUBMIT queued reads its completion
//      (status -ENODEV), then ENODEV;
// every thread is seen asleep in its system call (/proc/self/task/TID/
// syscall and stat) before the unbind. Afterwards: every ioctl and mmap()
// gives ENODEV, /dev/ecmxfN is gone, the mapping still reads (flags,
// layout) and writes; after close() the mapping still holds the module
// (refcnt, delete_module() refused); after munmap() the reference count
// is back. The step (82-unbind.sh) then unloads the module, binds again
// and uses the device.
// Exit status 0 when every check holds.

#include <ecmxf/device.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/kernel_link.hpp>
#include <ecmxf/bus/master.hpp>

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>

#include "bridge-ctl.hpp"
#include "uapi/linux/ecmxf.h"
#include "../../lib/link/pdo_ring.hpp"

using namespace std::chrono_literals;

namespace {

constexpr std::uint8_t kStateUpdate = 57; // ECAT_STATE_UPDATE: async
constexpr std::uint32_t kLongUs = 60'000'000; // commands that must not time out

int gFailures = 0;

void ok(bool good, const std::string &what)
{
	std::printf("guest-test: %s %s\n", good ? "ok  " : "FAIL", what.c_str());
	std::fflush(stdout);
	if (!good)
		gFailures++;
}

template <typename A, typename B> void eq(const std::string &what, const A &got, const B &want)
{
	ok(static_cast<long long>(got) == static_cast<long long>(want),
	   what + ": got " + std::to_string(static_cast<long long>(got)) + ", want " +
		   std::to_string(static_cast<long long>(want)));
}

/// An ioctl that must fail with @p want (errno read after the call).
template <typename T> void iocFails(const std::string &what, int fd, unsigned long req, T arg, int want);

/// errno after a call that must fail with @p want.
void failsWith(const std::string &what, long ret, int err, int want)
{
	ok(ret < 0 && err == want, what + ": got " + (ret < 0 ? std::string(std::strerror(err)) : "success") +
					   ", want " + std::strerror(want));
}

template <typename T> void iocFails(const std::string &what, int fd, unsigned long req, T arg, int want)
{
	errno = 0;
	const long ret = ::ioctl(fd, req, arg);
	const int err = errno;
	failsWith(what, ret, err, want);
}

[[noreturn]] void fatal(const std::string &what)
{
	std::printf("guest-test: FAIL %s\n", what.c_str());
	std::fflush(stdout);
	std::_Exit(1);
}

long moduleRefcnt()
{
	std::ifstream f("/sys/module/ecmxf/refcnt");
	long v = -1;
	f >> v;
	return v;
}

void bridge(const std::string &cmd)
{
	std::string reply;
	if (!ecmxf::ktest::bridgeCtl(cmd, reply))
		fatal("bridge ctl '" + cmd + "': " + reply);
}

long long bridgeState(const std::string &key)
{
	std::string reply;
	if (!ecmxf::ktest::bridgeCtl("state", reply))
		return -1;
	const auto p = reply.find(" " + key + "=");
	return p == std::string::npos ? -1 : std::strtoll(reply.c_str() + p + key.size() + 2, nullptr, 0);
}

/// Until @p cond holds, at most @p limit; true when it did.
bool waitUntil(const std::function<bool()> &cond, std::chrono::milliseconds limit)
{
	const auto end = std::chrono::steady_clock::now() + limit;
	while (!cond()) {
		if (std::chrono::steady_clock::now() > end)
			return false;
		std::this_thread::sleep_for(10ms);
	}
	return true;
}

/// Is thread @p tid of this process asleep (state S) in one of the
/// system calls @p nrs (x86-64 numbers)?
bool asleepIn(pid_t tid, std::initializer_list<long> nrs)
{
	const std::string dir = "/proc/self/task/" + std::to_string(tid);
	std::ifstream sc(dir + "/syscall");
	long nr = -1;
	if (!(sc >> nr) || std::find(nrs.begin(), nrs.end(), nr) == nrs.end())
		return false;
	std::ifstream st(dir + "/stat");
	std::string line;
	std::getline(st, line);
	const auto close = line.rfind(')');
	return close != std::string::npos && close + 2 < line.size() && line[close + 2] == 'S';
}

/// A thread that makes one blocking call; its result when it returns.
class Blocked
{
public:
	explicit Blocked(std::function<long(int &err)> call)
	{
		thread_ = std::thread([this, call = std::move(call)] {
			tid_ = static_cast<pid_t>(::syscall(SYS_gettid));
			int err = 0;
			ret_ = call(err);
			err_ = err;
			done_ = true;
		});
	}
	~Blocked()
	{
		if (thread_.joinable()) {
			if (done_)
				thread_.join();
			else
				thread_.detach(); // reported; the process exits soon
		}
	}
	Blocked(const Blocked &) = delete;
	Blocked &operator=(const Blocked &) = delete;

	/// Waits until the thread sleeps in one of @p nrs (30 s at most).
	bool asleep(std::initializer_list<long> nrs) const
	{
		return waitUntil([&] { return tid_ != 0 && !done_ && asleepIn(tid_, nrs); }, 30s);
	}
	/// Waits for the call to return (30 s at most).
	bool finish()
	{
		if (!waitUntil([&] { return done_.load(); }, 30s))
			return false;
		thread_.join();
		return true;
	}
	[[nodiscard]] bool done() const { return done_; }
	[[nodiscard]] long ret() const { return ret_; }
	[[nodiscard]] int err() const { return err_; }

private:
	std::thread thread_;
	std::atomic<pid_t> tid_{ 0 };
	std::atomic<bool> done_{ false };
	long ret_ = 0;
	int err_ = 0;
};

/// The call of @p b returns (after the unbind), else the test ends here:
/// the thread still uses this frame's variables.
void mustFinish(Blocked &b, const std::string &what)
{
	if (!b.finish())
		fatal(what + " did not return within 30 s of the unbind");
	ok(true, what + " returned");
}

// the numbers /proc/.../syscall shows: the architecture's own (arm64 has
// no poll(), only ppoll())
constexpr long kSysRead = SYS_read, kSysIoctl = SYS_ioctl, kSysPpoll = SYS_ppoll;
#ifdef SYS_poll
constexpr long kSysPoll = SYS_poll;
#else
constexpr long kSysPoll = SYS_ppoll;
#endif

/// The two mapped rings (raw uAPI: offsets from RING_SETUP).
struct Rings {
	std::uint8_t *out = nullptr, *in = nullptr;
	std::size_t outLen = 0, inLen = 0;
	ecmxf_ring_setup rs{};

	static std::atomic_ref<std::uint32_t> word(std::uint8_t *base, std::uint32_t off)
	{
		return std::atomic_ref<std::uint32_t>(*reinterpret_cast<std::uint32_t *>(base + off));
	}
	std::uint32_t flags() const
	{
		return word(out, rs.out.flags).load(std::memory_order_acquire) |
		       word(in, rs.in.flags).load(std::memory_order_acquire);
	}
	std::uint32_t inTail() const { return word(in, rs.in.tail).load(std::memory_order_acquire); }
	/// The status block's error, read under its sequence count (~0u: the
	/// count never settled).
	std::uint32_t statusError() const
	{
		// the library's reader of the latched status block
		const ecmxf::detail::PdoRingView view(in, rs.in);
		ecmxf_ring_status st{};
		return view.status(st) ? st.error : ~0u;
	}
	/// One cycle's ring work: every input frame there is, one output
	/// frame when there is room. Return: input frames taken.
	std::uint32_t exchange(std::uint32_t seq) const
	{
		auto inHead = word(in, rs.in.head);
		const std::uint32_t tail = inTail();
		const std::uint32_t head = inHead.load(std::memory_order_relaxed);
		const std::uint32_t n = tail - head;
		// (the frames would be read here)
		inHead.store(tail, std::memory_order_release);
		auto outTail = word(out, rs.out.tail);
		const std::uint32_t t = outTail.load(std::memory_order_relaxed);
		const std::uint32_t h = word(out, rs.out.head).load(std::memory_order_acquire);
		if (t - h < rs.out_entries && rs.out.frame_size >= sizeof(seq)) {
			std::uint8_t *slot = out + rs.out.frames + (t & (rs.out_entries - 1)) * rs.out.frame_stride;
			std::memset(slot, 0, rs.out.frame_size);
			std::memcpy(slot, &seq, sizeof(seq));
			outTail.store(t + 1, std::memory_order_release);
		}
		return n;
	}
	void unmap()
	{
		if (out)
			eq("munmap() of the output ring", ::munmap(out, outLen), 0);
		if (in)
			eq("munmap() of the input ring", ::munmap(in, inLen), 0);
		out = in = nullptr;
	}
};

/// The bus up on the bridge's default network (1 ms SYNC0, PDOs mapped).
void bringUp(ecmxf::Device &dev)
{
	ecmxf::Master m(dev);
	ecmxf::MasterConfig mc;
	mc.init.dc.sync0Ns = 1'000'000;
	m.bringUp(mc);
}

/// Claim, rings, both mapped, the chip's FIFO on (the pump runs).
Rings startRings(ecmxf::Device &dev, int fd)
{
	Rings r;
	if (::ioctl(fd, ECMXF_IOC_CLAIM) < 0)
		fatal(std::string("ECMXF_IOC_CLAIM: ") + std::strerror(errno));
	dev.pdo().fifoEnable(false);
	r.rs.out_entries = 16;
	r.rs.in_entries = 64;
	r.rs.flags = ECMXF_RING_F_POLL_IN;
	r.rs.poll_us = 1000;
	if (::ioctl(fd, ECMXF_IOC_RING_SETUP, &r.rs) < 0)
		fatal(std::string("ECMXF_IOC_RING_SETUP: ") + std::strerror(errno));
	void *o = ::mmap(nullptr, r.rs.out.mmap_size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, ECMXF_RING_OFF_OUT);
	void *i = ::mmap(nullptr, r.rs.in.mmap_size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, ECMXF_RING_OFF_IN);
	if (o == MAP_FAILED || i == MAP_FAILED)
		fatal(std::string("mmap of the rings: ") + std::strerror(errno));
	r.out = static_cast<std::uint8_t *>(o);
	r.in = static_cast<std::uint8_t *>(i);
	r.outLen = r.rs.out.mmap_size;
	r.inLen = r.rs.in.mmap_size;
	if (!r.rs.in.frame_size || !r.rs.out.frame_size || !r.rs.in.status)
		fatal("the default network has no PDO frames both ways");
	dev.pdo().fifoClear(ecmxf::FifoSelect::Both);
	dev.pdo().fifoEnable(true);
	return r;
}

/// Input frames arrive (the pump runs): at least @p n within 30 s, taken
/// from the ring as they come (a full ring would stop them).
bool inputsFlow(const Rings &r, std::uint32_t n)
{
	std::uint32_t got = 0;
	return waitUntil(
		[&] {
			got += r.exchange(0);
			return got >= n;
		},
		30s);
}

ecmxf_devinfo devinfo(int fd)
{
	ecmxf_devinfo d{};
	if (::ioctl(fd, ECMXF_IOC_DEVINFO, &d) < 0)
		fatal(std::string("ECMXF_IOC_DEVINFO: ") + std::strerror(errno));
	return d;
}

// ---- phase 1 ----------------------------------------------------------

void closeWhileMapped(const std::string &path, long base)
{
	std::printf("guest-test: info phase 1: close() with the rings mapped (base refcnt %ld)\n", base);
	auto dev = ecmxf::Device::open(path);
	dev->setMinimumTimeout(2s);
	bringUp(*dev);
	auto *kt = dynamic_cast<ecmxf::KernelLink *>(&dev->link());
	if (!kt)
		fatal("the device is not opened by the kernel transport");
	Rings r = startRings(*dev, kt->fd());
	ok(inputsFlow(r, 5), "the pump fills the input ring");
	dev.reset(); // close() of the claim holder's only descriptor
	const long held = moduleRefcnt();
	ok(held > base, "after close(): the mappings hold the module (refcnt " + std::to_string(held) + ")");

	const int x = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
	if (x < 0)
		fatal("open " + path);
	ecmxf_devinfo d = devinfo(x);
	ok((d.flags & ECMXF_DEVINFO_F_CLAIMED) && (d.flags & ECMXF_DEVINFO_F_RINGS) &&
		   !(d.flags & ECMXF_DEVINFO_F_CLAIM_MINE),
	   "after close() with the rings mapped: still claimed, rings still set up (devinfo of another fd)");
	eq("  devinfo.claim_pid is still ours", d.claim_pid, ::getpid());
	iocFails("  ECMXF_IOC_CLAIM from another fd", x, ECMXF_IOC_CLAIM, 0, EBUSY);
	ok(inputsFlow(r, 3), "  the pump still fills the input ring");
	ok(r.flags() & ECMXF_RING_S_ACTIVE, "  the flags still say ECMXF_RING_S_ACTIVE");

	eq("munmap() of the output ring", ::munmap(r.out, r.outLen), 0);
	r.out = nullptr;
	d = devinfo(x);
	ok(d.flags & ECMXF_DEVINFO_F_CLAIMED, "  with the input ring still mapped: still claimed");
	eq("munmap() of the input ring (the last mapping)", ::munmap(r.in, r.inLen), 0);
	r.in = nullptr;
	d = devinfo(x);
	ok(!(d.flags & (ECMXF_DEVINFO_F_CLAIMED | ECMXF_DEVINFO_F_RINGS)),
	   "  after the last munmap(): the file is released, no claim, no rings");
	eq("  devinfo.claim_pid", d.claim_pid, 0);
	errno = 0;
	eq("  ECMXF_IOC_CLAIM from another fd now works", ::ioctl(x, ECMXF_IOC_CLAIM), 0);
	eq("  and ECMXF_IOC_RELEASE", ::ioctl(x, ECMXF_IOC_RELEASE), 0);
	::close(x);
	eq("module refcnt after the last close", moduleRefcnt(), base);
}

// ---- phase 2 ----------------------------------------------------------

/// The cyclic loop: no system call, clocked by its input frames.
struct Loop {
	const Rings *r = nullptr;
	std::atomic<std::uint64_t> cycles{ 0 };
	std::atomic<bool> stop{ false }, done{ false };
	std::atomic<std::uint64_t> seenAt{ 0 }; ///< cycles done when it saw the error
	std::atomic<std::uint32_t> seenFlags{ 0 };

	void run()
	{
		std::uint32_t seq = 0;
		std::uint64_t n = 0;
		for (;;) {
			const std::uint32_t f = r->flags();
			if (f & ECMXF_RING_S_ERROR) {
				seenFlags = f;
				seenAt = n;
				break;
			}
			if (stop.load(std::memory_order_relaxed))
				break;
			if (r->inTail() == Rings::word(r->in, r->rs.in.head).load(std::memory_order_relaxed)) {
#if defined(__x86_64__) || defined(__i386__)
				__builtin_ia32_pause();
#endif
				continue; // no input frame yet: this cycle goes on
			}
			r->exchange(++seq);
			cycles.store(++n, std::memory_order_release);
		}
		done = true;
	}
};

int openDev(const std::string &path)
{
	const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
	if (fd < 0)
		fatal("open " + path + ": " + std::strerror(errno));
	return fd;
}

/// Another descriptor of the open file behind @p fd (its claim included).
int dupOf(int fd)
{
	const int d = ::fcntl(fd, F_DUPFD_CLOEXEC, 0);
	if (d < 0)
		fatal(std::string("dup: ") + std::strerror(errno));
	return d;
}

ecmxf_cmd stuckCmd()
{
	ecmxf_cmd c{};
	c.hdr.code = kStateUpdate;
	c.timeout_us = kLongUs;
	return c;
}

void unbindUnderLoad(const std::string &path, const std::string &spidev, long base)
{
	std::printf("guest-test: info phase 2: unbind %s under load\n", spidev.c_str());
	auto dev = ecmxf::Device::open(path);
	dev->setMinimumTimeout(2s);
	auto *kt = dynamic_cast<ecmxf::KernelLink *>(&dev->link());
	if (!kt)
		fatal("the device is not opened by the kernel transport");
	const int fdA = kt->fd();
	Rings r = startRings(*dev, fdA);
	ok(inputsFlow(r, 5), "the pump fills the input ring");

	// (a) the cyclic loop
	Loop loop;
	loop.r = &r;
	std::thread loopThread([&] { loop.run(); });
	const bool running = waitUntil([&] { return loop.cycles >= 50 || loop.done; }, 60s) && !loop.done;
	ok(running, "(a) the cyclic loop runs (" + std::to_string(loop.cycles.load()) + " cycles)");

	// (b) a sync command the chip runs, one queued behind it; through the
	// claim holder's open file (dup()s of it): while the claim is held no
	// other file may send them (uapi.rst, "Permissions")
	bridge("async-stuck 1");
	const int fdB = dupOf(fdA), fdB2 = dupOf(fdA);
	Blocked b1([fdB](int &err) {
		ecmxf_cmd c = stuckCmd();
		const long ret = ::ioctl(fdB, ECMXF_IOC_CMD, &c);
		err = errno;
		return ret;
	});
	ok(waitUntil([] { return bridgeState("async-stuck") == 0; }, 60s),
	   "(b) the chip runs the stuck ECAT_STATE_UPDATE");
	ok(b1.asleep({ kSysIoctl }), "(b) a thread sleeps in ECMXF_IOC_CMD for it");
	Blocked b2([fdB2](int &err) {
		ecmxf_cmd c = stuckCmd();
		const long ret = ::ioctl(fdB2, ECMXF_IOC_CMD, &c);
		err = errno;
		return ret;
	});
	ok(b2.asleep({ kSysIoctl }), "(b) a second one sleeps in ECMXF_IOC_CMD, queued behind it");
	// a completion that the unbind ends (the holder's file too)
	const int fdE = dupOf(fdA);
	ecmxf_submit s{};
	s.hdr.code = kStateUpdate;
	s.cookie = 0xE1;
	s.timeout_us = kLongUs;
	eq("ECMXF_IOC_SUBMIT of an async command queued behind it", ::ioctl(fdE, ECMXF_IOC_SUBMIT, &s), 0);

	// (c) a poll()er and a reader
	const int fdC = openDev(path), fdD = openDev(path);
	short revents = 0;
	Blocked c([fdC, &revents](int &err) {
		pollfd p{ fdC, POLLIN, 0 };
		const long ret = ::poll(&p, 1, 60'000);
		err = errno;
		revents = p.revents;
		return ret;
	});
	ok(c.asleep({ kSysPoll, kSysPpoll }), "(c) a thread sleeps in poll(POLLIN)");
	Blocked d([fdD](int &err) {
		ecmxf_completion rec{};
		const long ret = ::read(fdD, &rec, sizeof(rec));
		err = errno;
		return ret;
	});
	ok(d.asleep({ kSysRead }), "(c) a thread sleeps in read()");

	ok(!loop.done, "(a) the cyclic loop still runs before the unbind (" + std::to_string(loop.cycles.load()) +
			       " cycles)");
	const std::uint64_t n0 = loop.cycles;
	const long refBefore = moduleRefcnt();

	// the unbind
	const auto t0 = std::chrono::steady_clock::now();
	{
		const int u = ::open("/sys/bus/spi/drivers/ecmxf/unbind", O_WRONLY | O_CLOEXEC);
		if (u < 0)
			fatal("open the driver's unbind file");
		const ssize_t w = ::write(u, spidev.data(), spidev.size());
		ok(w == static_cast<ssize_t>(spidev.size()), "unbind " + spidev);
		::close(u);
	}
	const std::uint32_t flagsNow = r.flags();
	const std::uint64_t n1 = loop.cycles;
	const auto t1 = std::chrono::steady_clock::now();
	std::printf("guest-test: info the unbind took %lld ms; the loop had run %llu cycles before it, %llu when it "
		    "returned\n",
		    static_cast<long long>(std::chrono::duration_cast<std::chrono::milliseconds>(t1 - t0).count()),
		    static_cast<unsigned long long>(n0), static_cast<unsigned long long>(n1));
	ok((flagsNow & ECMXF_RING_S_ERROR) && !(flagsNow & ECMXF_RING_S_ACTIVE),
	   "the mapped flags words say ECMXF_RING_S_ERROR, not ACTIVE, when the unbind returns");

	// (a)
	const bool loopDone = waitUntil([&] { return loop.done.load(); }, 10s);
	ok(loopDone, "(a) the cyclic loop saw the error");
	if (!loopDone) {
		loop.stop = true;
		if (!waitUntil([&] { return loop.done.load(); }, 10s))
			fatal("the cyclic loop does not end");
	}
	loopThread.join();
	ok(loop.seenFlags & ECMXF_RING_S_ERROR, "(a) ... as ECMXF_RING_S_ERROR in the mapped flags");
	ok(loop.seenAt <= n1 + 1, "(a) ... within one cycle of the unbind's return (seen after cycle " +
					  std::to_string(loop.seenAt.load()) + ", the unbind returned during cycle " +
					  std::to_string(n1 + 1) + ")");
	eq("(a) the status block's error is ENODEV", r.statusError(), ENODEV);

	// (b)
	mustFinish(b1, "(b) the ECMXF_IOC_CMD the chip ran");
	failsWith("(b)   it", b1.ret(), b1.err(), ENODEV);
	mustFinish(b2, "(b) the queued ECMXF_IOC_CMD");
	failsWith("(b)   it", b2.ret(), b2.err(), ENODEV);

	// (c)
	mustFinish(c, "(c) poll()");
	eq("(c)   poll() return value", c.ret(), 1);
	ok((revents & POLLERR) && (revents & POLLHUP),
	   "(c)   revents has POLLERR | POLLHUP (" + std::to_string(revents) + ")");
	ecmxf_completion rec{};
	errno = 0;
	long n = ::read(fdC, &rec, sizeof(rec));
	failsWith("(c)   read() afterwards", n, errno, ENODEV);
	mustFinish(d, "(c) the blocked read()");
	failsWith("(c)   it", d.ret(), d.err(), ENODEV);
	pollfd p{ fdE, POLLIN, 0 };
	eq("the SUBMIT fd: poll()", ::poll(&p, 1, 0), 1);
	ok((p.revents & POLLIN) && (p.revents & POLLERR) && (p.revents & POLLHUP),
	   "  revents POLLIN | POLLERR | POLLHUP (" + std::to_string(p.revents) + ")");
	rec = {};
	n = ::read(fdE, &rec, sizeof(rec));
	eq("  read() gives the completion record", n, static_cast<long>(sizeof(rec)));
	eq("  its cookie", rec.cookie, 0xE1);
	eq("  its status", rec.status, -ENODEV);
	errno = 0;
	n = ::read(fdE, &rec, sizeof(rec));
	failsWith("  the next read()", n, errno, ENODEV);

	// the claim holder's descriptor and the node
	p = { fdA, POLLIN, 0 };
	eq("the holder's fd: poll()", ::poll(&p, 1, 0), 1);
	ok((p.revents & POLLERR) && (p.revents & POLLHUP),
	   "  revents POLLERR | POLLHUP (" + std::to_string(p.revents) + ")");
	ecmxf_devinfo di{};
	iocFails("  ECMXF_IOC_DEVINFO", fdA, ECMXF_IOC_DEVINFO, &di, ENODEV);
	ecmxf_cmd cmd{};
	cmd.hdr.code = 1; // FW_VERSION_GET
	iocFails("  ECMXF_IOC_CMD", fdA, ECMXF_IOC_CMD, &cmd, ENODEV);
	iocFails("  ECMXF_IOC_RING_SETUP", fdA, ECMXF_IOC_RING_SETUP, &r.rs, ENODEV);
	void *m = ::mmap(nullptr, r.inLen, PROT_READ, MAP_SHARED, fdA, ECMXF_RING_OFF_IN);
	failsWith("  mmap() of the input ring", m == MAP_FAILED ? -1 : 0, errno, ENODEV);
	if (m != MAP_FAILED)
		::munmap(m, r.inLen);
	errno = 0;
	const int again = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
	failsWith("open() of " + path, again, errno, ENOENT);
	if (again >= 0)
		::close(again);

	// the mapping: valid memory until munmap()
	eq("the mapping still reads: the input ring's entries",
	   Rings::word(r.in, r.rs.in.entries).load(std::memory_order_relaxed), r.rs.in_entries);
	eq("  the output ring's mask", Rings::word(r.out, r.rs.out.mask).load(std::memory_order_relaxed),
	   r.rs.out_entries - 1);
	std::uint8_t *slot = r.out + r.rs.out.frames;
	slot[0] = 0x5A;
	eq("  and writes (an output slot)", slot[0], 0x5A);

	for (int fd : { fdB, fdB2, fdC, fdD, fdE })
		eq("close() of a descriptor", ::close(fd), 0);
	dev.reset(); // close() of the holder's descriptor: the mappings keep the file
	const long held = moduleRefcnt();
	ok(held > base, "after every close(): the mappings still hold the module (refcnt " + std::to_string(held) +
				", base " + std::to_string(base) + ", before the unbind " + std::to_string(refBefore) +
				")");
	errno = 0;
	const long rm = ::syscall(SYS_delete_module, "ecmxf", O_NONBLOCK);
	const int rmErr = errno;
	ok(rm < 0 && (rmErr == EWOULDBLOCK || rmErr == EBUSY),
	   std::string("  delete_module(ecmxf) is refused: ") + (rm < 0 ? std::strerror(rmErr) : "it succeeded"));
	if (rm == 0)
		fatal("the module went away under a mapping");
	eq("  the flags still say ECMXF_RING_S_ERROR", r.flags() & ECMXF_RING_S_ERROR, ECMXF_RING_S_ERROR);
	r.unmap();
	eq("after munmap(): module refcnt", moduleRefcnt(), base);
}

} // namespace

int main(int argc, char **argv)
{
	if (argc != 3) {
		std::fprintf(stderr, "usage: ecmxf-guest-unbind DEV SPIDEV\n");
		return 2;
	}
	try {
		const std::string path = argv[1], spidev = argv[2];
		const long base = moduleRefcnt();
		if (base < 0)
			fatal("no /sys/module/ecmxf/refcnt");
		closeWhileMapped(path, base);
		unbindUnderLoad(path, spidev, base);
	} catch (const std::exception &e) {
		std::printf("guest-test: FAIL exception: %s\n", e.what());
		return 1;
	}
	std::printf("guest-test: unbind: %d failure(s)\n", gFailures);
	return gFailures ? 1 : 0;
}
