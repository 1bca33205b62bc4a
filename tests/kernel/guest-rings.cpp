// SPDX-License-Identifier: MIT
// ecmxf-guest-rings: the cyclic path through the kernel's mmap()ed PDO
// rings, inside the QEMU guest (Documentation/kernel-testing.rst, "PDO
// rings"). The bridge runs the network printed by --network (2 x EST-584
// + a digital I/O terminal whose inputs mirror its outputs) with its clock
// scaled by K (bridge --time-scale K).
//
//   ecmxf-guest-rings --network                  print the network file
//   ecmxf-guest-rings run DEV HZ CYCLES K        the cyclic run (below)
//   ecmxf-guest-rings run-lockstep DEV HZ CYCLES the strict run (below)
//   ecmxf-guest-rings int1-storm DEV HZ CYCLES   a level INT1 held (below)
//
// run-lockstep: the bridge runs a lock-step bus (bridge --lockstep: a bus
// cycle only when the chip's RxFIFO has its frame and the TxFIFO room, as
// fast as frames come). The application is clocked by its inputs
// (Cyclic::waitInputs()) with 8 output frames in flight, and every output
// frame carries the next sequence number and CSP targets that are a
// function of the frame's index. Strict checks: every TxPDO frame carries
// exactly the previous sequence number + 1; after a drain, bus cycles run
// = frames sent = frames received; chip RxFIFO underruns and TxFIFO drops,
// kernel in_ring/rx_fifo/tx_fifo overruns, refused and skipped outputs,
// failed cycles all 0; the WKC expected on every read; both drives' positions
// in every input frame of the move equal the targets of that same output
// frame (the one whose number the I/O terminal echoes), and end at the
// targets.
//
// run: brings the bus up at HZ (SYNC0 = 1/HZ of chip time), maps the
// drives for CSP, and runs the library's Cyclic (which picks the kernel
// rings) for CYCLES bus cycles with the application period 1/HZ x K of
// guest time (the chip's clock runs K times slower, so the application
// runs once per bus cycle). It checks:
//  - a 32-bit sequence counter in the I/O terminal's outputs comes back in
//    its inputs (every TxPDO frame, through onInputFrame): never a gap,
//    never backwards; a value seen twice only when the chip's RxFIFO ran
//    empty (the chip then repeats the last outputs), and never more repeats
//    than the chip counted RxFIFO underruns (bridge state);
//  - the working counter the kernel's pump reads equals the expected one;
//  - both EST-584 drives follow a synchronized CSP trajectory to their
//    targets: positions never go backwards, never run ahead of the latest
//    target sent, and end at the targets;
//  - a second claimant gets EBUSY and the holder's pid (ioctl, the
//    library's error, sysfs); PDO_DATA_FIFO_OP is EBUSY while the rings
//    exist; mmap() and RING_SETUP refuse bad arguments;
//  - each ring's overflow is counted: not consuming inputs for a while
//    overflows the input ring (in.dropped = in_ring_overruns = what the
//    Cyclic reports); producing outputs without waiting fills the output
//    ring (refused frames reported).
//
// int1-storm: the rings running while a level INT1 is held asserted by a
// source the pump never clears (the EtherCAT-frame flag, enabled by
// ECAT_INT_SET_ENABLE and never cleared): the pump's commands carry the
// FIFO flags' clear bits, after which the worker unmasks INT1 at once, and
// the line fires again at once. The pump may let one INT1 bring a FIFO
// command forward per period (lib/core ecmxf_pump_sched_kick_held()), so
// its commands stay within 3 per period (timer, one INT1, the WKC read
// every 10th and work left) and the exchanges within twice that plus one
// header refresh per 10 ms hold-off; at the link's rate they would be
// tens per period. The bridge runs at the guest's time (no scaling).
// Exit status 0 when every check holds.

#include <ecmxf/chip/chip.hpp>
#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/kernel_link.hpp>
#include <ecmxf/bus/master.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/pdo/process_image.hpp>

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "bridge-ctl.hpp"
#include "uapi/linux/ecmxf.h"

using namespace std::chrono_literals;

namespace {

int gFailures = 0;

void ok(bool good, const std::string &what)
{
	std::printf("guest-test: %s %s\n", good ? "ok  " : "FAIL", what.c_str());
	if (!good)
		gFailures++;
}

template <typename A, typename B>
void eq(const std::string &what, const A &got, const B &want)
{
	ok(static_cast<long long>(got) == static_cast<long long>(want),
	   what + ": got " + std::to_string(static_cast<long long>(got)) + ", want " +
		   std::to_string(static_cast<long long>(want)));
}

constexpr const char *kNetwork = "# ecmxf-guest-rings: 2 x EST-584 + digital I/O 4/4 in loopback\n"
				 "name 2x EST-584 + digital I/O loopback (rings)\n"
				 "slave EST-584\n"
				 "slave EST-584\n"
				 "slave dio outputs=4 inputs=4 loopback=yes\n";

/// A number from the bridge's "state" reply ("... key=123 ...").
std::uint64_t bridgeStat(const std::string &key)
{
	std::string reply;
	if (!ecmxf::ktest::bridgeCtl("state", reply))
		throw ecmxf::Error("bridge state: " + reply, EIO);
	const auto at = reply.find(" " + key + "=");
	if (at == std::string::npos)
		throw ecmxf::Error("bridge state has no " + key + ": " + reply, EIO);
	return std::strtoull(reply.c_str() + at + key.size() + 2, nullptr, 0);
}

/// Output frames the kernel's pump skipped since probe (sysfs).
std::uint64_t ringSkipped()
{
	std::ifstream f("/sys/class/ecmxf/ecmxf0/ring_skipped");
	std::uint64_t v = 0;
	f >> v;
	return v;
}

/// The I/O terminal's sequence counter as it comes back, frame by frame.
struct Echo {
	std::size_t offset = 0; ///< of the terminal's inputs in a TxPDO frame
	bool started = false;
	std::uint32_t last = 0;
	std::uint64_t frames = 0, repeats = 0, gaps = 0, backwards = 0;

	static void onFrame(void *ctx, std::span<const std::uint8_t> f) noexcept
	{
		auto &e = *static_cast<Echo *>(ctx);
		std::uint32_t v = 0;
		std::memcpy(&v, f.data() + e.offset, sizeof(v));
		e.frames++;
		if (v == 0) // before the first output frame reached the bus
			return;
		if (!e.started) {
			e.started = true;
		} else if (v == e.last) {
			e.repeats++;
		} else if (v == e.last + 1) {
			// the next one
		} else if (v > e.last) {
			e.gaps++;
		} else {
			e.backwards++;
		}
		e.last = v;
	}
};

/// ECMXF_IOC_* with errno.
struct Res {
	int ret;
	int err;
};
template <typename T> Res ioc(int fd, unsigned long req, T arg)
{
	errno = 0;
	const int r = ::ioctl(fd, req, arg);
	return { r, r < 0 ? errno : 0 };
}

/// Claim, FIFO-command and mmap rules with the rings running (fd of the
/// holder's transport: @p holder).
void claimChecks(const std::string &path, int holder, std::uint32_t outEntries)
{
	const int other = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
	if (other < 0) {
		ok(false, "open a second descriptor");
		return;
	}
	Res r = ioc(other, ECMXF_IOC_CLAIM, 0);
	eq("second claimant: ECMXF_IOC_CLAIM fails with EBUSY", r.err, EBUSY);
	ecmxf_devinfo d{};
	r = ioc(other, ECMXF_IOC_DEVINFO, &d);
	eq("  devinfo.claim_pid is the holder's pid", d.claim_pid, ::getpid());
	ok((d.flags & ECMXF_DEVINFO_F_CLAIMED) && !(d.flags & ECMXF_DEVINFO_F_CLAIM_MINE) &&
		   (d.flags & ECMXF_DEVINFO_F_RINGS),
	   "  devinfo flags: claimed, not mine, rings set up");
	std::ifstream sysfs("/sys/class/ecmxf/ecmxf0/claim_pid");
	long spid = -1;
	sysfs >> spid;
	eq("  sysfs claim_pid is the holder's pid", spid, ::getpid());
	void *m = ::mmap(nullptr, 4096, PROT_READ, MAP_SHARED, other, ECMXF_RING_OFF_IN);
	eq("  mmap() of the input ring by a non-holder: EPERM", m == MAP_FAILED ? errno : 0, EPERM);
	ecmxf_ring_setup rs{};
	rs.out_entries = rs.in_entries = 8;
	r = ioc(other, ECMXF_IOC_RING_SETUP, &rs);
	eq("  RING_SETUP by a non-holder: EPERM", r.err, EPERM);
	::close(other);

	// the holder: bad arguments
	m = ::mmap(nullptr, 4096, PROT_READ, MAP_PRIVATE, holder, ECMXF_RING_OFF_IN);
	eq("holder: mmap() MAP_PRIVATE: EINVAL", m == MAP_FAILED ? errno : 0, EINVAL);
	m = ::mmap(nullptr, 4096, PROT_READ, MAP_SHARED, holder, 0x20000000);
	eq("holder: mmap() at an unknown offset: EINVAL", m == MAP_FAILED ? errno : 0, EINVAL);
	m = ::mmap(nullptr, 64u << 20, PROT_READ, MAP_SHARED, holder, ECMXF_RING_OFF_OUT);
	eq("holder: mmap() longer than mmap_size: EINVAL", m == MAP_FAILED ? errno : 0, EINVAL);
	rs = {};
	rs.out_entries = 3;
	rs.in_entries = 8;
	eq("holder: RING_SETUP with 3 entries: EINVAL", ioc(holder, ECMXF_IOC_RING_SETUP, &rs).err, EINVAL);
	rs.out_entries = 8192;
	eq("holder: RING_SETUP with 8192 entries: EINVAL", ioc(holder, ECMXF_IOC_RING_SETUP, &rs).err, EINVAL);
	rs.out_entries = outEntries;
	rs.reserved[1] = 1;
	eq("holder: RING_SETUP with a reserved field set: EINVAL", ioc(holder, ECMXF_IOC_RING_SETUP, &rs).err,
	   EINVAL);
	rs.reserved[1] = 0;
	for (std::uint32_t f : { 1u << 4, 0x80u, 1u << 31 }) {
		rs.flags = f | ECMXF_RING_F_WKC_NEXT;
		eq("holder: RING_SETUP with an unknown flag " + std::to_string(f) + ": EINVAL",
		   ioc(holder, ECMXF_IOC_RING_SETUP, &rs).err, EINVAL);
	}
	rs.flags = 0;
	rs.poll_us = 10;
	eq("holder: RING_SETUP with poll_us 10: EINVAL", ioc(holder, ECMXF_IOC_RING_SETUP, &rs).err, EINVAL);
	// the pump owns the FIFO exchange
	ecmxf_cmd c{};
	c.hdr.code = 5; // ECAT_PDO_DATA_FIFO_OP
	c.hdr.data[0] = 0x02;
	eq("holder: ECAT_PDO_DATA_FIFO_OP while the rings exist: EBUSY", ioc(holder, ECMXF_IOC_CMD, &c).err, EBUSY);

	// poll(): EPOLLIN means a completion only, and the holder has submitted
	// nothing, whatever the rings hold (their frames are EPOLLRDBAND, which
	// Cyclic::waitInputs() waits for in the lock-step runs)
	pollfd p{ holder, POLLIN | POLLRDNORM, 0 };
	eq("holder: poll() for POLLIN with the rings running and no completion: nothing", ::poll(&p, 1, 200), 0);
}

/// A u32 of a ring mapping, as the other side of the ring sees it.
volatile std::uint32_t *ringWord(void *map, std::uint32_t off)
{
	return reinterpret_cast<volatile std::uint32_t *>(static_cast<std::uint8_t *>(map) + off);
}

/// poll() for POLLRDBAND on @p fd in a thread; the revents it returned, or
/// -1 when it was still blocked after 5 s (then it is left to the exit).
class Poller
{
public:
	explicit Poller(int fd)
	{
		t_ = std::thread([this, fd] {
			pollfd p{ fd, POLLRDBAND, 0 };
			const int n = ::poll(&p, 1, 20000);
			revents_.store(n > 0 ? p.revents : 0);
			done_.store(true);
		});
		// the thread is inside poll() before the caller acts, or soon
		// after: either way poll() sees the state the caller makes
		std::this_thread::sleep_for(50ms);
	}
	~Poller()
	{
		if (t_.joinable())
			t_.detach();
	}
	Poller(const Poller &) = delete;
	Poller &operator=(const Poller &) = delete;
	/// Blocks until poll() returned or 5 s passed.
	int result()
	{
		for (int i = 0; i < 500 && !done_.load(); i++)
			std::this_thread::sleep_for(10ms);
		if (!done_.load())
			return -1;
		t_.join();
		return revents_.load();
	}

private:
	std::thread t_;
	std::atomic<int> revents_{ 0 };
	std::atomic<bool> done_{ false };
};

/// Rings the test makes itself on the holder's descriptor @p holder (the
/// library's Cyclic stopped, the bus still in OP; @p dev, the holder's
/// device, turns the FIFOs on), one
/// bus cycle every @p period of guest time:
///  - what the kernel writes into the mapping (the output ring's head, the
///    input ring's tail, the dropped counts) it never reads back: a process
///    that scribbles on them changes no kernel count and stops nothing;
///  - ECMXF_IOC_CLAIM_BREAK by another descriptor stops the holder's rings
///    (ECONNABORTED), wakes its poll()ers, and leaves it only queries;
///  - RELEASE tears the rings down and wakes the holder's poll()ers.
void kernelOwnedChecks(ecmxf::Device &dev, const std::string &path, int holder, std::chrono::nanoseconds period)
{
	// Cyclic::stop() turned the chip's FIFOs off: on again for the pump
	dev.pdo().fifoEnable(true);
	// a loop of setup + mmap: the replaced rings live on while mapped, so
	// the kernel bounds how many sets exist (3: the library's, still
	// mapped, counts) and refuses the rest
	{
		std::vector<std::pair<void *, std::size_t>> maps;
		int refusedAt = -1;
		for (int i = 0; i < 8 && refusedAt < 0; i++) {
			ecmxf_ring_setup l{};
			l.out_entries = l.in_entries = 16;
			const Res lr = ioc(holder, ECMXF_IOC_RING_SETUP, &l);
			if (lr.ret < 0) {
				eq("setup + mmap loop: the refusal is EBUSY", lr.err, EBUSY);
				refusedAt = i;
				break;
			}
			void *m = ::mmap(nullptr, l.in.mmap_size, PROT_READ, MAP_SHARED, holder, ECMXF_RING_OFF_IN);
			if (m != MAP_FAILED)
				maps.emplace_back(m, l.in.mmap_size);
		}
		eq("setup + mmap loop: refused at the 3rd setup (the library's rings, two of the loop's mapped)",
		   refusedAt, 2);
		for (auto [m, n] : maps)
			::munmap(m, n);
	}
	ecmxf_ring_setup rs{};
	rs.out_entries = 256;
	rs.in_entries = 16;
	Res r = ioc(holder, ECMXF_IOC_RING_SETUP, &rs);
	eq("raw rings: RING_SETUP on the holder's descriptor", r.err, 0);
	if (r.ret < 0)
		return;
	void *om = ::mmap(nullptr, rs.out.mmap_size, PROT_READ | PROT_WRITE, MAP_SHARED, holder, ECMXF_RING_OFF_OUT);
	void *im = ::mmap(nullptr, rs.in.mmap_size, PROT_READ | PROT_WRITE, MAP_SHARED, holder, ECMXF_RING_OFF_IN);
	ok(om != MAP_FAILED && im != MAP_FAILED, "raw rings: both mapped");
	if (om == MAP_FAILED || im == MAP_FAILED)
		return;
	volatile std::uint32_t *outHead = ringWord(om, rs.out.head), *outTail = ringWord(om, rs.out.tail),
			       *outFlags = ringWord(om, rs.out.flags), *inTail = ringWord(im, rs.in.tail),
			       *inDropped = ringWord(im, rs.in.dropped);
	// one (all-zero) output frame per bus cycle; the input ring is never
	// read, so it fills (16) and overflows
	std::uint32_t tail = 0;
	const auto produce = [&](int cycles) {
		for (int i = 0; i < cycles; i++) {
			*outTail = ++tail;
			std::this_thread::sleep_for(period);
		}
	};
	produce(30);
	ok(*inDropped > 0, "raw rings: the input ring overflowed (" + std::to_string(*inDropped) + " dropped)");
	// scribble on what only the kernel writes
	*outHead = 0xDEAD0000u;
	*inTail = 0x12340000u;
	*inDropped = 999999u;
	produce(60);
	eq("scribbled: the output ring still runs (flags ACTIVE, not ERROR: the kernel's head is its own)",
	   *outFlags, ECMXF_RING_S_ACTIVE);
	ok(*outHead != 0xDEAD0000u && tail - *outHead <= rs.out_entries,
	   "scribbled: the kernel wrote its own output head back (" + std::to_string(*outHead) + ", tail " +
		   std::to_string(tail) + ")");
	eq("scribbled: the kernel wrote its own input tail back (16 frames stored, none read)", *inTail, 16);
	ok(*inDropped > 0 && *inDropped < 999999u,
	   "scribbled: the input ring's dropped count is the kernel's own, not added to the scribble (" +
		   std::to_string(*inDropped) + ")");

	// an operator breaks the claim
	{
		Poller waiter(holder); // no POLL_IN in the setup: blocks
		const int other = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
		eq("CLAIM_BREAK by another descriptor (root)", ioc(other, ECMXF_IOC_CLAIM_BREAK, 0).err, 0);
		const int rev = waiter.result();
		ok(rev >= 0 && (rev & POLLERR), "  the holder's poll() for its rings woke with POLLERR (revents " +
							 std::to_string(rev) + ")");
		eq("  the holder's rings stopped (flags ERROR)", *outFlags, ECMXF_RING_S_ERROR);
		eq("  the old holder: CLAIM is EBUSY", ioc(holder, ECMXF_IOC_CLAIM, 0).err, EBUSY);
		ecmxf_cmd c{};
		c.hdr.code = ECMXF_CMD_ECAT_STATE_UPDATE;
		eq("  the old holder: ECAT_STATE_UPDATE (chip class) is EBUSY", ioc(holder, ECMXF_IOC_CMD, &c).err,
		   EBUSY);
		ecmxf_devinfo d{};
		(void)ioc(other, ECMXF_IOC_DEVINFO, &d);
		ok(d.flags & ECMXF_DEVINFO_F_CLAIM_MINE, "  the breaker holds the claim");
		eq("  the breaker: CLAIM_BREAK of its own claim (nothing to break)",
		   ioc(other, ECMXF_IOC_CLAIM_BREAK, 0).err, 0);
		(void)ioc(other, ECMXF_IOC_DEVINFO, &d);
		ok(d.flags & ECMXF_DEVINFO_F_CLAIM_MINE, "  and keeps it");
		eq("  the breaker: RELEASE", ioc(other, ECMXF_IOC_RELEASE, 0).err, 0);
		eq("  CLAIM_BREAK with no claim held: ENOENT", ioc(other, ECMXF_IOC_CLAIM_BREAK, 0).err, ENOENT);
		::close(other);
	}
	::munmap(om, rs.out.mmap_size);
	::munmap(im, rs.in.mmap_size);
	// RELEASE wakes the holder's poll()ers
	eq("the old holder claims again", ioc(holder, ECMXF_IOC_CLAIM, 0).err, 0);
	rs = {};
	rs.out_entries = rs.in_entries = 16;
	eq("  and sets up rings", ioc(holder, ECMXF_IOC_RING_SETUP, &rs).err, 0);
	{
		Poller waiter(holder);
		eq("  RELEASE", ioc(holder, ECMXF_IOC_RELEASE, 0).err, 0);
		const int rev = waiter.result();
		ok(rev >= 0 && (rev & POLLERR),
		   "  a poll() for the released rings woke with POLLERR (revents " + std::to_string(rev) + ")");
	}
	// the library's way to it (ecmxf-util states --break-claim)
	{
		auto op = ecmxf::Device::open(path);
		ok(!op->link().breakClaim(), "Link::breakClaim() with no claim held: nullopt");
		eq("the old holder claims again", ioc(holder, ECMXF_IOC_CLAIM, 0).err, 0);
		const std::optional<std::uint32_t> was = op->link().breakClaim();
		ok(was && *was == static_cast<std::uint32_t>(::getpid()),
		   "Link::breakClaim() names the holder's pid (" + std::to_string(was.value_or(0)) + ")");
		eq("  the old holder: CLAIM is EBUSY while the operator's file is open",
		   ioc(holder, ECMXF_IOC_CLAIM, 0).err, EBUSY);
	}
	eq("the operator's file closed: the old holder may claim", ioc(holder, ECMXF_IOC_CLAIM, 0).err, 0);
}

int run(const std::string &path, unsigned hz, unsigned cycles, unsigned scale, bool fifoNext)
{
	const auto bus = std::chrono::nanoseconds(1'000'000'000LL / hz);
	const auto period = bus * scale; // guest time per bus cycle
	std::printf("guest-test: info rings: %u cycles at %u Hz (chip time), application period %lld us (scale %u)%s\n",
		    cycles, hz, static_cast<long long>(period.count() / 1000), scale,
		    fifoNext ? ", ECMXF_RING_F_FIFO_NEXT" : "");

	auto dev = ecmxf::Device::open(path);
	auto *kt = dynamic_cast<ecmxf::KernelLink *>(&dev->link());
	if (!kt) {
		ok(false, "the device is opened by the kernel transport");
		return 1;
	}
	// the guest under TCG on a loaded host can stall beyond a command's
	// default 100 ms (as the integration suite does)
	dev->setMinimumTimeout(std::chrono::seconds(2));
	ecmxf::Master master(*dev);
	ecmxf::MasterConfig mc;
	mc.init.dc.sync0Ns = static_cast<std::uint32_t>(bus.count());
	mc.pdoAssignments = { ecmxf::est584MotionPdos(0), ecmxf::est584MotionPdos(1) };
	master.bringUp(mc);
	ecmxf::ProcessImage image(master.pdos());
	const std::size_t ioOut = image.outputOffset(2), ioIn = image.inputOffset(2);

	Echo echo;
	echo.offset = ioIn;
	ecmxf::CyclicConfig cc;
	cc.period = period;
	cc.busCycle = 0ns; // the library's clock is the guest's: no estimate
	cc.rxFill = 4;
	cc.wkcEvery = 10;
	cc.fifoAnswerNextCycle = fifoNext;
	cc.onInputFrame = &Echo::onFrame;
	cc.context = &echo;
	ecmxf::Cyclic cyc(*dev, image, cc);
	ok(cyc.usesKernelRings(), "Cyclic over /dev/ecmxf0 uses the kernel's PDO rings");

	// a second claimant, with the library's words
	{
		auto dev2 = ecmxf::Device::open(path);
		try {
			ecmxf::Cyclic cyc2(*dev2, image, cc);
			ok(false, "a second Cyclic on another descriptor was refused");
		} catch (const ecmxf::Error &e) {
			const std::string want = "is claimed by process " + std::to_string(::getpid());
			ok(e.errnoValue() == EBUSY && std::string_view(e.what()).find(want) != std::string_view::npos,
			   std::string("a second Cyclic: EBUSY naming the holder: \"") + e.what() + "\"");
		}
	}

	// the axes time out on the guest's clock: K x the chip's time
	ecmxf::Cia402AxisConfig ac;
	ac.modes = { ecmxf::cia402::kModeCsp };
	ac.state.timeout *= scale;
	ac.modeTimeout *= scale;
	ac.ackTimeout *= scale;
	ecmxf::Cia402Axis a0(*dev, image, 0, ac);
	ecmxf::Cia402Axis a1(*dev, image, 1, ac);
	std::vector<ecmxf::Cia402Axis *> axes{ &a0, &a1 };
	std::uint32_t seq = 0;
	auto setSeq = [&] {
		seq++;
		std::memcpy(image.outputs().data() + ioOut, &seq, sizeof(seq));
	};
	for (auto *a : axes)
		a->setMode(ecmxf::cia402::kModeCsp, kt->now());
	cyc.start();
	claimChecks(path, kt->fd(), 16);

	// the state walk, then CSP (a few hundred cycles)
	std::uint64_t failed = 0;
	auto step = [&]() -> const ecmxf::CycleResult & {
		setSeq();
		const ecmxf::CycleResult &r = cyc.cycle();
		if (r.error && failed++ < 5)
			std::printf("guest-test: info cycle error %d: %s\n", r.error, r.message);
		for (auto *a : axes)
			a->update(kt->now());
		cyc.waitNextCycle();
		return r;
	};
	for (int i = 0; i < 4000 && !std::all_of(axes.begin(), axes.end(), [](auto *a) { return a->done(); }); i++)
		step();
	ok(a0.done() && a1.done(), "both drives in CSP mode");
	for (auto *a : axes)
		a->enable(kt->now());
	for (int i = 0; i < 4000 && !std::all_of(axes.begin(), axes.end(), [](auto *a) { return a->done(); }); i++)
		step();
	ok(a0.enabled() && a1.enabled(), "both drives OPERATION ENABLED over the rings");
	for (auto *a : axes)
		a->startCsp(kt->now());

	// the measured run: CYCLES bus cycles, the CSP move over most of them
	const std::array<std::int32_t, 2> from{ a0.position(), a1.position() };
	const std::array<std::int32_t, 2> to{ from[0] + 40000, from[1] - 25000 };
	const auto moveTime = bus * (cycles * 8 / 10);
	const ecmxf::CspTrajectory traj(from, to, moveTime);
	std::vector<std::int32_t> cmd0, cmd1;
	cmd0.reserve(cycles + 1);
	cmd1.reserve(cycles + 1);
	bool backwards0 = false, backwards1 = false, unknownPos = false;
	std::int32_t prev0 = from[0], prev1 = from[1];
	const ecmxf::CyclicStats s0 = cyc.stats();
	const ecmxf::LinkCounters k0 = kt->counters();
	const std::uint64_t skip0 = ringSkipped();
	const std::uint64_t under0 = bridgeStat("rx-underruns");
	const std::uint64_t bus0 = bridgeStat("bus-cycles"), txDrop0 = bridgeStat("tx-dropped");
	const Echo e0 = echo;
	// CYCLES bus cycles of chip time (K x as long on the guest's clock);
	// the application runs once per bus cycle as long as the guest keeps
	// up (a late cycle skips to the next boundary, lateCycles counts it)
	const auto tStart = kt->now();
	const auto runTime = period * cycles;
	while (kt->now() - tStart < runTime) {
		traj.apply(axes, (kt->now() - tStart) / scale + bus);
		cmd0.push_back(a0.cspTarget());
		cmd1.push_back(a1.cspTarget());
		const ecmxf::CycleResult &r = step();
		if (r.inputsUpdated) {
			const std::int32_t p0 = a0.position(), p1 = a1.position();
			backwards0 = backwards0 || p0 < prev0;
			backwards1 = backwards1 || p1 > prev1;
			// never beyond what was commanded so far (when the guest
			// stalls, targets jump and a drive ramps at its own speed
			// through positions between two targets)
			if (p0 < from[0] || p0 > cmd0.back() || p1 > from[1] || p1 < cmd1.back())
				unknownPos = true;
			prev0 = p0;
			prev1 = p1;
		}
	}
	// let the last targets arrive
	for (int i = 0; i < 50; i++)
		step();
	const ecmxf::CyclicStats s1 = cyc.stats();
	const ecmxf::LinkCounters k1 = kt->counters();
	const std::uint64_t skip1 = ringSkipped();
	const std::uint64_t under1 = bridgeStat("rx-underruns");
	const std::uint64_t bus1 = bridgeStat("bus-cycles"), txDrop1 = bridgeStat("tx-dropped");
	const std::uint64_t frames = echo.frames - e0.frames;
	std::printf("guest-test: info %u Hz: %llu cycles, %llu frames out, %llu frames in, %llu echo repeats, "
		    "%llu chip RxFIFO underruns, kernel: rx_fifo_underruns %llu "
		    "out_ring_underruns %llu, wkc reads %llu, late cycles %llu\n",
		    hz, static_cast<unsigned long long>(s1.cycles - s0.cycles),
		    static_cast<unsigned long long>(s1.framesPushed - s0.framesPushed),
		    static_cast<unsigned long long>(s1.framesPopped - s0.framesPopped),
		    static_cast<unsigned long long>(echo.repeats - e0.repeats),
		    static_cast<unsigned long long>(under1 - under0),
		    static_cast<unsigned long long>(k1.rxFifoUnderruns - k0.rxFifoUnderruns),
		    static_cast<unsigned long long>(k1.outRingUnderruns - k0.outRingUnderruns),
		    static_cast<unsigned long long>(s1.wkcReads - s0.wkcReads),
		    static_cast<unsigned long long>(s1.lateCycles - s0.lateCycles));
	eq("cycles without an error", s1.failedCycles - s0.failedCycles, 0);
	// every bus cycle made one TxPDO frame: it was received, or dropped and
	// counted (by the chip's full TxFIFO or the full input ring), or it is
	// still on its way (TxFIFO and ring at the two reads of the counts)
	{
		const std::uint64_t made = bus1 - bus0;
		const std::uint64_t lost = (txDrop1 - txDrop0) + (k1.inRingOverruns - k0.inRingOverruns);
		const std::uint64_t accounted = frames + lost;
		const std::uint64_t slack = 2 * (cyc.txDepth() + 256) + 4;
		std::printf("guest-test: info %u Hz: %llu bus cycles, %llu TxPDO frames received, %llu dropped by the "
			    "chip's TxFIFO, %llu by the input ring\n",
			    hz, static_cast<unsigned long long>(made), static_cast<unsigned long long>(frames),
			    static_cast<unsigned long long>(txDrop1 - txDrop0),
			    static_cast<unsigned long long>(k1.inRingOverruns - k0.inRingOverruns));
		ok(accounted + slack >= made && accounted <= made + slack,
		   "every TxPDO frame received or counted as dropped (" + std::to_string(accounted) + " for " +
			   std::to_string(made) + " bus cycles, give or take the " + std::to_string(slack) +
			   " in flight)");
		ok(made >= cycles - cycles / 20, "the bus ran " + std::to_string(made) + " cycles");
	}
	// under TCG on a shared host the guest can stall for longer than the
	// FIFOs and rings hold: a loss must then be counted, never silent
	// each gap is at least one frame lost; the frames lost that were
	// counted: outputs the full output ring refused (one per refusing
	// cycle), outputs the pump skipped, inputs the chip's TxFIFO or the
	// input ring dropped
	const std::uint64_t skipped = skip1 - skip0;
	const std::uint64_t counted = (s1.rxRefusals - s0.rxRefusals) + skipped + (txDrop1 - txDrop0) +
				      (k1.inRingOverruns - k0.inRingOverruns);
	ok(echo.gaps - e0.gaps <= counted, "sequence counter: gaps (" + std::to_string(echo.gaps - e0.gaps) +
						   ") only where frames were counted as lost (" +
						   std::to_string(counted) + ")");
	std::printf("guest-test: info %u Hz: gaps %llu; counted: %llu cycles with a refused output, %llu outputs "
		    "skipped by the pump, %llu inputs dropped by the TxFIFO, %llu by the input ring (all 0 unless "
		    "the guest stalled)\n",
		    hz, static_cast<unsigned long long>(echo.gaps - e0.gaps),
		    static_cast<unsigned long long>(s1.rxRefusals - s0.rxRefusals),
		    static_cast<unsigned long long>(skipped), static_cast<unsigned long long>(txDrop1 - txDrop0),
		    static_cast<unsigned long long>(k1.inRingOverruns - k0.inRingOverruns));
	eq("sequence counter: values going backwards (reordered frames)", echo.backwards - e0.backwards, 0);
	// the chip's underrun count is read before the window opens, the
	// frames after it: a repeat made before the first read can still be
	// on its way (in the TxFIFO or the input ring, whose depth is at most
	// 2 x (TxFIFO depth + 4) or 32: RingPath::start())
	{
		const std::uint64_t inFlight = cyc.txDepth() + std::max<std::uint64_t>(32, 2 * (cyc.txDepth() + 4));
		ok(echo.repeats - e0.repeats <= under1 - under0 + inFlight,
		   "sequence counter: repeats (" + std::to_string(echo.repeats - e0.repeats) +
			   ") only where the chip's RxFIFO ran empty (" + std::to_string(under1 - under0) +
			   " underruns, give or take the " + std::to_string(inFlight) +
			   " frames in flight when the window opened)");
	}
	eq("kernel: rx_fifo_overruns (frames refused by the chip: the pump keeps a margin)",
	   k1.rxFifoOverruns - k0.rxFifoOverruns, 0);
	ok(s1.wkcReads - s0.wkcReads >= cycles / 20, "the pump read the WKC (" +
							     std::to_string(s1.wkcReads - s0.wkcReads) + " times)");
	eq("WKC mismatches (expected WKC " + std::to_string(cyc.expectedWkc()) + ")", s1.wkcMismatches - s0.wkcMismatches,
	   0);
	eq("WKC as last read", cyc.lastResult().wkc, cyc.expectedWkc());
	ok(!backwards0 && !backwards1, "CSP: the drives never moved backwards");
	ok(!unknownPos, "CSP: every position read lies between the start and the latest target sent");
	eq("CSP: drive 0 at its target", a0.position(), to[0]);
	eq("CSP: drive 1 at its target", a1.position(), to[1]);
	ok(!a0.failed() && !a1.failed(), "CSP: no following error, still OPERATION ENABLED");

	// overflow of the input ring: no cycle() for a while
	{
		const ecmxf::CyclicStats before = cyc.stats();
		const ecmxf::LinkCounters kb = kt->counters();
		// 400 bus cycles: more than the input ring and the TxFIFO hold
		std::this_thread::sleep_for(period * 400);
		const ecmxf::CycleResult r = cyc.cycle();
		const ecmxf::LinkCounters ka = kt->counters();
		ok(r.txOverflow, "input ring overflow: the next cycle reports lost inputs");
		ok(ka.inRingOverruns > kb.inRingOverruns, "  kernel in_ring_overruns counted " +
								  std::to_string(ka.inRingOverruns - kb.inRingOverruns));
		eq("  the cycle's lost-frame count is the kernel's", r.txDroppedEstimate,
		   ka.inRingOverruns - kb.inRingOverruns);
		eq("  and the statistics have it", cyc.stats().txDroppedEstimate - before.txDroppedEstimate,
		   ka.inRingOverruns - kb.inRingOverruns);
		cyc.waitNextCycle();
	}
	// overflow of the output ring: cycles without waiting
	{
		const ecmxf::CyclicStats before = cyc.stats();
		const auto t0 = kt->now();
		const unsigned n = 1000;
		const std::uint64_t skipBefore = ringSkipped();
		unsigned refused = 0;
		for (unsigned i = 0; i < n; i++)
			if (cyc.cycle().rxRefused)
				refused++;
		const auto dt = kt->now() - t0;
		// at most the ring (16), the chip's RxFIFO and one frame per bus
		// cycle gone by can have been taken
		const long long taken = 16 + static_cast<long long>(cyc.rxDepth()) + dt / period + 2;
		ok(refused > 0, "output ring overflow: " + std::to_string(refused) + " of " + std::to_string(n) +
					" frames refused, reported by cycle() (the pump skipped " +
					std::to_string(ringSkipped() - skipBefore) + ")");
		std::printf("guest-test: info output ring overflow: %u refused; at most %lld could have been taken "
			    "by the ring, the RxFIFO and the bus in %lld us\n",
			    refused, taken, static_cast<long long>(dt.count() / 1000));
		eq("  the statistics count them", cyc.stats().rxRefusals - before.rxRefusals, refused);
	}
	// the pump's skip: with the FIFOs off the pump sends nothing and the
	// output ring fills; on again, the pump finds more frames than the
	// RxFIFO's room plus its fill level and drops the oldest, counted in
	// the status block (CycleResult::outputsSkipped) and in sysfs alike
	{
		// both counts at a point where the pump cannot skip: no new
		// outputs for 20 periods (the pump skips a backlog down to what
		// fits at once), then one cycle() reads the status block
		const auto settle = [&] {
			std::this_thread::sleep_for(period * 20);
			(void)cyc.cycle();
		};
		settle();
		const ecmxf::CyclicStats before = cyc.stats();
		const std::uint64_t skipBefore = ringSkipped();
		dev->pdo().fifoEnable(false);
		// one more answer: the header the pump goes by shows them off
		ecmxf::Command info;
		info.code = ECMXF_CMD_INFO_UPDATE_OP;
		(void)dev->command(info);
		for (unsigned i = 0; i < 64; i++)
			(void)cyc.cycle(); // the ring full, the rest refused
		dev->pdo().fifoEnable(true);
		for (int i = 0; i < 20; i++) {
			(void)cyc.cycle();
			(void)cyc.waitNextCycle();
		}
		settle();
		const std::uint64_t sys = ringSkipped() - skipBefore;
		const std::uint64_t lib = cyc.stats().outputsSkipped - before.outputsSkipped;
		std::printf("guest-test: info pump skip: %llu frames skipped (sysfs), %llu (status block)\n",
			    static_cast<unsigned long long>(sys), static_cast<unsigned long long>(lib));
		ok(sys > 0, "pump skip: the FIFOs on again with a full output ring, the pump dropped the oldest (" +
				    std::to_string(sys) + ")");
		eq("  the status block's out_skipped (CycleResult::outputsSkipped) counts what sysfs ring_skipped does",
		   lib, sys);
	}
	cyc.stop();
	std::printf("guest-test: info rings %u Hz: counters exchanges %llu int1 %llu\n", hz,
		    static_cast<unsigned long long>(kt->counters().exchanges),
		    static_cast<unsigned long long>(kt->counters().int1Irqs));
	kernelOwnedChecks(*dev, path, kt->fd(), period);
	return gFailures ? 1 : 0;
}

/// Lock-step: the checks on every TxPDO frame, inside onInputFrame.
struct Strict {
	// byte offsets in the frames
	std::size_t seqIn = 0, pos0In = 0, pos1In = 0;
	/// the targets each output frame carried, by its sequence number
	const std::vector<std::array<std::int32_t, 2>> *targets = nullptr;
	/// from this sequence number on the drives follow the targets
	std::uint32_t cspFrom = UINT32_MAX;
	std::uint32_t expect = 1; ///< the next sequence number due
	std::uint64_t frames = 0, seqErrors = 0, cspFrames = 0, posErrors = 0;
	int shown = 0;

	static std::int32_t i32(std::span<const std::uint8_t> f, std::size_t off) noexcept
	{
		std::int32_t v = 0;
		std::memcpy(&v, f.data() + off, sizeof(v));
		return v;
	}

	static void onFrame(void *ctx, std::span<const std::uint8_t> f) noexcept
	{
		auto &c = *static_cast<Strict *>(ctx);
		std::uint32_t v = 0;
		std::memcpy(&v, f.data() + c.seqIn, sizeof(v));
		c.frames++;
		if (v != c.expect) {
			if (c.shown++ < 5)
				std::printf("guest-test: info frame %llu: sequence %u, want %u\n",
					    static_cast<unsigned long long>(c.frames), v, c.expect);
			c.seqErrors++;
		}
		c.expect = v + 1;
		// the drives took the target of the same output frame as the
		// I/O terminal its counter: positions of that frame's targets
		if (v >= c.cspFrom && v < c.targets->size()) {
			c.cspFrames++;
			const auto &t = (*c.targets)[v];
			const std::int32_t p0 = i32(f, c.pos0In), p1 = i32(f, c.pos1In);
			if (p0 != t[0] || p1 != t[1]) {
				if (c.shown++ < 5)
					std::printf("guest-test: info frame %u: positions %d %d, targets %d %d\n", v, p0,
						    p1, t[0], t[1]);
				c.posErrors++;
			}
		}
	}
};

/// run-lockstep: the bridge runs a lock-step bus (bridge --lockstep); the
/// application is clocked by its inputs and keeps a few frames in flight.
int runLockstep(const std::string &path, unsigned hz, unsigned cycles, bool fifoNext)
{
	const auto bus = std::chrono::nanoseconds(1'000'000'000LL / hz);
	constexpr unsigned kInFlight = 8; // output frames ahead of the inputs
	std::printf("guest-test: info lock-step: %u cycles at %u Hz (chip time), %u frames in flight\n", cycles, hz,
		    kInFlight);

	auto dev = ecmxf::Device::open(path);
	auto *kt = dynamic_cast<ecmxf::KernelLink *>(&dev->link());
	if (!kt) {
		ok(false, "the device is opened by the kernel transport");
		return 1;
	}
	dev->setMinimumTimeout(std::chrono::seconds(2));
	ecmxf::Master master(*dev);
	ecmxf::MasterConfig mc;
	mc.init.dc.sync0Ns = static_cast<std::uint32_t>(bus.count());
	mc.pdoAssignments = { ecmxf::est584MotionPdos(0), ecmxf::est584MotionPdos(1) };
	master.bringUp(mc);
	ecmxf::ProcessImage image(master.pdos());
	const std::size_t ioOut = image.outputOffset(2);
	const std::size_t tgt0 = image.outputOffset(0) + image.outputEntry(0, 0x607A, 0).bitOffset / 8;
	const std::size_t tgt1 = image.outputOffset(1) + image.outputEntry(1, 0x607A, 0).bitOffset / 8;

	std::vector<std::array<std::int32_t, 2>> targets;
	targets.reserve(cycles + 40100);
	targets.push_back({ 0, 0 }); // sequence numbers start at 1
	Strict chk;
	chk.seqIn = image.inputOffset(2);
	chk.pos0In = image.inputOffset(0) + image.inputEntry(0, 0x6064, 0).bitOffset / 8;
	chk.pos1In = image.inputOffset(1) + image.inputEntry(1, 0x6064, 0).bitOffset / 8;
	chk.targets = &targets;

	ecmxf::CyclicConfig cc;
	cc.period = bus;
	cc.busCycle = bus;
	cc.rxFill = kInFlight; // the pump keeps up to this many in the RxFIFO
	cc.wkcEvery = 10;
	// the pump's read answered by its next FIFO command
	// (ECMXF_RING_F_WKC_NEXT); the other run reads within the cycle.
	// fifoNext: the FIFO command's answer too (ECMXF_RING_F_FIFO_NEXT)
	cc.wkcAnswerNextCycle = true;
	cc.fifoAnswerNextCycle = fifoNext;
	cc.onInputFrame = &Strict::onFrame;
	cc.context = &chk;
	ecmxf::Cyclic cyc(*dev, image, cc);
	ok(cyc.usesKernelRings(), "Cyclic over /dev/ecmxf0 uses the kernel's PDO rings");

	ecmxf::Cia402AxisConfig ac;
	ac.modes = { ecmxf::cia402::kModeCsp };
	ac.state.timeout *= 10;
	ac.modeTimeout *= 10;
	ac.ackTimeout *= 10;
	ecmxf::Cia402Axis a0(*dev, image, 0, ac);
	ecmxf::Cia402Axis a1(*dev, image, 1, ac);
	std::vector<ecmxf::Cia402Axis *> axes{ &a0, &a1 };
	for (auto *a : axes)
		a->setMode(ecmxf::cia402::kModeCsp, kt->now());
	cyc.start();

	// from here on every bus cycle takes one of our frames
	const std::uint64_t bus0 = bridgeStat("bus-cycles"), under0 = bridgeStat("rx-underruns");
	const std::uint64_t txDrop0 = bridgeStat("tx-dropped"), waits0 = bridgeStat("bus-waits");
	const std::uint64_t chipUs0 = bridgeStat("chip-time-us");
	const std::uint64_t skip0 = ringSkipped();
	const ecmxf::LinkCounters k0 = kt->counters();
	const std::uint64_t cmds0 = cyc.stats().commands;
	const auto t0 = kt->now();

	std::uint32_t seq = 0;
	std::uint64_t waitFailures = 0, errors = 0, wkcReads = 0, wkcBad = 0;
	auto read32 = [&](std::size_t off) {
		std::int32_t v = 0;
		std::memcpy(&v, image.outputs().data() + off, sizeof(v));
		return v;
	};
	// one output frame: when kInFlight are on their way, first wait for
	// the inputs of the oldest (cycle() then takes them)
	auto push = [&] {
		const ecmxf::CyclicStats &s = cyc.stats();
		if (s.framesPushed - s.framesPopped >= kInFlight) {
			const int rc = cyc.waitInputs(std::chrono::seconds(10));
			if (rc && waitFailures++ < 5)
				std::printf("guest-test: info waitInputs: %s\n", std::strerror(rc));
		}
		seq++;
		std::memcpy(image.outputs().data() + ioOut, &seq, sizeof(seq));
		targets.push_back({ read32(tgt0), read32(tgt1) });
		const ecmxf::CycleResult &r = cyc.cycle();
		if (r.error && errors++ < 5)
			std::printf("guest-test: info cycle error %d: %s\n", r.error, r.message);
		if (r.wkcRead) {
			wkcReads++;
			if (r.wkc != cyc.expectedWkc())
				wkcBad++;
		}
		for (auto *a : axes)
			a->update(kt->now());
	};
	auto allDone = [&] { return std::all_of(axes.begin(), axes.end(), [](auto *a) { return a->done(); }); };
	for (int i = 0; i < 20000 && !allDone() && !waitFailures; i++)
		push();
	ok(a0.done() && a1.done(), "both drives in CSP mode");
	for (auto *a : axes)
		a->enable(kt->now());
	for (int i = 0; i < 20000 && !allDone() && !waitFailures; i++)
		push();
	ok(a0.enabled() && a1.enabled(), "both drives OPERATION ENABLED over the rings");
	for (auto *a : axes)
		a->startCsp(kt->now());

	// CYCLES frames of a CSP move as a function of the frame's index
	const std::array<std::int32_t, 2> from{ a0.position(), a1.position() };
	const std::array<std::int32_t, 2> to{ from[0] + 40000, from[1] - 25000 };
	const ecmxf::CspTrajectory traj(from, to, bus * (cycles * 8 / 10));
	chk.cspFrom = seq + 1;
	const std::uint32_t seqCsp = seq + 1;
	const auto tCsp = kt->now();
	for (unsigned k = 0; k < cycles && !waitFailures; k++) {
		traj.apply(axes, bus * (k + 1));
		push();
	}
	const auto tCspEnd = kt->now();

	// drain: no more frames; every one sent runs on the bus
	std::uint64_t busNow = 0;
	for (int i = 0; i < 250; i++) {
		busNow = bridgeStat("bus-cycles") - bus0;
		if (busNow >= cyc.stats().framesPushed)
			break;
		std::this_thread::sleep_for(20ms);
	}
	const std::uint64_t pushed = cyc.stats().framesPushed;
	// the inputs still on their way (TxFIFO, input ring): INT1 and the
	// pump's timer bring them within a few of its ticks
	(void)cyc.waitInputs(std::chrono::seconds(2));
	std::this_thread::sleep_for(300ms);
	// one last cycle() takes every input frame there is (its own output
	// frame is the only one not accounted for)
	const std::uint64_t poppedBefore = cyc.stats().framesPopped;
	const ecmxf::CycleResult &last = cyc.cycle();
	if (last.error)
		errors++;
	const std::uint64_t popped = cyc.stats().framesPopped;
	const auto t1 = kt->now();

	const ecmxf::CyclicStats &s = cyc.stats();
	const ecmxf::LinkCounters k1 = kt->counters();
	const std::uint64_t under = bridgeStat("rx-underruns") - under0;
	const std::uint64_t txDrop = bridgeStat("tx-dropped") - txDrop0;
	const std::uint64_t waits = bridgeStat("bus-waits") - waits0;
	const std::uint64_t chipUs = bridgeStat("chip-time-us") - chipUs0;
	const std::uint64_t skipped = ringSkipped() - skip0;
	const double guestS = std::chrono::duration<double>(t1 - t0).count();
	const double cspS = std::chrono::duration<double>(tCspEnd - tCsp).count();
	std::printf("guest-test: info lock-step %u Hz: %llu frames out, %llu bus cycles, %llu frames in (%llu "
		    "in the last cycle), %llu CSP frames checked; guest time %.1f s (the %u CSP cycles %.1f s, %.0f "
		    "cycles/s), chip time %.1f s; the bus waited %llu times\n",
		    hz, static_cast<unsigned long long>(pushed), static_cast<unsigned long long>(busNow),
		    static_cast<unsigned long long>(popped), static_cast<unsigned long long>(popped - poppedBefore),
		    static_cast<unsigned long long>(chk.cspFrames), guestS, cycles, cspS,
		    cspS > 0 ? cycles / cspS : 0.0, static_cast<double>(chipUs) / 1e6,
		    static_cast<unsigned long long>(waits));
	std::printf("guest-test: info lock-step %u Hz: kernel: exchanges %llu, int1 %llu, rx_fifo_underruns %llu "
		    "(the bus waiting for the next frame), out_ring_underruns %llu, timeouts %llu, retries %llu, "
		    "lost_answers %llu, bad packets %llu; wkc reads %llu\n",
		    hz, static_cast<unsigned long long>(k1.exchanges - k0.exchanges),
		    static_cast<unsigned long long>(k1.int1Irqs - k0.int1Irqs),
		    static_cast<unsigned long long>(k1.rxFifoUnderruns - k0.rxFifoUnderruns),
		    static_cast<unsigned long long>(k1.outRingUnderruns - k0.outRingUnderruns),
		    static_cast<unsigned long long>(k1.timeouts - k0.timeouts),
		    static_cast<unsigned long long>(k1.retries - k0.retries),
		    static_cast<unsigned long long>(k1.lostAnswers - k0.lostAnswers),
		    static_cast<unsigned long long>((k1.badNotReady + k1.badStart + k1.badEnd + k1.badCheck +
						     k1.badLength) -
						    (k0.badNotReady + k0.badStart + k0.badEnd + k0.badCheck +
						     k0.badLength)),
		    static_cast<unsigned long long>(wkcReads));
	// the kernel's SPI exchanges per pump command: two per FIFO command
	// answered within the pump's cycle (the second, which fetches the
	// answer, repeats the packet and counts as a poll), one with
	// ECMXF_RING_F_FIFO_NEXT (the read rides an exchange of its own either
	// way, answered by the next FIFO command). Polls also count packets
	// sent again while the guest's chip had not answered yet.
	const std::uint64_t cmds = s.commands - cmds0;
	const std::uint64_t sent = k1.exchanges - k0.exchanges;
	const double perCmd = cmds ? static_cast<double>(sent) / static_cast<double>(cmds) : 0.0;
	std::printf("guest-test: info lock-step %u Hz: %llu pump commands, %llu exchanges (%llu polls): %.2f per "
		    "command%s\n",
		    hz, static_cast<unsigned long long>(cmds), static_cast<unsigned long long>(sent),
		    static_cast<unsigned long long>(k1.polls - k0.polls), perCmd,
		    fifoNext ? " (ECMXF_RING_F_FIFO_NEXT)" : "");
	ok(cmds >= pushed / 4, "the status block counted the pump's commands (" + std::to_string(cmds) + ")");
	if (fifoNext)
		ok(perCmd <= 1.5, "ECMXF_RING_F_FIFO_NEXT: at most 1.5 exchanges per pump command (" +
					  std::to_string(perCmd) + ")");
	eq("waitInputs failures (no inputs within 10 s)", waitFailures, 0);
	eq("cycles with an error", s.failedCycles, 0);
	eq("bus cycles run = output frames sent (after the drain)", busNow, pushed);
	eq("input frames received = bus cycles run", popped, busNow);
	eq("sequence counter: frames not exactly the previous + 1 (lost, repeated or reordered)", chk.seqErrors, 0);
	eq("sequence counter: the last frame's value is the last frame sent", chk.expect - 1, pushed);
	eq("chip: RxFIFO underruns (bridge rx-underruns)", under, 0);
	eq("chip: TxPDO frames dropped (bridge tx-dropped)", txDrop, 0);
	eq("kernel: in_ring_overruns", k1.inRingOverruns - k0.inRingOverruns, 0);
	eq("kernel: rx_fifo_overruns (frames the chip refused)", k1.rxFifoOverruns - k0.rxFifoOverruns, 0);
	eq("kernel: tx_fifo_overruns", k1.txFifoOverruns - k0.txFifoOverruns, 0);
	eq("output frames refused (cycles with a refusal)", s.rxRefusals, 0);
	eq("output frames the pump skipped (ring_skipped)", skipped, 0);
	eq("TxFIFO/input ring overflows seen by cycle()", s.txOverflows, 0);
	ok(wkcReads >= cycles / 100, "the pump read the WKC (" + std::to_string(wkcReads) + " times)");
	eq("WKC reads not the expected " + std::to_string(cyc.expectedWkc()), wkcBad, 0);
	eq("CSP: frames checked", chk.cspFrames, pushed - seqCsp + 1);
	eq("CSP: input frames whose positions are not their frame's targets", chk.posErrors, 0);
	eq("CSP: drive 0 at its target", a0.position(), to[0]);
	eq("CSP: drive 1 at its target", a1.position(), to[1]);
	ok(!a0.failed() && !a1.failed(), "CSP: no following error, still OPERATION ENABLED");
	cyc.stop();
	return gFailures ? 1 : 0;
}

/// int1-storm (above)
int int1Storm(const std::string &path, unsigned hz, unsigned cycles, bool fifoNext)
{
	using namespace std::chrono;
	const auto bus = nanoseconds(1'000'000'000LL / hz);
	auto dev = ecmxf::Device::open(path);
	auto *kt = dynamic_cast<ecmxf::KernelLink *>(&dev->link());
	if (!kt) {
		ok(false, "the device is opened by the kernel transport");
		return 1;
	}
	dev->setMinimumTimeout(seconds(2));
	ecmxf::Master master(*dev);
	ecmxf::MasterConfig mc;
	mc.init.dc.sync0Ns = static_cast<std::uint32_t>(bus.count());
	mc.pdoAssignments = { ecmxf::est584MotionPdos(0), ecmxf::est584MotionPdos(1) };
	master.bringUp(mc);
	ecmxf::ProcessImage image(master.pdos());

	// the frame flag held: set every bus cycle, cleared by nobody
	ecmxf::InterruptConfig ic;
	ic.sources = ecmxf::irq::kEcatPacket;
	dev->chip().setInterruptConfig(ic);

	ecmxf::CyclicConfig cc;
	cc.period = bus;
	cc.busCycle = 0ns;
	cc.rxFill = 4;
	cc.wkcEvery = 10;
	cc.fifoAnswerNextCycle = fifoNext;
	ecmxf::Cyclic cyc(*dev, image, cc);
	ok(cyc.usesKernelRings(), "Cyclic over /dev/ecmxf0 uses the kernel's PDO rings");
	cyc.start();
	for (unsigned i = 0; i < 50; i++) {
		(void)cyc.cycle();
		cyc.waitNextCycle();
	}
	const auto k0 = kt->counters();
	const auto t0 = steady_clock::now();
	std::uint64_t commands = 0;
	for (unsigned i = 0; i < cycles; i++) {
		commands += cyc.cycle().commands;
		cyc.waitNextCycle();
	}
	const auto k1 = kt->counters();
	const auto us = duration_cast<microseconds>(steady_clock::now() - t0).count();
	cyc.stop();
	ic.sources = 0;
	dev->chip().setInterruptConfig(ic);

	const std::uint64_t periods = static_cast<std::uint64_t>(us) * hz / 1'000'000 + 1;
	const std::uint64_t irqs = k1.int1Irqs - k0.int1Irqs;
	const std::uint64_t exchanges = k1.exchanges - k0.exchanges;
	const std::uint64_t holdoffs = static_cast<std::uint64_t>(us) / 10'000 + 1;
	std::printf("guest-test: info int1-storm at %u Hz%s: %u cycles in %lld us (%llu periods): %llu pump commands, "
		    "%llu exchanges, %llu INT1 interrupts\n",
		    hz, fifoNext ? " (fifo-next)" : "", cycles, static_cast<long long>(us),
		    static_cast<unsigned long long>(periods), static_cast<unsigned long long>(commands),
		    static_cast<unsigned long long>(exchanges), static_cast<unsigned long long>(irqs));
	ok(irqs > 1, "the level INT1 fired during the run (the frame flag held it asserted)");
	ok(commands <= 3 * periods + 20, "pump commands within 3 per period (no INT1 storm): " +
						 std::to_string(commands) + " in " + std::to_string(periods) +
						 " periods");
	ok(exchanges <= 6 * periods + 2 * holdoffs + 40,
	   "exchanges within 6 per period + 2 per 10 ms hold-off (no INT1 storm): " + std::to_string(exchanges));
	return gFailures ? 1 : 0;
}

} // namespace

int main(int argc, char **argv)
{
	try {
		if (argc == 2 && std::string_view(argv[1]) == "--network") {
			std::fputs(kNetwork, stdout);
			return 0;
		}
		if ((argc == 6 || (argc == 7 && std::string_view(argv[6]) == "fifo-next")) &&
		    std::string_view(argv[1]) == "run") {
			const int rc = run(argv[2], static_cast<unsigned>(std::atoi(argv[3])),
					   static_cast<unsigned>(std::atoi(argv[4])), static_cast<unsigned>(std::atoi(argv[5])),
					   argc == 7);
			std::printf("guest-test: rings: %d failure(s)\n", gFailures);
			return rc;
		}
		if ((argc == 5 || (argc == 6 && std::string_view(argv[5]) == "fifo-next")) &&
		    std::string_view(argv[1]) == "run-lockstep") {
			const int rc = runLockstep(argv[2], static_cast<unsigned>(std::atoi(argv[3])),
						   static_cast<unsigned>(std::atoi(argv[4])), argc == 6);
			std::printf("guest-test: rings (lock-step): %d failure(s)\n", gFailures);
			return rc;
		}
		if ((argc == 5 || (argc == 6 && std::string_view(argv[5]) == "fifo-next")) &&
		    std::string_view(argv[1]) == "int1-storm") {
			const int rc = int1Storm(argv[2], static_cast<unsigned>(std::atoi(argv[3])),
						 static_cast<unsigned>(std::atoi(argv[4])), argc == 6);
			std::printf("guest-test: rings (int1-storm): %d failure(s)\n", gFailures);
			return rc;
		}
		std::fprintf(stderr, "usage: ecmxf-guest-rings --network | run DEV HZ CYCLES SCALE [fifo-next] | "
				     "run-lockstep DEV HZ CYCLES [fifo-next] | int1-storm DEV HZ CYCLES [fifo-next]\n");
		return 2;
	} catch (const std::exception &e) {
		std::printf("guest-test: FAIL exception: %s\n", e.what());
		return 1;
	}
}
