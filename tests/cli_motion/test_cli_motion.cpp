// SPDX-License-Identifier: MIT
// ecmxf-util cia402 move / home: the unit called directly against a fresh
// in-process simulator (the default network: 2 x EST-584 + I/O), with the
// arguments exactly as `ecmxf-util cia402 ...` hands them over; and the
// demo program (ecmxf-demo --fast) run as a process.

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdio>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <sys/wait.h>

#include <ecmxf/error.hpp>

#include "../cli/json.hpp"
#include "ecmxf-util-cia402-motion.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using ecmxf_util::Args;
using ecmxf_util::Globals;
using ecmxf_util::UsageError;

namespace {

std::string run(std::vector<std::string_view> args, bool json = false)
{
	Globals g;
	g.json = json;
	std::ostringstream out;
	REQUIRE(ecmxf_util::cia402Motion(g, Args(args.begin(), args.end()), out) == 0);
	return out.str();
}

std::string usageError(std::vector<std::string_view> args)
{
	Globals g;
	std::ostringstream out;
	try {
		(void)ecmxf_util::cia402Motion(g, Args(args.begin(), args.end()), out);
	} catch (const UsageError &e) {
		return e.what();
	}
	FAIL("no usage error");
	return {};
}

} // namespace

TEST_CASE("cia402 move --pp: absolute, to the target", "[cli-motion]")
{
	const std::string out = run({ "-p", "1", "move", "--pp", "25000", "--velocity", "100000" });
	CHECK_THAT(out, Contains("slave 1: PP move from 0 to 25000: position 25000\n"));
	CHECK_THAT(out, Contains("drive disabled"));
}

TEST_CASE("cia402 move --pp --relative --json", "[cli-motion]")
{
	const auto j = testjson::parse(run({ "-p", "0", "move", "--pp", "-4000", "--relative", "--accel", "1000000" }, true));
	CHECK(j["slave"].num == 0);
	CHECK(j["mode"].str == "pp");
	CHECK(j["start"].num == 0);
	CHECK(j["target"].num == -4000);
	CHECK(j["position"].num == -4000);
	// 0x8637: OPERATION ENABLED, voltage, remote, target reached, trigger response
	CHECK(j["statusword"].num == 0x8637);
}

TEST_CASE("cia402 move --pv: the velocity is reached, then ramped to 0", "[cli-motion]")
{
	const auto j = testjson::parse(run({ "-p", "0", "move", "--pv", "30000", "--accel", "300000", "--time", "200" }, true));
	CHECK(j["mode"].str == "pv");
	CHECK(j["velocity_reached"].num == 30000);
	CHECK(j["velocity"].num == 0);
	// ramp up 0.1 s (1500 units) + 200 ms or a little more at 30000/s (>= 6000)
	// + ramp down 0.1 s (1500 units)
	CHECK(j["position"].num >= 9000);
	CHECK(j["position"].num < 12000);
}

TEST_CASE("cia402 move --csp: a trajectory to the target", "[cli-motion]")
{
	const std::string out = run({ "-p", "1", "move", "--csp", "80000", "--time", "400" });
	CHECK_THAT(out, Contains("slave 1: CSP move from 0 to 80000: position 80000\n"));
}

TEST_CASE("cia402 home --method 37", "[cli-motion]")
{
	const std::string out = run({ "-p", "0", "home", "--method", "37" });
	CHECK_THAT(out, Equals(std::string("slave 0: homing attained (method 37), position 0\n") +
			       out.substr(out.find('\n') + 1)));
	CHECK_THAT(out, Contains("statusword 0x"));
}

TEST_CASE("cia402 move: usage errors", "[cli-motion]")
{
	CHECK_THAT(usageError({ "move", "--pp", "1" }), Equals("cia402 move: which drive? (-p N)"));
	CHECK_THAT(usageError({ "-p", "0", "move" }), Equals("cia402 move: which mode? (--pp, --pv or --csp TARGET)"));
	CHECK_THAT(usageError({ "-p", "0", "move", "--pp", "1", "--csp", "2" }),
		   Equals("cia402 move: one of --pp, --pv, --csp only"));
	CHECK_THAT(usageError({ "-p", "0", "move", "--pp", "x1" }), Equals("cia402: --pp: 'x1' is not a number"));
	CHECK_THAT(usageError({ "-p", "200", "move", "--pp", "1" }), Equals("cia402: -p 200 out of range 0..127"));
	CHECK_THAT(usageError({ "-p", "0", "home", "--velocity", "5" }), Equals("cia402 home: only --method M"));
	CHECK_THAT(usageError({ "-p", "0", "move", "--pp" }), Equals("cia402: option '--pp' needs a value"));
	CHECK_THAT(usageError({ "-p", "0", "move", "--pp", "1", "--time", "0" }),
		   Equals("cia402 move: --time 0 (until stopped) is for --pv only; --pp needs 1..3600000 ms"));
	CHECK_THAT(usageError({ "-p", "0", "move", "--pv", "1", "--time", "3600001" }),
		   Equals("cia402: --time 3600001 out of range 0..3600000"));
	CHECK_THAT(usageError({ "-p", "0", "move", "--fast" }),
		   Equals("cia402: unknown argument '--fast' (try 'ecmxf-util cia402 move --help')"));
}

TEST_CASE("cia402 move: errors from the bus and the drive", "[cli-motion]")
{
	Globals g;
	std::ostringstream out;
	const std::vector<std::string_view> io{ "-p", "2", "move", "--pp", "100" };
	try {
		(void)ecmxf_util::cia402Motion(g, Args(io.begin(), io.end()), out);
		FAIL("no error");
	} catch (const ecmxf::Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Contains("slave 2: Cia402Axis: not mapped: 0x6040:00 (controlword) as an output"));
	}
	const std::vector<std::string_view> none{ "-p", "3", "home" };
	try {
		(void)ecmxf_util::cia402Motion(g, Args(none.begin(), none.end()), out);
		FAIL("no error");
	} catch (const ecmxf::Error &e) {
		CHECK_THAT(e.what(), Equals("slave position 3 out of range: the bus has 3 slaves (0..2)"));
	}
	const std::vector<std::string_view> bad{ "-p", "0", "home", "--method", "1" };
	try {
		(void)ecmxf_util::cia402Motion(g, Args(bad.begin(), bad.end()), out);
		FAIL("no error");
	} catch (const ecmxf::Error &e) {
		CHECK_THAT(e.what(), Contains("0x6098"));
		CHECK_THAT(e.what(), Contains("0x06090030"));
	}
}

TEST_CASE("cia402 move --help", "[cli-motion]")
{
	CHECK_THAT(run({ "move", "--help" }), Contains("Usage: ecmxf-util [global options] cia402 -p N move"));
}

#ifdef ECMXF_DEMO
TEST_CASE("ecmxf-demo --fast: every section, both axes at their targets, 0 WKC errors", "[demo]")
{
	FILE *p = ::popen(ECMXF_DEMO " --fast 2>&1", "r");
	REQUIRE(p != nullptr);
	std::string out;
	char buf[4096];
	std::size_t n = 0;
	while ((n = std::fread(buf, 1, sizeof buf, p)) > 0)
		out.append(buf, n);
	const int status = ::pclose(p);
	INFO(out);
	REQUIRE(WIFEXITED(status));
	CHECK(WEXITSTATUS(status) == 0);
	for (const char *h : { "== 1. Bring-up: the network to OP", "== 2. The slaves ==", "== 3. SDO",
			       "== 4. CiA-402: enable both drives", "== 5. Synchronized CSP move", "== 6. Summary ==" })
		CHECK_THAT(out, Contains(h));
	for (const char *step : { "   init ", "   scan ", "   states to PRE-OP ", "   PDO configuration ", "   PDO mapping ",
				  "   states to SAFE-OP ", "   states to OP ", "   FIFO enable " })
		CHECK_THAT(out, Contains(step));
	CHECK_THAT(out, Contains("0x00000E5C:0x00000584 OP        11   15"));
	CHECK_THAT(out, Contains("0x6081 profile velocity: read 50000, wrote 120000, read back 120000"));
	// EST-584 / CiA 301 abort codes
	CHECK_THAT(out, Contains("read  0x2FFF (no such object): abort 0x06020000"));
	CHECK_THAT(out, Contains("write 0x6064 (read-only):   abort 0x06010002"));
	CHECK_THAT(out, Contains("slave 0: SWITCH ON DISABLED -> READY TO SWITCH ON -> SWITCHED ON -> OPERATION ENABLED"));
	CHECK_THAT(out, Contains("slave 1: SWITCH ON DISABLED -> READY TO SWITCH ON -> SWITCHED ON -> OPERATION ENABLED"));
	CHECK_THAT(out, Contains("slave 0 final position 200000, target 200000: reached"));
	CHECK_THAT(out, Contains("slave 1 final position -75000, target -75000: reached"));
	CHECK_THAT(out, Contains(" 0 failed, 0 WKC errors"));
	CHECK_THAT(out, Contains("0 RxFIFO overruns (refused)"));
	CHECK_THAT(out, Contains("ecmxf-demo: all steps OK"));
}
#endif
