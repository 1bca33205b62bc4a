// SPDX-License-Identifier: MIT
/**
 * @file pdo_mapping.hpp
 * @brief Moved to <ecmxf/model/pdo_mapping.hpp> (the shared vocabulary of both masters,
 *        Documentation/architecture.rst); this header forwards there for
 *        one release (Documentation/library.rst, "API changes").
 */
#pragma once

#include <ecmxf/model/pdo_mapping.hpp>
