// SPDX-License-Identifier: MIT
// ecmxf-util scope and cia402 move --plot, run as programs: the files they
// write read back (CSV) and checked (SVG: xmllint, rsvg-convert), on sim:,
// unix: and sk-sim:; bad signals, triggers and output files give a clear
// error, a non-zero exit and no file. Also ecmxf-demo --plot DIR (both
// boards): the CSV read back, the SVG checked and its points read back
// equal to the CSV's values, a bad DIR refused.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli/cli_run.hpp"
#include "common/sim_server.hpp"
#include "scope/svg_traces.hpp"

using Catch::Matchers::Contains;
using clitest::run;
using ecmxftest::TempDir;

namespace {

/// The CSV's rows, each split at ',' (the signals here have no commas).
std::vector<std::vector<std::string>> csv(const std::string &file)
{
	std::ifstream in(file);
	REQUIRE(in.good());
	std::vector<std::vector<std::string>> rows;
	std::string line;
	while (std::getline(in, line)) {
		std::vector<std::string> f;
		std::stringstream ss(line);
		std::string cell;
		while (std::getline(ss, cell, ','))
			f.push_back(cell);
		if (!line.empty() && line.back() == ',')
			f.emplace_back();
		rows.push_back(f);
	}
	return rows;
}

bool svgOk(const std::string &file, int colours)
{
	const std::string cmd = std::string("sh ") + ECMXF_TEST_CHECK_SVG + " " + file + " " + std::to_string(colours) +
				" >/dev/null";
	return std::system(cmd.c_str()) == 0;
}

std::size_t column(const std::vector<std::string> &head, const std::string &name)
{
	for (std::size_t i = 0; i < head.size(); i++)
		if (head[i] == name)
			return i;
	FAIL("no column '" << name << "'");
	return 0;
}

} // namespace

TEST_CASE("scope cli: sim: process data and cycle figures as CSV and SVG")
{
	TempDir d;
	const auto r = run("-d sim: scope 0:position_actual_value 1:0x6064:0 0:statusword wkc rx_fifo --cycles 100 --csv " +
			   d.path + "/s.csv --svg " + d.path + "/s.svg");
	INFO(r.err);
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("100 samples\n"));
	CHECK_THAT(r.out, Contains("slave 0 Position actual value"));
	const auto rows = csv(d.path + "/s.csv");
	REQUIRE(rows.size() == 101);
	CHECK(rows[0] == std::vector<std::string>{ "time_us", "0:position_actual_value [inc]", "1:0x6064:0 [inc]",
						   "0:statusword", "wkc", "rx_fifo [frames]" });
	// 1 ms cycles on the simulator's clock, the working counter the bus's
	CHECK(rows[1][0] == "0.000");
	for (std::size_t i = 2; i < rows.size(); i++)
		CHECK(std::stod(rows[i][0]) > std::stod(rows[i - 1][0]));
	CHECK(std::stod(rows[100][0]) > 90000.0);
	const auto wkc = column(rows[0], "wkc");
	CHECK(std::stoi(rows[100][wkc]) > 0);
	CHECK(svgOk(d.path + "/s.svg", 3));

	// --json: the summary as an object
	const auto j = run("-d sim: scope wkc --cycles 5 --json");
	REQUIRE(j.status == 0);
	CHECK_THAT(j.out, Contains("{\"samples\": 5, \"triggered\": true, \"signals\": [{\"signal\": \"wkc\""));
}

TEST_CASE("scope cli: unix: an ecmxf-sim server's bus")
{
	TempDir d;
	const std::string sock = d.path + "/sim.sock";
	ecmxftest::SimServer server(sock);
	const auto r = run("-d unix:" + sock + " scope 0:0x6041:0 tx_fifo --time 50 --csv " + d.path + "/u.csv");
	INFO(r.err);
	REQUIRE(r.status == 0);
	const auto rows = csv(d.path + "/u.csv");
	REQUIRE(rows.size() >= 2);
	CHECK(rows[0] == std::vector<std::string>{ "time_us", "0:0x6041:0", "tx_fifo [frames]" });
	CHECK(std::stod(rows.back()[0]) >= 50000.0);
}

TEST_CASE("scope cli: sk-sim: the feedback slots and FIFO figures")
{
	TempDir d;
	const auto r = run("-d sk-sim: scope 0:position 0:statusword fifo_remaining --cycles 30 --csv " + d.path +
			   "/k.csv --svg " + d.path + "/k.svg");
	INFO(r.err);
	REQUIRE(r.status == 0);
	const auto rows = csv(d.path + "/k.csv");
	REQUIRE(rows.size() == 31);
	CHECK(rows[0] == std::vector<std::string>{ "time_us", "0:position [inc]", "0:statusword",
						   "fifo_remaining [entries]" });
	CHECK(svgOk(d.path + "/k.svg", 2));
	const auto bad = run("-d sk-sim: scope 0:position wkc");
	CHECK(bad.status == 1);
	CHECK_THAT(bad.err, Contains("scope signal \"wkc\": no such ECM-SK cycle figure"));
}

TEST_CASE("scope cli: bad signals, triggers and options are refused naming what is wrong")
{
	TempDir d;
	auto r = run("-d sim: scope 0:no_such_entry --svg " + d.path + "/x.svg");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("scope: scope signal \"0:no_such_entry\": slave 0 has no mapped entry \"no_such_entry\" "
				   "(mapped: 0x6041:0x00 Statusword"));
	r = run("-d sim: scope 9:statusword");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("slave 9 does not exist: the bus has 3 slaves (0..2)"));
	r = run("-d sim: scope 0:statusword --trigger '0:statusword>5'");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("\"0:statusword\" (slave 0 Statusword) is a word of bits or a code, not a number"));
	r = run("-d sim: scope wkc --trigger 'wkc>1000' --timeout 30 --csv " + d.path + "/t.csv");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("the trigger wkc>1000 did not come within 30 ms (--timeout): nothing written"));
	CHECK_FALSE(std::filesystem::exists(d.path + "/t.csv"));
	r = run("-d sim: scope wkc --trigger 'wkc~3'");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("--trigger 'wkc~3': SIGNAL>LEVEL (rising) or SIGNAL<LEVEL (falling)"));
	r = run("-d sim: scope wkc --trigger 'wkc>x'");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("'x' is not a real number"));
	r = run("-d sim: scope wkc --cycles 0");
	CHECK(r.status == 2);
	r = run("-d sim: scope wkc --cycles 5 --time 5");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("--cycles or --time, not both"));
	r = run("-d sim: scope wkc --pre 3");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("--pre is for --trigger"));
	r = run("-d sim: scope");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("scope: which signals?"));
	r = run("-d sim: scope wkc --trigger 'wkc>1' --pre 20 --buffer 10");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("20 pre-trigger samples do not fit a buffer of 10"));
}

TEST_CASE("scope cli: an unwritable file and a full disk fail, naming the file, nothing half-written")
{
	TempDir d;
	auto r = run("-d sim: scope wkc --cycles 5 --svg " + d.path + "/no/dir/x.svg");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("scope: writing " + d.path + "/no/dir/x.svg: No such file or directory"));
	r = run("-d sim: scope wkc --cycles 5 --csv /dev/full");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("scope: writing /dev/full: No space left on device"));
	// the CSV goes first: a failed SVG after it leaves the CSV whole, the SVG absent
	std::ofstream(d.path + "/dir") << "a file where a folder should be";
	r = run("-d sim: scope wkc --cycles 5 --csv " + d.path + "/ok.csv --svg " + d.path + "/dir/x.svg");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("writing " + d.path + "/dir/x.svg: Not a directory"));
	CHECK(csv(d.path + "/ok.csv").size() == 6);
	std::size_t entries = 0;
	for (const auto &e : std::filesystem::directory_iterator(d.path))
		entries += e.path().filename().string().find(".XXX") == std::string::npos;
	CHECK(entries == 2); // dir, ok.csv: no temporary file left
}

TEST_CASE("scope cli: cia402 move --plot on the ECM-XF records the move")
{
	TempDir d;
	const auto r = run("-d sim: cia402 -p 0 move --csp 20000 --time 200 --plot " + d.path + "/m.svg --csv " +
			   d.path + "/m.csv");
	INFO(r.err);
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("slave 0: CSP move from 0 to 20000: position 20000"));
	const auto rows = csv(d.path + "/m.csv");
	REQUIRE(rows.size() > 200);
	const auto &h = rows[0];
	const auto target = column(h, "0:0x607A:0 [inc]"), actual = column(h, "0:0x6064:0 [inc]"),
		   fe = column(h, "0:0x60F4:0 [inc]"), sw = column(h, "0:0x6041:0");
	CHECK(std::stoi(rows.back()[target]) == 20000);
	CHECK(std::stoi(rows.back()[actual]) == 20000);
	long maxLag = 0;
	bool enabled = true;
	for (std::size_t i = 1; i < rows.size(); i++) {
		// the drive's own following error within the limit it reports
		CHECK(std::labs(std::stol(rows[i][fe])) <= 20000);
		maxLag = std::max(maxLag, std::labs(std::stol(rows[i][target]) - std::stol(rows[i][actual])));
		enabled = enabled && (std::stoi(rows[i][sw]) & 0x6F) == 0x27; // OPERATION ENABLED throughout
	}
	CHECK(maxLag > 0); // the position follows its target a few cycles late (the pipeline)
	CHECK(enabled);
	CHECK(svgOk(d.path + "/m.svg", 4));

	auto u = run("-d sim: cia402 -p 0 move --csp 100 --csv " + d.path + "/only.csv");
	CHECK(u.status == 2);
	CHECK_THAT(u.err, Contains("cia402: --csv is written with --plot FILE.svg"));
	u = run("-d sim: cia402 -p 0 home --plot " + d.path + "/h.svg");
	CHECK(u.status == 2);
	CHECK_THAT(u.err, Contains("cia402 home: --plot and --csv are for move"));
	u = run("-d sim: cia402 -p 0 move --csp 100 --plot");
	CHECK(u.status == 2);
	CHECK_THAT(u.err, Contains("option '--plot' needs a value"));
}

TEST_CASE("scope cli: cia402 move --plot on the ECM-SK records the move")
{
	TempDir d;
	const auto r = run("-d sk-sim: cia402 -p 0 move 5000 --plot " + d.path + "/k.svg --csv " + d.path + "/k.csv");
	INFO(r.err);
	REQUIRE(r.status == 0);
	const auto rows = csv(d.path + "/k.csv");
	REQUIRE(rows.size() > 5);
	CHECK(rows[0] == std::vector<std::string>{ "time_us", "0:target [inc]", "0:position [inc]",
						   "0:following_error [inc]", "0:statusword" });
	CHECK(std::stoi(rows.back()[1]) == 5000);
	CHECK(std::stoi(rows.back()[2]) == 5000);
	for (std::size_t i = 1; i < rows.size(); i++)
		CHECK(std::stol(rows[i][3]) == std::stol(rows[i][1]) - std::stol(rows[i][2]));
	CHECK(svgOk(d.path + "/k.svg", 3));
	const auto u = run("-d sk-sim: cia402 -p 0 status --plot " + d.path + "/s.svg");
	CHECK(u.status == 2);
	CHECK_THAT(u.err, Contains("cia402: --plot and --csv are for move"));
}

#ifdef ECMXF_DEMO_PATH
namespace {

/// The demo's files in @p dir: exactly axis0/1 .csv/.svg (nothing left
/// over from writing them).
std::vector<std::string> filesIn(const std::string &dir)
{
	std::vector<std::string> v;
	for (const auto &e : std::filesystem::directory_iterator(dir))
		v.push_back(e.path().filename().string());
	std::sort(v.begin(), v.end());
	return v;
}

std::string slurp(const std::string &file)
{
	std::ifstream in(file);
	REQUIRE(in.good());
	std::stringstream ss;
	ss << in.rdbuf();
	return ss.str();
}

/// The SVG's traces are the CSV's columns: each point the row's time and
/// value (to the SVG's 3 decimals of a pixel), one point per row.
void svgIsCsv(const std::string &svgFile, const std::vector<std::vector<std::string>> &rows)
{
	const auto traces = scopetest::svgTraces(slurp(svgFile));
	REQUIRE(traces.size() + 1 == rows[0].size());
	for (std::size_t k = 0; k < traces.size(); k++) {
		INFO(svgFile << " trace " << traces[k].signal);
		CHECK_THAT(rows[0][k + 1], Catch::Matchers::StartsWith(traces[k].signal));
		REQUIRE(traces[k].points.size() + 1 == rows.size());
		std::size_t bad = 0;
		for (std::size_t i = 0; i < traces[k].points.size(); i++) {
			const auto [t, v] = traces[k].points[i];
			bad += std::fabs(t - std::stod(rows[i + 1][0])) > traces[k].timeTolerance ||
			       std::fabs(v - std::stod(rows[i + 1][k + 1])) > traces[k].valueTolerance;
		}
		CHECK(bad == 0u);
	}
}

clitest::Result demo(const std::string &args)
{
	return clitest::runProgram(ECMXF_DEMO_PATH, args);
}

} // namespace

TEST_CASE("scope cli: ecmxf-demo --plot DIR writes both axes' CSP move as CSV and SVG")
{
	TempDir d;
	const std::string dir = d.path + "/plots"; // made by the demo
	const auto r = demo("--fast --plot " + dir);
	INFO(r.out << r.err);
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("plots: " + dir + "/axis0.csv " + dir + "/axis0.svg " + dir + "/axis1.csv " + dir +
				   "/axis1.svg"));
	CHECK_THAT(r.out, Contains("ecmxf-demo: all steps OK"));
	CHECK(filesIn(dir) == std::vector<std::string>{ "axis0.csv", "axis0.svg", "axis1.csv", "axis1.svg" });
	const long to[2] = { 200000, -75000 };
	for (int a = 0; a < 2; a++) {
		const std::string n = std::to_string(a);
		INFO("axis " << n);
		const auto rows = csv(dir + "/axis" + n + ".csv");
		REQUIRE(rows.size() > 1000); // 1 s move + 100 ms settling at 1 ms
		CHECK(rows[0] == std::vector<std::string>{ "time_us", n + ":0x607A:0 [inc]", n + ":0x6064:0 [inc]",
							   n + ":0x60F4:0 [inc]", n + ":0x6041:0" });
		CHECK(std::stol(rows.back()[1]) == to[a]);
		CHECK(std::stol(rows.back()[2]) == to[a]);
		bool enabled = true, moved = false;
		for (std::size_t i = 1; i < rows.size(); i++) {
			enabled = enabled && (std::stoi(rows[i][4]) & 0x6F) == 0x27; // OPERATION ENABLED
			moved = moved || std::stol(rows[i][1]) != std::stol(rows[1][1]);
		}
		CHECK(enabled);
		CHECK(moved);
		CHECK(svgOk(dir + "/axis" + n + ".svg", 4));
		svgIsCsv(dir + "/axis" + n + ".svg", rows);
	}
	// a second run replaces the files
	const auto again = demo("--fast --plot=" + dir);
	CHECK(again.status == 0);
	CHECK(filesIn(dir).size() == 4u);
}

TEST_CASE("scope cli: ecmxf-demo --board ecm-sk --plot DIR writes both axes' move")
{
	TempDir d;
	const auto r = demo("--board ecm-sk --fast --plot " + d.path);
	INFO(r.out << r.err);
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("plots: " + d.path + "/axis0.csv"));
	CHECK(filesIn(d.path) == std::vector<std::string>{ "axis0.csv", "axis0.svg", "axis1.csv", "axis1.svg" });
	const long to[2] = { 20000, 50000 };
	for (int a = 0; a < 2; a++) {
		const std::string n = std::to_string(a);
		INFO("axis " << n);
		const auto rows = csv(d.path + "/axis" + n + ".csv");
		REQUIRE(rows.size() > 1000);
		CHECK(rows[0] == std::vector<std::string>{ "time_us", n + ":target [inc]", n + ":position [inc]",
							   n + ":following_error [inc]", n + ":statusword" });
		CHECK(std::stol(rows.back()[1]) == to[a]);
		CHECK(std::stol(rows.back()[2]) == to[a]);
		for (std::size_t i = 1; i < rows.size(); i++)
			CHECK(std::stol(rows[i][3]) == std::stol(rows[i][1]) - std::stol(rows[i][2]));
		CHECK(svgOk(d.path + "/axis" + n + ".svg", 3));
		svgIsCsv(d.path + "/axis" + n + ".svg", rows);
	}
}

TEST_CASE("scope cli: ecmxf-demo --plot with a bad DIR fails before the tour, naming it")
{
	TempDir d;
	const std::string file = d.path + "/file";
	std::ofstream(file) << "keep\n";
	for (const char *board : { "", "--board ecm-sk " }) {
		INFO(board);
		auto r = demo(std::string(board) + "--fast --plot " + file);
		CHECK(r.status == 1);
		CHECK_THAT(r.err, Contains("ecmxf-demo: --plot " + file + ": Not a directory"));
		CHECK_THAT(r.out, !Contains("== ")); // nothing of the tour ran
		CHECK(slurp(file) == "keep\n");
		r = demo(std::string(board) + "--fast --plot " + d.path + "/no/such");
		CHECK(r.status == 1);
		CHECK_THAT(r.err, Contains("ecmxf-demo: --plot " + d.path +
					   "/no/such: cannot make the directory: No such file or directory"));
		CHECK(!std::filesystem::exists(d.path + "/no"));
	}
	if (::geteuid() != 0) { // root writes anywhere
		const std::string ro = d.path + "/ro";
		std::filesystem::create_directory(ro);
		std::filesystem::permissions(ro, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
		const auto r = demo("--fast --plot " + ro);
		CHECK(r.status == 1);
		CHECK_THAT(r.err, Contains("ecmxf-demo: --plot " + ro + ": Permission denied"));
		CHECK(filesIn(ro).empty());
	} else {
		WARN("running as root: the unwritable directory case is not checked");
	}
	auto u = demo("--plot");
	CHECK(u.status == 2);
	CHECK_THAT(u.err, Contains("ecmxf-demo: --plot needs a directory"));
	u = demo("--plot=");
	CHECK(u.status == 2);
	CHECK_THAT(u.err, Contains("ecmxf-demo: --plot: an empty directory name"));
	CHECK(filesIn(d.path) == std::vector<std::string>{ "file" });
}
#endif
