// SPDX-License-Identifier: MIT
// Device: the one command runner over a Link, with the one map of outcomes
// to errors (lib/link/outcome.cpp); include/ecmxf/device.hpp,
// Documentation/library.rst.

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/engine_link.hpp>
#include <ecmxf/protocol.hpp>

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
#include "base/text.hpp"
#include "link/outcome.hpp"
#include "link/trace_writer.hpp"

namespace ecmxf {

namespace {

using std::chrono::microseconds;

/// @p t: zero, or a positive time in microseconds, as the link takes it.
std::uint32_t timeoutUs(microseconds t) noexcept
{
	const auto us = t.count();
	return us <= 0 ? 0u : static_cast<std::uint32_t>(std::min<std::int64_t>(us, UINT32_MAX));
}

} // namespace

// ---------------------------------------------------------------------------
// Device: the one command runner over a Link
// ---------------------------------------------------------------------------

class Device::Impl
{
public:
	explicit Impl(std::unique_ptr<Link> l) : link(std::move(l))
	{
		if (!link)
			throw Error("ecmxf::Device: no link given", EINVAL);
	}

	std::unique_ptr<Link> link;
	// the answer's data at the largest size, so that command() needs one
	// allocation (the Response) and transact() none
	std::array<std::uint8_t, ECMXF_DATA_MAX> rxData{};
	microseconds minTimeout{ 0 };
	/// The packet trace being recorded (lib/link/trace_writer.cpp), or null; the
	/// link writes to it.
	std::unique_ptr<detail::TraceWriter> trace;

	/// The link's request for @p c with @p payload, answering into @p rx,
	/// its timeout raised to minTimeout.
	[[nodiscard]] RawRequest request(const RawCommand &c, std::span<const std::uint8_t> payload,
					 std::span<std::uint8_t> rx) const noexcept
	{
		RawRequest req;
		req.data = c.data;
		req.reserved = c.reserved;
		req.control = c.control;
		req.code = c.code;
		req.param = c.param;
		req.len = c.len < 0 ? static_cast<std::uint16_t>(payload.size()) : static_cast<std::uint16_t>(c.len);
		req.tx = payload;
		req.rx = rx;
		req.timeoutUs = timeoutUs(floored(c.code, c.timeout));
		return req;
	}

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
};

Device::Device(std::unique_ptr<Link> link) : impl_(std::make_unique<Impl>(std::move(link))) {}

Device::Device(std::unique_ptr<ByteChannel> channel)
	: impl_(std::make_unique<Impl>(std::make_unique<EngineLink>(std::move(channel))))
{
}

Device::~Device() = default;

namespace {

RawCommand rawOf(const Command &c)
{
	RawCommand rc;
	rc.code = c.code;
	rc.param = c.param;
	rc.data = c.data;
	rc.len = c.len ? std::int32_t{ *c.len } : -1;
	rc.reserved = c.reserved;
	rc.control = c.control;
	rc.timeout = c.timeout;
	return rc;
}

} // namespace

Response Device::command(const Command &c)
{
	Link &l = *impl_->link;
	const std::size_t room = std::min<std::size_t>(l.dataSize(), ECMXF_DATA_MAX);
	if (c.payload.size() > room)
		throw Error(detail::commandName(c.code) + ": payload of " + std::to_string(c.payload.size()) +
				    " bytes does not fit the data section (" + std::to_string(room) + " bytes)",
			    EMSGSIZE);
	const RawRequest req = impl_->request(rawOf(c), c.payload, impl_->rxData);
	RawResult res;
	l.run(req, res);
	if (res.status != 0)
		detail::throwOutcome(l, req, res);
	Response rsp;
	rsp.header = res.header;
	rsp.data.assign(impl_->rxData.begin(),
			impl_->rxData.begin() + static_cast<std::ptrdiff_t>(std::min(res.rxLen, impl_->rxData.size())));
	rsp.ret = res.header.ret;
	return rsp;
}

Response Device::commandWithFetch(const Command &c, const Command &fetch)
{
	Link &l = *impl_->link;
	const std::size_t room = std::min<std::size_t>(l.dataSize(), ECMXF_DATA_MAX);
	for (const Command *k : { &c, &fetch })
		if (k->payload.size() > room)
			throw Error(detail::commandName(k->code) + ": payload of " + std::to_string(k->payload.size()) +
					    " bytes does not fit the data section (" + std::to_string(room) + " bytes)",
				    EMSGSIZE);
	std::array<RawRequest, 2> req{ impl_->request(rawOf(c), c.payload, {}),
				       impl_->request(rawOf(fetch), fetch.payload, impl_->rxData) };
	req[1].fetchesPrevious = true;
	std::array<RawResult, 2> res;
	l.runBatch(req, res);
	for (std::size_t i = 0; i < 2; i++)
		if (res[i].status != 0)
			detail::throwOutcome(l, req[i], res[i]);
	Response rsp;
	rsp.header = res[1].header;
	rsp.data.assign(impl_->rxData.begin(),
			impl_->rxData.begin() + static_cast<std::ptrdiff_t>(std::min(res[1].rxLen, impl_->rxData.size())));
	rsp.ret = res[1].header.ret;
	return rsp;
}

RawRequest Device::request(const RawCommand &c, std::span<const std::uint8_t> payload,
			   std::span<std::uint8_t> rx) const noexcept
{
	return impl_->request(c, payload, rx);
}

int Device::transact(const RawCommand &c, std::span<const std::uint8_t> payload, std::span<std::uint8_t> rx,
		     ResponseHeader &header) noexcept
{
	Link &l = *impl_->link;
	if (payload.size() > l.dataSize())
		return EMSGSIZE;
	const RawRequest req = impl_->request(c, payload, rx);
	RawResult res;
	l.run(req, res);
	if (!res.linkFailure)
		header = res.header;
	return -res.status;
}

std::size_t Device::pdoDataCapacity() const noexcept
{
	return impl_->link->dataSize();
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
	impl_->link->setAsyncPollInterval(interval);
}

std::chrono::nanoseconds Device::asyncPollInterval() const noexcept
{
	return impl_->link->asyncPollInterval();
}

ResponseHeader Device::lastHeader() const
{
	return impl_->link->lastHeader().value_or(ResponseHeader{});
}

std::uint16_t Device::dataSize() const
{
	return impl_->link->dataSize();
}

CheckType Device::checkType() const
{
	return impl_->link->checkType();
}

void Device::assumeFormat(std::uint16_t dataSize, CheckType check)
{
	impl_->link->assumeFormat(dataSize, check);
}

Link &Device::link() noexcept
{
	return *impl_->link;
}

const Link &Device::link() const noexcept
{
	return *impl_->link;
}

// ---------------------------------------------------------------------------
// The packet trace (the writer: lib/link/trace_writer.cpp)
// ---------------------------------------------------------------------------

void Device::startTrace(std::string_view path)
{
	auto w = std::make_unique<detail::TraceWriter>(path);
	link().attachTrace(w.get()); // the link writes its first record (its format)
	auto old = std::exchange(impl_->trace, std::move(w));
	if (old)
		old->close();
}

void Device::stopTrace()
{
	link().attachTrace(nullptr);
	auto w = std::exchange(impl_->trace, nullptr);
	if (w)
		w->close();
}

bool Device::tracing() const noexcept
{
	return impl_->trace != nullptr;
}

} // namespace ecmxf
