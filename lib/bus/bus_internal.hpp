// SPDX-License-Identifier: MIT
// Helpers shared by the bus layer (lib/bus/bus.cpp, sdo.cpp, slave_access.cpp,
// master.cpp), implemented in lib/bus/bus_helpers.cpp and, for the SDO
// abort, lib/bus/sdo.cpp. The command runner and the byte helpers are
// lib/device/runner.hpp. Not installed.
#pragma once

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/model/types_bus.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "device/runner.hpp"

namespace ecmxf {

class Bus;

namespace bus {

using detail::cmd;
using detail::hex;
using detail::le16;
using detail::le32;
using detail::put16;
using detail::put32;
using detail::rethrowWithPrefix;

/// "0x6064:00".
std::string objName(std::uint16_t index, std::uint8_t sub);
/// "slave 5", or "all slaves" for kAllSlaves.
std::string slaveLabel(std::uint8_t slave);

/// Valid slave position (0..127), or also kAllSlaves when @p allowAll.
void checkSlave(std::uint8_t slave, const char *what, bool allowAll);
/// Valid state for STATE_SET (1, 2, 3, 4, 8).
void checkState(State s, const char *what);

/// The one SDO-abort map: after an async command that moves an object
/// (ECAT_SDO_REQ, ECAT_PDO_CONFIG_SET/REQ) failed with @p e, rethrows
/// @p e unless it is a failure on the bus (EREMOTEIO); that becomes an
/// SdoError "@p what aborted: 0x06020000 Object not existing" with the
/// abort code ECAT_SDO_ABORTCODE_GET reads (lib/bus/sdo.cpp).
[[noreturn]] void throwSdoAbort(const Bus &bus, const std::string &what, const Error &e);

} // namespace bus
} // namespace ecmxf
