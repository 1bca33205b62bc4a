// SPDX-License-Identifier: MIT
/**
 * @file types_pdo.hpp
 * @brief Value types of the process-data, FIFO and cyclic-exchange calls.
 */
#pragma once

#include <cstdint>

namespace ecmxf {

} // namespace ecmxf
