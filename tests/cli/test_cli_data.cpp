// SPDX-License-Identifier: MIT
// ecmxf-util data (issue 29): the process image decoded by entry, --set of
// an output entry and its refusals, on sim: and on an ecmxf-sim server
// whose bus is left in PRE-OP.

#include <catch2/catch.hpp>

#include <string>

#include "cli_run.hpp"
#include "common/sim_server.hpp"
#include "json.hpp"

using Catch::Matchers::Contains;
using clitest::run;

TEST_CASE("data: every slave's entries with their values", "[cli][data]")
{
	const auto r = run("data");
	REQUIRE(r.status == 0);
	CHECK(r.err.empty());
	CHECK_THAT(r.out, Contains("slave 0: EST-584\n    out 0x6040:00  Controlword"));
	// SWITCH ON DISABLED, as the drive reports it by PDO
	CHECK_THAT(r.out, Contains("    in  0x6041:00  Statusword                     16 bit  0x0250 592\n"));
	CHECK_THAT(r.out, Contains("slave 2: Digital I/O 8 out / 8 in\n    out 0x7000:01"));
}

TEST_CASE("data: a standard object's unit after its value, none for words, codes and unknown entries",
	  "[cli][data]")
{
	const auto r = run("data -p 0");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("    out 0x607a:00  Target position                32 bit  0 inc\n"));
	CHECK_THAT(r.out, Contains("    in  0x6064:00  Position actual value          32 bit  0 inc\n"));
	CHECK_THAT(r.out, Contains("    in  0x6041:00  Statusword                     16 bit  0x0250 592\n"));
	const auto j = testjson::parse(run("data --json").out);
	REQUIRE(j.size() == 3);
	bool position = false, status = false;
	for (const auto &e : j[0]["inputs"].arr) {
		if (e["index"].num == 0x6064) {
			CHECK(e["unit"].str == "inc");
			position = true;
		}
		if (e["index"].num == 0x6041) {
			CHECK(e["unit"].kind == testjson::Json::Null);
			status = true;
		}
	}
	CHECK(position);
	CHECK(status);
	CHECK(j[2]["outputs"][0]["unit"].kind == testjson::Json::Null); // 0x7000:01: not a standard object
}

TEST_CASE("data --set: an output entry by name reaches the slave, --json", "[cli][data]")
{
	// Shutdown (6): the drive goes to READY TO SWITCH ON, seen in its
	// statusword; a signed entry prints as signed
	const auto r = run("data -p 0 --set Controlword=6 --set target_position=-1000 --json");
	REQUIRE(r.status == 0);
	const auto j = testjson::parse(r.out);
	REQUIRE(j.size() == 1);
	CHECK(j[0]["position"].num == 0);
	CHECK(j[0]["name"].str == "EST-584");
	CHECK(j[0]["outputs"][0]["name"].str == "Controlword");
	CHECK(j[0]["outputs"][0]["type"].str == "UNSIGNED16");
	CHECK(j[0]["outputs"][0]["value"].num == 6);
	CHECK(j[0]["outputs"][1]["index"].num == 0x607A);
	CHECK(j[0]["outputs"][1]["value"].num == -1000);
	CHECK(j[0]["inputs"][0]["name"].str == "Statusword");
	CHECK((static_cast<unsigned>(j[0]["inputs"][0]["value"].num) & 0x6F) == 0x21); // READY TO SWITCH ON
	// by INDEX:SUB too
	CHECK_THAT(run("data -p 2 --set 0x7000:01=0x5a").out, Contains("out 0x7000:01                                  8 bit  0x5a 90"));
}

TEST_CASE("data: refusals name the reason", "[cli][data][errors]")
{
	auto r = run("data -p 0 --set Statusword=1");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: data: --set Statusword: slave 0 0x6041:00 (Statusword) is an input (TxPDO): the "
		       "slave writes it\n");
	r = run("data -p 2 --set Foo=1");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: data: --set Foo: slave 2 maps no such output entry (its outputs: 0x7000:01)\n");
	r = run("data --set Controlword=6");
	CHECK(r.err == "ecmxf-util: data: --set needs the slave (-p N)\n");
	r = run("data -p 0 --set Controlword");
	CHECK(r.err == "ecmxf-util: data: --set 'Controlword': NAME=VALUE expected\n");
	r = run("data -p 0 --set Controlword=70000");
	CHECK(r.err == "ecmxf-util: data: --set Controlword: 70000 is out of range 0..65535\n");
	r = run("data -p 0 --set TargetPosition=nan");
	CHECK(r.status == 2);
	r = run("data -p 9");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("slave position 9 out of range"));
}

TEST_CASE("data: a bus left in PRE-OP is refused naming its state", "[cli][data][unix]")
{
	ecmxftest::TempDir dir;
	const std::string sock = dir.path + "/sim.sock";
	ecmxftest::SimServer server(sock);
	const std::string dev = "-d unix:" + sock + " ";
	REQUIRE(run(dev + "states PREOP").status == 0);
	const auto r = run(dev + "data");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("data: process data runs in SAFE-OP and OP: "));
	CHECK_THAT(r.err, Contains("PRE-OP"));
}

TEST_CASE("data --watch: one refresh per --interval, --count of them, JSON Lines, no escapes off a terminal",
	  "[cli][data]")
{
	auto r = run("data -p 0 --watch --interval 5 --count 3 --json");
	REQUIRE(r.status == 0);
	const auto lines = testjson::parseLines(r.out);
	REQUIRE(lines.size() == 3);
	for (const auto &l : lines)
		CHECK(l[0]["inputs"][0]["name"].str == "Statusword");
	r = run("data -p 2 -w --interval 1 --count 2");
	REQUIRE(r.status == 0);
	CHECK(clitest::lines(r.out).size() == 2 * 3); // per refresh: the slave, its output, its input
	CHECK(r.out.find('\x1b') == std::string::npos);
	r = run("data --count 3");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: data: --interval and --count are for --watch\n");
	r = run("data -w --interval 0");
	CHECK(r.err == "ecmxf-util: data: --interval: 0 is out of range 1..3600000\n");
}
