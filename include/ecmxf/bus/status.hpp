// SPDX-License-Identifier: MIT
/**
 * @file status.hpp
 * @brief Moved to <ecmxf/model/status.hpp> (the shared vocabulary of both masters,
 *        Documentation/architecture.rst); this header forwards there for
 *        one release (Documentation/library.rst, "API changes").
 */
#pragma once

#include <ecmxf/model/status.hpp>
