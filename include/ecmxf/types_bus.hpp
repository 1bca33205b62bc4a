// SPDX-License-Identifier: MIT
/**
 * @file types_bus.hpp
 * @brief Value types of the typed commands for bus bring-up, EtherCAT states, slaves, PDO, FIFO and SDO.
 */
#pragma once

#include <cstdint>

namespace ecmxf {

} // namespace ecmxf
