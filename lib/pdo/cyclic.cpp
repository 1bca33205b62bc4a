// SPDX-License-Identifier: MIT
// Cyclic: the allocation-free, exception-free cyclic exchange of the
// process image (include/ecmxf/pdo/cyclic.hpp, Documentation/process-data.rst).
//
// The exchange itself is a strategy (CyclicPath, pdo/cyclic_path.hpp).
// FifoCommandPath (fifo_command_path.cpp) drives the chip's FIFOs with
// ECAT_PDO_DATA_FIFO_OP over Device::transact(); RingPath, chosen when the
// Device's link offers the kernel's PDO rings (a KernelLink), moves
// the frames through the kernel's mmap()ed PDO rings, whose pump in the
// kernel sends those commands (Documentation/process-data.rst).

#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/model/types_bus.hpp>
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/pdo/realtime.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <cstdio>
#include <ctime>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "ecmxf-proto.h"
#include "ecmxf-pump.h"
#include "link/pdo_rings.hpp"
#include "pdo/cyclic_path.hpp"
#include "link/pdo_ring.hpp"

namespace ecmxf {

void detail::CyclicPath::readChip(Device &dev, const ProcessImage &image, const CyclicConfig &cfg)
{
	sizes = dev.pdo().fifoPackSizes();
	counts = dev.pdo().slaveCounts();
	rxDepth = dev.pdo().fifoRxCount();
	txDepth = dev.pdo().fifoTxCount();

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
	// the frames per command and the fill level: the protocol core's pump
	dataCapacity = cap;
	ecmxf_pump pump;
	ecmxf_pump_init(&pump, static_cast<u32>(sizes.rxPdoBytes), static_cast<u32>(sizes.txPdoBytes),
			static_cast<u32>(cap), rxDepth, 0, txDepth);
	perWrite = ecmxf_pump_per_write(&pump);
	perRead = ecmxf_pump_per_read(&pump);

	const unsigned maxFill = ecmxf_pump_max_fill(rxDepth);
	if (cfg.rxFill > maxFill)
		throw Error("Cyclic: rxFill " + std::to_string(cfg.rxFill) + " out of range (1.." +
				    std::to_string(maxFill) + ": the RxFIFO depth " + std::to_string(rxDepth) +
				    " minus a margin of 2)",
			    EINVAL);
	rxFill = cfg.rxFill ? cfg.rxFill : maxFill;
}

namespace {

using std::chrono::nanoseconds;
using detail::CyclicPath;
using detail::cycleFail;

constexpr const char *kNotStarted = "Cyclic: cycle() before start()";

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
	RingPath(Device &dev, ProcessImage &image, const CyclicConfig &cfg, std::unique_ptr<detail::PdoRings> rings);
	~RingPath() override;

	void start() override;
	void stop() override;
	void exchange(CycleResult &r, bool readWkc) noexcept override;
	Link &clock() noexcept override { return dev_.link(); }
	[[nodiscard]] bool kernelRings() const noexcept override { return true; }
	int waitInputs(nanoseconds timeout) noexcept override;

private:
	Device &dev_;
	ProcessImage &image_;
	const CyclicConfig &cfg_;
	/// the claim, the ring memory and the wait (the kernel link's)
	std::unique_ptr<detail::PdoRings> rings_;
	detail::PdoRingView &out_, &in_;
	/// the interrupt enables found by start(), restored by stop()
	InterruptConfig savedIrq_{};
	bool irqSaved_ = false;
	/// the kernel's counts as seen by the previous cycle
	std::uint32_t wkcReads_ = 0, outDropped_ = 0, inDropped_ = 0, txOverflows_ = 0, rxRefusals_ = 0;
	/// the status block's out_skipped at the last cycle
	std::uint32_t outSkipped_ = 0;
	std::uint32_t pumpFailures_ = 0;
	/// the status block's pump_ops at the last cycle
	std::uint32_t pumpOps_ = 0;
};

RingPath::RingPath(Device &dev, ProcessImage &image, const CyclicConfig &cfg,
		   std::unique_ptr<detail::PdoRings> rings)
	: dev_(dev), image_(image), cfg_(cfg), rings_(std::move(rings)), out_(rings_->out()), in_(rings_->in())
{
	readChip(dev, image, cfg);
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
}

void RingPath::start()
{
	// the FIFO off while the rings are made: the pump waits for it
	dev_.pdo().fifoEnable(false);
	if (sizes.rxPdoBytes)
		dev_.pdo().write(image_.outputs());

	// rings deep enough for a few cycles' worth of bus cycles
	const std::int64_t period = cfg_.period.count();
	const std::int64_t bus = cfg_.busCycle.count();
	const std::uint64_t perCycle = bus > 0 ? static_cast<std::uint64_t>((period + bus - 1) / bus) : 1;
	ecmxf_ring_setup rs{};
	rs.out_entries = pow2AtLeast(std::max<std::uint64_t>(16, 2ull * rxDepth));
	rs.in_entries = pow2AtLeast(std::max<std::uint64_t>(32, 4 * perCycle + txDepth));
	// CyclicConfig::wkcAnswerNextCycle / fifoAnswerNextCycle: the pump's
	// read / its FIFO command answered by its next cycle's FIFO command
	rs.flags = ECMXF_RING_F_POLL_IN | (cfg_.wkcAnswerNextCycle ? ECMXF_RING_F_WKC_NEXT : 0u) |
		   (cfg_.fifoAnswerNextCycle ? ECMXF_RING_F_FIFO_NEXT : 0u);
	// the pump's timer: once per cycle (INT1 wakes it earlier)
	rs.poll_us = static_cast<std::uint32_t>(std::clamp<std::int64_t>(period / 1000, 50, 100000));
	rs.rx_fill = rxFill;
	const std::int64_t wkcUs = cfg_.wkcEvery ? period / 1000 * static_cast<std::int64_t>(cfg_.wkcEvery) : 0;
	rs.wkc_us = static_cast<std::uint32_t>(std::clamp<std::int64_t>(wkcUs, cfg_.wkcEvery ? 1 : 0, 10'000'000));

	rings_->setup(rs);
	wkcReads_ = outDropped_ = inDropped_ = txOverflows_ = rxRefusals_ = pumpFailures_ = outSkipped_ = pumpOps_ = 0;

	dev_.pdo().fifoClear(FifoSelect::Both);
	// INT1 on every TxPDO frame (TxFIFO high mark 1) and when the RxFIFO
	// runs low: the pump runs when there is something to move
	FifoThresholds th;
	th.txHighEnabled = sizes.txPdoBytes > 0;
	th.txHigh = 1;
	th.rxLowEnabled = sizes.rxPdoBytes > 0 && rxFill > 1;
	th.rxLow = static_cast<std::uint8_t>(rxFill > 1 ? rxFill / 2 : 0);
	dev_.pdo().fifoSetThresholds(th);
	InterruptConfig ic = dev_.chip().interruptConfig();
	if (!irqSaved_)
		savedIrq_ = ic;
	irqSaved_ = true;
	ic.sources |= irq::kTxFifoHigh | irq::kRxFifoLow;
	dev_.chip().setInterruptConfig(ic);
	dev_.pdo().fifoEnable(true);
}

void RingPath::stop()
{
	dev_.pdo().fifoEnable(false);
	if (irqSaved_) {
		irqSaved_ = false;
		dev_.chip().setInterruptConfig(savedIrq_);
	}
}

void RingPath::exchange(CycleResult &r, bool) noexcept
{
	if (!in_.valid() || !out_.valid()) {
		cycleFail(r, EINVAL, kNoRings);
		return;
	}
	if ((in_.flags() | out_.flags()) & ECMXF_RING_S_ERROR) {
		ecmxf_ring_status st{};
		in_.status(st);
		cycleFail(r, st.error ? static_cast<int>(st.error) : EIO, kPumpStopped);
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
		// the pump's commands answered since the last cycle
		r.commands = (st.pump_ops - pumpOps_) + (st.wkc_reads - wkcReads_);
		pumpOps_ = st.pump_ops;
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
		// the pump dropped the oldest of a backlog (never silent)
		r.outputsSkipped = st.out_skipped - outSkipped_;
		outSkipped_ = st.out_skipped;
		if (st.pump_failures != pumpFailures_) {
			// frames lost in a failed command: this cycle reports it
			pumpFailures_ = st.pump_failures;
			cycleFail(r, st.error ? static_cast<int>(st.error) : EIO, kPumpFailed);
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
		Link &t = clock();
		const nanoseconds deadline = t.now() + std::max(timeout, nanoseconds(0));
		for (;;) {
			if (in_.count() > 0)
				return 0;
			if ((in_.flags() | out_.flags()) & ECMXF_RING_S_ERROR)
				return pumpError();
			const nanoseconds left = deadline - t.now();
			if (left.count() <= 0)
				return ETIMEDOUT;
			const int w = rings_->wait(left);
			if (w < 0)
				return -w;
			if (w == 1 && in_.count() == 0)
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
		checkRealtime(cfg.realtime);
		checkBusState(dev);
		// one Cyclic per Device: two would share the chip's FIFOs, each
		// taking the other's input frames and topping up its own outputs
		claim_ = std::make_unique<DeviceClaim>(dev);
		// a link with the kernel's rings moves the frames through them;
		// any other link runs the FIFO commands
		if (auto rings = dev.link().openPdoRings())
			path = std::make_unique<RingPath>(dev, image, cfg, std::move(rings));
		else
			path = detail::makeFifoCommandPath(dev, image, cfg);
		last.expectedWkc = path->counts.expectedWkc();
	}

	/// Process data runs in SAFE-OP (inputs) and OP: in INIT or PRE-OP the
	/// chip's FIFOs exchange nothing and cycle() would fail every time
	/// with no word why. ENETDOWN naming the state. ERROR is let through.
	static void checkBusState(Device &dev)
	{
		(void)dev.bus().slaveCount(); // a fresh response header
		const std::uint8_t st = dev.lastHeader().ecatState;
		const unsigned s = st & 0x0Fu;
		// ERROR (0x10): a slave failed while the bus was up; the exchange
		// still runs (the working counter shows it), so a Cyclic may be
		// made again during the fault handling
		if (s == 4 || s == 8 || (st & 0x10u))
			return;
		char hex[8];
		std::snprintf(hex, sizeof(hex), "0x%02x", st);
		const std::string name = s == 0 ? std::string("no network initialised")
						: stateName(static_cast<State>(s));
		throw Error("Cyclic: the bus is in " + name + " (ECAT state " + hex +
				    "): process data needs SAFE-OP or OP; bring the bus up first "
				    "(Master::bringUp(), or Bus::stateSet() to SAFE-OP/OP)",
			    ENETDOWN);
	}

	/// The Devices that have a Cyclic, process-wide.
	class DeviceClaim
	{
	public:
		explicit DeviceClaim(Device &dev) : dev_(&dev)
		{
			const std::lock_guard<std::mutex> lock(mutex());
			auto &set = devices();
			if (std::find(set.begin(), set.end(), dev_) != set.end())
				throw Error("Cyclic: this Device already has a Cyclic (one cyclic exchange per "
					    "Device: destroy the first one, or use it for both images' slaves)",
					    EBUSY);
			set.push_back(dev_);
		}
		~DeviceClaim()
		{
			const std::lock_guard<std::mutex> lock(mutex());
			std::erase(devices(), dev_);
		}
		DeviceClaim(const DeviceClaim &) = delete;
		DeviceClaim &operator=(const DeviceClaim &) = delete;

	private:
		static std::mutex &mutex()
		{
			static std::mutex m;
			return m;
		}
		static std::vector<const Device *> &devices()
		{
			static std::vector<const Device *> v;
			return v;
		}
		const Device *dev_;
	};
	std::unique_ptr<DeviceClaim> claim_;

	CyclicConfig cfg;
	std::unique_ptr<CyclicPath> path;
	CycleResult last;
	CyclicStats stats;
	bool started = false;
	std::vector<std::pair<void *, Cyclic::ExitHook>> exitHooks;
	nanoseconds epoch{ 0 };
	std::uint64_t tick = 0; ///< the cycle boundary waited for last
};

Cyclic::Cyclic(Device &device, ProcessImage &image, CyclicConfig config)
	: impl_(std::make_unique<Impl>(device, image, config))
{
}

Cyclic::~Cyclic()
{
	// newest first; a hook may remove itself (and only itself) meanwhile
	while (!impl_->exitHooks.empty()) {
		const auto [owner, hook] = impl_->exitHooks.back();
		impl_->exitHooks.pop_back();
		hook(owner, *this);
	}
}

bool Cyclic::running() const noexcept
{
	return impl_->started;
}

void Cyclic::addExitHook(void *owner, ExitHook hook)
{
	removeExitHook(owner);
	impl_->exitHooks.emplace_back(owner, hook);
}

void Cyclic::removeExitHook(void *owner) noexcept
{
	auto &v = impl_->exitHooks;
	v.erase(std::remove_if(v.begin(), v.end(), [owner](const auto &h) { return h.first == owner; }), v.end());
}

void Cyclic::start()
{
	// on the thread that will run the cycle; before the path's commands,
	// so that they run as the cycle will
	applyRealtime(impl_->cfg.realtime);
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
		cycleFail(r, EINVAL, kNotStarted);
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
	s.outputsSkipped += r.outputsSkipped;
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
	Link &t = m.path->clock();
	try {
		// one clock read (is the cycle late?) and one absolute sleep to
		// the boundary: the two system calls of a steady cycle's pacing
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
		t.sleepUntil(next);
	} catch (...) {
		return EIO;
	}
	return 0;
}

std::chrono::nanoseconds Cyclic::boundary() const noexcept
{
	const Impl &m = *impl_;
	return m.epoch + nanoseconds(static_cast<std::int64_t>(m.tick) * m.cfg.period.count());
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
