// SPDX-License-Identifier: MIT
/**
 * @file plot.hpp
 * @brief A Recorder's samples as CSV and as an SVG plot, made by the
 *        library itself (no plotting library).
 *
 * CSV: a header row `time_us,SIGNAL [UNIT],...` (the signal's text as
 * added; no brackets without a unit), then one row per sample: the time in
 * µs relative to the trigger (3 decimals: ns), then each signal's value
 * (integers exactly; an empty cell for a figure not sampled). A field with
 * a comma or a quote is quoted (RFC 4180).
 *
 * SVG: a time axis, one y-axis per unit (each signal drawn on its unit's
 * axis, scaled to that unit's minimum and maximum), a grid, a legend with
 * each signal's label and unit, and the minimum and maximum of each signal
 * marked and written. Each trace is a <polyline class="trace"> carrying
 * its scale (data-signal, data-unit, data-vmin, data-vmax; the plot area
 * and time range on the <svg>: data-plot="x y width height", data-tmin,
 * data-tmax in µs), so a reader can take the values back from the points.
 *
 * writeCsv() / writeSvg() write the file whole or not at all (a temporary
 * file renamed over it); a failure throws ecmxf::Error naming the file and
 * the reason (EACCES, ENOSPC...).
 */
#pragma once

#include <string>

#include <ecmxf/export.hpp>
#include <ecmxf/scope/recorder.hpp>

namespace ecmxf {

struct SvgOptions {
	unsigned width = 1000;  ///< pixels (400..10000)
	unsigned height = 560;  ///< pixels (300..10000)
	std::string title;      ///< above the plot; empty: none
};

[[nodiscard]] ECMXF_EXPORT std::string csvText(const Recorder &recorder);
[[nodiscard]] ECMXF_EXPORT std::string svgText(const Recorder &recorder, const SvgOptions &options = {});
ECMXF_EXPORT void writeCsv(const Recorder &recorder, const std::string &path);
ECMXF_EXPORT void writeSvg(const Recorder &recorder, const std::string &path, const SvgOptions &options = {});

} // namespace ecmxf
