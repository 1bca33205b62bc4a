// SPDX-License-Identifier: MIT
/**
 * @file types_cia402.hpp
 * @brief Moved to <ecmxf/model/types_cia402.hpp> (the shared vocabulary of both masters,
 *        Documentation/architecture.rst); this header forwards there for
 *        one release (Documentation/library.rst, "API changes").
 */
#pragma once

#include <ecmxf/model/types_cia402.hpp>
