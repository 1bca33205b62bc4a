// SPDX-License-Identifier: MIT
// ecmxf-util scope and cia402 move --plot, run as programs: the files they
// write read back (CSV) and checked (SVG: xmllint, rsvg-convert), on sim:,
// unix: and sk-sim:; bad signals, triggers and output files give a clear
// error, a non-zero exit and no file.

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli/cli_run.hpp"
#include "common/sim_server.hpp"

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
