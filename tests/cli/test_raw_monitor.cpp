// SPDX-License-Identifier: MIT
// ecmxf-util raw and monitor as programs against the in-process simulator
// (default network: 2 x EST-584 + digital I/O). Expected values come from
// Documentation/simulator.rst and protocol-core.rst: power-on header (no
// network: ECAT state 0, error status 0x01 "link", ECM status 0x40 "FIFO
// enabled", no interrupt flags before bus cycles run), the first fresh
// index 1 (the power-on NOP answer carries index 0 and a fresh index
// differs from the last one seen), INIT_OP clearing "FIFO enabled" and
// setting "Ethernet initialised" / "PDO configured", a dropped slave
// making the ECAT state ERROR and STATE_GET answer 0x10, the WKC error
// counter saturating at 255.

#include <catch2/catch.hpp>

#include <string>

#include "cli_run.hpp"
#include "json.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using clitest::lines;
using clitest::run;
using testjson::Json;

TEST_CASE("raw INFO_UPDATE_OP prints the power-on response header field by field", "[cli][raw]")
{
	for (const char *code : { "0", "INFO_UPDATE_OP", "info_update_op", "ECM_CMD_INFO_UPDATE_OP" }) {
		const auto r = run(std::string("raw ") + code);
		REQUIRE(r.status == 0);
		CHECK(r.err.empty());
		CHECK(r.out == "crcErrCnt    0\n"
			       "wkcErrCnt    0\n"
			       "txFifoCnt    0\n"
			       "rxFifoCnt    0\n"
			       "ecatState    0x00 (NONE)\n"
			       "errStatus    0x01\n"
			       "ecmStatus    0x40\n"
			       "index        1\n"
			       "code         0 (INFO_UPDATE_OP)\n"
			       "ret          0 (0x00)\n"
			       "len          0\n"
			       "intFlags     0x00000000\n"
			       "gpioIntFlag  0x00 0x00\n"
			       "gpioIn       0x00 0x00\n"
			       "data         -\n");
	}
}

TEST_CASE("raw SLV_CNT_GET: 0 slaves before ECAT_INIT_OP, the name without ECAT_ works", "[cli][raw]")
{
	const auto r = run("raw SLV_CNT_GET");
	REQUIRE(r.status == 0);
	// an INFO_UPDATE first (index 1) to see the sticky command-error bit
	CHECK(r.out == "crcErrCnt    0\n"
		       "wkcErrCnt    0\n"
		       "txFifoCnt    0\n"
		       "rxFifoCnt    0\n"
		       "ecatState    0x00 (NONE)\n"
		       "errStatus    0x01\n"
		       "ecmStatus    0x40\n"
		       "index        2\n"
		       "code         16 (ECAT_SLV_CNT_GET)\n"
		       "ret          0 (0x00)\n"
		       "len          0\n"
		       "intFlags     0x00000000\n"
		       "gpioIntFlag  0x00 0x00\n"
		       "gpioIn       0x00 0x00\n"
		       "data         -\n");
	CHECK(run("raw 16").out == r.out);
	CHECK(run("raw 0x10").out == r.out);
}

TEST_CASE("raw FW_VERSION_GET --json: header members by name and the data as hex", "[cli][raw][json]")
{
	const auto r = run("raw FW_VERSION_GET --json");
	REQUIRE(r.status == 0);
	const Json j = testjson::parse(r.out);
	const Json &h = j["header"];
	CHECK(h["code"].num == 56);
	CHECK(h["name"].str == "FW_VERSION_GET");
	CHECK(h["ret"].num == 0x30); // ChipConfig::fwVersion
	CHECK(h["len"].num == 20);
	CHECK(h["errStatus"].num == 1);
	CHECK(h["ecmStatus"].num == 0x40);
	CHECK(h["ecatState"].num == 0);
	CHECK(h["gpioIn"].size() == 2);
	// 20 bytes: version fields 0..3 zero, "ecmxf-simulator", NUL padded
	CHECK(j["data"].str == "00000000"
			       "65636d78662d73696d756c61746f72"
			       "00");
}

TEST_CASE("raw with a payload prints the answer's data as a hex dump", "[cli][raw]")
{
	// FW_VERSION_GET answers 20 bytes: two dump lines of 16 + 4
	const auto r = run("raw 56");
	REQUIRE(r.status == 0);
	const auto l = lines(r.out);
	REQUIRE(l.size() == 17);
	CHECK(l[14] == "data         20 bytes");
	CHECK(l[15] == "  0000  00 00 00 00 65 63 6d 78 66 2d 73 69 6d 75 6c 61");
	CHECK(l[16] == "  0010  74 6f 72 00");
}

TEST_CASE("raw: a command the chip refuses prints its header and exits 1", "[cli][raw][errors]")
{
	// SLV_INFO_GET before ECAT_INIT_OP: command error (error status bit 7)
	const auto r = run("raw ECAT_SLV_INFO_GET --param 0 --data 3");
	CHECK(r.status == 1);
	CHECK_THAT(r.out, Contains("errStatus    0x81\n"));
	CHECK(r.err == "ecmxf-util: raw: ECAT_SLV_INFO_GET: the chip refused the command (error status "
		       "bit 7, command error)\n");
}

TEST_CASE("raw: bad arguments are usage errors naming the argument and its range", "[cli][raw][errors]")
{
	auto r = run("raw FROB");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: raw: unknown command 'FROB' (a code 0..255 or a name of 'ecmxf-util "
		       "commands')\n");
	r = run("raw 256");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: raw: CODE: 256 is out of range 0..255\n");
	r = run("raw 0 --param 0x100");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: raw: --param: 0x100 is out of range 0..255\n");
	r = run("raw 0 --data 1,2,3,4,5");
	CHECK(r.err == "ecmxf-util: raw: --data: 5 bytes, at most 4 (B0,B1,B2,B3)\n");
	r = run("raw 0 --payload 0a0");
	CHECK(r.err == "ecmxf-util: raw: --payload: '0a0': odd number of hex digits\n");
	r = run("raw 0 --payload zz");
	CHECK(r.err == "ecmxf-util: raw: --payload: 'zz' is not hex bytes (e.g. 0a0b0c or 0a:0b:0c)\n");
	r = run("raw 0 --len");
	CHECK(r.err == "ecmxf-util: raw: option '--len' needs a value\n");
	r = run("raw");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: raw: missing CODE (try 'ecmxf-util raw --help')\n");
}

TEST_CASE("raw --datagram BRD of AL status: every slave answers, all in INIT", "[cli][raw]")
{
	// BRD ORs the slaves' bytes; WKC = number of slaves (3); INIT = 1
	const auto r = run("raw --datagram BRD 0x0130 1 --json");
	REQUIRE(r.status == 0);
	const Json j = testjson::parse(r.out);
	CHECK(j["type"].str == "BRD");
	CHECK(j["ado"].num == 0x130);
	CHECK(j["wkc"].num == 3);
	CHECK(j["data"].str == "01");
	const auto t = run("raw --datagram brd 0x130 2");
	REQUIRE(t.status == 0);
	CHECK(t.out == "BRD ADP 0x0000 ADO 0x0130, 2 bytes: working counter 3\n"
		       "  0000  01 00\n");
	// APRD position 2 -> ADP -2
	const auto a = run("raw --datagram APRD 2:0x0130 1");
	REQUIRE(a.status == 0);
	CHECK(a.out == "APRD ADP 0xfffe ADO 0x0130, 1 bytes: working counter 1\n"
		       "  0000  01\n");
	auto e = run("raw --datagram XRD 0 1");
	CHECK(e.status == 2);
	CHECK_THAT(e.err, StartsWith("ecmxf-util: raw: --datagram: unknown type 'XRD'"));
	e = run("raw --datagram FPRD 0x1001 1");
	CHECK(e.err == "ecmxf-util: raw: --datagram FPRD: ADDR '0x1001' must be STATION:REGISTER\n");
	e = run("raw --datagram BWR 0x0f00 2 aa");
	CHECK(e.err == "ecmxf-util: raw: --datagram: DATA has 1 bytes, LEN says 2\n");
}

TEST_CASE("monitor on a quiet bus prints nothing and ends after --duration", "[cli][monitor]")
{
	const auto r = run("monitor --duration 200");
	CHECK(r.status == 0);
	CHECK(r.out.empty());
	CHECK(r.err.empty());
	CHECK(run("monitor --duration 200 --json").out.empty());
}

TEST_CASE("monitor: bus to OP, then slave 1 drops out: state, slaves, WKC burst (JSON Lines)",
	  "[cli][monitor][json]")
{
	const auto r = run("monitor --sim-at 0:op --sim-at 500:drop=1 --count 6 --json");
	REQUIRE(r.status == 0);
	const auto ev = testjson::parseLines(r.out);
	REQUIRE(ev.size() == 6);
	CHECK(ev[0]["type"].str == "state");
	CHECK(ev[0]["from"].num == 0);
	CHECK(ev[0]["to"].num == 8);
	CHECK(ev[0]["to_name"].str == "OP");
	CHECK(ev[1]["type"].str == "error_status");
	REQUIRE(ev[1]["set"].size() == 1);
	CHECK(ev[1]["set"][0].str == "link at INIT_OP");
	CHECK(ev[2]["type"].str == "ecm_status");
	REQUIRE(ev[2]["set"].size() == 2);
	CHECK(ev[2]["set"][0].str == "Ethernet initialised");
	CHECK(ev[2]["set"][1].str == "PDO configured");
	REQUIRE(ev[2]["cleared"].size() == 1);
	CHECK(ev[2]["cleared"][0].str == "FIFO enabled");

	CHECK(ev[3]["type"].str == "state");
	CHECK(ev[3]["from_name"].str == "OP");
	CHECK(ev[3]["to_name"].str == "ERROR");
	CHECK(ev[3]["time_ms"].num >= 500);
	REQUIRE(ev[3]["slaves"].size() == 1);
	const Json &s = ev[3]["slaves"][0];
	CHECK(s["position"].num == 1);
	CHECK_FALSE(s["answering"].b);
	CHECK(s["al_status_code"].kind == Json::Null);
	CHECK(ev[3]["text"].str == "ECAT state OP -> ERROR; slave 1: not answering");

	CHECK(ev[4]["type"].str == "wkc_burst");
	CHECK(ev[4]["increase"].num >= 1);
	// the counter saturates at 255: the burst ends there
	CHECK(ev[5]["type"].str == "wkc_burst_end");
	CHECK(ev[5]["errors"].num == 255);
	CHECK(ev[5]["count"].num == 255);
	for (std::size_t i = 1; i < ev.size(); i++)
		CHECK(ev[i]["time_ms"].num >= ev[i - 1]["time_ms"].num);
}

TEST_CASE("monitor: SPI CRC errors, link lost and back, a chip reset (text lines)", "[cli][monitor]")
{
	const auto r = run("monitor --sim-at 0:op --sim-at 100:crc=2 --sim-at 200:link-down "
			   "--sim-at 300:link-up --sim-at 400:reset --duration 500");
	REQUIRE(r.status == 0);
	const auto l = lines(r.out);
	REQUIRE(l.size() >= 9);
	std::vector<std::string> text;
	for (const std::string &x : l) {
		REQUIRE(x.size() > 14);
		CHECK(x.substr(10, 5) == " ms  ");
		text.push_back(x.substr(15));
	}
	CHECK(text[0] == "ECAT state NONE -> OP");
	CHECK(text[3] == "error status 0x03 -> 0x43: set SPI CRC error");
	CHECK(text[4] == "SPI CRC errors +2 (count 2)");
	// link down: ECAT state ERROR (the master's view), link bits cleared:
	// the link event for bit 0, error_status for bit 1
	CHECK(text[5] == "ECAT state OP -> ERROR; slave 0: not answering; slave 1: not answering; "
			 "slave 2: not answering");
	CHECK(text[6] == "EtherCAT link down (error status 0x40)");
	CHECK(text[7] == "error status 0x43 -> 0x40: cleared link at INIT_OP");
	CHECK_THAT(r.out, Contains("EtherCAT link up (error status 0x41)\n"));
	CHECK(text.back() == "the chip reset (ECAT state NONE, ECM status 0x40)");
}

TEST_CASE("monitor: usage errors", "[cli][monitor][errors]")
{
	auto r = run("monitor --count 0");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: monitor: --count: 0 is out of range 1..4294967295\n");
	r = run("monitor --interval x");
	CHECK(r.err == "ecmxf-util: monitor: --interval: 'x' is not a number (decimal or 0x hex)\n");
	r = run("monitor --sim-at 5:frob");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: monitor: --sim-at: unknown action 'frob' (op, drop=N, return, "
		       "link-down, link-up, crc=N, reset)\n");
	r = run("monitor --frob");
	CHECK(r.err == "ecmxf-util: monitor: unknown argument '--frob' (try 'ecmxf-util monitor --help')\n");
}
