// SPDX-License-Identifier: MIT
//
// chip.cpp - the simulated ECM-XF: public API, virtual time and the SPI
// front end (packet validation, the one-exchange-late response, the
// INFO_UPDATE rule, header fields, error bits, INT0/INT1).
//
// The behaviour follows the manuals (ver. 050 where they differ) and the
// decisions of the protocol digest; Documentation/simulator.rst lists what
// the simulator chose where the manuals are silent.

#include "chip_impl.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace ecmxf::sim {

namespace {

/// WARM_RESET: the chip boots; INT0 shows busy meanwhile.
constexpr Nanos kResetTime = 50 * kMs;
/// SPI_RECONFIG_OP: the chip re-arms its SPI DMA at the new size.
constexpr Nanos kReconfigTime = 50 * kMs;

Network loadNetwork(const std::string &file)
{
	return file.empty() ? Network::defaultNetwork() : Network::fromFile(file);
}

} // namespace

void applyChipOption(ChipConfig &config, std::string_view key, std::string_view value)
{
	const auto bad = [&](std::string_view expected) {
		throw std::invalid_argument("chip option " + std::string(key) + ": bad value '" +
					    std::string(value) + "' (expected " + std::string(expected) + ")");
	};
	if (key == "crc32-coverage") {
		if (value == "frame")
			config.crcCoverage = ChipConfig::CrcCoverage::Frame;
		else if (value == "valid")
			config.crcCoverage = ChipConfig::CrcCoverage::Valid;
		else
			bad("frame or valid");
	} else if (key == "crc-type-set-fixed") {
		if (value == "drop")
			config.crcTypeSetFixed = false;
		else if (value == "accept")
			config.crcTypeSetFixed = true;
		else
			bad("drop or accept");
	} else if (key == "init-op") {
		if (value == "strict")
			config.initOpLenient = false;
		else if (value == "lenient")
			config.initOpLenient = true;
		else
			bad("strict or lenient");
	} else {
		throw std::invalid_argument("unknown chip option '" + std::string(key) + "' (known: " +
					    std::string(kChipOptions) + ")");
	}
}

// ======================================================================
// FrameFifo
// ======================================================================

void FrameFifo::configure(std::size_t depth, std::size_t frame)
{
	depth_ = depth;
	frame_ = frame;
	buf_.assign(depth * frame, 0);
	head_ = count_ = 0;
}

bool FrameFifo::push(const std::uint8_t *src)
{
	if (count_ >= depth_)
		return false;
	const std::size_t slot = (head_ + count_) % depth_;
	if (frame_)
		std::memcpy(buf_.data() + slot * frame_, src, frame_);
	count_++;
	return true;
}

bool FrameFifo::pushDropOldest(const std::uint8_t *src)
{
	if (depth_ == 0)
		return true;
	bool dropped = false;
	if (count_ >= depth_) {
		head_ = (head_ + 1) % depth_;
		count_--;
		dropped = true;
	}
	push(src);
	return dropped;
}

bool FrameFifo::pop(std::uint8_t *dst)
{
	if (count_ == 0)
		return false;
	if (frame_)
		std::memcpy(dst, buf_.data() + head_ * frame_, frame_);
	head_ = (head_ + 1) % depth_;
	count_--;
	return true;
}

// ======================================================================
// Chip (public API)
// ======================================================================

Chip::Chip(const std::string &networkFile, ChipConfig config)
	: impl_(std::make_unique<Impl>(loadNetwork(networkFile), std::move(config)))
{
}

Chip::Chip(Network network, ChipConfig config)
	: impl_(std::make_unique<Impl>(std::move(network), std::move(config)))
{
}

Chip::~Chip() = default;

void Chip::exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso)
{
	impl_->exchange(mosi, miso);
}

std::vector<std::uint8_t> Chip::exchange(std::span<const std::uint8_t> mosi)
{
	std::vector<std::uint8_t> miso(mosi.size());
	impl_->exchange(mosi, miso);
	return miso;
}

bool Chip::int0() const
{
	return impl_->int0();
}

bool Chip::int1() const
{
	return impl_->int1();
}

bool Chip::ready() const
{
	return impl_->ready();
}

void Chip::advance(std::chrono::nanoseconds dt)
{
	impl_->advance(dt.count());
}

std::chrono::nanoseconds Chip::now() const
{
	return std::chrono::nanoseconds(impl_->now());
}

std::chrono::nanoseconds Chip::nextLockstepCycle() const
{
	const Nanos t = impl_->nextLockstepCycle();
	return t < 0 ? std::chrono::nanoseconds::max() : std::chrono::nanoseconds(t);
}

FaultPlan &Chip::faults()
{
	return impl_->faults();
}

Network &Chip::network()
{
	return impl_->network();
}

std::size_t Chip::dataSize() const
{
	return impl_->dataSize();
}

std::size_t Chip::packetSize() const
{
	return impl_->packetSize();
}

const ChipStats &Chip::stats() const
{
	return impl_->stats();
}

Chip::FifoLevels Chip::fifoLevels() const
{
	return impl_->fifoLevels();
}

// ======================================================================
// Impl: construction, time
// ======================================================================

Chip::Impl::Impl(Network net, ChipConfig cfg)
	: net_(std::move(net)), cfg_(std::move(cfg)), epoch_(std::chrono::steady_clock::now())
{
	for (const auto &[key, value] : net_.chipOptions())
		applyChipOption(cfg_, key, value);
	if (cfg_.spiClockHz == 0)
		throw std::invalid_argument("ChipConfig: spiClockHz must not be 0");
	if (cfg_.processingTime.count() < 0)
		throw std::invalid_argument("ChipConfig: processingTime must not be negative");
	if (cfg_.fwVersionData.size() > 20)
		throw std::invalid_argument("ChipConfig: fwVersionData has more than 20 bytes");
	emcyLog_.resize(64);
	sdoData_.reserve(256);
	stations_.assign(net_.size(), 0);
	powerOn();
}

void Chip::Impl::syncPaced()
{
	if (cfg_.timeMode != TimeMode::Paced)
		return;
	const auto wall = std::chrono::duration_cast<std::chrono::nanoseconds>(
		std::chrono::steady_clock::now() - epoch_);
	if (wall.count() > now_)
		advanceTo(wall.count());
}

void Chip::Impl::advance(Nanos dt)
{
	if (cfg_.timeMode == TimeMode::Paced || dt <= 0)
		return;
	advanceTo(now_ + dt);
}

Nanos Chip::Impl::now()
{
	syncPaced();
	return now_;
}

void Chip::Impl::advanceTo(Nanos t)
{
	for (;;) {
		Nanos ev = t;
		// lock-step: a bus cycle that waits for the FIFOs is no event;
		// it runs once an exchange gave it its frame (or TxFIFO room)
		const bool waits = busWaits();
		if (cyclesOn_ && !waits && nextCycle_ < ev)
			ev = nextCycle_;
		const bool timedJob = job_.active && !job_.stuck;
		if (timedJob && job_.next < ev)
			ev = job_.next;
		if (ev > now_) {
			const Nanos dt = ev - now_;
			if (!cyclesOn_) {
				// no frames on the wire: every slave just sees time pass
				for (std::size_t i = 0; i < net_.size(); i++)
					net_.at(i).idle(std::chrono::nanoseconds(dt));
			}
			periph_.advance(std::chrono::nanoseconds(dt));
			now_ = ev;
		}
		bool did = false;
		if (cyclesOn_ && nextCycle_ <= now_) {
			if (waits) {
				// the cycle is late by however long the bus waits
				if (!waiting_)
					stats_.busWaits++;
				waiting_ = true;
				nextCycle_ = now_;
			} else {
				waiting_ = false;
				busCycle();
				nextCycle_ += cycleNs_;
				did = true;
			}
		}
		if (job_.active && !job_.stuck && job_.next <= now_) {
			stepJob();
			did = true;
		}
		if (!did && now_ >= t)
			break;
	}
}

bool Chip::Impl::busWaits() const
{
	if (!cfg_.lockstep || !cyclesOn_ || !fifoEnabled_ || !layoutValid_ || wkcStopped_)
		return false;
	// a frame for the cycle's outputs, room for its inputs (a lost link
	// puts no frame into the TxFIFO)
	return (rxSize_ > 0 && rxFifo_.count() == 0) ||
	       (txSize_ > 0 && !faults_.linkLost && txFifo_.full());
}

Nanos Chip::Impl::nextLockstepCycle()
{
	syncPaced();
	if (!cfg_.lockstep || !cyclesOn_ || !fifoEnabled_ || !layoutValid_ || wkcStopped_ || busWaits())
		return -1;
	return nextCycle_;
}

// ======================================================================
// Impl: INT lines
// ======================================================================

bool Chip::Impl::ready()
{
	syncPaced();
	return now_ >= busyUntil_ && !faults_.int0StuckBusy;
}

bool Chip::Impl::int0()
{
	// polarity bit 1: INT0 active high (ready = high), the default
	return ready() == ((polarity_ & 0x02) != 0);
}

bool Chip::Impl::int1Asserted() const
{
	const std::uint32_t flags = intFlags_ | periph_.intFlags();
	if (flags & intEnable_)
		return true;
	const auto gpioEnable =
		static_cast<std::uint16_t>(gpioIntEnable_ | ((periphIntEnable_ & 0x0Fu) << 8));
	if (periph_.gpioIntFlags() & gpioEnable)
		return true;
	// QEI interrupts (u8PeripIntEnable bits 4..7) show as the encoder flag
	return (periphIntEnable_ & 0xF0u) && (periph_.intFlags() & ECMXF_INT_ENCODER);
}

bool Chip::Impl::int1()
{
	syncPaced();
	// polarity bit 0: INT1 active high; the default 0 is active low
	return int1Asserted() == ((polarity_ & 0x01) != 0);
}

// ======================================================================
// Impl: power-on state
// ======================================================================

void Chip::Impl::powerOn()
{
	dataSize_ = ECMXF_DATA_DEFAULT;
	check_ = ECMXF_CHECK_FIXED;
	pendingCheck_ = -1;
	havePrev_ = false;
	prevIndex_ = prevCode_ = 0;
	crcErrCnt_ = 0;
	errStatus_ = 0;
	intFlags_ = 0;
	intEnable_ = 0;
	gpioIntEnable_ = periphIntEnable_ = 0;
	polarity_ = 0x02;
	periph_.reset();

	initialized_ = false;
	ethInit_ = false;
	linkAtInit_ = false;
	lrw_ = true;
	busShift_ = false;
	initParam_ = 0;
	slaves_.clear();
	slots_.clear();
	ecatState_ = ECMXF_ECAT_NONE;
	opReached_ = false;
	cyclesOn_ = false;
	cycleNs_ = kMs;
	cycleCount_ = 0;
	dcActive_ = false;
	layoutValid_ = false;
	wkcStopped_ = false;
	rxSize_ = txSize_ = 0;
	outImage_.clear();
	inImage_.clear();
	inSlaves_ = outSlaves_ = 0;
	lastWkc_ = 0;
	wkcErrCnt_ = wkcConti_ = 0;
	wkcMax_ = 255;

	fifoEnabled_ = true; // "ECM-XF enables the RxPDO FIFO by default"
	rxDepth_ = txDepth_ = 64;
	rxFifo_.configure(rxDepth_, 0);
	txFifo_.configure(txDepth_, 0);
	fifoThEnable_ = txHigh_ = rxLow_ = 0;

	job_ = AsyncJob{};
	skipLinkWait_ = false;

	sdoData_.clear();
	abortCode_ = 0;
	pdoCfg_.fill(0);
	eepromRet_ = 0;
	eepromData_.clear();
	rawResult_.clear();
	foeResult_.clear();
	mbxRead_.clear();
	for (auto &e : emcyLog_)
		e = EmergencyLog{};
	emcyHead_ = emcyCount_ = 0;
	emcySeq_ = 0;

	motors_.fill(Motor{});
	motorTotal_ = 0;

	// the first response answers nothing
	prepare(0, 0, 0, 0);
	pending_.hdr.ecm_status |= ECMXF_STS_NOP;
}

// ======================================================================
// Impl: the SPI front end
// ======================================================================

void Chip::Impl::exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso)
{
	syncPaced();
	stats_.exchanges++;
	const bool wasReady = now_ >= busyUntil_;
	if (cfg_.timeMode == TimeMode::Virtual) {
		const auto bits = static_cast<Nanos>(mosi.size()) * 8;
		advanceTo(now_ + bits * kSec / static_cast<Nanos>(cfg_.spiClockHz));
	}

	// what the chip shifts out: the response prepared after the last
	// valid packet, at the configured size
	const std::size_t n = packetSize();
	std::uint8_t *tx = txBuf_.data();
	encodePending(tx, n);

	if (!wasReady)
		stats_.busyExchanges++;
	bool notReady = !wasReady && cfg_.notReadyWhileBusy;
	if (!notReady && faults_.notReady > 0) {
		faults_.notReady--;
		notReady = true;
	}
	if (notReady) {
		put32(tx + ECMXF_HDR_SIZE + dataSize_, ECMXF_NOT_READY_WORD);
		stats_.notReady++;
	} else if (faults_.misoBitErrors > 0) {
		faults_.misoBitErrors--;
		tx[ECMXF_HDR_SIZE + dataSize_] ^= 0x01; // one bit of the check word
	}
	const std::size_t copy = std::min(miso.size(), n);
	std::memcpy(miso.data(), tx, copy);
	if (miso.size() > copy)
		std::memset(miso.data() + copy, 0, miso.size() - copy);

	if (notReady)
		return; // the chip did not take the packet in

	busyUntil_ = now_ + cfg_.processingTime.count();
	process(mosi);
}

void Chip::Impl::process(std::span<const std::uint8_t> mosi)
{
	const std::size_t n = packetSize();
	if (mosi.size() != n) {
		badPacket();
		return;
	}
	std::uint8_t *rx = rxBuf_.data();
	std::memcpy(rx, mosi.data(), n);
	if (faults_.mosiBitErrors > 0) {
		faults_.mosiBitErrors--;
		rx[ECMXF_HDR_SIZE + dataSize_] ^= 0x01; // one bit of the check word
	}

	ecmxf_cmd_hdr h{};
	const std::uint8_t *data = nullptr;
	ecmxf_fault f = ecmxf_decode_cmd(rx, n, codecCheck(check_), &h, &data);
	bool fixedOnly = false;
	// the manual asks hosts to send SPI_RECONFIG_OP with the fixed word;
	// NEXTW's example host code sends CRC_TYPE_SET so too
	const bool fixedTaken = rx[0x0C] == ECMXF_CMD_SPI_RECONFIG_OP ||
				(cfg_.crcTypeSetFixed && rx[0x0C] == ECMXF_CMD_CRC_TYPE_SET);
	if (f == ECMXF_FAULT_CHECK && check_ != ECMXF_CHECK_FIXED && fixedTaken &&
	    ecmxf_decode_cmd(rx, n, ECMXF_CHECK_FIXED, &h, &data) == ECMXF_FAULT_NONE) {
		f = ECMXF_FAULT_NONE;
		fixedOnly = true;
	}
	if (f != ECMXF_FAULT_NONE) {
		badPacket();
		return;
	}
	if (fixedOnly && crcErrCnt_ < 255)
		crcErrCnt_++;

	applyHeader(h);
	const bool repeat = havePrev_ && h.index == prevIndex_ && h.code == prevCode_;
	havePrev_ = true;
	prevIndex_ = h.index;
	prevCode_ = h.code;
	if (repeat || h.code == ECMXF_CMD_INFO_UPDATE_OP) {
		prepare(h.index, ECMXF_CMD_INFO_UPDATE_OP, 0, 0);
		return;
	}
	execute(h, std::span<const std::uint8_t>(data, dataSize_));
}

void Chip::Impl::badPacket()
{
	stats_.badPackets++;
	if (crcErrCnt_ < 255)
		crcErrCnt_++;
	errStatus_ |= ECMXF_ERR_SPI_CRC;
	intFlags_ |= ECMXF_INT_CRC_ERR;
	// an INFO_UPDATE-like refresh; the bad packet is not "the previous"
	prepare(prevIndex_, ECMXF_CMD_INFO_UPDATE_OP, 0, 0);
}

void Chip::Impl::applyHeader(const ecmxf_cmd_hdr &h)
{
	const unsigned c = h.control;
	if (c & ECMXF_CTL_CLR_CRC_CNT)
		crcErrCnt_ = 0;
	unsigned clear = 0;
	if (c & ECMXF_CTL_CLR_ASYNC_ERR)
		clear |= ECMXF_ERR_ASYNC;
	if (c & ECMXF_CTL_CLR_SPI_ERR)
		clear |= ECMXF_ERR_SPI;
	if (c & ECMXF_CTL_CLR_FIFO_ERR)
		clear |= ECMXF_ERR_FIFO;
	if (c & ECMXF_CTL_CLR_SPI_CRC_ERR)
		clear |= ECMXF_ERR_SPI_CRC;
	if (c & ECMXF_CTL_CLR_CMD_ERR)
		clear |= ECMXF_ERR_CMD;
	errStatus_ = static_cast<std::uint8_t>(errStatus_ & ~clear);
	intFlags_ &= ~h.int_clear;
	periph_.applyHeader(h);
	if (c & ECMXF_CTL_REFRESH_STATE)
		refreshStates();
}

void Chip::Impl::execute(const ecmxf_cmd_hdr &h, std::span<const std::uint8_t> data)
{
	if (ecmxf_cmd_is_async(h.code, h.param)) {
		if (h.code == ECMXF_CMD_WARM_RESET) {
			powerOn();
			busyUntil_ = now_ + kResetTime;
			return;
		}
		bool ok = false;
		if (!job_.active && h.len <= dataSize_)
			ok = startAsync(h, data);
		if (!ok)
			errStatus_ |= ECMXF_ERR_CMD;
		prepare(h.index, h.code, 0, 0);
		return;
	}

	Result r{};
	if (h.len > dataSize_ && h.code != ECMXF_CMD_SPI_RECONFIG_OP) {
		// a data length beyond the data section is a bad parameter:
		// nothing runs (Documentation/simulator.rst, the project's decision)
		r.cmdError = true;
	} else {
		r = immediate(h, data, std::span<std::uint8_t>(pending_.data.data(), dataSize_));
	}
	if (r.cmdError) {
		errStatus_ |= ECMXF_ERR_CMD;
		r.len = 0;
	}
	if (h.code == ECMXF_CMD_SPI_RECONFIG_OP && !r.cmdError)
		busyUntil_ = std::max(busyUntil_, now_ + kReconfigTime);
	prepare(h.index, h.code, r.ret, r.len);
	if (pendingCheck_ >= 0) {
		// CRC_TYPE_SET: its own answer still goes out in the old type
		check_ = static_cast<ecmxf_check>(pendingCheck_);
		pendingCheck_ = -1;
	}
}

void Chip::Impl::prepare(std::uint8_t index, std::uint8_t code, std::uint8_t ret, std::size_t len)
{
	ecmxf_rsp_hdr &r = pending_.hdr;
	r = ecmxf_rsp_hdr{};
	fillHeader(r);
	r.index = index;
	r.code = code;
	r.ret = ret;
	r.len = static_cast<std::uint16_t>(len);
	pending_.len = len;
	pending_.check = check_;
}

std::uint8_t Chip::Impl::ecatStateByte() const
{
	if (initialized_ && faults_.linkLost)
		return ECMXF_ECAT_ERROR;
	return ecatState_;
}

void Chip::Impl::fillHeader(ecmxf_rsp_hdr &r) const
{
	r.crc_err_cnt = crcErrCnt_;
	r.wkc_err_cnt = wkcErrCnt_;
	r.tx_fifo_cnt = static_cast<std::uint8_t>(std::min<std::size_t>(txFifo_.count(), 255));
	r.rx_fifo_cnt = static_cast<std::uint8_t>(std::min<std::size_t>(rxFifo_.count(), 255));
	r.ecat_state = ecatStateByte();
	unsigned err = errStatus_ & ECMXF_ERR_FAULT_MASK;
	if (!faults_.linkLost) {
		err |= ECMXF_ERR_LINK_HW;
		if (linkAtInit_)
			err |= ECMXF_ERR_LINK_SW;
	}
	r.err_status = static_cast<std::uint8_t>(err);
	unsigned st = static_cast<unsigned>(check_) & ECMXF_STS_CHECK_MASK;
	if (dcActive_ && cyclesOn_ && now_ >= dcStableAt_)
		st |= ECMXF_STS_DC_STABLE;
	if (ethInit_)
		st |= ECMXF_STS_ETH_INIT;
	if (layoutValid_ && !wkcStopped_)
		st |= ECMXF_STS_PDO_CONFIGURED;
	if (fifoEnabled_)
		st |= ECMXF_STS_FIFO_EN;
	if (job_.active)
		st |= ECMXF_STS_BUSY;
	r.ecm_status = static_cast<std::uint8_t>(st);
	r.int_flags = intFlags_ | periph_.intFlags();
	periph_.fillHeader(r);
}

void Chip::Impl::encodePending(std::uint8_t *pkt, std::size_t n) const
{
	const std::size_t dn = n - ECMXF_HDR_SIZE - ECMXF_TRAILER_SIZE;
	ecmxf_rsp_hdr h = pending_.hdr;
	const std::size_t len = std::min(pending_.len, dn);
	if (h.len > dn)
		h.len = static_cast<std::uint16_t>(dn);
	h.ecm_status = static_cast<std::uint8_t>((h.ecm_status & ~ECMXF_STS_CHECK_MASK) |
						 static_cast<unsigned>(pending_.check));
	ecmxf_encode_rsp(pkt, n, codecCheck(pending_.check), &h, pending_.data.data(), len);
}

ecmxf_check Chip::Impl::codecCheck(ecmxf_check check) const
{
	if (check == ECMXF_CHECK_FIXED || cfg_.crcCoverage != ChipConfig::CrcCoverage::Valid)
		return check;
	return static_cast<ecmxf_check>(static_cast<unsigned>(check) | ECMXF_CHECK_COVER_VALID);
}

// ======================================================================
// Impl: async commands
// ======================================================================

void Chip::Impl::startJob(std::uint8_t code, Nanos firstStep, std::function<AsyncJob::Step()> step)
{
	job_.active = true;
	job_.code = code;
	job_.stuck = false;
	if (faults_.asyncStuckBusy) {
		faults_.asyncStuckBusy = false;
		job_.stuck = true;
	}
	job_.next = now_ + std::max<Nanos>(firstStep, 1);
	job_.step = std::move(step);
}

void Chip::Impl::startJobOnce(std::uint8_t code, Nanos after, std::function<void()> work)
{
	startJob(code, after, [work = std::move(work)] {
		work();
		return AsyncJob::Step::Done;
	});
}

void Chip::Impl::stepJob()
{
	const AsyncJob::Step r = job_.step();
	if (r == AsyncJob::Step::Running) {
		if (job_.next <= now_)
			job_.next = now_ + 1;
		return;
	}
	endJob(r == AsyncJob::Step::Done);
}

void Chip::Impl::endJob(bool ok)
{
	job_.active = false;
	job_.stuck = false;
	job_.step = nullptr;
	if (!ok)
		errStatus_ |= ECMXF_ERR_ASYNC;
}

} // namespace ecmxf::sim
