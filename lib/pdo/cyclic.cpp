// SPDX-License-Identifier: MIT
// Cyclic: the allocation-free, exception-free cyclic exchange of the
// process image (include/ecmxf/pdo/cyclic.hpp, Documentation/process-data.rst).
//
// The exchange itself is a strategy (CyclicPath). FifoCommandPath drives
// the chip's FIFOs with ECAT_PDO_DATA_FIFO_OP over Device::transact();
// RingPath, chosen when the Device's transport is a KernelTransport, moves
// the frames through the kernel's mmap()ed PDO rings, whose pump in the
// kernel sends those commands (Documentation/process-data.rst).

#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/kernel_transport.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/link/transport.hpp>

#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "ecmxf-proto.h"
#include "pdo/pdo_ring.hpp"

namespace ecmxf {

namespace {

using std::chrono::nanoseconds;

/// Frames kept free in the RxFIFO: the header's FIFO counts lag by up to
/// two exchanges (spec, "PDO exchange details").
constexpr unsigned kRxMargin = 2;

// Static failure texts: cycle() may not build strings.
#define ECMXF_FIFO_OP "ECAT_PDO_DATA_FIFO_OP: "
#define ECMXF_WC_GET "ECAT_PDO_WC_GET: "
#define ECMXF_TEXTS(P)                                                                                         \
	switch (err) {                                                                                         \
	case ETIMEDOUT:                                                                                        \
		return P "timed out waiting for the chip's answer";                                            \
	case EBADMSG:                                                                                          \
		return P "bad packets in a row (check word mismatch): the SPI link is failing";               \
	case EIO:                                                                                              \
		return P "the transport failed, or bad packets in a row";                                      \
	case EPROTO:                                                                                           \
		return P "the answer was lost on the wire";                                                    \
	case ECONNRESET:                                                                                       \
		return P "the chip reset while the command was in flight";                                     \
	case EMSGSIZE:                                                                                         \
		return P "the data does not fit the data section (was SPI_RECONFIG_OP sent meanwhile?)";      \
	case EBUSY:                                                                                            \
		return P "the device refused the command (busy)";                                             \
	case EREMOTEIO:                                                                                        \
		return P "the chip refused the command (error status bit 7, command error)";                  \
	case ECANCELED:                                                                                        \
		return P "the command was cancelled";                                                          \
	default:                                                                                               \
		return P "failed";                                                                             \
	}

const char *fifoOpText(int err) noexcept
{
	ECMXF_TEXTS(ECMXF_FIFO_OP)
}

const char *wcGetText(int err) noexcept
{
	ECMXF_TEXTS(ECMXF_WC_GET)
}

#undef ECMXF_TEXTS

constexpr const char *kNotWholeFrames = ECMXF_FIFO_OP "the TxPDO data is not a whole number of frames";
constexpr const char *kShortWkc = ECMXF_WC_GET "the answer is shorter than 4 bytes";
constexpr const char *kNotStarted = "Cyclic: cycle() before start()";

#undef ECMXF_FIFO_OP
#undef ECMXF_WC_GET

void fail(CycleResult &r, int err, const char *text) noexcept
{
	r.error = err;
	r.message = text;
}

/// How one cycle's frames travel between the image and the bus.
class CyclicPath
{
public:
	CyclicPath() = default;
	CyclicPath(const CyclicPath &) = delete;
	CyclicPath &operator=(const CyclicPath &) = delete;
	virtual ~CyclicPath() = default;

	/// Prepares the exchange (may send commands; throws ecmxf::Error).
	virtual void start() = 0;
	/// Ends it (throws ecmxf::Error).
	virtual void stop() = 0;
	/// One cycle: outputs out, inputs in; fills @p r (its WKC fields hold
	/// the previous read). Allocates nothing, throws nothing.
	virtual void exchange(CycleResult &r, bool readWkc) noexcept = 0;
	/// The clock the cycle is paced on.
	virtual Transport &clock() noexcept = 0;
	/// Cyclic::waitInputs() after its checks.
	virtual int waitInputs(nanoseconds timeout) noexcept = 0;
	/// The kernel's PDO rings carry the frames.
	[[nodiscard]] virtual bool kernelRings() const noexcept { return false; }

	/// Reads the frame sizes, slave counts and FIFO depths and checks the
	/// image and the configuration against them (throws ecmxf::Error).
	void readChip(Device &dev, const ProcessImage &image, const CyclicConfig &cfg);

	// what the path found out when it was set up
	FifoPackSizes sizes{};
	PdoSlaveCounts counts{};
	unsigned rxDepth = 0;
	unsigned txDepth = 0;
	unsigned rxFill = 0;
	unsigned perWrite = 0;
	unsigned perRead = 0;
};

/// The FIFO-command path: ECAT_PDO_DATA_FIFO_OP over Device::transact().
class FifoCommandPath final : public CyclicPath
{
public:
	FifoCommandPath(Device &dev, ProcessImage &image, const CyclicConfig &cfg);

	void start() override;
	void stop() override;
	void exchange(CycleResult &r, bool readWkc) noexcept override;
	Transport &clock() noexcept override { return dev_.transport(); }
	int waitInputs(nanoseconds timeout) noexcept override;

private:
	/// One ECAT_PDO_DATA_FIFO_OP: @p frames copies of the output frame,
	/// with a read when @p read. False (and @p r failed) on an error.
	bool fifoOp(CycleResult &r, unsigned frames, bool read, ResponseHeader &h) noexcept;
	/// Hands the TxPDO frames of the last answer over; their number, or -1
	/// (and @p r failed) when they are not whole frames.
	int takeFrames(CycleResult &r, const ResponseHeader &h) noexcept;

	Device &dev_;
	ProcessImage &image_;
	const CyclicConfig &cfg_;
	std::vector<std::uint8_t> txBuf_, rxBuf_;
	/// RxFIFO count after our last write, TxFIFO count after our last read
	/// (the answers' headers), and when those answers came.
	unsigned rxLevel_ = 0;
	unsigned txLevel_ = 0;
	nanoseconds rxTime_{ 0 }, txTime_{ 0 };
	unsigned maxReads_ = 0;
};

void CyclicPath::readChip(Device &dev, const ProcessImage &image, const CyclicConfig &cfg)
{
	sizes = dev.fifoPackSizes();
	counts = dev.pdoSlaveCounts();
	rxDepth = dev.fifoRxCount();
	txDepth = dev.fifoTxCount();

	const std::size_t outBytes = image.outputs().size();
	const std::size_t inBytes = image.inputs().size();
	if (outBytes != sizes.rxPdoBytes)
		throw Error("Cyclic: the process image has " + std::to_string(outBytes) +
				    " output bytes but the chip's RxPDO frame is " + std::to_string(sizes.rxPdoBytes) +
				    " bytes (FIFO_PACK_SIZE_GET 0): the mapping does not match the bus",
			    EINVAL);
	if (inBytes != sizes.txPdoBytes)
		throw Error("Cyclic: the process image has " + std::to_string(inBytes) +
				    " input bytes but the chip's TxPDO frame is " + std::to_string(sizes.txPdoBytes) +
				    " bytes (FIFO_PACK_SIZE_GET 1): the mapping does not match the bus",
			    EINVAL);
	const std::size_t cap = dev.pdoDataCapacity();
	for (int dir = 0; dir < 2; dir++) {
		const std::size_t n = dir == 0 ? sizes.rxPdoBytes : sizes.txPdoBytes;
		if (n > cap)
			throw Error(std::string("Cyclic: the ") + (dir == 0 ? "RxPDO" : "TxPDO") + " frame (" +
					    std::to_string(n) + " bytes) does not fit the SPI data section (" +
					    std::to_string(cap) + " bytes); enlarge it with SPI_RECONFIG_OP",
				    EMSGSIZE);
	}
	perWrite = sizes.rxPdoBytes ? static_cast<unsigned>(std::min<std::size_t>(255, cap / sizes.rxPdoBytes)) : 0;
	perRead = sizes.txPdoBytes ? static_cast<unsigned>(cap / sizes.txPdoBytes) : 0;

	const unsigned maxFill = rxDepth > kRxMargin ? rxDepth - kRxMargin : 1;
	if (cfg.rxFill > maxFill)
		throw Error("Cyclic: rxFill " + std::to_string(cfg.rxFill) + " out of range (1.." +
				    std::to_string(maxFill) + ": the RxFIFO depth " + std::to_string(rxDepth) +
				    " minus a margin of 2)",
			    EINVAL);
	rxFill = cfg.rxFill ? cfg.rxFill : maxFill;
}

FifoCommandPath::FifoCommandPath(Device &dev, ProcessImage &image, const CyclicConfig &cfg)
	: dev_(dev), image_(image), cfg_(cfg)
{
	readChip(dev, image, cfg);
	maxReads_ = perRead ? txDepth / perRead + 2 : 0;
	const std::size_t cap = dev.pdoDataCapacity();
	txBuf_.assign(cap, 0);
	rxBuf_.assign(cap, 0);
}

void FifoCommandPath::start()
{
	if (sizes.rxPdoBytes)
		dev_.pdoWrite(image_.outputs());
	dev_.fifoClear(FifoSelect::Both);
	dev_.fifoEnable(true);
	rxLevel_ = 0;
	txLevel_ = 0;
	rxTime_ = txTime_ = clock().now();
}

void FifoCommandPath::stop()
{
	dev_.fifoEnable(false);
}

bool FifoCommandPath::fifoOp(CycleResult &r, unsigned frames, bool read, ResponseHeader &h) noexcept
{
	const std::size_t frameBytes = sizes.rxPdoBytes;
	const std::span<const std::uint8_t> out = image_.outputs();
	for (unsigned i = 0; i < frames; i++)
		std::memcpy(txBuf_.data() + i * frameBytes, out.data(), frameBytes);
	RawCommand c;
	c.code = ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP;
	c.param = static_cast<std::uint8_t>(frames);
	c.data[0] = static_cast<std::uint8_t>((frames ? 0x01 : 0x00) | (read ? 0x02 : 0x00));
	// error status bits 5 and 7 then belong to this command alone
	c.control = ECMXF_CTL_CLR_CMD_ERR | ECMXF_CTL_CLR_FIFO_ERR;
	c.timeout = cfg_.commandTimeout;
	const int err = dev_.transact(c, std::span<const std::uint8_t>(txBuf_.data(), frames * frameBytes), rxBuf_, h);
	r.commands++;
	if (err) {
		fail(r, err, fifoOpText(err));
		return false;
	}
	if (h.errStatus & ECMXF_ERR_CMD) {
		fail(r, EREMOTEIO, fifoOpText(EREMOTEIO));
		return false;
	}
	return true;
}

int FifoCommandPath::takeFrames(CycleResult &r, const ResponseHeader &h) noexcept
{
	const std::size_t size = sizes.txPdoBytes;
	if (!size || h.len % size != 0) {
		fail(r, EPROTO, kNotWholeFrames);
		return -1;
	}
	const std::size_t n = h.len / size;
	if (n == 0)
		return 0;
	if (cfg_.onInputFrame)
		for (std::size_t i = 0; i < n; i++)
			cfg_.onInputFrame(cfg_.context, std::span<const std::uint8_t>(rxBuf_.data() + i * size, size));
	std::memcpy(image_.inputs().data(), rxBuf_.data() + (n - 1) * size, size);
	r.framesPopped += static_cast<unsigned>(n);
	r.inputsUpdated = true;
	return static_cast<int>(n);
}

int FifoCommandPath::waitInputs(nanoseconds timeout) noexcept
{
	if (!sizes.txPdoBytes)
		return EINVAL;
	// once per bus cycle: a new input frame can only come with one
	const nanoseconds step = cfg_.busCycle.count() > 0 ? cfg_.busCycle : cfg_.period;
	try {
		Transport &t = clock();
		const nanoseconds deadline = t.now() + std::max(timeout, nanoseconds(0));
		for (;;) {
			// a FIFO command that moves no frame: its answer's header
			// has the TxFIFO count
			RawCommand c;
			c.code = ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP;
			c.control = ECMXF_CTL_CLR_CMD_ERR;
			c.timeout = cfg_.commandTimeout;
			ResponseHeader h{};
			const int err = dev_.transact(c, {}, rxBuf_, h);
			if (err)
				return err;
			if (h.errStatus & ECMXF_ERR_CMD)
				return EREMOTEIO;
			if (h.txFifoCnt > 0)
				return 0;
			const nanoseconds now = t.now();
			if (now >= deadline)
				return ETIMEDOUT;
			t.sleepFor(std::min(step, deadline - now));
		}
	} catch (...) {
		return EIO;
	}
}

void FifoCommandPath::exchange(CycleResult &r, bool readWkc) noexcept
{
	const bool haveOut = sizes.rxPdoBytes > 0;
	const bool haveIn = sizes.txPdoBytes > 0;
	ResponseHeader h{};

	// frames to push: up to the target level, at least this cycle's
	// outputs. The RxFIFO count is from our last write; since then about
	// one frame per bus cycle went out (one per application cycle when
	// the bus cycle is not configured).
	unsigned want = 0;
	if (haveOut) {
		std::uint64_t gone = 1;
		if (cfg_.busCycle.count() > 0) {
			const nanoseconds dt = clock().now() - rxTime_;
			gone = dt.count() > 0 ? static_cast<std::uint64_t>(dt / cfg_.busCycle) : 0;
		}
		const unsigned level = gone >= rxLevel_ ? 0u : rxLevel_ - static_cast<unsigned>(gone);
		want = level < rxFill ? rxFill - level : 1u;
	}

	// the writes; the first command also reads
	bool first = haveOut || haveIn;
	unsigned left = want;
	while (first || left > 0) {
		const unsigned k = std::min(left, perWrite);
		const bool read = first && haveIn;
		if (!fifoOp(r, k, read, h))
			return;
		r.framesPushed += k;
		// return value bit 0 clear: the RxFIFO was full, the newest
		// frames were refused, and more would be too
		const bool refused = k && !(h.ret & 0x01);
		if (k) {
			rxLevel_ = h.rxFifoCnt;
			rxTime_ = clock().now();
		}
		if (read) {
			const int n = takeFrames(r, h);
			if (n < 0)
				return;
			// the answer's TxFIFO count is right after the read: popped +
			// left = what was queued; a full FIFO has dropped its oldest
			const unsigned queued = static_cast<unsigned>(n) + h.txFifoCnt;
			const nanoseconds now = clock().now();
			if (txDepth && queued >= txDepth) {
				r.txOverflow = true;
				if (cfg_.busCycle.count() > 0) {
					const auto made = static_cast<std::uint64_t>((now - txTime_) / cfg_.busCycle);
					const std::uint64_t expected = txLevel_ + made;
					r.txDroppedEstimate = expected > queued
								      ? static_cast<std::uint32_t>(std::min<std::uint64_t>(
										expected - queued, UINT32_MAX))
								      : 0;
				}
			}
			txTime_ = now;
			txLevel_ = h.txFifoCnt;
			// more queued than one answer holds: read on while the
			// answer's count says so (a count that lags shows up as
			// an empty read, or as frames left for the next cycle)
			for (unsigned reads = 0; h.txFifoCnt > 0 && reads < maxReads_; reads++) {
				if (!fifoOp(r, 0, true, h))
					return;
				const int m = takeFrames(r, h);
				if (m < 0)
					return;
				txLevel_ = h.txFifoCnt;
				txTime_ = clock().now();
				if (m == 0)
					break;
			}
		}
		first = false;
		left -= k;
		if (refused) {
			r.rxRefused = true;
			break;
		}
	}

	if (readWkc) {
		RawCommand c;
		c.code = ECMXF_CMD_ECAT_PDO_WC_GET;
		c.param = 3;
		c.control = ECMXF_CTL_CLR_CMD_ERR;
		c.timeout = cfg_.commandTimeout;
		std::array<std::uint8_t, 4> v{};
		const int err = dev_.transact(c, {}, v, h);
		r.commands++;
		if (err) {
			fail(r, err, wcGetText(err));
			return;
		}
		if (h.errStatus & ECMXF_ERR_CMD) {
			fail(r, EREMOTEIO, wcGetText(EREMOTEIO));
			return;
		}
		if (h.len < 4) {
			fail(r, EPROTO, kShortWkc);
			return;
		}
		r.wkcRead = true;
		r.wkc = static_cast<std::uint32_t>(v[0]) | static_cast<std::uint32_t>(v[1]) << 8 |
			static_cast<std::uint32_t>(v[2]) << 16 | static_cast<std::uint32_t>(v[3]) << 24;
		r.wkcOk = r.wkc == r.expectedWkc;
	}

	r.rxFifoCount = h.rxFifoCnt;
	r.txFifoCount = h.txFifoCnt;
	r.wkcErrorCount = h.wkcErrCnt;
	r.ecatState = h.ecatState;
	r.errStatus = h.errStatus;
	r.ecmStatus = h.ecmStatus;
	r.intFlags = h.intFlags;
}

// ---------------------------------------------------------------------------
// RingPath: the kernel's PDO rings
// ---------------------------------------------------------------------------

constexpr const char *kPumpStopped =
	"PDO rings: the kernel's pump stopped (the chip reset or the link was lost); stop() and start() again";
constexpr const char *kNoRings = "PDO rings: not mapped (start() failed?)";
constexpr const char *kPumpFailed =
	"PDO rings: a command of the kernel's pump failed (no answer in time, or bad packets): its output frames "
	"are not sent again, the input frames of its answer are lost";

std::uint32_t pow2AtLeast(std::uint64_t n) noexcept
{
	std::uint32_t p = 2;
	while (p < n && p < 4096)
		p <<= 1;
	return p;
}

/// The kernel-ring path: claim, ECMXF_IOC_RING_SETUP, mmap(); each cycle
/// one output frame into the output ring and every input frame out of the
/// input ring, with no system call. The kernel's pump moves them to and
/// from the chip's FIFOs and reads the working counter.
class RingPath final : public CyclicPath
{
public:
	RingPath(Device &dev, ProcessImage &image, const CyclicConfig &cfg, KernelTransport &kt);
	~RingPath() override;

	void start() override;
	void stop() override;
	void exchange(CycleResult &r, bool readWkc) noexcept override;
	Transport &clock() noexcept override { return dev_.transport(); }
	[[nodiscard]] bool kernelRings() const noexcept override { return true; }
	int waitInputs(nanoseconds timeout) noexcept override;

private:
	void unmap() noexcept;
	[[noreturn]] void sysFail(const char *call, int err) const;

	Device &dev_;
	ProcessImage &image_;
	const CyclicConfig &cfg_;
	KernelTransport &kt_;
	void *outMap_ = MAP_FAILED;
	void *inMap_ = MAP_FAILED;
	std::size_t outLen_ = 0, inLen_ = 0;
	detail::PdoRingView out_, in_;
	/// the interrupt enables found by start(), restored by stop()
	InterruptConfig savedIrq_{};
	bool irqSaved_ = false;
	/// the kernel's counts as seen by the previous cycle
	std::uint32_t wkcReads_ = 0, outDropped_ = 0, inDropped_ = 0, txOverflows_ = 0, rxRefusals_ = 0;
	std::uint32_t pumpFailures_ = 0;
};

void RingPath::sysFail(const char *call, int err) const
{
	std::string m = kt_.name();
	m.append(": ").append(call).append(" failed: ").append(std::strerror(err));
	throw Error(m, err);
}

RingPath::RingPath(Device &dev, ProcessImage &image, const CyclicConfig &cfg, KernelTransport &kt)
	: dev_(dev), image_(image), cfg_(cfg), kt_(kt)
{
	readChip(dev, image, cfg);
	if (::ioctl(kt_.fd(), ECMXF_IOC_CLAIM) < 0) {
		const int err = errno;
		if (err != EBUSY)
			sysFail("ECMXF_IOC_CLAIM", err);
		std::uint32_t pid = 0;
		try {
			pid = kt_.devInfo().claimPid;
		} catch (const Error &) {
			// the pid is a courtesy; EBUSY is the answer
		}
		throw Error(kt_.name() + ": the cyclic path (PDO rings) is claimed by " +
				    (pid ? "process " + std::to_string(pid) : std::string("another process")) +
				    " (ECMXF_IOC_CLAIM: EBUSY)",
			    EBUSY);
	}
}

RingPath::~RingPath()
{
	// not stopped (an exception on the way): the FIFO off and the
	// interrupt enables back, as far as the link lets us
	if (irqSaved_) {
		try {
			stop();
		} catch (const Error &) {
			// nothing more to do in a destructor
		}
	}
	unmap();
	::ioctl(kt_.fd(), ECMXF_IOC_RELEASE);
}

void RingPath::unmap() noexcept
{
	if (outMap_ != MAP_FAILED)
		::munmap(outMap_, outLen_);
	if (inMap_ != MAP_FAILED)
		::munmap(inMap_, inLen_);
	outMap_ = inMap_ = MAP_FAILED;
	out_ = in_ = detail::PdoRingView();
}

void RingPath::start()
{
	// the FIFO off while the rings are made: the pump waits for it
	dev_.fifoEnable(false);
	if (sizes.rxPdoBytes)
		dev_.pdoWrite(image_.outputs());

	// rings deep enough for a few cycles' worth of bus cycles
	const std::int64_t period = cfg_.period.count();
	const std::int64_t bus = cfg_.busCycle.count();
	const std::uint64_t perCycle = bus > 0 ? static_cast<std::uint64_t>((period + bus - 1) / bus) : 1;
	ecmxf_ring_setup rs{};
	rs.out_entries = pow2AtLeast(std::max<std::uint64_t>(16, 2ull * rxDepth));
	rs.in_entries = pow2AtLeast(std::max<std::uint64_t>(32, 4 * perCycle + txDepth));
	rs.flags = ECMXF_RING_F_POLL_IN;
	// the pump's timer: once per cycle (INT1 wakes it earlier)
	rs.poll_us = static_cast<std::uint32_t>(std::clamp<std::int64_t>(period / 1000, 50, 100000));
	rs.rx_fill = rxFill;
	const std::int64_t wkcUs = cfg_.wkcEvery ? period / 1000 * static_cast<std::int64_t>(cfg_.wkcEvery) : 0;
	rs.wkc_us = static_cast<std::uint32_t>(std::clamp<std::int64_t>(wkcUs, cfg_.wkcEvery ? 1 : 0, 10'000'000));

	unmap();
	if (::ioctl(kt_.fd(), ECMXF_IOC_RING_SETUP, &rs) < 0)
		sysFail("ECMXF_IOC_RING_SETUP", errno);
	outMap_ = ::mmap(nullptr, rs.out.mmap_size, PROT_READ | PROT_WRITE, MAP_SHARED, kt_.fd(), ECMXF_RING_OFF_OUT);
	if (outMap_ == MAP_FAILED)
		sysFail("mmap of the output ring", errno);
	outLen_ = rs.out.mmap_size;
	inMap_ = ::mmap(nullptr, rs.in.mmap_size, PROT_READ | PROT_WRITE, MAP_SHARED, kt_.fd(), ECMXF_RING_OFF_IN);
	if (inMap_ == MAP_FAILED) {
		const int err = errno;
		unmap();
		sysFail("mmap of the input ring", err);
	}
	inLen_ = rs.in.mmap_size;
	out_ = detail::PdoRingView(outMap_, rs.out);
	in_ = detail::PdoRingView(inMap_, rs.in);
	wkcReads_ = outDropped_ = inDropped_ = txOverflows_ = rxRefusals_ = pumpFailures_ = 0;

	dev_.fifoClear(FifoSelect::Both);
	// INT1 on every TxPDO frame (TxFIFO high mark 1) and when the RxFIFO
	// runs low: the pump runs when there is something to move
	FifoThresholds th;
	th.txHighEnabled = sizes.txPdoBytes > 0;
	th.txHigh = 1;
	th.rxLowEnabled = sizes.rxPdoBytes > 0 && rxFill > 1;
	th.rxLow = static_cast<std::uint8_t>(rxFill > 1 ? rxFill / 2 : 0);
	dev_.fifoSetThresholds(th);
	InterruptConfig ic = dev_.interruptConfig();
	if (!irqSaved_)
		savedIrq_ = ic;
	irqSaved_ = true;
	ic.sources |= irq::kTxFifoHigh | irq::kRxFifoLow;
	dev_.setInterruptConfig(ic);
	dev_.fifoEnable(true);
}

void RingPath::stop()
{
	dev_.fifoEnable(false);
	if (irqSaved_) {
		irqSaved_ = false;
		dev_.setInterruptConfig(savedIrq_);
	}
}

void RingPath::exchange(CycleResult &r, bool) noexcept
{
	if (!in_.valid() || !out_.valid()) {
		fail(r, EINVAL, kNoRings);
		return;
	}
	if ((in_.flags() | out_.flags()) & ECMXF_RING_S_ERROR) {
		ecmxf_ring_status st{};
		in_.status(st);
		fail(r, st.error ? static_cast<int>(st.error) : EIO, kPumpStopped);
		return;
	}
	// outputs: this cycle's frame; a full ring refuses it
	if (sizes.rxPdoBytes) {
		if (out_.push(image_.outputs()))
			r.framesPushed = 1;
		else
			r.rxRefused = true;
	}
	// inputs: every frame there is, oldest first; the newest to the image
	if (sizes.txPdoBytes) {
		const std::span<std::uint8_t> img = image_.inputs();
		const std::uint32_t n = in_.consume([&](std::span<const std::uint8_t> f) {
			if (cfg_.onInputFrame)
				cfg_.onInputFrame(cfg_.context, f);
			// the slot is freed after the loop: copy each, the newest last
			std::memcpy(img.data(), f.data(), std::min(f.size(), img.size()));
		});
		r.framesPopped = n;
		r.inputsUpdated = n > 0;
	}
	ecmxf_ring_status st{};
	if (in_.status(st)) {
		if (st.wkc_reads != wkcReads_) {
			wkcReads_ = st.wkc_reads;
			r.wkcRead = true;
			r.wkc = st.wkc;
			r.wkcOk = r.wkc == r.expectedWkc;
		}
		r.rxFifoCount = st.rx_fifo_cnt;
		r.txFifoCount = st.tx_fifo_cnt;
		r.wkcErrorCount = st.wkc_err_cnt;
		r.ecatState = st.ecat_state;
		r.errStatus = st.err_status;
		r.ecmStatus = st.ecm_status;
		r.intFlags = st.int_flags;
		if (st.rx_refusals != rxRefusals_) {
			rxRefusals_ = st.rx_refusals;
			r.rxRefused = true;
		}
		if (st.tx_overflows != txOverflows_) {
			txOverflows_ = st.tx_overflows;
			r.txOverflow = true;
		}
		if (st.pump_failures != pumpFailures_) {
			// frames lost in a failed command: this cycle reports it
			pumpFailures_ = st.pump_failures;
			fail(r, st.error ? static_cast<int>(st.error) : EIO, kPumpFailed);
		}
	}
	// frames the chip refused, frames the input ring had no room for
	const std::uint32_t od = out_.dropped();
	if (od != outDropped_) {
		outDropped_ = od;
		r.rxRefused = true;
	}
	const std::uint32_t id = in_.dropped();
	if (id != inDropped_) {
		r.txOverflow = true;
		r.txDroppedEstimate += id - inDropped_;
		inDropped_ = id;
	}
}

int RingPath::waitInputs(nanoseconds timeout) noexcept
{
	if (!in_.valid() || !sizes.txPdoBytes)
		return EINVAL;
	const auto pumpError = [&]() -> int {
		ecmxf_ring_status st{};
		in_.status(st);
		return st.error ? static_cast<int>(st.error) : EIO;
	};
	try {
		Transport &t = clock();
		const nanoseconds deadline = t.now() + std::max(timeout, nanoseconds(0));
		for (;;) {
			if (in_.count() > 0)
				return 0;
			if ((in_.flags() | out_.flags()) & ECMXF_RING_S_ERROR)
				return pumpError();
			const nanoseconds left = deadline - t.now();
			if (left.count() <= 0)
				return ETIMEDOUT;
			// the ring was set up with ECMXF_RING_F_POLL_IN: POLLRDBAND
			// while the input ring holds frames, POLLERR once the pump
			// stopped (POLLIN is the completions' bit)
			pollfd p{ kt_.fd(), POLLRDBAND, 0 };
			timespec ts{ static_cast<time_t>(left.count() / 1'000'000'000),
				     static_cast<long>(left.count() % 1'000'000'000) };
			const int n = ::ppoll(&p, 1, &ts, nullptr);
			if (n < 0 && errno != EINTR)
				return errno;
			if (n > 0 && (p.revents & (POLLERR | POLLHUP | POLLNVAL)) && in_.count() == 0)
				return pumpError();
		}
	} catch (...) {
		return EIO;
	}
}

} // namespace

// ---------------------------------------------------------------------------
// Cyclic
// ---------------------------------------------------------------------------

class Cyclic::Impl
{
public:
	Impl(Device &dev, ProcessImage &image, CyclicConfig c) : cfg(c)
	{
		if (cfg.period.count() <= 0)
			throw Error("Cyclic: the cycle period must be positive (got " +
					    std::to_string(cfg.period.count()) + " ns)",
				    EINVAL);
		if (cfg.busCycle.count() < 0)
			throw Error("Cyclic: the bus cycle must not be negative (got " +
					    std::to_string(cfg.busCycle.count()) + " ns)",
				    EINVAL);
		// a kernel transport brings its rings; anything else the commands
		if (auto *kt = dynamic_cast<KernelTransport *>(&dev.transport()))
			path = std::make_unique<RingPath>(dev, image, cfg, *kt);
		else
			path = std::make_unique<FifoCommandPath>(dev, image, cfg);
		last.expectedWkc = path->counts.expectedWkc();
	}

	CyclicConfig cfg;
	std::unique_ptr<CyclicPath> path;
	CycleResult last;
	CyclicStats stats;
	bool started = false;
	nanoseconds epoch{ 0 };
	std::uint64_t tick = 0; ///< the cycle boundary waited for last
};

Cyclic::Cyclic(Device &device, ProcessImage &image, CyclicConfig config)
	: impl_(std::make_unique<Impl>(device, image, config))
{
}

Cyclic::~Cyclic() = default;

void Cyclic::start()
{
	impl_->path->start();
	impl_->stats = CyclicStats{};
	CycleResult fresh;
	fresh.expectedWkc = impl_->path->counts.expectedWkc();
	impl_->last = fresh;
	impl_->epoch = impl_->path->clock().now();
	impl_->tick = 0;
	impl_->started = true;
}

void Cyclic::stop()
{
	impl_->started = false;
	impl_->path->stop();
}

const CycleResult &Cyclic::cycle() noexcept
{
	Impl &m = *impl_;
	CycleResult &r = m.last;
	// a fresh result; the working counter stays "as last read"
	const std::uint32_t wkc = r.wkc;
	const bool wkcOk = r.wkcOk;
	r = CycleResult{};
	r.wkc = wkc;
	r.wkcOk = wkcOk;
	r.expectedWkc = m.path->counts.expectedWkc();
	if (!m.started) {
		fail(r, EINVAL, kNotStarted);
		return r;
	}

	const bool readWkc = m.cfg.wkcEvery != 0 && m.stats.cycles % m.cfg.wkcEvery == 0;
	m.path->exchange(r, readWkc);

	CyclicStats &s = m.stats;
	s.cycles++;
	if (r.error)
		s.failedCycles++;
	s.commands += r.commands;
	s.framesPushed += r.framesPushed;
	s.framesPopped += r.framesPopped;
	if (r.rxRefused)
		s.rxRefusals++;
	if (r.txOverflow)
		s.txOverflows++;
	s.txDroppedEstimate += r.txDroppedEstimate;
	if (r.wkcRead) {
		s.wkcReads++;
		if (!r.wkcOk)
			s.wkcMismatches++;
	}
	return r;
}

int Cyclic::waitNextCycle() noexcept
{
	Impl &m = *impl_;
	Transport &t = m.path->clock();
	try {
		const nanoseconds now = t.now();
		const std::int64_t period = m.cfg.period.count();
		nanoseconds next = m.epoch + nanoseconds(static_cast<std::int64_t>(m.tick + 1) * period);
		if (next < now) {
			// late: skip to the next boundary still ahead
			m.stats.lateCycles++;
			m.tick = static_cast<std::uint64_t>((now - m.epoch).count() / period) + 1;
			next = m.epoch + nanoseconds(static_cast<std::int64_t>(m.tick) * period);
		} else {
			m.tick++;
		}
		t.sleepFor(next - now);
	} catch (...) {
		return EIO;
	}
	return 0;
}

int Cyclic::waitInputs(std::chrono::nanoseconds timeout) noexcept
{
	if (!impl_->started)
		return EINVAL;
	return impl_->path->waitInputs(timeout);
}

const CycleResult &Cyclic::lastResult() const noexcept
{
	return impl_->last;
}

const CyclicStats &Cyclic::stats() const noexcept
{
	return impl_->stats;
}

const CyclicConfig &Cyclic::config() const noexcept
{
	return impl_->cfg;
}

FifoPackSizes Cyclic::packSizes() const noexcept
{
	return impl_->path->sizes;
}

PdoSlaveCounts Cyclic::slaveCounts() const noexcept
{
	return impl_->path->counts;
}

std::uint32_t Cyclic::expectedWkc() const noexcept
{
	return impl_->path->counts.expectedWkc();
}

unsigned Cyclic::rxDepth() const noexcept
{
	return impl_->path->rxDepth;
}

unsigned Cyclic::txDepth() const noexcept
{
	return impl_->path->txDepth;
}

unsigned Cyclic::rxFill() const noexcept
{
	return impl_->path->rxFill;
}

unsigned Cyclic::framesPerWrite() const noexcept
{
	return impl_->path->perWrite;
}

unsigned Cyclic::framesPerRead() const noexcept
{
	return impl_->path->perRead;
}

bool Cyclic::usesKernelRings() const noexcept
{
	return impl_->path->kernelRings();
}

} // namespace ecmxf
