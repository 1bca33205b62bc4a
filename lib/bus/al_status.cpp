// SPDX-License-Identifier: MIT
// EtherCAT states and AL status codes in words: stateName(), alStatusText()
// (the AKD2G table, seed 003) and AlStatusError. The bus layer's helpers
// are lib/bus/bus_helpers.cpp.

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

namespace {

/// The one table of EtherCAT state names (ecatStateName() in
/// lib/bus/status.cpp and the command line's names are built on it).
constexpr struct {
	State state;
	const char *name;
} kStateNames[] = { { State::None, "NONE" },     { State::Init, "INIT" },   { State::PreOp, "PRE-OP" },
		    { State::Boot, "BOOT" },     { State::SafeOp, "SAFE-OP" }, { State::Op, "OP" } };

} // namespace

std::string stateName(State s)
{
	for (const auto &n : kStateNames)
		if (n.state == s)
			return n.name;
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

} // namespace ecmxf
