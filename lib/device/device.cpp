// SPDX-License-Identifier: MIT
// Device: the protocol core's exchange engine (lib/core) run over a
// Transport, with a synchronous raw command call and its errors
// (see include/ecmxf/device.hpp and Documentation/library.rst).

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/protocol.hpp>
#include <ecmxf/link/transport.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <utility>

#include "ecmxf-proto.h"
#include "device/lib_text.hpp"
#include "trace/trace_writer.hpp"
#include "link/transport_command.hpp"

namespace ecmxf {

// ---------------------------------------------------------------------------
// Error, Transport: the out-of-line parts
// ---------------------------------------------------------------------------

Error::Error(const std::string &message, int errnoValue, std::optional<std::uint8_t> errorStatus)
	: std::runtime_error(message), errno_(errnoValue), errorStatus_(errorStatus)
{
}

Error::~Error() = default;

Transport::~Transport() = default;

void Transport::sleepFor(std::chrono::nanoseconds duration)
{
	if (duration > std::chrono::nanoseconds::zero())
		std::this_thread::sleep_for(duration);
}

namespace {

using std::chrono::nanoseconds;
using std::chrono::microseconds;

/// How long one wait for INT0 lasts before the engine's deadlines are
/// applied without an exchange.
constexpr nanoseconds kReadyWait = std::chrono::milliseconds(10);

using detail::bitList;
using detail::commandName;
using detail::hex8;

/// "10000 ms", or "250 us" for timeouts that are not whole milliseconds.
std::string duration(std::uint64_t ns)
{
	return detail::durationUs(ns / 1000u);
}

} // namespace

// ---------------------------------------------------------------------------
// Device
// ---------------------------------------------------------------------------

class Device::Impl
{
public:
	explicit Impl(std::unique_ptr<Transport> t) : transport(std::move(t))
	{
		if (!transport)
			throw Error("ecmxf::Device: no transport given", EINVAL);
		ecmxf_engine_init(&engine, ECMXF_DATA_DEFAULT, ECMXF_CHECK_FIXED);
	}

	Response command(const Command &c);
	int transact(const RawCommand &c, std::span<const std::uint8_t> payload, std::span<std::uint8_t> answer,
		     ResponseHeader &header) noexcept;

	std::unique_ptr<Transport> transport;
	ecmxf_engine engine{};
	// one packet each way and the answer's data, at the largest size, so
	// that exchanges allocate nothing
	std::array<std::uint8_t, ECMXF_PKT_MAX> tx{};
	std::array<std::uint8_t, ECMXF_PKT_MAX> rx{};
	std::array<std::uint8_t, ECMXF_DATA_MAX> rxData{};
	/// The current command was answered and ran on the chip (async).
	bool ranAsync = false;
	/// Pause between the polls of a running async command.
	nanoseconds asyncPoll{ 0 };
	microseconds minTimeout{ 0 };

	/// @p t raised to minTimeout (t zero: the table's time for @p code).
	[[nodiscard]] microseconds floored(std::uint8_t code, microseconds t) const noexcept
	{
		if (minTimeout <= microseconds::zero())
			return t;
		microseconds eff = t;
		if (eff <= microseconds::zero()) {
			const auto ci = commandInfo(code);
			eff = std::chrono::milliseconds(ci ? ci->timeoutMs : 100u);
		}
		return eff < minTimeout ? minTimeout : t;
	}
	/// The packet trace being recorded (lib/trace/trace.cpp), or null.
	std::unique_ptr<detail::TraceWriter> trace;

private:
	std::uint64_t nowNs() const
	{
		const auto t = transport->now().count();
		return t > 0 ? static_cast<std::uint64_t>(t) : 0;
	}
	void step(ecmxf_xfer &x);
	/// An xfer for @p c with @p payload, answering into @p answer.
	static ecmxf_xfer makeXfer(const RawCommand &c, std::span<const std::uint8_t> payload,
				   std::span<std::uint8_t> answer) noexcept;
	/// Submits @p x and runs the owner loop until it is final. Returns the
	/// submit result (0 or a negative errno); throws what the transport or
	/// step() throws, after withdrawing @p x from the engine.
	int run(ecmxf_xfer &x);
	[[noreturn]] void fail(const Command &c, const ecmxf_xfer &x, std::uint64_t exhaustedBefore) const;
};

/// One turn of the owner loop of Documentation/protocol-core.rst.
void Device::Impl::step(ecmxf_xfer &x)
{
	std::uint64_t now = nowNs();

	// the command was answered and runs on the chip: poll it at the pace
	// asked for (none by default: each poll waits for INT0 only, so the
	// completion is seen one exchange after it happens)
	if (asyncPoll > nanoseconds::zero() && ecmxf_engine_running(&engine, &x)) {
		const std::uint64_t deadline = ecmxf_engine_deadline(&engine);
		if (deadline > now)
			transport->sleepFor(nanoseconds(
				static_cast<std::int64_t>(std::min<std::uint64_t>(
					deadline - now, static_cast<std::uint64_t>(asyncPoll.count())))));
		now = nowNs();
	}

	// the hold-off after SPI_RECONFIG_OP / WARM_RESET
	const std::uint64_t notBefore = ecmxf_engine_not_before(&engine);
	if (now < notBefore) {
		transport->sleepFor(nanoseconds(static_cast<std::int64_t>(notBefore - now)));
		return;
	}

	const std::uint64_t deadline = ecmxf_engine_deadline(&engine);
	const std::uint64_t left = deadline > now ? deadline - now : 0;
	const nanoseconds wait(static_cast<std::int64_t>(
		std::min<std::uint64_t>(left, static_cast<std::uint64_t>(kReadyWait.count()))));
	if (!transport->waitReady(wait)) {
		ecmxf_engine_poll_time(&engine, nowNs());
		return;
	}

	const std::size_t n = ecmxf_engine_pkt_size(&engine);
	const std::uint64_t sentNs = nowNs();
	const int r = ecmxf_engine_next(&engine, sentNs, tx.data(), n);
	if (r == -EAGAIN)
		return; // hold-off: the next turn sleeps
	if (r < 0)
		throw Error("ecmxf::Device: the protocol engine refused to build a packet (errno " +
				    std::to_string(-r) + ")",
			    -r);
	transport->exchange(std::span<const std::uint8_t>(tx.data(), n), std::span<std::uint8_t>(rx.data(), n));
	const std::uint64_t recvNs = nowNs();
	if (trace) {
		trace->packet(sentNs, '>', std::span<const std::uint8_t>(tx.data(), n));
		trace->packet(recvNs, '<', std::span<const std::uint8_t>(rx.data(), n));
	}
	ecmxf_engine_input(&engine, recvNs, rx.data(), n);
	if (ecmxf_engine_running(&engine, &x))
		ranAsync = true;
}

void Device::Impl::fail(const Command &c, const ecmxf_xfer &x, std::uint64_t exhaustedBefore) const
{
	const std::string name = commandName(c.code) + ": ";
	const std::uint8_t status = x.rsp.err_status;
	const std::uint8_t faultBits = static_cast<std::uint8_t>(status & ECMXF_ERR_FAULT_MASK);

	switch (x.status) {
	case -ETIMEDOUT: {
		const std::string after = duration(x.deadline_ns - x.started_ns);
		throw Error(name + "timed out after " + after +
				    (ranAsync ? " waiting for the async command to complete"
					      : " waiting for the chip's answer"),
			    ETIMEDOUT);
	}
	case -EBADMSG:
	case -EPROTO:
	case -EIO:
		if (ecmxf_engine_get_stats(&engine)->exhausted > exhaustedBefore)
			throw Error(name + std::to_string(ecmxf_engine_retries(&engine) + 1u) + " bad packets in a row (" +
					    ecmxf_fault_name(x.fault) + ")",
				    -x.status);
		throw Error(name + "the answer was lost on the wire and the command is not safe to "
				   "send again (it may have run)",
			    -x.status);
	case -EBUSY:
		throw Error(name + "chip refused: another async command is running (error status " +
				    hex8(faultBits) + ")",
			    EBUSY, status);
	case -EREMOTEIO:
		throw Error(name + "the async command failed (error status " +
				    bitList(faultBits ? faultBits : ECMXF_ERR_ASYNC) + ")",
			    EREMOTEIO, status);
	case -ECONNRESET:
		throw Error(name + "the chip reset while the command was in flight", ECONNRESET);
	case -EMSGSIZE:
		throw Error(name + "the answer (" + std::to_string(x.rsp.len) +
				    " bytes) is larger than the receive buffer (" + std::to_string(x.rx_size) +
				    " bytes)",
			    EMSGSIZE);
	case -ECANCELED:
		throw Error(name + "the command was cancelled", ECANCELED);
	default:
		throw Error(name + "failed (errno " + std::to_string(-x.status) + ")", -x.status);
	}
}

ecmxf_xfer Device::Impl::makeXfer(const RawCommand &c, std::span<const std::uint8_t> payload,
				  std::span<std::uint8_t> answer) noexcept
{
	ecmxf_xfer x{};
	x.hdr.code = c.code;
	x.hdr.param = c.param;
	std::copy(c.data.begin(), c.data.end(), x.hdr.data);
	x.hdr.reserved = c.reserved;
	x.hdr.control = c.control;
	x.tx_data = payload.empty() ? nullptr : payload.data();
	x.tx_len = static_cast<std::uint16_t>(payload.size());
	x.hdr.len = c.len < 0 ? x.tx_len : static_cast<std::uint16_t>(c.len);
	x.rx_buf = answer.empty() ? nullptr : answer.data();
	x.rx_size = static_cast<std::uint16_t>(std::min<std::size_t>(answer.size(), UINT16_MAX));
	const auto us = c.timeout.count();
	x.timeout_us = us <= 0 ? 0u : static_cast<std::uint32_t>(std::min<std::int64_t>(us, UINT32_MAX));
	return x;
}

int Device::Impl::run(ecmxf_xfer &x)
{
	const int r = ecmxf_engine_submit(&engine, &x, nowNs());
	if (r != 0)
		return r;
	ranAsync = false;
	try {
		while (x.status == -EINPROGRESS)
			step(x);
	} catch (...) {
		// a transport failure: nothing may keep pointing at x
		ecmxf_engine_cancel(&engine, &x);
		throw;
	}
	return 0;
}

Response Device::Impl::command(const Command &c)
{
	// the kernel runs the protocol itself (lib/link/transport_command.cpp)
	if (transport->runsProtocol())
		return detail::runOnCommandTransport(static_cast<CommandTransport &>(*transport), c, trace.get());

	const std::string name = commandName(c.code) + ": ";
	if (c.payload.size() > ecmxf_engine_data_size(&engine))
		throw Error(name + "payload of " + std::to_string(c.payload.size()) +
				    " bytes does not fit the data section (" + std::to_string(ecmxf_engine_data_size(&engine)) +
				    " bytes)",
			    EMSGSIZE);
	RawCommand rc;
	rc.code = c.code;
	rc.param = c.param;
	rc.data = c.data;
	rc.len = c.len ? std::int32_t{ *c.len } : -1;
	rc.reserved = c.reserved;
	rc.control = c.control;
	rc.timeout = c.timeout;
	ecmxf_xfer x = makeXfer(rc, c.payload, rxData);

	const std::uint64_t exhaustedBefore = ecmxf_engine_get_stats(&engine)->exhausted;
	const int r = run(x);
	switch (r) {
	case 0:
		break;
	case -EBUSY:
		throw Error(name + "another async command is still running in this device", EBUSY);
	case -EMSGSIZE:
		throw Error(name + "payload does not fit the data section", EMSGSIZE);
	default:
		throw Error(name + "invalid command (e.g. a data size outside 32..1408 or an unknown "
				   "check type)",
			    -r);
	}
	if (x.status != 0)
		fail(c, x, exhaustedBefore);

	Response rsp;
	rsp.header = detail::headerFrom(x.rsp);
	rsp.data.assign(rxData.begin(), rxData.begin() + x.rx_len);
	rsp.ret = x.rsp.ret;
	return rsp;
}

int Device::Impl::transact(const RawCommand &c, std::span<const std::uint8_t> payload,
			   std::span<std::uint8_t> answer, ResponseHeader &header) noexcept
{
	// the kernel runs the protocol itself (lib/link/transport_command.cpp)
	if (transport->runsProtocol())
		return detail::transactOnCommandTransport(static_cast<CommandTransport &>(*transport), c, payload,
							  answer, header, trace.get());
	if (payload.size() > ecmxf_engine_data_size(&engine))
		return EMSGSIZE;
	ecmxf_xfer x = makeXfer(c, payload, answer);
	int r = 0;
	try {
		r = run(x);
	} catch (...) {
		// the transport could not make the transfer; x was withdrawn
		return EIO;
	}
	header = detail::headerFrom(x.rsp);
	if (r != 0)
		return -r;
	return x.status == 0 ? 0 : -x.status;
}

// Device::open(): lib/device/device_open.cpp

Device::Device(std::unique_ptr<Transport> transport) : impl_(std::make_unique<Impl>(std::move(transport)))
{
}

Device::~Device() = default;

Response Device::command(const Command &c)
{
	const microseconds t = impl_->floored(c.code, c.timeout);
	if (t == c.timeout)
		return impl_->command(c);
	Command raised = c;
	raised.timeout = t;
	return impl_->command(raised);
}

void Device::setMinimumTimeout(std::chrono::microseconds floor) noexcept
{
	impl_->minTimeout = floor > microseconds::zero() ? floor : microseconds::zero();
}

std::chrono::microseconds Device::minimumTimeout() const noexcept
{
	return impl_->minTimeout;
}

void Device::setAsyncPollInterval(std::chrono::nanoseconds interval) noexcept
{
	impl_->asyncPoll = interval > std::chrono::nanoseconds::zero() ? interval : std::chrono::nanoseconds::zero();
}

std::chrono::nanoseconds Device::asyncPollInterval() const noexcept
{
	return impl_->asyncPoll;
}

ResponseHeader Device::lastHeader() const
{
	if (impl_->transport->runsProtocol())
		return static_cast<const CommandTransport &>(*impl_->transport).lastHeader().value_or(ResponseHeader{});
	const ecmxf_rsp_hdr *h = ecmxf_engine_last_header(&impl_->engine);
	return h ? detail::headerFrom(*h) : ResponseHeader{};
}

// the packet format the engine uses (it follows SPI_RECONFIG_OP,
// CRC_TYPE_SET and WARM_RESET); the typed calls are in commands_chip.cpp
std::uint16_t Device::dataSize() const
{
	// the kernel's engine talks to the chip, not impl_->engine
	if (impl_->transport->runsProtocol())
		return static_cast<const CommandTransport &>(*impl_->transport).dataSize();
	return static_cast<std::uint16_t>(ecmxf_engine_data_size(&impl_->engine));
}

CheckType Device::checkType() const
{
	// the kernel's engine talks to the chip, not impl_->engine: the
	// driver's own view if it gives one (the ECM status bits of the last
	// response lag behind CRC_TYPE_SET and a reset), else those bits
	if (impl_->transport->runsProtocol()) {
		const auto &ct = static_cast<const CommandTransport &>(*impl_->transport);
		if (const std::optional<std::uint8_t> now = ct.checkTypeNow())
			return static_cast<CheckType>(*now & ECMXF_STS_CHECK_MASK);
		return static_cast<CheckType>(lastHeader().ecmStatus & ECMXF_STS_CHECK_MASK);
	}
	return static_cast<CheckType>(impl_->engine.check & ECMXF_STS_CHECK_MASK);
}

void Device::assumeFormat(std::uint16_t dataSize, CheckType check)
{
	if (impl_->transport->runsProtocol())
		throw Error("ecmxf::Device::assumeFormat: the transport runs the protocol itself and tracks the "
			    "chip's format (kernel device)",
			    EOPNOTSUPP);
	if (ecmxf_engine_set_format(&impl_->engine, dataSize, static_cast<enum ecmxf_check>(check)) != 0)
		throw Error("ecmxf::Device::assumeFormat: data section size " + std::to_string(dataSize) +
				    " or check type " + std::to_string(static_cast<unsigned>(check)) +
				    " is out of range (32..1408 bytes; 0 fixed .. 3 CRC-32)",
			    EINVAL);
}

Transport &Device::transport() noexcept
{
	return *impl_->transport;
}

// ---------------------------------------------------------------------------
// The trace slot for lib/trace/trace.cpp
// ---------------------------------------------------------------------------

std::unique_ptr<detail::TraceWriter> &TraceAccess::slot(Device &d) noexcept
{
	return d.impl_->trace;
}

const std::unique_ptr<detail::TraceWriter> &TraceAccess::slot(const Device &d) noexcept
{
	return d.impl_->trace;
}

void TraceAccess::writeFormat(Device &d, detail::TraceWriter &w) noexcept
{
	if (d.impl_->transport->runsProtocol()) {
		w.comment("kernel transport: request and response records");
		return;
	}
	// engine.check has no accessor in the core; the field is read here only
	w.format(ecmxf_engine_data_size(&d.impl_->engine), d.impl_->engine.check);
}

int Device::transact(const RawCommand &c, std::span<const std::uint8_t> payload, std::span<std::uint8_t> rx,
		     ResponseHeader &header) noexcept
{
	const microseconds t = impl_->floored(c.code, c.timeout);
	if (t == c.timeout)
		return impl_->transact(c, payload, rx, header);
	RawCommand raised = c;
	raised.timeout = t;
	return impl_->transact(raised, payload, rx, header);
}

std::size_t Device::pdoDataCapacity() const noexcept
{
	if (impl_->transport->runsProtocol())
		return static_cast<const CommandTransport &>(*impl_->transport).dataSize();
	return ecmxf_engine_data_size(&impl_->engine);
}

} // namespace ecmxf
