// SPDX-License-Identifier: MIT
/**
 * @file types_cia402.hpp
 * @brief Value types of the typed commands for the chip's CiA-402 engine and the CiA-402 state codes.
 */
#pragma once

#include <cstdint>

namespace ecmxf {

} // namespace ecmxf
