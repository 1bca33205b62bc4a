// SPDX-License-Identifier: MIT
// EngineLink: the protocol core's exchange engine (lib/core) run over a
// ByteChannel; the owner loop of Documentation/protocol-core.rst
// (include/ecmxf/link/engine_link.hpp).

#include <ecmxf/error.hpp>
#include <ecmxf/link/engine_link.hpp>
#include <ecmxf/link/sim_channel.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <exception>
#include <span>
#include <string>
#include <utility>

#include "ecmxf-proto.h"
#include "base/text.hpp"
#include "link/wire_header.hpp"
#include "link/outcome.hpp"
#include "link/trace_writer.hpp"

namespace ecmxf {

namespace {

using std::chrono::nanoseconds;

/// How long one wait for INT0 lasts before the engine's deadlines are
/// applied without an exchange.
constexpr nanoseconds kReadyWait = std::chrono::milliseconds(10);

} // namespace

class EngineLink::Engine
{
public:
	explicit Engine(std::unique_ptr<ByteChannel> c) : channel(std::move(c))
	{
		if (!channel)
			throw Error("ecmxf::EngineLink: no byte channel given", EINVAL);
		ecmxf_engine_init(&engine, ECMXF_DATA_DEFAULT, ECMXF_CHECK_FIXED);
	}

	void runBatch(std::span<const RawRequest> reqs, std::span<RawResult> res, bool leaveLast) noexcept;

	std::unique_ptr<ByteChannel> channel;
	ecmxf_engine engine{};
	// one packet each way at the largest size: exchanges allocate nothing
	std::array<std::uint8_t, ECMXF_PKT_MAX> tx{};
	std::array<std::uint8_t, ECMXF_PKT_MAX> rx{};
	/// Pause between the polls of a running async command.
	nanoseconds asyncPoll{ 0 };
	/// The packet trace being recorded, or null.
	detail::TraceWriter *trace = nullptr;
	/// The text of the last failure of the channel (RawResult::linkFailure).
	std::array<char, 256> failure{};

private:
	/// A command of a batch in the engine: its transfer and where its
	/// outcome goes. The engine holds at most two commands, one running
	/// async command and its fetch; a command left in flight by a batch
	/// keeps its slot until a later exchange answers it.
	struct Slot {
		ecmxf_xfer x{};
		RawResult *res = nullptr;
		bool used = false;
		bool ranAsync = false;
		std::uint64_t exhaustedBefore = 0;
	};
	std::array<Slot, 6> slots_{};

	/// The channel's coarse clock (ByteChannel::coarseNow()): between
	/// exchanges, what the channel learned without a system call (over
	/// spidev the time of INT0's ready edge); the engine's deadlines are
	/// then seen late by at most one exchange, never early.
	[[nodiscard]] std::uint64_t nowNs() const
	{
		const auto t = channel->coarseNow().count();
		return t > 0 ? static_cast<std::uint64_t>(t) : 0;
	}
	/// The channel's clock, read: where a command's time starts.
	[[nodiscard]] std::uint64_t readNowNs() const
	{
		const auto t = channel->now().count();
		return t > 0 ? static_cast<std::uint64_t>(t) : 0;
	}
	void step();
	Slot *freeSlot() noexcept
	{
		for (Slot &s : slots_)
			if (!s.used)
				return &s;
		return nullptr;
	}
	static void fill(Slot &s, ecmxf_engine &e);
	void collect() noexcept;
	void failAll(int status, const char *why) noexcept;
	const char *keepFailure(const char *what) noexcept
	{
		std::snprintf(failure.data(), failure.size(), "%s", what);
		return failure.data();
	}
};

/// One turn of the owner loop of Documentation/protocol-core.rst.
void EngineLink::Engine::step()
{
	std::uint64_t now = nowNs();

	// the command was answered and runs on the chip, nothing else to
	// send but its polls: poll it at the pace asked for (none by default:
	// each poll waits for INT0 only, so the completion is seen one
	// exchange after it happens)
	const ecmxf_xfer *a = engine.async;
	if (asyncPoll > nanoseconds::zero() && a && !engine.nxt && (!engine.cur || engine.cur->owner == a)) {
		const std::uint64_t deadline = ecmxf_engine_deadline(&engine);
		if (deadline > now)
			channel->sleepFor(nanoseconds(static_cast<std::int64_t>(std::min<std::uint64_t>(
				deadline - now, static_cast<std::uint64_t>(asyncPoll.count())))));
		now = nowNs();
	}

	// the hold-off after SPI_RECONFIG_OP / WARM_RESET
	const std::uint64_t notBefore = ecmxf_engine_not_before(&engine);
	if (now < notBefore) {
		channel->sleepFor(nanoseconds(static_cast<std::int64_t>(notBefore - now)));
		return;
	}

	const std::uint64_t deadline = ecmxf_engine_deadline(&engine);
	const std::uint64_t left = deadline > now ? deadline - now : 0;
	const nanoseconds wait(static_cast<std::int64_t>(
		std::min<std::uint64_t>(left, static_cast<std::uint64_t>(kReadyWait.count()))));
	if (!channel->waitReady(wait)) {
		ecmxf_engine_poll_time(&engine, nowNs());
		return;
	}

	const std::size_t n = ecmxf_engine_pkt_size(&engine);
	const std::uint64_t sentNs = nowNs();
	const std::uint64_t holdBefore = ecmxf_engine_not_before(&engine);
	const int r = ecmxf_engine_next(&engine, sentNs, tx.data(), n);
	if (r == -EAGAIN)
		return; // hold-off: the next turn sleeps
	if (r < 0)
		throw Error("the protocol engine refused to build a packet (errno " + std::to_string(-r) + ")", -r);
	channel->exchange(std::span<const std::uint8_t>(tx.data(), n), std::span<std::uint8_t>(rx.data(), n));
	const std::uint64_t recvNs = nowNs();
	if (trace) {
		trace->packet(sentNs, '>', std::span<const std::uint8_t>(tx.data(), n));
		trace->packet(recvNs, '<', std::span<const std::uint8_t>(rx.data(), n));
	}
	ecmxf_engine_input(&engine, recvNs, rx.data(), n);
	// a hold-off began with this exchange (SPI_RECONFIG_OP, WARM_RESET):
	// it counts from the coarse clock, which may lag; from the clock read
	// now it is never cut short (the engine's field: it has no setter)
	if (ecmxf_engine_not_before(&engine) > holdBefore) {
		const std::uint64_t t = readNowNs();
		if (t > sentNs)
			engine.not_before_ns += t - sentNs;
	}
}

/// The outcome of a finished transfer in its RawResult.
void EngineLink::Engine::fill(Slot &s, ecmxf_engine &e)
{
	const ecmxf_xfer &x = s.x;
	RawResult &res = *s.res;
	res.status = x.status;
	res.header = detail::headerFrom(x.rsp);
	res.rxLen = x.rx_len;
	res.ranAsync = s.ranAsync;
	res.waitedUs =
		static_cast<std::uint32_t>(std::min<std::uint64_t>((x.deadline_ns - x.started_ns) / 1000u, UINT32_MAX));
	if (x.status == -ECANCELED && !res.linkFailure)
		res.linkFailure = detail::kFetchNotSent;
	if (x.status == -EBADMSG || x.status == -EPROTO || x.status == -EIO) {
		if (ecmxf_engine_get_stats(&e)->exhausted > s.exhaustedBefore)
			res.badPackets = ecmxf_engine_retries(&e) + 1u;
		else
			res.answerLost = true;
		res.fault = ecmxf_fault_name(x.fault);
	}
}

/// Hands the outcome of every finished transfer to its RawResult.
void EngineLink::Engine::collect() noexcept
{
	for (Slot &s : slots_) {
		if (!s.used)
			continue;
		if (ecmxf_engine_running(&engine, &s.x))
			s.ranAsync = true;
		if (s.x.status == -EINPROGRESS)
			continue;
		fill(s, engine);
		s.used = false;
	}
}

/// The channel failed: nothing may keep pointing at the transfers.
void EngineLink::Engine::failAll(int status, const char *why) noexcept
{
	for (Slot &s : slots_) {
		if (!s.used)
			continue;
		if (s.x.status == -EINPROGRESS)
			ecmxf_engine_cancel(&engine, &s.x);
		fill(s, engine);
		if (s.x.status == -ECANCELED) {
			s.res->status = status;
			s.res->linkFailure = why;
		}
		s.used = false;
	}
}

void EngineLink::Engine::runBatch(std::span<const RawRequest> reqs, std::span<RawResult> res,
				  bool leaveLast) noexcept
{
	const std::size_t n = std::min(reqs.size(), res.size());
	for (std::size_t i = 0; i < n; i++)
		res[i] = RawResult{};

	std::size_t next = 0;  // the next request to submit
	Slot *last = nullptr; // the slot of request n - 1
	try {
		// the time the batch's commands start at: one read of the clock
		// (which may fail too: a server gone, in the try like the rest)
		const std::uint64_t start = n ? readNowNs() : nowNs();
		// commands an earlier batch left in flight: their time starts now
		for (Slot &s : slots_)
			if (s.used && s.x.status == -EINPROGRESS && !ecmxf_engine_running(&engine, &s.x)) {
				const std::uint64_t t = s.x.deadline_ns - s.x.started_ns;
				s.x.started_ns = start;
				s.x.deadline_ns = s.x.started_ns + t;
			}
		for (;;) {
			// hand the engine what it takes now, in order
			while (next < n) {
				const RawRequest &req = reqs[next];
				const bool withFetch = next + 1 < n && reqs[next + 1].fetchesPrevious;
				if (req.fetchesPrevious) {
					// its async command failed before it was paired
					res[next].status = -ECANCELED;
					res[next].linkFailure = detail::kFetchNotSent;
					next++;
					continue;
				}
				Slot *s = freeSlot();
				Slot *f = nullptr;
				if (s) {
					s->used = true;
					f = withFetch ? freeSlot() : nullptr;
					s->used = false;
				}
				if (!s || (withFetch && !f))
					break;
				ecmxf_xfer &x = s->x;
				x = ecmxf_xfer{};
				if (req.tx.size() > ecmxf_engine_data_size(&engine)) {
					res[next].status = -EMSGSIZE;
					res[next].linkFailure = "the payload does not fit the data section";
					next++;
					continue;
				}
				detail::headerTo(req, x.hdr);
				x.hdr.reserved = req.reserved;
				x.tx_data = req.tx.empty() ? nullptr : req.tx.data();
				x.tx_len = static_cast<std::uint16_t>(req.tx.size());
				x.rx_buf = req.rx.empty() ? nullptr : req.rx.data();
				x.rx_size = static_cast<std::uint16_t>(std::min<std::size_t>(req.rx.size(), UINT16_MAX));
				x.timeout_us = req.timeoutUs;
				x.flags = req.noAutoClear ? ECMXF_XF_NO_AUTO_CLEAR : 0u;
				if (withFetch) {
					const RawRequest &fr = reqs[next + 1];
					ecmxf_xfer &fx = f->x;
					fx = ecmxf_xfer{};
					detail::headerTo(fr, fx.hdr);
					fx.hdr.reserved = fr.reserved;
					fx.tx_data = fr.tx.empty() ? nullptr : fr.tx.data();
					fx.tx_len = static_cast<std::uint16_t>(fr.tx.size());
					fx.rx_buf = fr.rx.empty() ? nullptr : fr.rx.data();
					fx.rx_size =
						static_cast<std::uint16_t>(std::min<std::size_t>(fr.rx.size(), UINT16_MAX));
					fx.timeout_us = fr.timeoutUs;
					fx.flags = fr.noAutoClear ? ECMXF_XF_NO_AUTO_CLEAR : 0u;
					x.fetch = &fx;
				}
				if (!ecmxf_engine_can_submit(&engine, &x) && !ecmxf_engine_idle(&engine))
					break; // after the exchange that frees a slot
				const std::uint64_t exhausted = ecmxf_engine_get_stats(&engine)->exhausted;
				// a command handed over after exchanges of this batch
				// starts at the coarse time, later than the batch's
				const int r = ecmxf_engine_submit(&engine, &x, std::max(start, nowNs()));
				if (r != 0) {
					res[next].status = r;
					res[next].linkFailure =
						r == -EBUSY ? "another async command is still running on this device"
						: r == -EMSGSIZE
							? "the payload does not fit the data section"
							: "invalid command (e.g. a data size outside 32..1408 or an unknown check type)";
					if (withFetch) {
						res[next + 1].status = -ECANCELED;
						res[next + 1].linkFailure = detail::kFetchNotSent;
						next++;
					}
					next++;
					continue;
				}
				s->used = true;
				s->res = &res[next];
				s->ranAsync = false;
				s->exhaustedBefore = exhausted;
				if (next == n - 1)
					last = s;
				if (withFetch) {
					f->used = true;
					f->res = &res[next + 1];
					f->ranAsync = false;
					f->exhaustedBefore = exhausted;
					if (next + 1 == n - 1)
						last = f;
					next++;
				}
				next++;
			}
			collect();
			bool waiting = false;
			for (const Slot &s : slots_)
				if (s.used && !(leaveLast && &s == last && ecmxf_engine_sent(&engine, &s.x)))
					waiting = true;
			if (!waiting && next >= n) {
				if (leaveLast && last && last->used)
					last->res->status = -EINPROGRESS;
				return;
			}
			step();
		}
	} catch (const Error &e) {
		failAll(-(e.errnoValue() ? e.errnoValue() : EIO), keepFailure(e.what()));
	} catch (const std::exception &ex) {
		failAll(-EIO, keepFailure(ex.what()));
	} catch (...) {
		failAll(-EIO, "the byte channel failed");
	}
	// requests never handed over (the channel failed first)
	for (std::size_t i = next; i < n; i++)
		if (res[i].status == 0 && !res[i].linkFailure) {
			res[i].status = -EIO;
			res[i].linkFailure = failure.data();
		}
}

EngineLink::EngineLink(std::unique_ptr<ByteChannel> channel) : e_(std::make_unique<Engine>(std::move(channel)))
{
}

EngineLink::~EngineLink() = default;

void EngineLink::run(const RawRequest &req, RawResult &res) noexcept
{
	e_->runBatch(std::span<const RawRequest>(&req, 1), std::span<RawResult>(&res, 1), false);
}

void EngineLink::runBatch(std::span<const RawRequest> reqs, std::span<RawResult> res, bool leaveLast) noexcept
{
	e_->runBatch(reqs, res, leaveLast);
}

void EngineLink::settle() noexcept
{
	e_->runBatch({}, {}, false);
}

void EngineLink::setPipelining(bool on) noexcept
{
	ecmxf_engine_set_pipeline(&e_->engine, on);
}

bool EngineLink::pipelining() const noexcept
{
	return e_->engine.pipeline;
}

std::uint16_t EngineLink::dataSize() const noexcept
{
	return static_cast<std::uint16_t>(ecmxf_engine_data_size(&e_->engine));
}

CheckType EngineLink::checkType() const noexcept
{
	// engine.check has no accessor in the core; the field is read here only
	return static_cast<CheckType>(e_->engine.check & ECMXF_STS_CHECK_MASK);
}

std::optional<ResponseHeader> EngineLink::lastHeader() const noexcept
{
	const ecmxf_rsp_hdr *h = ecmxf_engine_last_header(&e_->engine);
	if (!h)
		return std::nullopt;
	return detail::headerFrom(*h);
}

std::string EngineLink::name() const
{
	return e_->channel->name();
}

std::chrono::nanoseconds EngineLink::now() const
{
	return e_->channel->now();
}

void EngineLink::sleepFor(std::chrono::nanoseconds duration)
{
	e_->channel->sleepFor(duration);
}

void EngineLink::sleepUntil(std::chrono::nanoseconds deadline)
{
	e_->channel->sleepUntil(deadline);
}

std::chrono::nanoseconds EngineLink::coarseNow() const
{
	return e_->channel->coarseNow();
}

void EngineLink::assumeFormat(std::uint16_t dataSize, CheckType check)
{
	if (ecmxf_engine_set_format(&e_->engine, dataSize, static_cast<enum ecmxf_check>(check)) != 0)
		throw Error(name() + ": data section size " + std::to_string(dataSize) + " or check type " +
				    std::to_string(static_cast<unsigned>(check)) +
				    " is out of range (32..1408 bytes; 0 fixed .. 3 CRC-32)",
			    EINVAL);
	if (e_->trace)
		e_->trace->format(ecmxf_engine_data_size(&e_->engine), e_->engine.check);
}

void EngineLink::setAsyncPollInterval(std::chrono::nanoseconds interval) noexcept
{
	e_->asyncPoll = interval > nanoseconds::zero() ? interval : nanoseconds::zero();
}

std::chrono::nanoseconds EngineLink::asyncPollInterval() const noexcept
{
	return e_->asyncPoll;
}

LinkCounters EngineLink::counters() const
{
	const ecmxf_engine_stats *s = ecmxf_engine_get_stats(&e_->engine);
	LinkCounters c;
	c.exchanges = s->exchanges;
	c.badNotReady = s->faults[ECMXF_FAULT_NOT_READY];
	c.badStart = s->faults[ECMXF_FAULT_START];
	c.badEnd = s->faults[ECMXF_FAULT_END];
	c.badCheck = s->faults[ECMXF_FAULT_CHECK];
	c.badLength = s->faults[ECMXF_FAULT_LENGTH];
	c.retries = s->retries;
	c.polls = s->polls;
	c.exhausted = s->exhausted;
	c.timeouts = s->timeouts;
	c.asyncErrors = s->async_errors;
	c.busyRejects = s->busy_rejects;
	c.lostAnswers = s->lost_answers;
	c.chipResets = s->chip_resets;
	return c;
}

sim::Chip *EngineLink::simulator() noexcept
{
	// the channel is the link's own: which one it is stays in this layer
	auto *sim = dynamic_cast<SimChannel *>(e_->channel.get());
	return sim ? &sim->chip() : nullptr;
}

void EngineLink::attachTrace(detail::TraceWriter *trace) noexcept
{
	e_->trace = trace;
	if (trace)
		trace->format(ecmxf_engine_data_size(&e_->engine), e_->engine.check);
}

ByteChannel &EngineLink::channel() noexcept
{
	return *e_->channel;
}

CrcCoverage EngineLink::crcCoverage() const noexcept
{
	return static_cast<CrcCoverage>(ecmxf_engine_cover(&e_->engine));
}

} // namespace ecmxf
