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
//
// Two ways to run a cycle: the synchronous one (exchange()), whose FIFO
// commands are answered within the cycle, and, with
// CyclicConfig::fifoAnswerNextCycle, the one that leaves the cycle's FIFO
// command in flight (exchangeAhead()): its answer comes with the next
// cycle's first exchange, which sends the next FIFO command, and is taken
// then: one SPI exchange per cycle.

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
#include <optional>
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

/// The response header fields of CycleResult from @p h.
void showHeader(CycleResult &r, const ResponseHeader &h) noexcept
{
	r.rxFifoCount = h.rxFifoCnt;
	r.txFifoCount = h.txFifoCnt;
	r.wkcErrorCount = h.wkcErrCnt;
	r.ecatState = h.ecatState;
	r.errStatus = h.errStatus;
	r.ecmStatus = h.ecmStatus;
	r.intFlags = h.intFlags;
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
	/// CyclicConfig::fifoAnswerNextCycle's cycle: one FIFO command sent
	/// and left in flight, the previous cycle's answer taken.
	void exchangeAhead(CycleResult &r, bool readWkc) noexcept;
	/// Takes the answer to the FIFO command of set @p set (exchangeAhead())
	/// into @p r; @p shown gets its header.
	void takeAhead(CycleResult &r, int set, ResponseHeader &shown) noexcept;
	/// The RxFIFO level to plan with: the count of the last answer taken
	/// plus @p inFlight frames no header has shown yet, less about one
	/// frame per bus cycle since the chip ran that command (one per
	/// application cycle when the bus cycle is not configured).
	[[nodiscard]] unsigned rxEstimate(unsigned inFlight) const noexcept;
	/// @p n copies of the image's output frame at @p dst.
	void copyOutputs(std::uint8_t *dst, unsigned n) const noexcept;
	/// A full TxFIFO found by an answer (@p res, @p h) to a command the
	/// chip ran at @p at: r.txOverflow and the estimate of the frames lost.
	void noteOverrun(CycleResult &r, const ecmxf_pump_result &res, const ResponseHeader &h,
			 nanoseconds at) const noexcept;
	/// One ECAT_PDO_DATA_FIFO_OP as @p pl plans it (copies of the output
	/// frame, a read): false (and @p r failed) when the transport fails or
	/// the chip refuses the command. @p res and @p proto (0 or the pump's
	/// -EPROTO) tell the rest of its answer.
	bool fifoOp(CycleResult &r, const ecmxf_pump_plan &pl, ResponseHeader &h, ecmxf_pump_result &res,
		    int &proto, bool withWkc = false) noexcept;
	/// The working counter read answered in @p res, its data in @p data,
	/// into @p r.
	static void takeWkc(CycleResult &r, const RawResult &res, std::span<const std::uint8_t, 4> data) noexcept;
	/// The working counter read of set @p set (fifoOp(withWkc)) into @p r.
	void takeWkc(CycleResult &r, int set) noexcept
	{
		const auto s = static_cast<std::size_t>(set);
		takeWkc(r, batch_[s][1], wkcBuf_[s]);
	}
	/// Hands the @p n TxPDO frames of an answer (its data in @p data) over;
	/// false (and @p r failed) when the pump found the answer's data bad
	/// (@p proto).
	bool takeFrames(CycleResult &r, const ResponseHeader &h, unsigned n, int proto,
			std::span<const std::uint8_t> data) noexcept;
	bool takeFrames(CycleResult &r, const ResponseHeader &h, unsigned n, int proto) noexcept
	{
		return takeFrames(r, h, n, proto, rxBuf_);
	}

	Device &dev_;
	ProcessImage &image_;
	const CyclicConfig &cfg_;
	std::vector<std::uint8_t> txBuf_, rxBuf_;
	/// RxFIFO count after our last write, TxFIFO count after our last read
	/// (the answers' headers), and when those answers came.
	unsigned rxLevel_ = 0;
	unsigned txLevel_ = 0;
	nanoseconds rxTime_{ 0 }, txTime_{ 0 };
	/// exchange() calls since start(), and the one whose command gave
	/// rxLevel_ (for the level estimate without a bus cycle)
	std::uint64_t cycles_ = 0, rxCycle_ = 0;
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
	/// CyclicConfig::fifoAnswerNextCycle: the FIFO command whose answer
	/// the next exchange on the link fetches. Two sets used in turn: the
	/// engine fills the last cycle's (its result, its rx buffer; it may
	/// send its tx frames again after a bad packet) while this cycle's
	/// command goes out in the same exchange.
	struct Ahead {
		/// [0] the cycle's ECAT_PDO_WC_GET (answered within the
		/// cycle), [1] its ECAT_PDO_DATA_FIFO_OP
		std::array<RawResult, 2> res{};
		std::vector<std::uint8_t> tx, rx;
		std::array<std::uint8_t, 4> wkc{};
		ecmxf_pump_plan plan{};
		/// when the exchange that sent it ended (the chip ran it then:
		/// its answer's header counts are of that time), and in which
		/// cycle
		nanoseconds sentAt{ 0 };
		std::uint64_t cycle = 0;
	};
	std::array<Ahead, 2> ahead_{};
	/// The set whose FIFO command's answer is not taken yet, or -1.
	int aheadSet_ = -1;

public:
	~FifoCommandPath() override
	{
		// nothing may keep pointing at batch_ / wkcBuf_ / ahead_
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
	if (cfg.fifoAnswerNextCycle)
		for (Ahead &a : ahead_) {
			a.tx.assign(dataCapacity, 0);
			a.rx.assign(dataCapacity, 0);
		}
	ecmxf_pump_init(&pump_, static_cast<u32>(sizes.rxPdoBytes), static_cast<u32>(sizes.txPdoBytes),
			static_cast<u32>(dataCapacity), rxDepth, rxFill, txDepth);
}

void FifoCommandPath::start()
{
	// a stop() that threw may have left a command in flight
	dev_.link().settle();
	wkcSet_ = -1;
	aheadSet_ = -1;
	if (sizes.rxPdoBytes)
		dev_.pdo().write(image_.outputs());
	dev_.pdo().fifoClear(FifoSelect::Both);
	dev_.pdo().fifoEnable(true);
	rxLevel_ = 0;
	txLevel_ = 0;
	cycles_ = rxCycle_ = 0;
	rxTime_ = txTime_ = clock().now();
}

void FifoCommandPath::stop()
{
	// the answers in flight are fetched; the last FIFO command's (its
	// input frames) is dropped: no cycle reports it
	dev_.link().settle();
	wkcSet_ = -1;
	aheadSet_ = -1;
	dev_.pdo().fifoEnable(false);
}

bool FifoCommandPath::fifoOp(CycleResult &r, const ecmxf_pump_plan &pl, ResponseHeader &h, ecmxf_pump_result &res,
			     int &proto, bool withWkc) noexcept
{
	copyOutputs(txBuf_.data(), pl.push);
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

void FifoCommandPath::copyOutputs(std::uint8_t *dst, unsigned n) const noexcept
{
	const std::size_t frameBytes = sizes.rxPdoBytes;
	const std::span<const std::uint8_t> out = image_.outputs();
	for (unsigned i = 0; i < n; i++)
		std::memcpy(dst + i * frameBytes, out.data(), frameBytes);
}

bool FifoCommandPath::takeFrames(CycleResult &r, const ResponseHeader &h, unsigned n, int proto,
				 std::span<const std::uint8_t> data) noexcept
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
			cfg_.onInputFrame(cfg_.context, data.subspan(i * size, size));
	std::memcpy(image_.inputs().data(), data.data() + (n - 1) * size, size);
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
		// fifoAnswerNextCycle: the answer in flight first; frames in it
		// are the next cycle()'s
		if (aheadSet_ >= 0) {
			dev_.link().settle();
			const Ahead &a = ahead_[static_cast<std::size_t>(aheadSet_)];
			if (a.plan.read && a.res[1].status == 0 && a.res[1].header.len >= sizes.txPdoBytes)
				return 0;
		}
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

void FifoCommandPath::takeWkc(CycleResult &r, const RawResult &res, std::span<const std::uint8_t, 4> data) noexcept
{
	if (res.status) {
		cycleFail(r, -res.status, wcGetText(-res.status));
		return;
	}
	const ecmxf_rsp_hdr rh = detail::wireHeader<ecmxf_rsp_hdr>(res.header);
	std::uint32_t wkc = 0;
	const int werr = ecmxf_pump_wkc_answer(&rh, data.data(), res.header.len, &wkc);
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
	if (cfg_.fifoAnswerNextCycle) {
		exchangeAhead(r, readWkc);
		return;
	}
	const bool haveOut = sizes.rxPdoBytes > 0;
	ResponseHeader h{};

	// the RxFIFO level to plan with: the count from our last write, less
	// about one frame per bus cycle since
	cycles_++;
	const unsigned level = haveOut ? rxEstimate(0) : 0;

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
			rxCycle_ = cycles_;
		}
		if (pl.read) {
			if (!takeFrames(r, h, res.popped, proto))
				return;
			const nanoseconds now = clock().coarseNow();
			noteOverrun(r, res, h, now);
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

	showHeader(r, h);
}

unsigned FifoCommandPath::rxEstimate(unsigned inFlight) const noexcept
{
	std::uint64_t gone = cycles_ - rxCycle_;
	// the link's coarse clock: an estimate needs no clock read (over
	// spidev the end of the last sleep, or INT0's last ready edge)
	if (cfg_.busCycle.count() > 0) {
		const nanoseconds dt = dev_.link().coarseNow() - rxTime_;
		gone = dt.count() > 0 ? static_cast<std::uint64_t>(dt / cfg_.busCycle) : 0;
	}
	const std::uint64_t have = std::uint64_t{ rxLevel_ } + inFlight;
	return gone >= have ? 0u : static_cast<unsigned>(have - gone);
}

void FifoCommandPath::noteOverrun(CycleResult &r, const ecmxf_pump_result &res, const ResponseHeader &h,
				  nanoseconds at) const noexcept
{
	// a full TxFIFO dropped its oldest (the pump: popped + left reached
	// the depth)
	if (!res.tx_overrun)
		return;
	r.txOverflow = true;
	if (cfg_.busCycle.count() > 0) {
		const unsigned queued = res.popped + h.txFifoCnt;
		const std::uint64_t made = at > txTime_ ? static_cast<std::uint64_t>((at - txTime_) / cfg_.busCycle) : 0;
		const std::uint64_t expected = txLevel_ + made;
		r.txDroppedEstimate =
			expected > queued ? static_cast<std::uint32_t>(std::min<std::uint64_t>(expected - queued, UINT32_MAX))
					  : 0;
	}
}

void FifoCommandPath::takeAhead(CycleResult &r, int set, ResponseHeader &shown) noexcept
{
	Ahead &a = ahead_[static_cast<std::size_t>(set)];
	const RawResult &res = a.res[1];
	if (!res.linkFailure)
		shown = res.header;
	if (res.status) {
		cycleFail(r, -res.status, fifoOpText(-res.status));
		return;
	}
	const ResponseHeader &h = res.header;
	const ecmxf_rsp_hdr rh = detail::wireHeader<ecmxf_rsp_hdr>(h);
	ecmxf_pump_result pr;
	const int proto = ecmxf_pump_answer(&pump_, &a.plan, &rh, h.len, &pr);
	if (proto == -EREMOTEIO) {
		cycleFail(r, EREMOTEIO, fifoOpText(EREMOTEIO));
		return;
	}
	r.framesPushed += a.plan.push;
	if (a.plan.push) {
		// the chip ran the command, and made its answer, when it was sent
		rxLevel_ = h.rxFifoCnt;
		rxTime_ = a.sentAt;
		rxCycle_ = a.cycle;
	}
	if (a.plan.read) {
		if (!takeFrames(r, h, pr.popped, proto, a.rx))
			return;
		noteOverrun(r, pr, h, a.sentAt);
		txTime_ = a.sentAt;
		txLevel_ = h.txFifoCnt;
	}
	if (pr.refused)
		r.rxRefused = true;
}

void FifoCommandPath::exchangeAhead(CycleResult &r, bool readWkc) noexcept
{
	const bool haveOut = sizes.rxPdoBytes > 0;
	cycles_++;
	const int prev = aheadSet_;
	const int set = prev == 0 ? 1 : 0;
	Ahead &a = ahead_[static_cast<std::size_t>(set)];

	// the level: the last answer's count, plus the frames of the command
	// still in flight (no header shows them yet), less the bus cycles
	// since the chip ran the answered command
	const unsigned inFlight = prev >= 0 ? ahead_[static_cast<std::size_t>(prev)].plan.push : 0;
	const unsigned level = haveOut ? rxEstimate(inFlight) : 0;

	// one FIFO command: it reads and offers at least this cycle's outputs.
	// The follow-up writes and reads of exchange() would need its answer:
	// a backlog is left to the next cycles.
	ecmxf_pump_next(&pump_, level, haveOut ? pump_.rx_fill : 0, ECMXF_PUMP_F_READ | ECMXF_PUMP_F_ONE, &a.plan);
	copyOutputs(a.tx.data(), a.plan.push);
	ecmxf_cmd_hdr hdr;
	const u32 len = ecmxf_pump_fifo_cmd(&pump_, &a.plan, false, &hdr);
	std::array<RawRequest, 2> req{};
	// a working counter read goes first: its answer comes back in the
	// exchange that sends the FIFO command (two exchanges), and the FIFO
	// command's answer is left in flight as in any cycle
	const std::size_t first = readWkc ? 0 : 1;
	if (readWkc) {
		ecmxf_cmd_hdr wh;
		ecmxf_pump_wkc_cmd(&wh);
		req[0] = dev_.request(rawCommand(wh, cfg_.commandTimeout), {}, a.wkc);
	}
	req[1] = dev_.request(rawCommand(hdr, cfg_.commandTimeout), std::span<const std::uint8_t>(a.tx.data(), len),
			      a.rx);
	dev_.link().runBatch(std::span<const RawRequest>(req).subspan(first),
			     std::span<RawResult>(a.res).subspan(first), true);
	a.sentAt = clock().coarseNow();
	a.cycle = cycles_;
	aheadSet_ = set;
	r.commands += static_cast<unsigned>(2 - first);

	if (readWkc)
		takeWkc(r, a.res[0], a.wkc);
	ResponseHeader shown{};
	bool taken = false;
	// the previous cycle's command: this batch's first exchange fetched
	// its answer (the batch waits for every answer but the last)
	if (prev >= 0) {
		Ahead &p = ahead_[static_cast<std::size_t>(prev)];
		if (p.res[1].status == -EINPROGRESS)
			dev_.link().settle();
		takeAhead(r, prev, shown);
		taken = true;
	}
	// a link that does not pipeline ran it to its end (or it failed
	// before it was sent): take it now
	if (a.res[1].status != -EINPROGRESS) {
		aheadSet_ = -1;
		takeAhead(r, set, shown);
		taken = true;
	}
	if (!taken) {
		// the first cycle: no answer yet, the latest header the chip sent
		if (const std::optional<ResponseHeader> lh = dev_.link().lastHeader())
			shown = *lh;
	}
	showHeader(r, shown);
}
} // namespace

std::unique_ptr<CyclicPath> makeFifoCommandPath(Device &dev, ProcessImage &image, const CyclicConfig &cfg)
{
	return std::make_unique<FifoCommandPath>(dev, image, cfg);
}

} // namespace ecmxf::detail
