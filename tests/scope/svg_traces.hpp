// SPDX-License-Identifier: MIT
// The traces of an ecmxf::svgText() plot turned back into values: each
// <polyline class="trace">'s points through its scale (data-vmin/vmax on
// the trace, data-plot and data-tmin/tmax on the <svg>, plot.hpp). Used
// by tests/scope (the writer) and tests/scope_cli (the programs' files).
#pragma once

#include <catch2/catch.hpp>

#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace scopetest {

/// The value of attribute @p name in the tag text @p tag (REQUIREd).
inline std::string svgAttr(const std::string &tag, const std::string &name)
{
	const auto at = tag.find(" " + name + "=\"");
	REQUIRE(at != std::string::npos);
	const auto from = at + name.size() + 3;
	return tag.substr(from, tag.find('"', from) - from);
}

struct SvgTrace {
	std::string signal, unit;
	std::vector<std::pair<double, double>> points; ///< (time in us, value), as drawn
	double timeTolerance = 0;                      ///< the points' 3 decimals of a pixel, in us
	double valueTolerance = 0;                     ///< the same in the trace's unit
};

/// Every trace of @p svg, in the order drawn (the recorder's signals').
inline std::vector<SvgTrace> svgTraces(const std::string &svg)
{
	const auto open = svg.find("<svg ");
	REQUIRE(open != std::string::npos);
	const std::string root = svg.substr(open, svg.find('>', open) - open);
	std::istringstream plot(svgAttr(root, "data-plot"));
	double px = 0, py = 0, pw = 0, ph = 0;
	plot >> px >> py >> pw >> ph;
	REQUIRE(pw > 0);
	REQUIRE(ph > 0);
	const double tmin = std::stod(svgAttr(root, "data-tmin")), tmax = std::stod(svgAttr(root, "data-tmax"));
	std::vector<SvgTrace> traces;
	for (auto at = svg.find("<polyline class=\"trace\""); at != std::string::npos;
	     at = svg.find("<polyline class=\"trace\"", at + 1)) {
		const std::string tag = svg.substr(at, svg.find("/>", at) - at);
		SvgTrace tr;
		tr.signal = svgAttr(tag, "data-signal");
		tr.unit = svgAttr(tag, "data-unit");
		const double vmin = std::stod(svgAttr(tag, "data-vmin")), vmax = std::stod(svgAttr(tag, "data-vmax"));
		tr.timeTolerance = (tmax - tmin) / pw * 0.001;
		tr.valueTolerance = (vmax - vmin) / ph * 0.001;
		std::istringstream pts(svgAttr(tag, "points"));
		for (std::string xy; pts >> xy;) {
			const auto comma = xy.find(',');
			const double x = std::stod(xy.substr(0, comma)), y = std::stod(xy.substr(comma + 1));
			tr.points.emplace_back(tmin + (x - px) / pw * (tmax - tmin), vmin + (py + ph - y) / ph * (vmax - vmin));
		}
		traces.push_back(std::move(tr));
	}
	return traces;
}

} // namespace scopetest
