// SPDX-License-Identifier: MIT
// Internal: the one command runner of the typed calls (the view classes
// Chip, Peripherals, Chip402, SlaveAccess, Bus, Sdo, ProcessData), and the
// byte and message helpers they share. Not installed.
//
// The refusal rule, the same for every typed call:
//  - an immediate command goes out with control bit 7 (clear command
//    error), so error status bit 7 in its own answer means the chip refused
//    this command; the call clears the bit again with one INFO_UPDATE_OP
//    and throws @p refusal (the view's documented errno: EINVAL for the
//    chip, peripheral, slave and bus calls, EREMOTEIO for the process-data
//    and CiA-402 engine calls) with
//    "[context: ]NAME: the chip refused the command (error status bit 7,
//    command error[: hint])[; the command exists only in firmware of
//    manual ver. 050]", the command's NAME left out when the context
//    starts with it ("ECAT_STATE_GET for slave 4: the chip refused ...");
//  - an async command: a bit 7 left set from before is cleared first (the
//    engine sees a refusal only as a newly set bit). Device reports a
//    refusal as EBUSY; with the chip's busy bit set it is one (EBUSY,
//    "another async command is still running on the chip"), else the
//    parameters were refused: @p refusal with the same text as above,
//    its hint being @p hint, or for a slave that is not on the bus
//    "slave N is not on the bus (M slaves found by ECAT_INIT_OP)";
//  - an async failure (EREMOTEIO) is explained by @p onFailure where the
//    caller has one; every other error passes with "context: " in front
//    (unless its message already starts so).
#pragma once

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "base/text.hpp"

namespace ecmxf::detail {

/// A command with @p code and @p param.
Command cmd(std::uint8_t code, std::uint8_t param = 0);
/// A command with parametric data bytes 0..3.
Command cmdData(std::uint8_t code, std::uint8_t param, std::uint8_t d0, std::uint8_t d1 = 0, std::uint8_t d2 = 0,
		std::uint8_t d3 = 0);

/// Runs an immediate command (the refusal rule above). @p context names
/// the operation in every message (empty: the command's name says it
/// all), e.g. "EEPROM read of slave 5, word 0x0000"; @p hint is what a
/// refusal most likely means ("slave 5 does not exist"); @p refusal the
/// errno of a refusal, the view's documented one.
Response immediate(Device &dev, Command c, const std::string &context = {}, const std::string &hint = {},
		   int refusal = EINVAL);
/// Runs an async command to its completion (the refusal rule above).
/// @p onFailure, when given, explains an async failure (the chip's error
/// code, from its *_GET); it runs after the failure, with the chip free.
/// @p slave >= 0 names the slave the command is about, for the reason of
/// a refusal without @p hint.
Response async(Device &dev, const Command &c, const std::string &context = {}, const std::string &hint = {},
	       const std::function<std::string()> &onFailure = {}, int slave = -1, int refusal = EINVAL);
/// async() with the result fetch @p fetch (Device::commandWithFetch()):
/// returns the fetch's answer; a refusal of the fetch (error status bit
/// 7 in its answer) as immediate() reports it.
Response asyncWithFetch(Device &dev, const Command &c, Command fetch, const std::string &context = {},
			int slave = -1, int refusal = EINVAL);

/// Rethrows the exception being handled (an ecmxf::Error or subclass) with
/// @p prefix before its message, keeping its type and fields.
[[noreturn]] void rethrowWithPrefix(const std::string &prefix);

/// The host's time limit for an async command with a chip-side
/// @p chipTimeout: the table's default, or longer when the chip may take
/// longer (zero: the table's default).
std::chrono::microseconds hostTimeout(std::chrono::microseconds chipTimeout, std::uint8_t code);
/// @p t as the chip's 32-bit µs field (EINVAL beyond).
std::uint32_t chipTimeoutField(const std::string &what, std::chrono::microseconds t);
/// EPROTO unless the answer has @p n data bytes at least.
void needData(const std::string &what, const Response &r, std::size_t n);
/// Error(@p what + ": " + @p why, EINVAL).
[[noreturn]] void invalid(const std::string &what, const std::string &why);

/// "slave 5".
std::string slaveText(unsigned slave);

} // namespace ecmxf::detail
