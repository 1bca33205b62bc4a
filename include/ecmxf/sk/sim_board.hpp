// SPDX-License-Identifier: MIT
/**
 * @file sim_board.hpp
 * @brief Moved to <ecmxf/sim/sk_board.hpp> (the simulators,
 *        Documentation/architecture.rst); this header forwards there for
 *        one release (Documentation/library.rst, "API changes").
 */
#pragma once

#include <ecmxf/sim/sk_board.hpp>
