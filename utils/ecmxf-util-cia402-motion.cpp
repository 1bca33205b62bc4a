// SPDX-License-Identifier: MIT
/*
 * ecmxf-util cia402 move / home - the dispatch point of the motion
 * commands. Not implemented yet: another unit replaces this file.
 */
#include "ecmxf-util.hpp"

namespace ecmxf_util {

int cia402Motion(Globals &, const Args &)
{
	throw UsageError("cia402 move/home: not implemented");
}

} // namespace ecmxf_util
