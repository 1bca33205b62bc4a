// SPDX-License-Identifier: MIT
/**
 * @file types_chip.hpp
 * @brief Moved to <ecmxf/model/types_chip.hpp> (the shared vocabulary of both masters,
 *        Documentation/architecture.rst); this header forwards there for
 *        one release (Documentation/library.rst, "API changes").
 */
#pragma once

#include <ecmxf/model/types_chip.hpp>
