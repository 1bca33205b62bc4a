// SPDX-License-Identifier: MIT
// Helpers shared by the bus commands, SDO and Master (lib/bus/commands_bus.cpp,
// lib/bus/sdo.cpp, lib/bus/al_status.cpp, lib/bus/master.cpp). Not installed.
#pragma once

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/bus/types_bus.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace ecmxf::bus {

/// "0x1D" style: @p v in hex with @p digits digits.
std::string hex(std::uint64_t v, int digits);
/// "0x6064:00".
std::string objName(std::uint16_t index, std::uint8_t sub);

/// Little-endian reads from @p d at @p off (0 for missing bytes).
std::uint16_t le16(const std::vector<std::uint8_t> &d, std::size_t off = 0);
std::uint32_t le32(const std::vector<std::uint8_t> &d, std::size_t off = 0);
void put16(std::vector<std::uint8_t> &d, std::uint16_t v);
void put32(std::vector<std::uint8_t> &d, std::uint32_t v);

/// A command with @p code and @p param.
Command cmd(std::uint8_t code, std::uint8_t param = 0);

/// Runs an immediate command; the chip's refusal (error status bit 7 in
/// its answer) becomes Error(@p what + ": the chip refused ...", EINVAL).
Response immediate(Device &dev, Command c, const std::string &what);

/// Runs an async command. A refusal (EBUSY from Device) is explained:
/// another async command still running, or the slave not on the bus, or a
/// parameter the chip does not take. Other errors pass unchanged.
Response async(Device &dev, const Command &c, const std::string &what, int slave = -1);

/// Rethrows @p e (an ecmxf::Error or subclass, caught as such) with
/// @p prefix before its message, keeping its type and fields.
[[noreturn]] void rethrowWithPrefix(const std::string &prefix);

/// Valid slave position (0..127), or also kAllSlaves when @p allowAll.
void checkSlave(std::uint8_t slave, const char *what, bool allowAll);
/// Valid state for STATE_SET (1, 2, 3, 4, 8).
void checkState(State s, const char *what);

} // namespace ecmxf::bus
