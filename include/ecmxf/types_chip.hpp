// SPDX-License-Identifier: MIT
/**
 * @file types_chip.hpp
 * @brief Value types of the typed commands for the chip, its link and peripherals, EEPROM, FoE, raw datagrams, MDIO, mailbox.
 */
#pragma once

#include <cstdint>

namespace ecmxf {

} // namespace ecmxf
