// SPDX-License-Identifier: MIT
// Link and ByteChannel: the defaults of the capabilities
// (include/ecmxf/link/link.hpp, byte_channel.hpp).

#include <ecmxf/error.hpp>
#include <ecmxf/link/byte_channel.hpp>
#include <ecmxf/link/link.hpp>

#include <algorithm>
#include <cerrno>
#include <thread>

#include "ecmxf-proto.h"
#include "base/text.hpp"
#include "link/outcome.hpp"
#include "link/pdo_rings.hpp"

namespace ecmxf {

namespace {

void sleepSteady(std::chrono::nanoseconds duration)
{
	if (duration > std::chrono::nanoseconds::zero())
		std::this_thread::sleep_for(duration);
}

} // namespace

void detail::checkReset(const Link &link, LinkReset kind, std::uint32_t param)
{
	if (kind == LinkReset::AsyncCmd && (param & ~7u))
		throw Error(link.name() + ": ASYNCCMD_RESET parameter " + std::to_string(param) +
				    " has bits outside 0..2 (clear busy, skip link, abandon)",
			    EINVAL);
	if (kind != LinkReset::AsyncCmd && param)
		throw Error(link.name() + ": a reset parameter is only allowed for ASYNCCMD_RESET", EINVAL);
}

ByteChannel::~ByteChannel() = default;

void ByteChannel::sleepFor(std::chrono::nanoseconds duration)
{
	sleepSteady(duration);
}

void ByteChannel::sleepUntil(std::chrono::nanoseconds deadline)
{
	sleepFor(deadline - now());
}

Link::~Link() = default;

std::chrono::nanoseconds Link::now() const
{
	return std::chrono::duration_cast<std::chrono::nanoseconds>(
		std::chrono::steady_clock::now().time_since_epoch());
}

void Link::sleepFor(std::chrono::nanoseconds duration)
{
	sleepSteady(duration);
}

void Link::sleepUntil(std::chrono::nanoseconds deadline)
{
	sleepFor(deadline - now());
}

void Link::runBatch(std::span<const RawRequest> reqs, std::span<RawResult> res, bool) noexcept
{
	const std::size_t n = std::min(reqs.size(), res.size());
	for (std::size_t i = 0; i < n; i++) {
		if (reqs[i].fetchesPrevious && i > 0 && res[i - 1].status != 0) {
			res[i] = RawResult{};
			res[i].status = -ECANCELED;
			res[i].linkFailure = detail::kFetchNotSent;
			continue;
		}
		run(reqs[i], res[i]);
	}
}

void Link::reset(LinkReset kind, std::uint32_t param, std::uint32_t timeoutUs)
{
	detail::checkReset(*this, kind, param);
	RawRequest req;
	switch (kind) {
	case LinkReset::AsyncCmd:
		req.code = ECMXF_CMD_ASYNCCMD_RESET;
		req.param = static_cast<std::uint8_t>(param);
		// a command error left from before would read as this one's
		req.control = ECMXF_CTL_CLR_CMD_ERR;
		break;
	case LinkReset::Warm:
		// the engine switches to the power-on format and waits for the NOP
		req.code = ECMXF_CMD_WARM_RESET;
		break;
	case LinkReset::Link:
		throw Error(name() + ": only the kernel module's link can be resynchronised (ECMXF_IOC_RESET)",
			    EOPNOTSUPP);
	}
	req.timeoutUs = timeoutUs;
	RawResult res;
	run(req, res);
	if (res.status != 0)
		detail::throwOutcome(*this, req, res);
	if (res.header.errStatus & ECMXF_ERR_CMD)
		throw Error(detail::commandName(req.code) + ": the chip refused the command (error status " +
				    detail::hex8(res.header.errStatus) + ")",
			    EINVAL, res.header.errStatus);
}

void Link::assumeFormat(std::uint16_t, CheckType)
{
	throw Error(name() + ": this link tracks the chip's packet format itself", EOPNOTSUPP);
}

void Link::setAsyncPollInterval(std::chrono::nanoseconds) noexcept {}

std::chrono::nanoseconds Link::asyncPollInterval() const noexcept
{
	return std::chrono::nanoseconds::zero();
}

std::unique_ptr<detail::PdoRings> Link::openPdoRings()
{
	return nullptr;
}

std::optional<std::uint32_t> Link::breakClaim()
{
	throw Error(name() + ": no claim to break (only the kernel module's /dev/ecmxfN has one)", EOPNOTSUPP);
}

} // namespace ecmxf
