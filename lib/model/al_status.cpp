// SPDX-License-Identifier: MIT
// EtherCAT states and AL status codes in words: stateName(), alStatusText()
// (the AKD2G table, seed 003) and AlStatusError. The shared vocabulary of
// both masters (Documentation/architecture.rst, "model").

#include <ecmxf/model/types_bus.hpp>
#include <ecmxf/protocol.hpp>

#include <cerrno>
#include <cinttypes>
#include <cstdio>

#include "base/text.hpp"
#include "ecmxf-proto.h"

namespace ecmxf {

// ---------------------------------------------------------------------------
// states and AL status codes
// ---------------------------------------------------------------------------

namespace {

/// The one table of EtherCAT state names (ecatStateName() in
/// lib/model/status.cpp and the command line's names are built on it).
constexpr detail::CodeText<State> kStateNames[] = {
	{ State::None, "NONE" }, { State::Init, "INIT" },     { State::PreOp, "PRE-OP" },
	{ State::Boot, "BOOT" }, { State::SafeOp, "SAFE-OP" }, { State::Op, "OP" },
};

} // namespace

std::string stateName(State s)
{
	const std::string_view name = detail::textOf(kStateNames, s, {});
	if (name.empty())
		return detail::hex(static_cast<std::uint8_t>(s), 2);
	return std::string(name);
}

namespace {

/// The AKD2G "AL Status Code" table (seed 003), its wording.
constexpr detail::CodeText<std::uint16_t> kAlStatusTexts[] = {
	{ 0x0000, "No error" },
	{ 0x0011, "Invalid requested state change" },
	{ 0x0012, "Unknown requested state" },
	{ 0x0015, "Invalid mailbox boot configuration" },
	{ 0x0016, "Invalid mailbox configuration" },
	{ 0x001A, "Multiple sync errors" },
	{ 0x001B, "Sync manager watchdog" },
	{ 0x001D, "Invalid output configuration SM2 (Rx)" },
	{ 0x001E, "Invalid input configuration SM3 (Tx)" },
	{ 0x0024, "Invalid input mapping (too many PDO entries)" },
	{ 0x0025, "Invalid output mapping (too many PDO entries)" },
	{ 0x002C, "Fatal sync error (PLL was unlocked)" },
	{ 0x002D, "No fatal sync error (Transition SafeOp to Op took too long)" },
	{ 0x002E, "No sync error (SYNC0 did not occur)" },
	{ 0x0030, "Invalid DC sync error (cycle time via register 0x9A0 is not an allowed value)" },
	{ 0x0032, "DC PLL sync error (shift time too short)" },
	{ 0x0034, "Too many missed SM2 events" },
};

} // namespace

std::string_view alStatusText(std::uint16_t code) noexcept
{
	return detail::textOf(kAlStatusTexts, code, "unknown AL status code");
}

AlStatusError::AlStatusError(const std::string &message, int errnoValue, std::uint8_t slave, State requested,
			     State reached, std::uint16_t alStatusCode, std::optional<std::uint8_t> errorStatus)
	: Error(message, errnoValue, errorStatus), slave_(slave), requested_(requested), reached_(reached),
	  alStatusCode_(alStatusCode)
{
}

AlStatusError::~AlStatusError() = default;

void AlStatusError::rethrowWithPrefix(std::string_view prefix) const
{
	throw AlStatusError(std::string(prefix).append(what()), errnoValue(), slave(), requested(), reached(),
			    alStatusCode(), errorStatus());
}

} // namespace ecmxf
