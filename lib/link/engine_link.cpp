// SPDX-License-Identifier: MIT
// EngineLink: the protocol core's exchange engine (lib/core) run over a
// ByteChannel; the owner loop of Documentation/protocol-core.rst
// (include/ecmxf/link/engine_link.hpp).

#include <ecmxf/error.hpp>
#include <ecmxf/link/engine_link.hpp>

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
#include "device/lib_text.hpp"
#include "trace/trace_writer.hpp"

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

	void run(const RawRequest &req, RawResult &res) noexcept;

	std::unique_ptr<ByteChannel> channel;
	ecmxf_engine engine{};
	// one packet each way at the largest size: exchanges allocate nothing
	std::array<std::uint8_t, ECMXF_PKT_MAX> tx{};
	std::array<std::uint8_t, ECMXF_PKT_MAX> rx{};
	/// The current command was answered and ran on the chip (async).
	bool ranAsync = false;
	/// Pause between the polls of a running async command.
	nanoseconds asyncPoll{ 0 };
	/// The packet trace being recorded, or null.
	detail::TraceWriter *trace = nullptr;
	/// The text of the last failure of the channel (RawResult::linkFailure).
	std::array<char, 256> failure{};

private:
	[[nodiscard]] std::uint64_t nowNs() const
	{
		const auto t = channel->now().count();
		return t > 0 ? static_cast<std::uint64_t>(t) : 0;
	}
	void step(ecmxf_xfer &x);
	const char *keepFailure(const char *what) noexcept
	{
		std::snprintf(failure.data(), failure.size(), "%s", what);
		return failure.data();
	}
};

/// One turn of the owner loop of Documentation/protocol-core.rst.
void EngineLink::Engine::step(ecmxf_xfer &x)
{
	std::uint64_t now = nowNs();

	// the command was answered and runs on the chip: poll it at the pace
	// asked for (none by default: each poll waits for INT0 only, so the
	// completion is seen one exchange after it happens)
	if (asyncPoll > nanoseconds::zero() && ecmxf_engine_running(&engine, &x)) {
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
	if (ecmxf_engine_running(&engine, &x))
		ranAsync = true;
}

void EngineLink::Engine::run(const RawRequest &req, RawResult &res) noexcept
{
	res = RawResult{};
	if (req.tx.size() > ecmxf_engine_data_size(&engine)) {
		res.status = -EMSGSIZE;
		res.linkFailure = "the payload does not fit the data section";
		return;
	}
	ecmxf_xfer x{};
	detail::headerTo(req, x.hdr);
	x.hdr.reserved = req.reserved;
	x.tx_data = req.tx.empty() ? nullptr : req.tx.data();
	x.tx_len = static_cast<std::uint16_t>(req.tx.size());
	x.rx_buf = req.rx.empty() ? nullptr : req.rx.data();
	x.rx_size = static_cast<std::uint16_t>(std::min<std::size_t>(req.rx.size(), UINT16_MAX));
	x.timeout_us = req.timeoutUs;
	x.flags = req.noAutoClear ? ECMXF_XF_NO_AUTO_CLEAR : 0u;

	const std::uint64_t exhaustedBefore = ecmxf_engine_get_stats(&engine)->exhausted;
	const int r = ecmxf_engine_submit(&engine, &x, nowNs());
	switch (r) {
	case 0:
		break;
	case -EBUSY:
		res.status = r;
		res.linkFailure = "another async command is still running on this device";
		return;
	case -EMSGSIZE:
		res.status = r;
		res.linkFailure = "the payload does not fit the data section";
		return;
	default:
		res.status = r;
		res.linkFailure = "invalid command (e.g. a data size outside 32..1408 or an unknown check type)";
		return;
	}
	ranAsync = false;
	try {
		while (x.status == -EINPROGRESS)
			step(x);
	} catch (const Error &e) {
		// the channel failed: nothing may keep pointing at x
		ecmxf_engine_cancel(&engine, &x);
		res.status = -(e.errnoValue() ? e.errnoValue() : EIO);
		res.linkFailure = keepFailure(e.what());
		return;
	} catch (const std::exception &ex) {
		ecmxf_engine_cancel(&engine, &x);
		res.status = -EIO;
		res.linkFailure = keepFailure(ex.what());
		return;
	} catch (...) {
		ecmxf_engine_cancel(&engine, &x);
		res.status = -EIO;
		res.linkFailure = "the byte channel failed";
		return;
	}
	res.status = x.status;
	res.header = detail::headerFrom(x.rsp);
	res.rxLen = x.rx_len;
	res.ranAsync = ranAsync;
	res.waitedUs = static_cast<std::uint32_t>(
		std::min<std::uint64_t>((x.deadline_ns - x.started_ns) / 1000u, UINT32_MAX));
	if (x.status == -EBADMSG || x.status == -EPROTO || x.status == -EIO) {
		if (ecmxf_engine_get_stats(&engine)->exhausted > exhaustedBefore)
			res.badPackets = ecmxf_engine_retries(&engine) + 1u;
		else
			res.answerLost = true;
		res.fault = ecmxf_fault_name(x.fault);
	}
}

EngineLink::EngineLink(std::unique_ptr<ByteChannel> channel) : e_(std::make_unique<Engine>(std::move(channel)))
{
}

EngineLink::~EngineLink() = default;

void EngineLink::run(const RawRequest &req, RawResult &res) noexcept
{
	e_->run(req, res);
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
	return e_->channel->simulator();
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
