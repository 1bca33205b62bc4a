// SPDX-License-Identifier: MIT
/*
 * ecmxf-util cia402 move / home (ecmxf-util-cia402-motion.cpp).
 */
#pragma once

#include <ostream>

#include "ecmxf-util.hpp"

namespace ecmxf_util {

/// cia402 move / home: @p args are all of cia402's arguments
/// ("-p", "1", "move", "--pp", "1000"...). Output to stdout.
int cia402Motion(Globals &g, const Args &args);
/// The same, writing to @p out (tests).
int cia402Motion(Globals &g, const Args &args, std::ostream &out);

extern const char *const kCia402MotionHelp;

} // namespace ecmxf_util
