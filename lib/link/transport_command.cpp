// SPDX-License-Identifier: MIT
// CommandTransport (include/ecmxf/link/transport.hpp) and Device::command() over
// it: the transport runs the protocol (the kernel module), the library maps
// the outcome to ecmxf::Error with the same words as over byte transports.

#include <ecmxf/error.hpp>
#include <ecmxf/protocol.hpp>
#include <ecmxf/link/transport.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "ecmxf-proto.h"
#include "device/lib_text.hpp"
#include "trace/trace_writer.hpp"
#include "link/transport_command.hpp"

namespace ecmxf {

CommandTransport::CommandTransport(std::string name) : name_(std::move(name)) {}

CommandTransport::~CommandTransport() = default;

void CommandTransport::exchange(std::span<const std::uint8_t>, std::span<std::uint8_t>)
{
	throw Error(name_ + ": this transport runs the protocol itself and takes whole commands, "
			    "not SPI packets",
		    EOPNOTSUPP);
}

bool CommandTransport::waitReady(std::chrono::nanoseconds)
{
	throw Error(name_ + ": this transport runs the protocol itself; there is no INT0 to wait for",
		    EOPNOTSUPP);
}

std::chrono::nanoseconds CommandTransport::now() const
{
	return std::chrono::duration_cast<std::chrono::nanoseconds>(
		std::chrono::steady_clock::now().time_since_epoch());
}

int CommandTransport::run(const RawRequest &req, RawResult &res, const char *&failedCall) noexcept
{
	res = RawResult{};
	failedCall = "";
	const int r = doCommand(req, res, failedCall);
	// headers the chip sent: success and the outcomes it reported
	if (r == 0 && (res.status == 0 || res.status == -EBUSY || res.status == -EREMOTEIO ||
		       res.status == -EMSGSIZE))
		last_ = res.header;
	return r;
}

namespace detail {

int transactOnCommandTransport(CommandTransport &t, const RawCommand &c, std::span<const std::uint8_t> payload,
			       std::span<std::uint8_t> answer, ResponseHeader &header, TraceWriter *trace) noexcept
{
	if (payload.size() > ECMXF_DATA_MAX)
		return EMSGSIZE;
	RawRequest req;
	req.data = c.data;
	req.reserved = c.reserved;
	req.control = c.control;
	req.code = c.code;
	req.param = c.param;
	req.len = c.len < 0 ? static_cast<std::uint16_t>(payload.size()) : static_cast<std::uint16_t>(c.len);
	req.tx = payload;
	req.rx = answer;
	const auto us = c.timeout.count();
	req.timeoutUs = us <= 0 ? 0u : static_cast<std::uint32_t>(std::min<std::int64_t>(us, UINT32_MAX));

	RawResult res;
	const char *call = "";
	try {
		if (trace)
			trace->request(static_cast<std::uint64_t>(t.now().count()), req);
	} catch (...) {
		// a trace that cannot be written does not stop the cyclic path
	}
	const int r = t.run(req, res, call);
	if (r < 0)
		return -r;
	try {
		if (trace)
			trace->response(static_cast<std::uint64_t>(t.now().count()), res,
					std::span<const std::uint8_t>(answer.data(), std::min(res.rxLen, answer.size())));
	} catch (...) {
	}
	header = res.header;
	return res.status == 0 ? 0 : -res.status;
}

Response runOnCommandTransport(CommandTransport &t, const Command &c, TraceWriter *trace)
{
	std::string name = commandName(c.code);
	name += ": ";
	if (c.payload.size() > ECMXF_DATA_MAX)
		throw Error(name + "payload of " + std::to_string(c.payload.size()) +
				    " bytes does not fit the largest data section (1408 bytes)",
			    EMSGSIZE);

	Response rsp;
	rsp.data.resize(ECMXF_DATA_MAX);
	RawRequest req;
	req.data = c.data;
	req.reserved = c.reserved;
	req.control = c.control;
	req.code = c.code;
	req.param = c.param;
	req.len = c.len.value_or(static_cast<std::uint16_t>(c.payload.size()));
	req.tx = c.payload;
	req.rx = rsp.data;
	const auto us = c.timeout.count();
	req.timeoutUs = us <= 0 ? 0u : static_cast<std::uint32_t>(std::min<std::int64_t>(us, UINT32_MAX));

	RawResult res;
	const char *call = "";
	if (trace)
		trace->request(static_cast<std::uint64_t>(t.now().count()), req);
	const int r = t.run(req, res, call);
	if (r < 0) {
		throw Error(name + t.name() + ": " + call + " failed: " + std::strerror(-r), -r);
	}
	if (trace)
		trace->response(static_cast<std::uint64_t>(t.now().count()), res,
				std::span<const std::uint8_t>(rsp.data.data(), std::min(res.rxLen, rsp.data.size())));

	const std::uint8_t status = res.header.errStatus;
	const std::uint8_t faultBits = static_cast<std::uint8_t>(status & ECMXF_ERR_FAULT_MASK);
	switch (res.status) {
	case 0:
		break;
	case -ETIMEDOUT: {
		const auto info = commandInfo(c.code);
		const std::uint64_t limit = req.timeoutUs ? req.timeoutUs
							  : static_cast<std::uint64_t>(info ? info->timeoutMs : 100u) * 1000u;
		throw Error(name + "timed out after " + durationUs(limit) +
				    (ecmxf_cmd_is_async(c.code, c.param)
					     ? " waiting for the answer and the async command's completion"
					     : " waiting for the chip's answer"),
			    ETIMEDOUT);
	}
	case -EBADMSG:
		throw Error(name + "the link kept delivering bad packets (check word mismatch); " + t.name() +
				    "'s counters tell more",
			    EBADMSG);
	case -EPROTO:
		throw Error(name + "the link kept delivering bad packets (wrong start/end word or data length); " +
				    t.name() + "'s counters tell more",
			    EPROTO);
	case -EIO:
		throw Error(name + "the chip kept answering not ready (check word 0x87654321)", EIO);
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
		throw Error(name + "the answer (" + std::to_string(res.header.len) +
				    " bytes) is larger than the receive buffer (" + std::to_string(req.rx.size()) +
				    " bytes)",
			    EMSGSIZE);
	case -ECANCELED:
		throw Error(name + "the command was cancelled (ECMXF_IOC_RESET)", ECANCELED);
	default:
		throw Error(name + "failed: " + std::strerror(-res.status), -res.status);
	}
	rsp.data.resize(std::min(res.rxLen, rsp.data.size()));
	rsp.header = res.header;
	rsp.ret = res.header.ret;
	return rsp;
}

} // namespace detail
} // namespace ecmxf
