// SPDX-License-Identifier: MIT
// FifoCommandPath: the cyclic exchange over ECAT_PDO_DATA_FIFO_OP commands
// through Device::transact() (sim:, spidev: and unix: devices; the kernel's
// devices use its PDO rings, RingPath in cyclic.cpp).
//
// Every decision is the protocol core's pump (lib/core/ecmxf-pump.c and
// ecmxf-pump-sched.c), the policy the kernel's pump runs too: what each
// command carries and what its answer means, the commands of a cycle
// (ecmxf_pump_cycle_*), the RxFIFO estimate and the TxFIFO loss estimate
// (ecmxf_pump_est_*), the FIFO commands in flight and which answer is
// whose (ecmxf_pump_flight). This file copies the frames, runs the
// commands, reads the clock and reports the cycle.
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
#include "base/text.hpp"
#include "link/wire_header.hpp"
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

/// A time on the link's clock for the protocol core (never negative).
u64 coreTime(nanoseconds t) noexcept
{
	return t.count() > 0 ? static_cast<u64>(t.count()) : 0;
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
	void takeAhead(CycleResult &r, unsigned set, ResponseHeader &shown) noexcept;
	/// @p n copies of the image's output frame at @p dst.
	void copyOutputs(std::uint8_t *dst, unsigned n) const noexcept;
	/// A full TxFIFO (the estimate's @p overrun, @p dropped) into @p r.
	static void noteOverrun(CycleResult &r, bool overrun, std::uint32_t dropped) noexcept
	{
		if (overrun) {
			r.txOverflow = true;
			r.txDroppedEstimate = dropped;
		}
	}
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
	/// the protocol core's pump: the plans and the answers' meaning
	ecmxf_pump pump_{};
	/// its RxFIFO and TxFIFO estimate (the counts of the last answers,
	/// when the chip ran them, the cycles)
	ecmxf_pump_est est_{};
	/// its schedule and the FIFO commands in flight
	/// (CyclicConfig::fifoAnswerNextCycle: the sets of ahead_)
	ecmxf_pump_sched sched_{};
	ecmxf_pump_flight flight_{};
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
		/// when the exchange that sent it ended (the chip ran it then:
		/// its answer's header counts are of that time), and in which
		/// cycle
		nanoseconds sentAt{ 0 };
		std::uint64_t cycle = 0;
	};
	/// (their plans and which is in flight: flight_)
	std::array<Ahead, 2> ahead_{};

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
	txBuf_.assign(dataCapacity, 0);
	rxBuf_.assign(dataCapacity, 0);
	if (cfg.fifoAnswerNextCycle)
		for (Ahead &a : ahead_) {
			a.tx.assign(dataCapacity, 0);
			a.rx.assign(dataCapacity, 0);
		}
	ecmxf_pump_init(&pump_, static_cast<u32>(sizes.rxPdoBytes), static_cast<u32>(sizes.txPdoBytes),
			static_cast<u32>(dataCapacity), rxDepth, rxFill, txDepth);
	ecmxf_pump_sched_init(&sched_, cfg.fifoAnswerNextCycle ? ECMXF_PUMP_S_FIFO_NEXT : 0, 0, 0);
}

void FifoCommandPath::start()
{
	// a stop() that threw may have left a command in flight
	dev_.link().settle();
	wkcSet_ = -1;
	flight_ = ecmxf_pump_flight{};
	if (sizes.rxPdoBytes)
		dev_.pdo().write(image_.outputs());
	dev_.pdo().fifoClear(FifoSelect::Both);
	dev_.pdo().fifoEnable(true);
	ecmxf_pump_est_start(&est_, coreTime(cfg_.busCycle), coreTime(clock().now()));
}

void FifoCommandPath::stop()
{
	// the answers in flight are fetched; the last FIFO command's (its
	// input frames) is dropped: no cycle reports it
	dev_.link().settle();
	wkcSet_ = -1;
	flight_ = ecmxf_pump_flight{};
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
		const unsigned newest = flight_.newest;
		if (flight_.busy[newest]) {
			dev_.link().settle();
			const Ahead &a = ahead_[newest];
			if (flight_.plan[newest].read && a.res[1].status == 0 && a.res[1].header.len >= sizes.txPdoBytes)
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
	ResponseHeader h{};

	// the cycle's commands as the pump plans them: the first writes (at
	// least this cycle's outputs, up to the fill level of the estimate)
	// and reads, read-only commands for a TxFIFO backlog, more writes.
	// The image is the only frame: as many copies as the plan wants.
	ecmxf_pump_cycle cyc;
	ecmxf_pump_cycle_start(&cyc, ecmxf_pump_est_cycle(&est_, &pump_, 0, coreTime(clock().coarseNow())), readWkc);
	ecmxf_pump_plan pl;
	bool withWkc = false;
	while (ecmxf_pump_cycle_next(&pump_, &cyc, &pl, &withWkc)) {
		ecmxf_pump_result res;
		int proto = 0;
		if (!fifoOp(r, pl, h, res, proto, withWkc))
			return;
		r.framesPushed += pl.push;
		// the chip ran the command, and made its answer, by now
		const u64 at = coreTime(clock().coarseNow());
		ecmxf_pump_est_pushed(&est_, &pl, h.rxFifoCnt, at, est_.cycles);
		if (!takeFrames(r, h, res.popped, proto))
			return;
		std::uint32_t dropped = 0;
		const bool overrun =
			ecmxf_pump_cycle_answer(&pump_, &cyc, &est_, &pl, &res, h.txFifoCnt, at, &dropped);
		noteOverrun(r, overrun, dropped);
	}
	r.rxRefused = cyc.refused;

	if (ecmxf_pump_cycle_wkc_alone(&cyc)) {
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

void FifoCommandPath::takeAhead(CycleResult &r, unsigned set, ResponseHeader &shown) noexcept
{
	Ahead &a = ahead_[set];
	const RawResult &res = a.res[1];
	if (!res.linkFailure)
		shown = res.header;
	std::uint32_t skipped = 0;
	if (ecmxf_pump_sched_finish(&flight_, set, res.status, &skipped) != ECMXF_PUMP_DONE_ANSWER) {
		cycleFail(r, -res.status, fifoOpText(-res.status));
		return;
	}
	const ecmxf_pump_plan &pl = flight_.plan[set];
	const ResponseHeader &h = res.header;
	const ecmxf_rsp_hdr rh = detail::wireHeader<ecmxf_rsp_hdr>(h);
	ecmxf_pump_result pr;
	const int proto = ecmxf_pump_answer(&pump_, &pl, &rh, h.len, &pr);
	if (proto == -EREMOTEIO) {
		cycleFail(r, EREMOTEIO, fifoOpText(EREMOTEIO));
		return;
	}
	r.framesPushed += pl.push;
	// the chip ran the command, and made its answer, when it was sent
	ecmxf_pump_est_pushed(&est_, &pl, h.rxFifoCnt, coreTime(a.sentAt), a.cycle);
	if (!takeFrames(r, h, pr.popped, proto, a.rx))
		return;
	std::uint32_t dropped = 0;
	noteOverrun(r, ecmxf_pump_est_popped(&est_, &pl, &pr, h.txFifoCnt, coreTime(a.sentAt), &dropped), dropped);
	r.rxRefused = r.rxRefused || pr.refused > 0;
}

void FifoCommandPath::exchangeAhead(CycleResult &r, bool readWkc) noexcept
{
	// the level: the last answer's count, plus the frames of the command
	// still in flight (no header shows them yet), less the bus cycles
	// since the chip ran the answered command
	const unsigned level =
		ecmxf_pump_est_cycle(&est_, &pump_, ecmxf_pump_flight_pushed(&flight_), coreTime(clock().coarseNow()));
	// the set: the one not in flight; the other one, if in flight, is the
	// previous cycle's command, whose answer this cycle's exchange fetches
	const unsigned set = ecmxf_pump_sched_fifo(&sched_, &flight_, 0);
	const unsigned prev = set ^ 1U;
	const bool prevInFlight = flight_.busy[prev];
	Ahead &a = ahead_[set];
	const ecmxf_pump_plan &pl = flight_.plan[set];

	// one FIFO command: it reads and offers at least this cycle's outputs.
	// The follow-up writes and reads of exchange() would need its answer:
	// a backlog is left to the next cycles.
	ecmxf_pump_cycle_ahead(&pump_, &flight_, set, level);
	copyOutputs(a.tx.data(), pl.push);
	ecmxf_cmd_hdr hdr;
	const u32 len = ecmxf_pump_fifo_cmd(&pump_, &pl, false, &hdr);
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
	a.cycle = est_.cycles;
	ecmxf_pump_sched_sent(&flight_, set, 0);
	r.commands += static_cast<unsigned>(2 - first);

	if (readWkc)
		takeWkc(r, a.res[0], a.wkc);
	ResponseHeader shown{};
	bool taken = false;
	// the previous cycle's command: this batch's first exchange fetched
	// its answer (the batch waits for every answer but the last)
	if (prevInFlight) {
		if (ahead_[prev].res[1].status == -EINPROGRESS)
			dev_.link().settle();
		takeAhead(r, prev, shown);
		taken = true;
	}
	// a link that does not pipeline ran it to its end (or it failed
	// before it was sent): take it now
	if (a.res[1].status != -EINPROGRESS) {
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
