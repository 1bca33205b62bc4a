// SPDX-License-Identifier: MIT
// ecmxf-demo --plot DIR: the directory checked before the tour, and each
// axis's recording of the CSP move written as DIR/axisN.csv and
// DIR/axisN.svg (ecmxf::writeCsv, ecmxf::writeSvg; ecmxf-demo-plot.cpp).
#pragma once

#include <string>
#include <vector>

#include <ecmxf/scope/recorder.hpp>

/// DIR is a directory that can be written, or is made (its parent
/// existing); else throws ecmxf::Error naming DIR and the reason (ENOTDIR,
/// ENOENT, EACCES...). Before anything runs: a tour is not wasted.
void demoPlotDir(const std::string &dir);

struct DemoAxisPlot {
	const ecmxf::Recorder *recorder = nullptr;
	std::string title;
};

/// Writes DIR/axisN.csv and DIR/axisN.svg for each of @p plots (N its
/// index): all or none. Each file goes to a hidden name in DIR first
/// (written whole by the library), and all are renamed to their names
/// once every one is written; a failure removes them and throws, the
/// files of an earlier run left as they were. Returns the files' paths.
std::vector<std::string> writeDemoPlots(const std::string &dir, const std::vector<DemoAxisPlot> &plots);
