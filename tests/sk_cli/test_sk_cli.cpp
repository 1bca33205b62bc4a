// SPDX-License-Identifier: MIT
// ecmxf-util -d sk-...: each command the ECM-SK offers, --json, the
// commands it cannot do (with why), bad values; and the board's state kept
// between runs through an ecmxf-sim --board ecm-sk server.

#include <catch2/catch.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include <ecmxf/error.hpp>
#include <ecmxf/link/unix_channel.hpp>

#include "cli/cli_run.hpp"
#include "common/sim_server.hpp"

using Catch::Matchers::Contains;
using clitest::run;

TEST_CASE("sk cli: info and slaves on a fresh sk-sim:, as text and JSON")
{
	auto r = run("-d sk-sim: info");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("504 bytes, 42 slots of 12 bytes, up to 40 slaves"));
	CHECK_THAT(r.out, Contains("State:         INIT"));
	r = run("-d sk-sim:?slot=16 --json info");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("\"frame_size\": 512"));
	CHECK_THAT(r.out, Contains("\"state\": \"INIT\""));
	r = run("-d sk-sim: slaves");
	REQUIRE(r.status == 0);
	const auto l = clitest::lines(r.out);
	REQUIRE(l.size() == 3);
	CHECK_THAT(l[0], Contains("Drive"));
	CHECK_THAT(l[0], Contains("0x00000e5c:0x0000a2d2"));
	CHECK_THAT(l[1], Contains("STEP"));
	CHECK_THAT(l[2], Contains("IO"));
	r = run("-d sk-sim: --json slaves");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("{\"position\": 1, \"state\": \"PREOP\", \"type\": \"STEP\""));
	// states -p N would move the whole board: refused (issue 29)
	const auto st = run("-d sk-sim: states -p 1 PREOP");
	CHECK(st.status == 1);
	CHECK_THAT(st.err, Contains("states: not on the ECM-SK: states -p N: the board has one state for the whole bus"));
	// the ECM-XF's field names (issue 29): vendor_id, product_code as numbers
	CHECK_THAT(r.out, Contains("{\"position\": 0, \"state\": \"PREOP\", \"type\": \"Drive\", \"vendor_id\": 3676, "
				   "\"product_code\": 41682}"));
	CHECK_THAT(r.out, !Contains("identity"));
}

TEST_CASE("sk cli: upload and download through the SDO slot")
{
	auto r = run("-d sk-sim: upload -p 1 -t uint32 0x1018:2");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("1412")); // 0x584
	// the board brought up silently, as the ECM-XF's bus (issue 29)
	CHECK(r.err.empty());
	// IgH's split form INDEX SUB
	r = run("-d sk-sim: upload -p 1 -t uint32 0x1018 2");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("1412"));
	r = run("-d sk-sim: --json upload -p 0 0x1018:1");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("\"size\": 4"));
	r = run("-d sk-sim: download -p 1 -t int8 0x6098 37");
	CHECK(r.status == 0);
	r = run("-d sk-sim: upload -p 0 0x5FFF");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("0x06020000"));
	r = run("-d sk-sim: upload -p 0 -t uint64 0x1018:1");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("1, 2 or 4 bytes"));
	r = run("-d sk-sim: upload -p 3 0x1000");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("out of range"));
	// a standard object has its type from CiA 402 (0x6098 INTEGER8)
	r = run("-d sk-sim: download -p 1 0x6098 37");
	CHECK(r.status == 0);
	r = run("-d sk-sim: download -p 1 0x6098 200");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("200 is out of range -128..127 (0x6098:00 Homing method is INTEGER8)"));
	r = run("-d sk-sim: download -p 1 0x2001 37");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("-t TYPE is required"));
	r = run("-d sk-sim: download -p 1 -t int8 0x6098 300");
	CHECK(r.status == 2);
}

TEST_CASE("sk cli: cia402 enable, move, status, io, lio, states, reset")
{
	auto r = run("-d sk-sim: -q cia402 -p 1 move 4000");
	REQUIRE(r.status == 0);
	// a long ramp (1000 targets): the FIFO is kept under CONFIG3's 100,
	// nothing is abandoned (it would be counted, and the move fail)
	r = run("-d sk-sim: --json cia402 -p 0 move 1000000");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("\"position_actual\": 1000000"));
	r = run("-d sk-sim: --json cia402 -p 1 move -2500");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("\"position_actual\": -2500"));
	CHECK_THAT(r.out, Contains("\"state\": \"OPERATION ENABLED\""));
	r = run("-d sk-sim: cia402 -p 0 enable");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("statusword 0x"));
	r = run("-d sk-sim: cia402 -p 1 home 37");
	CHECK(r.status == 0);
	r = run("-d sk-sim: cia402 -p 2 enable");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("refused SV_ON for slave 2 in OP")); // -p 2: its bus position, never the slot
	r = run("-d sk-sim: cia402 -p 1 dance");
	CHECK(r.status == 2);
	r = run("-d sk-sim: io -p 2 0x5");
	CHECK(r.status == 0);
	r = run("-d sk-sim: --json io -p 2");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("\"inputs\": "));
	r = run("-d sk-sim:?lio=9 lio");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("0x09"));
	r = run("-d sk-sim: lio 64");
	CHECK(r.status == 2);
	r = run("-d sk-sim: states OP");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("OP"));
	r = run("-d sk-sim: states SAFEOP");
	CHECK(r.status == 0);
	r = run("-d sk-sim: states BOOT");
	CHECK(r.status == 2);
	r = run("-d sk-sim: --json reset");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("\"state\": \"INIT\""));
}

TEST_CASE("sk cli: bad values of io, cia402 and -p are usage errors")
{
	for (const char *args : { "io -p 2 0x100000000", "io -p 2 -1", "io -p 2 five", "io -p 2 1 2",
				  "cia402 -p 1 move 2147483648", "cia402 -p 1 move", "cia402 -p 1 home 200",
				  "cia402 -p 1 home", "cia402", "upload -p 128 0x1000", "upload -p x 0x1000",
				  "upload -p 0 0x10000", "upload -p 0", "lio 1 2", "states", "reset now",
				  "info extra" }) {
		INFO(args);
		const auto r = run(std::string("-d sk-sim: ") + args);
		CHECK(r.status == 2);
		CHECK_FALSE(r.err.empty());
	}
}

TEST_CASE("sk cli: what the ECM-SK cannot do is refused with why, bad URIs are named")
{
	for (const char *cmd : { "eeprom", "pdos", "foe_read", "gpio", "raw", "monitor", "sii_read", "emergency" }) {
		INFO(cmd);
		const auto r = run(std::string("-d sk-sim: ") + cmd);
		CHECK(r.status == 1);
		CHECK_THAT(r.err, Contains("not on the ECM-SK"));
	}
	auto r = run("-d sk-sim: frobnicate");
	CHECK(r.status == 2);
	r = run("-d sk-sim:?slot=14 info");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("slot=14"));
	r = run("-d sk-spidev:/dev/spidev0.0 info");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("busy=<chip>:<line> is required"));
	// sk-usb: with no board at that USB path says so (whatever this machine has)
	r = run("-d sk-usb:?path=9-9.9 info");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("no ECM-SK (USB ID 16C0:05DF at USB path 9-9.9)"));
	r = run("-d sk-usb:/dev/null info");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("sk-usb:/dev/null: not a hidraw node"));
	r = run("-d sk-usb:?path=x info");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("bad path value \"x\""));
	r = run("-d sk-sim: info --trace"); // --trace records on the ECM-SK too (below); without a file: usage
	CHECK(r.status == 2);
	r = run("-d sk-sim: help");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("LIO_RD"));
}

TEST_CASE("sk cli: the board behind sk-unix: keeps its state between runs")
{
	ecmxftest::TempDir dir;
	const std::string sock = dir.path + "/sk.sock";
	ecmxftest::SimServer server(sock, { "--board", "ecm-sk" });
	auto r = run("-d sk-unix:" + sock + " states OP");
	CHECK(r.status == 0);
	r = run("-d sk-unix:" + sock + " --json info");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("\"state\": \"OP\""));
	r = run("-d sk-unix:" + sock + " lio 5");
	CHECK(r.status == 0);
}

TEST_CASE("sk cli: --trace FILE records the frames on sk-sim: and sk-unix:, decode reads them back")
{
	ecmxftest::TempDir dir;
	const std::string t1 = dir.path + "/a.trace", t2 = dir.path + "/b.trace";
	// a URI with options of its own: --trace is added as &trace=
	auto r = run("-d 'sk-sim:?ex=3' --trace " + t1 + " states PREOP");
	REQUIRE(r.status == 0);
	r = run("decode " + t1);
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("host>board 504 bytes (12-byte slots): SET_STATE (0x0001)\n"
				   "    CRC-8 (byte 3) 0xE7: OK\n"));
	CHECK_THAT(r.out, Contains(" 0 bad (0 not ready), "));
	CHECK_THAT(r.out, Contains(" of them ECM-SK frames\n"));
	r = run("-d sk-sim: decode --json " + t1); // decode runs with an ECM-SK device too
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("\"sk\": true, \"size\": 504, \"slot_size\": 12, \"crc\": \"ok\""));

	const std::string sock = dir.path + "/sk.sock";
	ecmxftest::SimServer server(sock, { "--board", "ecm-sk", "--settings", "slot=16" });
	r = run("-d 'sk-unix:" + sock + "?slot=16' --trace " + t2 + " info");
	CHECK(r.status == 0);
	r = run("decode " + t2);
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("board>host 512 bytes (16-byte slots): "));
	CHECK_THAT(r.out, Contains("    CRC-8 (byte 3) 0x00: not checked (nocrc)\n"));

	r = run("-d sk-sim: --trace /nonexistent-dir/x.trace info");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("cannot create the trace file \"/nonexistent-dir/x.trace\": No such file or directory"));
	// a trace that cannot be written fails the run
	r = run("-d sk-sim: --trace /dev/full info");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("ecmxf-util: writing the trace file \"/dev/full\" failed: No space left on device"));
}

TEST_CASE("sk cli: ecmxf-demo --board ecm-sk --fast runs every step")
{
	std::FILE *p = popen(ECMXF_DEMO_BINARY " --board ecm-sk --fast 2>&1", "r");
	REQUIRE(p != nullptr);
	std::string out;
	char buf[4096];
	std::size_t n;
	while ((n = std::fread(buf, 1, sizeof(buf), p)) > 0)
		out.append(buf, n);
	const int st = pclose(p);
	CHECK(WIFEXITED(st));
	CHECK(WEXITSTATUS(st) == 0);
	CHECK_THAT(out, Contains("all steps worked"));
	CHECK_THAT(out, Contains("end: drive 20000 (target 20000), step 50000 (target 50000); 0 dropped"));
}

TEST_CASE("sk cli: one command table: --help with -d lists what the device can do, each side says why not")
{
	for (const char *args : { "--help -d sk-sim:", "-d sk-sim: --help", "-d sk-sim: help" }) {
		INFO(args);
		const auto r = run(args);
		REQUIRE(r.status == 0);
		CHECK_THAT(r.out, Contains("Commands on an ECM-SK"));
		CHECK_THAT(r.out, Contains("\n  lio "));
		CHECK_THAT(r.out, Contains("\n  upload "));
		CHECK_FALSE(r.out.find("\n  eeprom ") != std::string::npos);
		CHECK_THAT(r.out, Contains("Not on the ECM-SK (each says why): adc,"));
	}
	auto r = run("--help");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("\n  eeprom "));
	CHECK_FALSE(r.out.find("\n  lio ") != std::string::npos);
	for (const char *cmd : { "master", "reg_read", "sii_write", "xml", "cstruct", "commands" }) {
		INFO(cmd);
		r = run(std::string("-d sk-sim: ") + cmd);
		CHECK(r.status == 1);
		CHECK_THAT(r.err, Contains(std::string(cmd) + ": not on the ECM-SK: "));
	}
	for (const char *cmd : { "io -p 0", "lio" }) {
		INFO(cmd);
		r = run(std::string("-d sim: ") + cmd);
		CHECK(r.status == 1);
		CHECK_THAT(r.err, Contains("not on the ECM-XF: "));
	}
	r = run("i"); // on the ECM-XF "i" is still info: io is not one of its commands
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("firmware version:"));
	r = run("-d sk-sim: help upload");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("On an ECM-SK (-d sk-...): SDO_RD"));
}

TEST_CASE("sk cli: slaves -v adds revision and serial number (0x1018:03/04), -p takes lists and ranges")
{
	auto r = run("-d sk-sim: slaves -v");
	REQUIRE(r.status == 0);
	auto l = clitest::lines(r.out);
	REQUIRE(l.size() == 4);
	CHECK_THAT(l[0], Contains("POS STATE  TYPE   VENDOR:PRODUCT        REVISION   SERIAL"));
	CHECK_THAT(l[1], Contains("Drive  0x00000e5c:0x0000a2d2 0x"));
	CHECK_THAT(l[3], Contains("IO"));
	r = run("-d sk-sim: --json slaves -v");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("\"revision\": "));
	CHECK_THAT(r.out, Contains("\"serial_number\": "));
	// without -v the fields of before
	CHECK_THAT(run("-d sk-sim: --json slaves").out, !Contains("revision"));
	r = run("-d sk-sim: slaves -p 0,2");
	REQUIRE(r.status == 0);
	l = clitest::lines(r.out);
	REQUIRE(l.size() == 2);
	CHECK_THAT(l[0], Contains("Drive"));
	CHECK_THAT(l[1], Contains("IO"));
	r = run("-d sk-sim: slaves -p 1-2");
	REQUIRE(r.status == 0);
	CHECK(clitest::lines(r.out).size() == 2);
	r = run("-d sk-sim: slaves -p 0-5");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("slave position 5 out of range: the bus has 3 slaves (0..2)"));
	r = run("-d sk-sim: info -v");
	CHECK(r.status == 2); // -v is the slave list's only
}
