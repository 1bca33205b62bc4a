// SPDX-License-Identifier: MIT
// The one map from a command's outcome on a Link to ecmxf::Error
// (lib/link/outcome.hpp).

#include <ecmxf/error.hpp>
#include <ecmxf/protocol.hpp>

#include <cerrno>
#include <cstring>
#include <string>

#include "ecmxf-proto.h"
#include "base/text.hpp"
#include "link/outcome.hpp"

namespace ecmxf::detail {

void throwOutcome(const Link &link, const RawRequest &req, const RawResult &res)
{
	const std::string name = commandName(req.code) + ": ";
	const int err = -res.status;
	const std::uint8_t status = res.header.errStatus;
	const std::uint8_t faultBits = static_cast<std::uint8_t>(status & ECMXF_ERR_FAULT_MASK);

	// the link's own failure: its text names the link
	if (res.linkFailure)
		throw Error(name + res.linkFailure, err);

	switch (res.status) {
	case -ETIMEDOUT: {
		std::uint64_t us = res.waitedUs;
		if (!us) {
			const auto info = commandInfo(req.code);
			us = req.timeoutUs ? req.timeoutUs : static_cast<std::uint64_t>(info ? info->timeoutMs : 100u) * 1000u;
		}
		const char *what = res.ranAsync ? " waiting for the async command to complete"
				   : res.waitedUs || !ecmxf_cmd_is_async(req.code, req.param)
					   ? " waiting for the chip's answer"
					   : " waiting for the answer and the async command's completion";
		throw Error(name + "timed out after " + durationUs(us) + what, ETIMEDOUT);
	}
	case -EBADMSG:
	case -EPROTO:
	case -EIO:
		if (res.badPackets)
			throw Error(name + std::to_string(res.badPackets) + " bad packets in a row (" +
					    (res.fault ? res.fault : "?") + ")",
				    err);
		if (res.answerLost)
			throw Error(name + "the answer was lost on the wire and the command is not safe to "
					   "send again (it may have run)",
				    err);
		if (res.status == -EIO)
			throw Error(name + "the chip kept answering not ready (check word 0x87654321)", EIO);
		throw Error(name + "the link kept delivering bad packets (" +
				    (res.status == -EBADMSG ? "check word mismatch" : "wrong start/end word or data length") +
				    "); " + link.name() + "'s counters tell more",
			    err);
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
		throw Error(name + "the command was cancelled", ECANCELED);
	default:
		throw Error(name + "failed: " + std::strerror(err), err);
	}
}

} // namespace ecmxf::detail
