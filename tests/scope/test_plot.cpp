// SPDX-License-Identifier: MIT
// The scope's writers (include/ecmxf/scope/plot.hpp): the CSV read back
// gives the recorded values, the SVG's points turned back through their
// scale give the recorded values, the SVG passes xmllint and renders
// (check-svg.sh), and a file that cannot be written is an error naming it,
// with nothing half-written left.

#include <catch2/catch.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <ecmxf/scope/plot.hpp>
#include <ecmxf/scope/recorder.hpp>

#include "../common/thrown.hpp"
#include "svg_traces.hpp"

using namespace std::chrono_literals;
using ecmxftest::thrown;
using scopetest::svgAttr;

namespace {

/// Three signals, two units; a sine, a ramp and a step, pre-trigger
/// samples included (negative times).
struct Recorded {
	std::int64_t a = 0, b = 0, c = 0;
	ecmxf::Recorder rec{ 400 };
	Recorded()
	{
		rec.addValue("0:target", "inc", &a);
		rec.addValue("0:actual", "inc", &b);
		rec.addValue("1:word, \"quoted\"", "", &c, false);
		ecmxf::RecorderTrigger t;
		t.edge = ecmxf::TriggerEdge::Rising;
		t.signal = "0:target";
		t.level = 1;
		t.preSamples = 20;
		rec.arm(t);
		for (int i = 0; !rec.done(); i++) {
			a = i < 50 ? 0 : static_cast<std::int64_t>(100000 * std::sin((i - 50) / 40.0)) + 1;
			b = a / 2 - 7 * i;
			c = (i / 30) % 2 ? 0x1237 : 0x0031;
			rec.sample(std::chrono::microseconds(1000 * i + 3));
		}
	}
};

std::vector<std::string> split(const std::string &line)
{
	// RFC 4180: quotes around a field, "" inside for one quote
	std::vector<std::string> r;
	std::string f;
	bool q = false;
	for (std::size_t i = 0; i < line.size(); i++) {
		const char ch = line[i];
		if (q) {
			if (ch == '"' && i + 1 < line.size() && line[i + 1] == '"')
				f += '"', i++;
			else if (ch == '"')
				q = false;
			else
				f += ch;
		} else if (ch == '"') {
			q = true;
		} else if (ch == ',') {
			r.push_back(f);
			f.clear();
		} else {
			f += ch;
		}
	}
	r.push_back(f);
	return r;
}

std::string tmpDir()
{
	const auto d = std::filesystem::temp_directory_path() / ("ecmxf-scope-" + std::to_string(::getpid()));
	std::filesystem::create_directories(d);
	return d.string();
}

} // namespace

TEST_CASE("scope csv: the header names each signal with its unit and the values read back exactly")
{
	Recorded r;
	REQUIRE(r.rec.size() == 400);
	std::istringstream in(ecmxf::csvText(r.rec));
	std::string line;
	REQUIRE(std::getline(in, line));
	const auto head = split(line);
	REQUIRE(head.size() == 4);
	CHECK(head[0] == "time_us");
	CHECK(head[1] == "0:target [inc]");
	CHECK(head[2] == "0:actual [inc]");
	CHECK(head[3] == "1:word, \"quoted\"");
	std::size_t i = 0;
	while (std::getline(in, line)) {
		const auto f = split(line);
		REQUIRE(f.size() == 4);
		REQUIRE(i < r.rec.size());
		CHECK(std::stod(f[0]) * 1000 == static_cast<double>(r.rec.time(i).count()));
		for (std::size_t k = 0; k < 3; k++)
			CHECK(std::stod(f[k + 1]) == r.rec.value(i, k));
		i++;
	}
	CHECK(i == r.rec.size());
	CHECK(r.rec.time(0) == -20ms); // 20 pre-trigger samples
}

TEST_CASE("scope svg: each trace's points are the recorded values on its unit's axis")
{
	Recorded r;
	const std::string svg = ecmxf::svgText(r.rec, { 1000, 560, "a <test> & more" });
	CHECK(svg.find("a &lt;test&gt; &amp; more") != std::string::npos);
	const std::string root = svg.substr(svg.find("<svg "), svg.find('>', svg.find("<svg ")) - svg.find("<svg "));
	CHECK(std::stod(svgAttr(root, "data-tmin")) == -20000);
	CHECK(std::stod(svgAttr(root, "data-tmax")) == 379000);
	// two y-axes: inc and none
	CHECK(std::count(svg.begin(), svg.end(), '\n') > 10);
	std::size_t axes = 0;
	for (auto at = svg.find("class=\"y-axis\""); at != std::string::npos; at = svg.find("class=\"y-axis\"", at + 1))
		axes++;
	CHECK(axes == 2);
	const auto traces = scopetest::svgTraces(svg);
	REQUIRE(traces.size() == 3);
	for (std::size_t k = 0; k < traces.size(); k++) {
		const auto &tr = traces[k];
		REQUIRE(tr.points.size() == r.rec.size());
		for (std::size_t i = 0; i < tr.points.size(); i++) {
			// the points have 3 decimals of a pixel
			CHECK(std::fabs(tr.points[i].first - static_cast<double>(r.rec.time(i).count()) / 1000) <=
			      tr.timeTolerance);
			CHECK(std::fabs(tr.points[i].second - r.rec.value(i, k)) <= tr.valueTolerance);
		}
	}
	// the minimum and maximum of each signal, marked and written
	CHECK(svg.find("<g class=\"max\" data-signal=\"0:target\">") != std::string::npos);
	double top = r.rec.value(0, 0);
	for (std::size_t i = 0; i < r.rec.size(); i++)
		top = std::max(top, r.rec.value(i, 0));
	char text[64];
	std::snprintf(text, sizeof(text), ">max %.6g inc</text>", top);
	CHECK(svg.find(text) != std::string::npos);
	CHECK(svg.find("1:word, &quot;quoted&quot;") != std::string::npos);
	CHECK(svg.find("time (ms, 0 = trigger)") != std::string::npos);
	CHECK(thrown([&] { (void)ecmxf::svgText(r.rec, { 10, 560, "" }); }).errnoValue() == EINVAL);
}

TEST_CASE("scope svg: valid XML that renders (xmllint, rsvg-convert)")
{
	Recorded r;
	const std::string dir = tmpDir();
	const std::string file = dir + "/plot.svg";
	ecmxf::writeSvg(r.rec, file);
	const std::string cmd = std::string("sh ") + ECMXF_TEST_CHECK_SVG + " " + file + " 3";
	CHECK(std::system(cmd.c_str()) == 0);
	// a picture without a single trace drawn fails the same check
	ecmxf::Recorder none(4);
	std::int64_t z = 0;
	none.addValue("z", "", &z);
	none.arm();
	std::ofstream(dir + "/blank.svg") << "<?xml version=\"1.0\"?><svg xmlns=\"http://www.w3.org/2000/svg\" "
					     "width=\"400\" height=\"300\"><rect width=\"400\" height=\"300\" "
					     "fill=\"white\"/></svg>\n";
	const std::string blank = std::string("sh ") + ECMXF_TEST_CHECK_SVG + " " + dir + "/blank.svg 1 2>/dev/null";
	CHECK(std::system(blank.c_str()) != 0);
	std::ofstream(dir + "/broken.svg") << "<svg><g></svg>\n";
	const std::string broken = std::string("sh ") + ECMXF_TEST_CHECK_SVG + " " + dir + "/broken.svg 1 2>/dev/null";
	CHECK(std::system(broken.c_str()) != 0);
	std::filesystem::remove_all(dir);
}

TEST_CASE("scope files: unwritable paths and a full disk are errors naming the file, nothing half-written")
{
	Recorded r;
	const std::string dir = tmpDir();
	// the old file stays whole when the new one cannot be written
	const std::string file = dir + "/keep.csv";
	std::ofstream(file) << "old\n";
	auto e = thrown([&] { ecmxf::writeCsv(r.rec, dir + "/no/such/dir.csv"); });
	CHECK(e.errnoValue() == ENOENT);
	CHECK(std::string(e.what()).find("writing " + dir + "/no/such/dir.csv: ") != std::string::npos);
	e = thrown([] {
		std::int64_t v = 0;
		ecmxf::Recorder x(2);
		x.addValue("v", "", &v);
		x.arm();
		x.sample(0ns);
		ecmxf::writeSvg(x, "/dev/full");
	});
	CHECK(e.errnoValue() == ENOSPC);
	CHECK(std::string(e.what()) == "writing /dev/full: " + std::string(std::strerror(ENOSPC)));
	// a folder that cannot be written (root writes anywhere: a file in
	// place of the folder stands for it)
	std::ofstream(dir + "/notadir") << "x";
	e = thrown([&] { ecmxf::writeCsv(r.rec, dir + "/notadir/plot.csv"); });
	CHECK(e.errnoValue() == ENOTDIR);
	ecmxf::writeCsv(r.rec, file);
	std::ifstream in(file);
	std::string first;
	std::getline(in, first);
	CHECK(first == "time_us,0:target [inc],0:actual [inc],\"1:word, \"\"quoted\"\"\"");
	// no temporary file left beside it
	std::size_t files = 0;
	for (const auto &f : std::filesystem::directory_iterator(dir))
		files += f.path().filename().string().rfind("keep.csv", 0) == 0;
	CHECK(files == 1);
	std::filesystem::remove_all(dir);
}
