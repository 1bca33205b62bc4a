// SPDX-License-Identifier: MIT
/**
 * @file export.hpp
 * @brief Symbol visibility of libecmxf: the library is built with hidden
 *        visibility, and everything public is marked ECMXF_EXPORT.
 */
#pragma once

/*
 * Every public header includes this one before any declaration of its own:
 * a consumer compiling below C++20 gets this one message instead of a
 * cascade from <span>, concepts and designated initialisers.  CMake
 * consumers get -std=c++20 from the imported target (cxx_std_20),
 * pkg-config ones from ecmxf.pc's Cflags.
 * #error does not stop the compiler; the include of a header that does not
 * exist does (a fatal error), so nothing follows the message.
 */
#if !defined(__cplusplus) || __cplusplus < 202002L
#error "libecmxf needs C++20 (-std=c++20, or CMake's cxx_std_20 that ecmxf::ecmxf carries): this translation unit is compiled below C++20"
#include <ecmxf/stop-here-libecmxf-needs-cxx20>
#else

#define ECMXF_EXPORT __attribute__((visibility("default")))

#endif /* C++20 */
