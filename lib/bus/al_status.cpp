// SPDX-License-Identifier: MIT
// EtherCAT states and AL status codes in words: stateName(), alStatusText()
// (the AKD2G table, seed 003), AlStatusError, and the helpers the bus
// commands share (lib/bus/bus_internal.hpp).

#include "bus/bus_internal.hpp"

#include <ecmxf/protocol.hpp>

#include <cerrno>
#include <cinttypes>
#include <cstdio>

#include "ecmxf-proto.h"

namespace ecmxf {

// ---------------------------------------------------------------------------
// states and AL status codes
// ---------------------------------------------------------------------------

std::string stateName(State s)
{
	switch (s) {
	case State::None:
		return "NONE";
	case State::Init:
		return "INIT";
	case State::PreOp:
		return "PRE-OP";
	case State::Boot:
		return "BOOT";
	case State::SafeOp:
		return "SAFE-OP";
	case State::Op:
		return "OP";
	}
	return bus::hex(static_cast<std::uint8_t>(s), 2);
}

std::string_view alStatusText(std::uint16_t code) noexcept
{
	// AKD2G "AL Status Code" table (seed 003), its wording
	switch (code) {
	case 0x0000:
		return "No error";
	case 0x0011:
		return "Invalid requested state change";
	case 0x0012:
		return "Unknown requested state";
	case 0x0015:
		return "Invalid mailbox boot configuration";
	case 0x0016:
		return "Invalid mailbox configuration";
	case 0x001A:
		return "Multiple sync errors";
	case 0x001B:
		return "Sync manager watchdog";
	case 0x001D:
		return "Invalid output configuration SM2 (Rx)";
	case 0x001E:
		return "Invalid input configuration SM3 (Tx)";
	case 0x0024:
		return "Invalid input mapping (too many PDO entries)";
	case 0x0025:
		return "Invalid output mapping (too many PDO entries)";
	case 0x002C:
		return "Fatal sync error (PLL was unlocked)";
	case 0x002D:
		return "No fatal sync error (Transition SafeOp to Op took too long)";
	case 0x002E:
		return "No sync error (SYNC0 did not occur)";
	case 0x0030:
		return "Invalid DC sync error (cycle time via register 0x9A0 is not an allowed value)";
	case 0x0032:
		return "DC PLL sync error (shift time too short)";
	case 0x0034:
		return "Too many missed SM2 events";
	default:
		return "unknown AL status code";
	}
}

AlStatusError::AlStatusError(const std::string &message, int errnoValue, std::uint8_t slave, State requested,
			     State reached, std::uint16_t alStatusCode, std::optional<std::uint8_t> errorStatus)
	: Error(message, errnoValue, errorStatus), slave_(slave), requested_(requested), reached_(reached),
	  alStatusCode_(alStatusCode)
{
}

AlStatusError::~AlStatusError() = default;

// ---------------------------------------------------------------------------
// shared helpers
// ---------------------------------------------------------------------------

namespace bus {

std::string hex(std::uint64_t v, int digits)
{
	char buf[32];
	std::snprintf(buf, sizeof(buf), "0x%0*" PRIX64, digits, v);
	return buf;
}

std::string objName(std::uint16_t index, std::uint8_t sub)
{
	char buf[16];
	std::snprintf(buf, sizeof(buf), "0x%04X:%02X", index, sub);
	return buf;
}

std::uint16_t le16(const std::vector<std::uint8_t> &d, std::size_t off)
{
	std::uint16_t v = 0;
	for (std::size_t i = 0; i < 2 && off + i < d.size(); i++)
		v = static_cast<std::uint16_t>(v | d[off + i] << (8 * i));
	return v;
}

std::uint32_t le32(const std::vector<std::uint8_t> &d, std::size_t off)
{
	std::uint32_t v = 0;
	for (std::size_t i = 0; i < 4 && off + i < d.size(); i++)
		v |= static_cast<std::uint32_t>(d[off + i]) << (8 * i);
	return v;
}

void put16(std::vector<std::uint8_t> &d, std::uint16_t v)
{
	d.push_back(static_cast<std::uint8_t>(v));
	d.push_back(static_cast<std::uint8_t>(v >> 8));
}

void put32(std::vector<std::uint8_t> &d, std::uint32_t v)
{
	put16(d, static_cast<std::uint16_t>(v));
	put16(d, static_cast<std::uint16_t>(v >> 16));
}

Command cmd(std::uint8_t code, std::uint8_t param)
{
	Command c;
	c.code = code;
	c.param = param;
	return c;
}

Response immediate(Device &dev, Command c, const std::string &what)
{
	// the clear bit is applied before the command runs, so bit 7 in this
	// command's answer is about this command alone
	c.control = static_cast<std::uint8_t>(c.control | ECMXF_CTL_CLR_CMD_ERR);
	Response r = dev.command(c);
	if (r.header.errStatus & ECMXF_ERR_CMD)
		throw Error(std::string(what).append(": the chip refused the command (error status bit 7: "
						     "a parameter it does not accept)"),
			    EINVAL, r.header.errStatus);
	return r;
}

Response async(Device &dev, const Command &c, const std::string &what, int slave)
{
	try {
		return dev.command(c);
	} catch (const Error &e) {
		if (e.errnoValue() != EBUSY) {
			// Device's message already starts with the command name
			const std::string prefix = std::string(what).append(": ");
			if (std::string_view(e.what()).substr(0, prefix.size()) == prefix)
				throw;
			rethrowWithPrefix(prefix);
		}
		// error status bit 7: the chip did not start it. Find out why
		// (immediate commands work while an async one runs).
		const bool busy = (dev.lastHeader().ecmStatus & ECMXF_STS_BUSY) != 0;
		std::string why;
		int err = EINVAL;
		if (busy) {
			why = "another async command is still running on the chip";
			err = EBUSY;
		} else if (slave >= 0 && slave != kAllSlaves) {
			std::uint8_t n = 0;
			try {
				n = dev.command(cmd(ECMXF_CMD_ECAT_SLV_CNT_GET)).ret;
			} catch (const Error &) {
				n = 0;
			}
			if (static_cast<unsigned>(slave) >= n)
				why = "slave " + std::to_string(slave) + " is not on the bus (" + std::to_string(n) +
				      " slaves found by ECAT_INIT_OP)";
		}
		if (why.empty())
			why = "a parameter it does not accept, or the network is not initialised (ECAT_INIT_OP)";
		throw Error(std::string(what).append(": the chip refused the command (error status bit 7): ").append(why),
			    err, e.errorStatus());
	}
}

void rethrowWithPrefix(const std::string &prefix)
{
	try {
		throw;
	} catch (const AlStatusError &e) {
		throw AlStatusError(std::string(prefix).append(e.what()), e.errnoValue(), e.slave(), e.requested(),
				    e.reached(), e.alStatusCode(), e.errorStatus());
	} catch (const SdoError &e) {
		throw SdoError(std::string(prefix).append(e.what()), e.errnoValue(), e.abortCode(), e.errorStatus());
	} catch (const Error &e) {
		throw Error(std::string(prefix).append(e.what()), e.errnoValue(), e.errorStatus());
	}
}

void checkSlave(std::uint8_t slave, const char *what, bool allowAll)
{
	if (slave <= kMaxSlavePosition || (allowAll && slave == kAllSlaves))
		return;
	throw Error(std::string(what).append(": slave ").append(std::to_string(slave)).append(
			    allowAll ? " out of range (0..127, or 0xFF for all slaves)" : " out of range (0..127)"),
		    EINVAL);
}

void checkState(State s, const char *what)
{
	switch (s) {
	case State::Init:
	case State::PreOp:
	case State::Boot:
	case State::SafeOp:
	case State::Op:
		return;
	case State::None:
		break;
	}
	throw Error(std::string(what).append(": state ").append(hex(static_cast<std::uint8_t>(s), 2)).append(
			    " is not one of INIT (1), PRE-OP (2), BOOT (3), SAFE-OP (4), OP (8)"),
		    EINVAL);
}

} // namespace bus
} // namespace ecmxf
