// SPDX-License-Identifier: MIT
// The one command runner of the typed calls and their shared helpers
// (lib/device/runner.hpp: the refusal rule).

#include "device/runner.hpp"

#include <ecmxf/protocol.hpp>
#include <ecmxf/model/status.hpp>
#include <ecmxf/model/types_bus.hpp>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <string_view>

#include "base/text.hpp"
#include "ecmxf-proto.h"

namespace ecmxf::detail {

namespace {

/// Clears a command error (bit 7) the chip still shows, so that the next
/// refusal is seen as new. A failure here is left to the next command.
void clearCommandError(Device &d)
{
	Command c = cmd(ECMXF_CMD_INFO_UPDATE_OP);
	c.control = ECMXF_CTL_CLR_CMD_ERR;
	try {
		d.command(c);
	} catch (const Error &) {
		// the error being reported matters more; the next command reports
		// a link that is really gone
	}
}

std::string where(const std::string &context)
{
	return context.empty() ? std::string() : context + ": ";
}

/// "[context: ][NAME: ]": the command is named once, by the context when it
/// starts with its name ("ECAT_STATE_SET PRE-OP for slave 4"), else after it.
std::string named(const std::string &context, std::uint8_t code)
{
	const std::string name = commandName(code);
	std::string s = where(context);
	if (context.compare(0, name.size(), name) != 0 || (context.size() > name.size() && context[name.size()] != ' '))
		s.append(name).append(": ");
	return s;
}

/// "[context: ][NAME: ]the chip refused the command (error status bit 7,
/// command error[: why])[; ver. 050 note]", NAME left out when the context
/// starts with it.
std::string refusalText(const std::string &context, std::uint8_t code, const std::string &why)
{
	std::string s = named(context, code);
	s.append("the chip refused the command (error status bit 7, command error");
	if (!why.empty())
		s.append(": ").append(why);
	s.append(")");
	const auto ci = commandInfo(code);
	if (ci && !ci->inV038)
		s.append("; the command exists only in firmware of manual ver. 050");
	return s;
}

/// Rethrows the Error being handled with "context: " in front, unless
/// there is no context or the message starts with it already.
[[noreturn]] void rethrowIn(const std::string &context, const Error &e)
{
	const std::string prefix = where(context);
	if (prefix.empty() || std::string_view(e.what()).substr(0, prefix.size()) == prefix)
		throw;
	rethrowWithPrefix(prefix);
}

} // namespace

Command cmd(std::uint8_t code, std::uint8_t param)
{
	Command c;
	c.code = code;
	c.param = param;
	return c;
}

Command cmdData(std::uint8_t code, std::uint8_t param, std::uint8_t d0, std::uint8_t d1, std::uint8_t d2,
		std::uint8_t d3)
{
	Command c = cmd(code, param);
	c.data = { d0, d1, d2, d3 };
	return c;
}

Response immediate(Device &dev, Command c, const std::string &context, const std::string &hint, int refusal)
{
	// the clear bit is applied before the command runs, so bit 7 in this
	// command's answer is about this command alone
	c.control = static_cast<std::uint8_t>(c.control | ECMXF_CTL_CLR_CMD_ERR);
	Response r;
	try {
		r = dev.command(c);
	} catch (const Error &e) {
		rethrowIn(context, e);
	}
	if (r.header.errStatus & ECMXF_ERR_CMD) {
		clearCommandError(dev);
		throw Error(refusalText(context, c.code, hint), refusal, r.header.errStatus);
	}
	return r;
}

namespace {

Response runAsync(Device &dev, const Command &c, const Command *fetch, const std::string &context,
		  const std::string &hint, const std::function<std::string()> &onFailure, int slave, int refusal)
{
	// the engine sees a refusal only as a newly set bit 7
	if (dev.lastHeader().errStatus & ECMXF_ERR_CMD)
		clearCommandError(dev);
	Response r;
	try {
		r = fetch ? dev.commandWithFetch(c, *fetch) : dev.command(c);
	} catch (const Error &e) {
		if (e.errnoValue() == EREMOTEIO && onFailure)
			throw Error(named(context, c.code) + "the async command failed: " + onFailure(),
				    EREMOTEIO, e.errorStatus());
		if (e.errnoValue() != EBUSY || !e.errorStatus())
			rethrowIn(context, e);
		// error status bit 7: the chip did not start it. Find out why
		// (immediate commands work while an async one runs).
		if (dev.lastHeader().ecmStatus & ECMXF_STS_BUSY)
			throw Error(refusalText(context, c.code, "another async command is still running on the chip"),
				    EBUSY, e.errorStatus());
		std::string why = hint;
		if (why.empty() && slave >= 0 && slave != kAllSlaves) {
			std::uint8_t n = 0;
			try {
				n = dev.command(cmd(ECMXF_CMD_ECAT_SLV_CNT_GET)).ret;
			} catch (const Error &) {
				n = 0;
			}
			if (static_cast<unsigned>(slave) >= n)
				why = slaveText(static_cast<unsigned>(slave)) + " is not on the bus (" +
				      std::to_string(n) + " slaves found by ECAT_INIT_OP)";
		}
		if (why.empty())
			why = "a parameter it does not accept, or the network is not initialised (ECAT_INIT_OP)";
		throw Error(refusalText(context, c.code, why), refusal, e.errorStatus());
	}
	if (fetch && (r.header.errStatus & ECMXF_ERR_CMD)) {
		clearCommandError(dev);
		throw Error(refusalText(context, fetch->code, hint), refusal, r.header.errStatus);
	}
	return r;
}

} // namespace

Response async(Device &dev, const Command &c, const std::string &context, const std::string &hint,
	       const std::function<std::string()> &onFailure, int slave, int refusal)
{
	return runAsync(dev, c, nullptr, context, hint, onFailure, slave, refusal);
}

Response asyncWithFetch(Device &dev, const Command &c, Command fetch, const std::string &context, int slave,
			int refusal)
{
	// the clear bit goes out with every poll, so bit 7 in the answer that
	// brings the result is about the fetch alone
	fetch.control = static_cast<std::uint8_t>(fetch.control | ECMXF_CTL_CLR_CMD_ERR);
	return runAsync(dev, c, &fetch, context, {}, {}, slave, refusal);
}

void rethrowWithPrefix(const std::string &prefix)
{
	try {
		throw;
	} catch (const Error &e) {
		e.rethrowWithPrefix(prefix);
		throw; // not reached: rethrowWithPrefix() throws (a virtual call is not taken as noreturn)
	}
	// a non-ecmxf exception has passed as it is
}

std::chrono::microseconds hostTimeout(std::chrono::microseconds chipTimeout, std::uint8_t code)
{
	using std::chrono::microseconds;
	if (chipTimeout <= microseconds::zero())
		return microseconds::zero();
	const auto ci = commandInfo(code);
	const microseconds dflt(static_cast<std::int64_t>(ci ? ci->timeoutMs : 1000u) * 1000);
	return std::max(dflt, chipTimeout + std::chrono::seconds(1));
}

std::uint32_t chipTimeoutField(const std::string &what, std::chrono::microseconds t)
{
	if (t < std::chrono::microseconds::zero() || t.count() > static_cast<std::int64_t>(UINT32_MAX))
		invalid(what, "timeout of " + std::to_string(t.count()) + " us is out of range (0..4294967295 us)");
	return static_cast<std::uint32_t>(t.count());
}

void needData(const std::string &what, const Response &r, std::size_t n)
{
	if (r.data.size() < n)
		throw Error(what + ": the chip answered " + std::to_string(r.data.size()) + " data bytes, expected " +
				    std::to_string(n),
			    EPROTO);
}

void invalid(const std::string &what, const std::string &why)
{
	throw Error(what + ": " + why, EINVAL);
}

std::string slaveText(unsigned slave)
{
	return "slave " + std::to_string(slave);
}

} // namespace ecmxf::detail
