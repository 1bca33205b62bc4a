// SPDX-License-Identifier: MIT
/**
 * @file export.hpp
 * @brief Symbol visibility of libecmxf: the library is built with hidden
 *        visibility, and everything public is marked ECMXF_EXPORT.
 */
#pragma once

#define ECMXF_EXPORT __attribute__((visibility("default")))
