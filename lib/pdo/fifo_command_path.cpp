// SPDX-License-Identifier: MIT
// FifoCommandPath: the cyclic exchange over ECAT_PDO_DATA_FIFO_OP commands
// through Device::transact() (sim:, spidev: and unix: devices; the kernel's
// devices use its PDO rings, RingPath in cyclic.cpp).
//
// What each command carries and what its answer means is the protocol
// core's pump (lib/core/ecmxf-pump.c), the policy the kernel's pump runs
// too: this file copies the frames, runs the commands and reports the
// cycle. Its own part is the level estimate: the RxFIFO count of the last
// write, less one frame per bus cycle since.

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/pdo/process_image.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <vector>

#include "ecmxf-proto.h"
#include "device/lib_text.hpp"
#include "ecmxf-pump.h"
#include "pdo/cyclic_path.hpp"

namespace ecmxf::detail {

namespace {

using std::chrono::nanoseconds;

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
constexpr const char *kTooManyFrames = ECMXF_FIFO_OP "the TxPDO data holds more frames than the data section can";
constexpr const char *kShortWkc = ECMXF_WC_GET "the answer is shorter than 4 bytes";

#undef ECMXF_FIFO_OP
#undef ECMXF_WC_GET


/// The command the pump built, as Device::transact() takes it.
RawCommand rawCommand(const ecmxf_cmd_hdr &hdr, std::chrono::microseconds timeout) noexcept
{
	RawCommand c;
	c.code = hdr.code;
	c.param = hdr.param;
	std::copy(std::begin(hdr.data), std::end(hdr.data), c.data.begin());
	c.control = hdr.control;
	c.reserved = hdr.reserved;
	c.timeout = timeout;
	return c;
}

/// The FIFO-command path: ECAT_PDO_DATA_FIFO_OP over Device::transact().
class FifoCommandPath final : public CyclicPath
{
public:
	FifoCommandPath(Device &dev, ProcessImage &image, const CyclicConfig &cfg);

	void start() override;
	void stop() override;
	void exchange(CycleResult &r, bool readWkc) noexcept override;
	Link &clock() noexcept override { return dev_.link(); }
	int waitInputs(nanoseconds timeout) noexcept override;

private:
	/// One ECAT_PDO_DATA_FIFO_OP as @p pl plans it (copies of the output
	/// frame, a read): false (and @p r failed) when the transport fails or
	/// the chip refuses the command. @p res and @p proto (0 or the pump's
	/// -EPROTO) tell the rest of its answer.
	bool fifoOp(CycleResult &r, const ecmxf_pump_plan &pl, ResponseHeader &h, ecmxf_pump_result &res,
		    int &proto, bool withWkc = false) noexcept;
	/// The working counter read of set @p set (fifoOp(withWkc)) into @p r.
	void takeWkc(CycleResult &r, int set) noexcept;
	/// Hands the @p n TxPDO frames of the last answer over; false (and @p r
	/// failed) when the pump found the answer's data bad (@p proto).
	bool takeFrames(CycleResult &r, const ResponseHeader &h, unsigned n, int proto) noexcept;

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
	/// the protocol core's pump: the plans and the answers' meaning
	ecmxf_pump pump_{};
	/// The working counter read rides behind the cycle's first FIFO
	/// command: over a link that pipelines, its answer is fetched by the
	/// next exchange (the next cycle's first), so a cycle costs two
	/// exchanges. Two sets of results and buffers, used in turn: the
	/// engine fills the last cycle's while this cycle's batch runs.
	std::array<std::array<RawResult, 2>, 2> batch_{};
	std::array<std::array<std::uint8_t, 4>, 2> wkcBuf_{};
	/// The set whose working counter read is not taken yet, or -1.
	int wkcSet_ = -1;

public:
	~FifoCommandPath() override
	{
		// nothing may keep pointing at wkcRes_ / wkcBuf_
		dev_.link().settle();
	}
};

FifoCommandPath::FifoCommandPath(Device &dev, ProcessImage &image, const CyclicConfig &cfg)
	: dev_(dev), image_(image), cfg_(cfg)
{
	readChip(dev, image, cfg);
	maxReads_ = perRead ? txDepth / perRead + 2 : 0;
	txBuf_.assign(dataCapacity, 0);
	rxBuf_.assign(dataCapacity, 0);
	ecmxf_pump_init(&pump_, static_cast<u32>(sizes.rxPdoBytes), static_cast<u32>(sizes.txPdoBytes),
			static_cast<u32>(dataCapacity), rxDepth, rxFill, txDepth);
}

void FifoCommandPath::start()
{
	if (sizes.rxPdoBytes)
		dev_.pdo().pdoWrite(image_.outputs());
	dev_.pdo().fifoClear(FifoSelect::Both);
	dev_.pdo().fifoEnable(true);
	rxLevel_ = 0;
	txLevel_ = 0;
	rxTime_ = txTime_ = clock().now();
}

void FifoCommandPath::stop()
{
	dev_.link().settle();
	wkcSet_ = -1;
	dev_.pdo().fifoEnable(false);
}

bool FifoCommandPath::fifoOp(CycleResult &r, const ecmxf_pump_plan &pl, ResponseHeader &h, ecmxf_pump_result &res,
			     int &proto, bool withWkc) noexcept
{
	const std::size_t frameBytes = sizes.rxPdoBytes;
	const std::span<const std::uint8_t> out = image_.outputs();
	for (unsigned i = 0; i < pl.push; i++)
		std::memcpy(txBuf_.data() + i * frameBytes, out.data(), frameBytes);
	ecmxf_cmd_hdr hdr;
	const u32 len = ecmxf_pump_fifo_cmd(&pump_, &pl, false, &hdr);
	const std::span<const std::uint8_t> payload(txBuf_.data(), len);
	int err = 0;
	if (!withWkc) {
		err = dev_.transact(rawCommand(hdr, cfg_.commandTimeout), payload, rxBuf_, h);
	} else {
		ecmxf_cmd_hdr wh;
		ecmxf_pump_wkc_cmd(&wh);
		const int prev = wkcSet_;
		const int set = prev == 0 ? 1 : 0;
		const std::array<RawRequest, 2> req{
			dev_.request(rawCommand(hdr, cfg_.commandTimeout), payload, rxBuf_),
			dev_.request(rawCommand(wh, cfg_.commandTimeout), {}, wkcBuf_[static_cast<std::size_t>(set)]),
		};
		std::array<RawResult, 2> &res2 = batch_[static_cast<std::size_t>(set)];
		// the read rides in the exchange that fetches the FIFO command's
		// answer; its own answer may be left to the next exchange
		// (CyclicConfig::wkcAnswerNextCycle)
		dev_.link().runBatch(req, res2, cfg_.wkcAnswerNextCycle);
		wkcSet_ = set;
		// a failed cycle reports the FIFO command's failure; the read's
		// outcome, when it is in, is moot
		if (res2[0].status && res2[1].status != -EINPROGRESS)
			wkcSet_ = -1;
		r.commands++;
		err = -res2[0].status;
		if (!res2[0].linkFailure)
			h = res2[0].header;
		// the last cycle's read was answered by this batch's first exchange
		if (prev >= 0)
			takeWkc(r, prev);
	}
	r.commands++;
	if (err) {
		cycleFail(r, err, fifoOpText(err));
		return false;
	}
	const ecmxf_rsp_hdr rh = detail::wireHeader<ecmxf_rsp_hdr>(h);
	proto = ecmxf_pump_answer(&pump_, &pl, &rh, h.len, &res);
	if (proto == -EREMOTEIO) {
		cycleFail(r, EREMOTEIO, fifoOpText(EREMOTEIO));
		return false;
	}
	return true;
}

bool FifoCommandPath::takeFrames(CycleResult &r, const ResponseHeader &h, unsigned n, int proto) noexcept
{
	const std::size_t size = sizes.txPdoBytes;
	if (proto) {
		cycleFail(r, EPROTO, size && h.len % size ? kNotWholeFrames : kTooManyFrames);
		return false;
	}
	if (n == 0)
		return true;
	if (cfg_.onInputFrame)
		for (std::size_t i = 0; i < n; i++)
			cfg_.onInputFrame(cfg_.context, std::span<const std::uint8_t>(rxBuf_.data() + i * size, size));
	std::memcpy(image_.inputs().data(), rxBuf_.data() + (n - 1) * size, size);
	r.framesPopped += n;
	r.inputsUpdated = true;
	return true;
}

int FifoCommandPath::waitInputs(nanoseconds timeout) noexcept
{
	if (!sizes.txPdoBytes)
		return EINVAL;
	// once per bus cycle: a new input frame can only come with one
	const nanoseconds step = cfg_.busCycle.count() > 0 ? cfg_.busCycle : cfg_.period;
	try {
		Link &t = clock();
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

void FifoCommandPath::takeWkc(CycleResult &r, int set) noexcept
{
	const RawResult &res = batch_[static_cast<std::size_t>(set)][1];
	if (res.status) {
		cycleFail(r, -res.status, wcGetText(-res.status));
		return;
	}
	const ecmxf_rsp_hdr rh = detail::wireHeader<ecmxf_rsp_hdr>(res.header);
	std::uint32_t wkc = 0;
	const int werr = ecmxf_pump_wkc_answer(&rh, wkcBuf_[static_cast<std::size_t>(set)].data(), res.header.len, &wkc);
	if (werr) {
		cycleFail(r, -werr, werr == -EREMOTEIO ? wcGetText(EREMOTEIO) : kShortWkc);
		return;
	}
	r.wkcRead = true;
	r.wkc = wkc;
	r.wkcOk = r.wkc == r.expectedWkc;
}

void FifoCommandPath::exchange(CycleResult &r, bool readWkc) noexcept
{
	const bool haveOut = sizes.rxPdoBytes > 0;
	ResponseHeader h{};

	// the RxFIFO level to plan with: the count from our last write, less
	// about one frame per bus cycle since (one per application cycle when
	// the bus cycle is not configured)
	unsigned level = 0;
	if (haveOut) {
		std::uint64_t gone = 1;
		// the link's coarse clock: an estimate needs no clock read (over
		// spidev the end of the last sleep, or INT0's last ready edge)
		if (cfg_.busCycle.count() > 0) {
			const nanoseconds dt = clock().coarseNow() - rxTime_;
			gone = dt.count() > 0 ? static_cast<std::uint64_t>(dt / cfg_.busCycle) : 0;
		}
		level = gone >= rxLevel_ ? 0u : rxLevel_ - static_cast<unsigned>(gone);
	}

	// the writes, planned by the pump; the first command also reads and
	// offers at least this cycle's outputs. The image is the only frame:
	// as many copies as the plan wants.
	bool first = true;
	bool wkcCarried = false;
	unsigned pushed = 0;
	for (;;) {
		ecmxf_pump_plan pl;
		const unsigned flags = first ? ECMXF_PUMP_F_READ | ECMXF_PUMP_F_ONE : 0;
		if (!ecmxf_pump_next(&pump_, level + pushed, haveOut ? pump_.rx_fill : 0, flags, &pl))
			break;
		ecmxf_pump_result res;
		int proto = 0;
		const bool withWkc = first && readWkc;
		wkcCarried |= withWkc;
		if (!fifoOp(r, pl, h, res, proto, withWkc))
			return;
		r.framesPushed += pl.push;
		if (pl.push) {
			rxLevel_ = h.rxFifoCnt;
			rxTime_ = clock().coarseNow();
		}
		if (pl.read) {
			if (!takeFrames(r, h, res.popped, proto))
				return;
			// a full TxFIFO dropped its oldest (the pump: popped + left
			// reached the depth)
			const nanoseconds now = clock().coarseNow();
			if (res.tx_overrun) {
				r.txOverflow = true;
				if (cfg_.busCycle.count() > 0) {
					const unsigned queued = res.popped + h.txFifoCnt;
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
				ecmxf_pump_plan rd;
				ecmxf_pump_next(&pump_, 0, 0, ECMXF_PUMP_F_READ, &rd);
				ecmxf_pump_result more;
				if (!fifoOp(r, rd, h, more, proto))
					return;
				if (!takeFrames(r, h, more.popped, proto))
					return;
				txLevel_ = h.txFifoCnt;
				txTime_ = clock().coarseNow();
				if (more.popped == 0)
					break;
			}
		}
		first = false;
		pushed += pl.push;
		// return value bit 0 clear: the RxFIFO was full, the newest
		// frames were refused, and more would be too
		if (res.refused) {
			r.rxRefused = true;
			break;
		}
	}

	if (readWkc && !wkcCarried) {
		// no FIFO command went out to carry it: on its own
		ecmxf_cmd_hdr wh;
		ecmxf_pump_wkc_cmd(&wh);
		const int set = wkcSet_ == 0 ? 1 : 0;
		if (wkcSet_ >= 0)
			dev_.link().settle();
		std::array<RawResult, 2> &res2 = batch_[static_cast<std::size_t>(set)];
		res2[1] = RawResult{};
		dev_.link().run(dev_.request(rawCommand(wh, cfg_.commandTimeout), {}, wkcBuf_[static_cast<std::size_t>(set)]), res2[1]);
		r.commands++;
		if (wkcSet_ >= 0)
			takeWkc(r, wkcSet_);
		wkcSet_ = set;
		if (!res2[1].linkFailure)
			h = res2[1].header;
	}
	// over a link that runs one command at a time, this cycle's read is
	// in already
	if (wkcSet_ >= 0 && batch_[static_cast<std::size_t>(wkcSet_)][1].status != -EINPROGRESS) {
		takeWkc(r, wkcSet_);
		wkcSet_ = -1;
	}

	r.rxFifoCount = h.rxFifoCnt;
	r.txFifoCount = h.txFifoCnt;
	r.wkcErrorCount = h.wkcErrCnt;
	r.ecatState = h.ecatState;
	r.errStatus = h.errStatus;
	r.ecmStatus = h.ecmStatus;
	r.intFlags = h.intFlags;
}
} // namespace

std::unique_ptr<CyclicPath> makeFifoCommandPath(Device &dev, ProcessImage &image, const CyclicConfig &cfg)
{
	return std::make_unique<FifoCommandPath>(dev, image, cfg);
}

} // namespace ecmxf::detail
