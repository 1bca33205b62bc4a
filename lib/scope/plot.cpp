// SPDX-License-Identifier: MIT
// A Recorder's samples as CSV and SVG (include/ecmxf/scope/plot.hpp).

#include <ecmxf/scope/plot.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <vector>

#include <ecmxf/error.hpp>

#include "base/os.hpp"

namespace ecmxf {

namespace {

std::string csvField(const std::string &s)
{
	if (s.find_first_of(",\"\r\n") == std::string::npos)
		return s;
	std::string r = "\"";
	for (const char c : s)
		r += c == '"' ? std::string("\"\"") : std::string(1, c);
	return r + "\"";
}

/// A value as text: integers exactly, others with 17 significant digits.
std::string number(double v)
{
	char buf[40];
	if (std::isnan(v))
		return {};
	if (v == std::trunc(v) && std::fabs(v) < 1e17)
		std::snprintf(buf, sizeof(buf), "%.0f", v);
	else
		std::snprintf(buf, sizeof(buf), "%.17g", v);
	return buf;
}

/// A number for a person: few digits.
std::string shortNumber(double v)
{
	char buf[40];
	std::snprintf(buf, sizeof(buf), "%.6g", v);
	return buf;
}

std::string fixed(double v, int decimals = 3)
{
	char buf[48];
	std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
	return buf;
}

std::string xml(std::string_view s)
{
	std::string r;
	for (const char c : s) {
		switch (c) {
		case '&': r += "&amp;"; break;
		case '<': r += "&lt;"; break;
		case '>': r += "&gt;"; break;
		case '"': r += "&quot;"; break;
		case '\'': r += "&apos;"; break;
		default:
			// XML 1.0 has no other control characters
			if (static_cast<unsigned char>(c) >= 0x20 || c == '\t' || c == '\n')
				r += c;
			else
				r += '?';
		}
	}
	return r;
}

double usOf(std::chrono::nanoseconds t)
{
	return static_cast<double>(t.count()) / 1000.0;
}

/// Ticks of "nice" steps (1, 2, 5 x 10^n) over [lo, hi].
std::vector<double> ticks(double lo, double hi, int want)
{
	std::vector<double> r;
	const double span = hi - lo;
	if (!(span > 0) || !std::isfinite(span))
		return { lo };
	const double raw = span / want;
	const double mag = std::pow(10.0, std::floor(std::log10(raw)));
	double step = mag;
	for (const double m : { 1.0, 2.0, 5.0, 10.0 })
		if (m * mag >= raw) {
			step = m * mag;
			break;
		}
	for (double t = std::ceil(lo / step) * step; t <= hi + step * 1e-9; t += step)
		r.push_back(std::fabs(t) < step * 1e-9 ? 0.0 : t);
	return r;
}

constexpr const char *kColours[] = { "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
				     "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22" };

struct Axis {
	std::string unit;
	double lo = 0, hi = 0;
	bool any = false;
};

} // namespace

std::string csvText(const Recorder &rec)
{
	const auto &sig = rec.signals();
	// the comma appended on its own: "," + std::string&& makes GCC 12's
	// -Wrestrict fail a Release (-O3) build with a false positive
	std::string out = "time_us";
	for (const RecordedSignal &s : sig) {
		out += ',';
		out += csvField(s.unit.empty() ? s.name : s.name + " [" + s.unit + "]");
	}
	out += '\n';
	for (std::size_t i = 0; i < rec.size(); i++) {
		out += fixed(usOf(rec.time(i)));
		for (std::size_t k = 0; k < sig.size(); k++) {
			out += ',';
			out += number(rec.value(i, k));
		}
		out += '\n';
	}
	return out;
}

std::string svgText(const Recorder &rec, const SvgOptions &o)
{
	if (o.width < 400 || o.width > 10000 || o.height < 300 || o.height > 10000)
		throw Error("svg: a plot of " + std::to_string(o.width) + "x" + std::to_string(o.height) +
				    " pixels (400..10000 x 300..10000)",
			    EINVAL);
	const auto &sig = rec.signals();
	const std::size_t n = rec.size();
	// one axis per unit, in the order the units first appear
	std::vector<Axis> axes;
	std::vector<std::size_t> axisOf(sig.size());
	for (std::size_t k = 0; k < sig.size(); k++) {
		std::size_t a = 0;
		while (a < axes.size() && axes[a].unit != sig[k].unit)
			a++;
		if (a == axes.size())
			axes.push_back(Axis{ sig[k].unit });
		axisOf[k] = a;
		for (std::size_t i = 0; i < n; i++) {
			const double v = rec.value(i, k);
			if (std::isnan(v))
				continue;
			Axis &ax = axes[a];
			ax.lo = ax.any ? std::min(ax.lo, v) : v;
			ax.hi = ax.any ? std::max(ax.hi, v) : v;
			ax.any = true;
		}
	}
	for (Axis &ax : axes) {
		if (!ax.any)
			ax.lo = 0, ax.hi = 1;
		if (ax.hi == ax.lo)
			ax.lo -= 1, ax.hi += 1;
		const double pad = (ax.hi - ax.lo) * 0.05;
		ax.lo -= pad;
		ax.hi += pad;
	}
	double tmin = n ? usOf(rec.time(0)) : 0, tmax = n ? usOf(rec.time(n - 1)) : 1;
	if (tmax <= tmin)
		tmax = tmin + 1;
	// the time axis in the unit its span reads best in
	const double span = tmax - tmin;
	const double tdiv = span >= 5e6 ? 1e6 : span >= 5e3 ? 1e3 : 1;
	const char *tunit = tdiv == 1e6 ? "s" : tdiv == 1e3 ? "ms" : "µs";

	const double axisW = 72, legendW = 260;
	const double px = 16 + axisW * static_cast<double>(axes.size());
	const double py = o.title.empty() ? 20 : 40;
	const double pw = std::max(100.0, o.width - px - legendW - 20);
	const double ph = std::max(100.0, o.height - py - 56);
	const auto X = [&](double tus) { return px + (tus - tmin) / (tmax - tmin) * pw; };
	const auto Y = [&](const Axis &a, double v) { return py + ph - (v - a.lo) / (a.hi - a.lo) * ph; };

	std::string s;
	s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
	s += "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" + std::to_string(o.width) +
	     "\" height=\"" + std::to_string(o.height) + "\" viewBox=\"0 0 " + std::to_string(o.width) + " " +
	     std::to_string(o.height) + "\" font-family=\"sans-serif\" font-size=\"11\" data-plot=\"" + fixed(px) +
	     " " + fixed(py) + " " + fixed(pw) + " " + fixed(ph) + "\" data-tmin=\"" + number(tmin) +
	     "\" data-tmax=\"" + number(tmax) + "\">\n";
	s += "<rect x=\"0\" y=\"0\" width=\"" + std::to_string(o.width) + "\" height=\"" + std::to_string(o.height) +
	     "\" fill=\"white\"/>\n";
	if (!o.title.empty())
		s += "<text x=\"" + fixed(px) + "\" y=\"24\" font-size=\"15\" font-weight=\"bold\">" + xml(o.title) +
		     "</text>\n";
	// grid: the time ticks and the first axis's ticks
	s += "<g class=\"grid\" stroke=\"#dddddd\" stroke-width=\"1\">\n";
	const auto tt = ticks(tmin / tdiv, tmax / tdiv, 8);
	for (const double t : tt)
		s += "<line x1=\"" + fixed(X(t * tdiv)) + "\" y1=\"" + fixed(py) + "\" x2=\"" + fixed(X(t * tdiv)) +
		     "\" y2=\"" + fixed(py + ph) + "\"/>\n";
	if (!axes.empty())
		for (const double v : ticks(axes[0].lo, axes[0].hi, 6))
			s += "<line x1=\"" + fixed(px) + "\" y1=\"" + fixed(Y(axes[0], v)) + "\" x2=\"" + fixed(px + pw) +
			     "\" y2=\"" + fixed(Y(axes[0], v)) + "\"/>\n";
	s += "</g>\n";
	s += "<rect class=\"frame\" x=\"" + fixed(px) + "\" y=\"" + fixed(py) + "\" width=\"" + fixed(pw) +
	     "\" height=\"" + fixed(ph) + "\" fill=\"none\" stroke=\"black\"/>\n";
	// the time axis
	s += "<g class=\"time-axis\">\n";
	for (const double t : tt) {
		const double x = X(t * tdiv);
		s += "<line x1=\"" + fixed(x) + "\" y1=\"" + fixed(py + ph) + "\" x2=\"" + fixed(x) + "\" y2=\"" +
		     fixed(py + ph + 5) + "\" stroke=\"black\"/>";
		s += "<text x=\"" + fixed(x) + "\" y=\"" + fixed(py + ph + 18) + "\" text-anchor=\"middle\">" +
		     shortNumber(t) + "</text>\n";
	}
	s += "<text x=\"" + fixed(px + pw / 2) + "\" y=\"" + fixed(py + ph + 38) +
	     "\" text-anchor=\"middle\">time (" + tunit + (rec.triggered() ? ", 0 = trigger" : "") + ")</text>\n";
	s += "</g>\n";
	// the y-axes, one per unit, left of the plot
	for (std::size_t a = 0; a < axes.size(); a++) {
		const Axis &ax = axes[a];
		const double x = px - axisW * static_cast<double>(a);
		s += "<g class=\"y-axis\" data-unit=\"" + xml(ax.unit) + "\">\n";
		s += "<line x1=\"" + fixed(x) + "\" y1=\"" + fixed(py) + "\" x2=\"" + fixed(x) + "\" y2=\"" +
		     fixed(py + ph) + "\" stroke=\"black\"/>\n";
		for (const double v : ticks(ax.lo, ax.hi, 6)) {
			const double y = Y(ax, v);
			s += "<line x1=\"" + fixed(x - 4) + "\" y1=\"" + fixed(y) + "\" x2=\"" + fixed(x) + "\" y2=\"" +
			     fixed(y) + "\" stroke=\"black\"/>";
			s += "<text x=\"" + fixed(x - 6) + "\" y=\"" + fixed(y + 4) + "\" text-anchor=\"end\">" +
			     shortNumber(v) + "</text>\n";
		}
		s += "<text transform=\"translate(" + fixed(x - axisW + 12) + "," + fixed(py + ph / 2) +
		     ") rotate(-90)\" text-anchor=\"middle\">" + xml(ax.unit.empty() ? "(no unit)" : ax.unit) +
		     "</text>\n";
		s += "</g>\n";
	}
	// the traces, their minimum and maximum, the legend
	std::string legend;
	for (std::size_t k = 0; k < sig.size(); k++) {
		const Axis &ax = axes[axisOf[k]];
		const char *colour = kColours[k % std::size(kColours)];
		s += "<polyline class=\"trace\" data-signal=\"" + xml(sig[k].name) + "\" data-unit=\"" + xml(sig[k].unit) +
		     "\" data-vmin=\"" + number(ax.lo) + "\" data-vmax=\"" + number(ax.hi) + "\" fill=\"none\" stroke=\"" +
		     colour + "\" stroke-width=\"1.5\" points=\"";
		std::size_t lo = n, hi = n;
		for (std::size_t i = 0; i < n; i++) {
			const double v = rec.value(i, k);
			if (std::isnan(v))
				continue;
			if (lo == n || v < rec.value(lo, k))
				lo = i;
			if (hi == n || v > rec.value(hi, k))
				hi = i;
			s += fixed(X(usOf(rec.time(i)))) + "," + fixed(Y(ax, v)) + " ";
		}
		if (s.back() == ' ')
			s.pop_back();
		s += "\"/>\n";
		std::string range = "no samples";
		if (lo != n) {
			const std::string unit = sig[k].unit.empty() ? "" : " " + sig[k].unit;
			range = "min " + shortNumber(rec.value(lo, k)) + ", max " + shortNumber(rec.value(hi, k)) + unit;
			for (const auto &[i, what] : { std::pair{ lo, "min" }, std::pair{ hi, "max" } }) {
				const double x = X(usOf(rec.time(i))), y = Y(ax, rec.value(i, k));
				s += "<g class=\"" + std::string(what) + "\" data-signal=\"" + xml(sig[k].name) + "\">";
				s += "<circle cx=\"" + fixed(x) + "\" cy=\"" + fixed(y) + "\" r=\"3\" fill=\"" + colour + "\"/>";
				s += "<text x=\"" + fixed(std::min(x + 5, px + pw - 60)) + "\" y=\"" +
				     fixed(what[1] == 'a' ? std::max(y - 5, py + 10) : std::min(y + 13, py + ph - 3)) +
				     "\" fill=\"" + colour + "\">" + what + " " + xml(shortNumber(rec.value(i, k)) + unit) +
				     "</text></g>\n";
			}
		}
		const double ly = py + 8 + 34 * static_cast<double>(k);
		const double lx = px + pw + 16;
		legend += "<line x1=\"" + fixed(lx) + "\" y1=\"" + fixed(ly) + "\" x2=\"" + fixed(lx + 22) + "\" y2=\"" +
			  fixed(ly) + "\" stroke=\"" + colour + "\" stroke-width=\"3\"/>";
		legend += "<text x=\"" + fixed(lx + 28) + "\" y=\"" + fixed(ly + 4) + "\">" +
			  xml(sig[k].label + (sig[k].unit.empty() ? "" : " [" + sig[k].unit + "]")) + "</text>";
		legend += "<text x=\"" + fixed(lx + 28) + "\" y=\"" + fixed(ly + 18) + "\" fill=\"#555555\">" +
			  xml(range) + "</text>\n";
	}
	s += "<g class=\"legend\">\n" + legend + "</g>\n";
	s += "</svg>\n";
	return s;
}

void writeCsv(const Recorder &rec, const std::string &path)
{
	detail::writeFileWhole(path, csvText(rec));
}

void writeSvg(const Recorder &rec, const std::string &path, const SvgOptions &options)
{
	detail::writeFileWhole(path, svgText(rec, options));
}

} // namespace ecmxf
