// SPDX-License-Identifier: MIT
/*
 * ecmxf-util cia402 move / home (ecmxf-util-cia402-motion.cpp).
 */
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include <ecmxf/bus/master.hpp>
#include <ecmxf/scope/recorder.hpp>

#include "ecmxf-util.hpp"

namespace ecmxf_util {

/// cia402 move / home: @p args are all of cia402's arguments
/// ("-p", "1", "move", "--pp", "1000"...). Output to stdout.
int cia402Motion(Globals &g, const Args &args);
/// The same, writing to @p out (tests).
int cia402Motion(Globals &g, const Args &args, std::ostream &out);

extern const char *const kCia402MotionHelp;

/// --plot FILE.svg and --csv FILE.csv of a command that records (cia402
/// move, on both masters): taken out of @p args ("--plot F" or
/// "--plot=F"); --csv without --plot, a value missing or empty, an option
/// twice: UsageError.
struct PlotFiles {
	std::optional<std::string> svg, csv;
	[[nodiscard]] bool any() const noexcept { return svg || csv; }
};
PlotFiles takePlotFiles(std::string_view cmd, Args &args);
/// Writes the files asked for (CSV first), each whole or not at all;
/// throws ecmxf::Error naming the file.
void writePlotFiles(const ecmxf::Recorder &rec, const PlotFiles &files, const std::string &title);

/// The bus to OP as cia402 move wants it: SYNC0 1 ms, every EST-584 with
/// the motion PDOs (est584MotionPdos()).
void bringUpMotion(ecmxf::Master &m);

} // namespace ecmxf_util
