// SPDX-License-Identifier: MIT
// ecmxf-util's bus, slave and peripheral commands run as a program against
// the simulator (a fresh chip at every call): states, upload, download,
// pdos, sii_read, eeprom, foe_read/foe_write, gpio, qei, adc, dac,
// emergency, reset, cia402. Expected values come from the simulator's
// documentation (Documentation/sim-slaves.rst, sim-peripherals.rst), the
// EST-584 manual's default mapping (5.4.1), the CiA-402 statusword codes
// and the ETG abort / AL status code tables, not from the tool's output.

#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "cli_run.hpp"
#include "json.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using clitest::lines;
using clitest::run;
using testjson::Json;

namespace {

const std::string kServo = std::string("-d sim:") + ECMXF_TEST_NETWORK_DIR + "/servo-io.net ";

} // namespace

// ------------------------------------------------------------------ states

TEST_CASE("states PREOP brings a fresh bus up and lists every slave in PRE-OP", "[cli][states]")
{
	const auto r = run("states preop");
	REQUIRE(r.status == 0);
	CHECK(r.err.empty());
	CHECK(r.out == "0    PREOP  +\n1    PREOP  +\n2    PREOP  +\n");
}

TEST_CASE("states --break-claim: only the kernel module has a claim to break, nothing else happens",
	  "[cli][states]")
{
	const auto r = run("states --break-claim SAFEOP");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("no claim to break (only the kernel module's /dev/ecmxfN has one)"));
	CHECK(r.out.empty());
	const auto bad = run("states --break-claim=yes SAFEOP");
	CHECK(bad.status == 2);
}

TEST_CASE("states OP --json: every slave of the default network in OP without error", "[cli][states][json]")
{
	const auto r = run("states OP --json");
	REQUIRE(r.status == 0);
	const Json j = testjson::parse(r.out);
	CHECK(j["requested"].str == "OP");
	REQUIRE(j["slaves"].size() == 3);
	for (std::size_t i = 0; i < 3; i++) {
		const Json &s = j["slaves"][i];
		CHECK(s["position"].num == static_cast<double>(i));
		CHECK(s["state"].str == "OP");
		CHECK(s["al_state"].num == 8);
		CHECK_FALSE(s["error"].b);
		CHECK(s["al_status_code"].num == 0);
		CHECK(s["al_status_text"].str == "No error");
	}
}

TEST_CASE("states -p 1 SAFEOP moves only that slave and prints only it", "[cli][states]")
{
	const auto r = run("states -p 1 SAFE-OP");
	REQUIRE(r.status == 0);
	CHECK(r.out == "1    SAFEOP +\n");
}

TEST_CASE("states OP on the servo network without DC fails with AL status 0x0030", "[cli][states][errors]")
{
	// the servo needs SYNC0 for SAFE-OP -> OP (sim-slaves.rst): S+E 0x0030
	const auto r = run(kServo + "states --no-dc OP");
	CHECK(r.status == 1);
	CHECK(r.out.empty());
	CHECK_THAT(r.err, StartsWith("ecmxf-util: states: "));
	CHECK_THAT(r.err, Contains("slave 0 (AKD2G-like servo)"));
	CHECK_THAT(r.err, Contains("stays in SAFE-OP, AL status 0x0030 Invalid DC sync error"));
	// with DC (the default) the same network reaches OP
	const auto ok = run(kServo + "states OP");
	CHECK(ok.status == 0);
	CHECK(ok.out == "0    OP     +\n1    OP     +\n2    OP     +\n");
}

TEST_CASE("states: usage errors and a position beyond the bus", "[cli][states][errors]")
{
	auto r = run("states -p 5 OP");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: states: slave position 5 out of range: the bus has 3 slaves (0..2)\n");
	r = run("states FOO");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: states: unknown state 'FOO' (INIT, PREOP, SAFEOP, OP or BOOT)\n");
	r = run("states");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: states: which state? (INIT, PREOP, SAFEOP, OP or BOOT)\n");
	r = run("states -p 128 OP");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: states: -p: 128 is out of range 0..127\n");
}

// ---------------------------------------------------------- upload/download

TEST_CASE("upload without -t prints the object's hex and unsigned value", "[cli][sdo]")
{
	// 0x1000 device type of the EST-584: 0x00030192 (sim-slaves.rst)
	auto r = run("upload -p 0 0x1000");
	REQUIRE(r.status == 0);
	CHECK(r.out == "0x00030192 197010\n");
	r = run("upload -p 1 0x1000:0 -t uint32 -v");
	REQUIRE(r.status == 0);
	CHECK(r.out == "197010\nbytes: 92 01 03 00\n");
	r = run(kServo + "upload -p 0 4096");
	REQUIRE(r.status == 0);
	CHECK(r.out == "0x00020192 131474\n");
}

TEST_CASE("upload --json gives the value, size and bytes", "[cli][sdo][json]")
{
	const auto r = run("--json upload -p 0 0x1000");
	REQUIRE(r.status == 0);
	const Json j = testjson::parse(r.out);
	CHECK(j["position"].num == 0);
	CHECK(j["index"].num == 0x1000);
	CHECK(j["sub"].num == 0);
	CHECK(j["type"].kind == Json::Null);
	CHECK(j["size"].num == 4);
	CHECK(j["value"].num == 0x00030192);
	CHECK(j["hex"].str == "92010300");
	const auto s = run("upload -p 0 0x6064 -t int32 --json");
	REQUIRE(s.status == 0);
	const Json k = testjson::parse(s.out);
	CHECK(k["type"].str == "int32");
	CHECK(k["value"].num == 0); // position actual after power-on
}

TEST_CASE("upload errors: abort code and text, size mismatch, no -p, no mailbox", "[cli][sdo][errors]")
{
	auto r = run("upload -p 0 0x1234");
	CHECK(r.status == 1);
	CHECK(r.out.empty());
	CHECK(r.err == "ecmxf-util: upload: SDO upload 0x1234:00 from slave 0 aborted: 0x06020000 Object not existing\n");
	r = run("upload -p 0 0x6064 -t int16");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: upload: slave 0 0x6064:00 has 4 bytes, type int16 has 2\n");
	r = run("upload 0x6064");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: upload: which slave? -p/--position N is required (try 'ecmxf-util upload --help')\n");
	r = run("upload -p 3 0x6064");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: upload: slave position 3 out of range: the bus has 3 slaves (0..2)\n");
	// the dio has no mailbox: 0x08000023 (sim-slaves.rst)
	r = run("upload -p 2 0x1000");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, StartsWith("ecmxf-util: upload: SDO upload 0x1000:00 from slave 2 aborted: 0x08000023"));
	r = run("upload -p 0 0x6064 -t int24");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, StartsWith("ecmxf-util: upload: unknown type 'int24'"));
}

TEST_CASE("download writes silently and reports the slave's abort codes", "[cli][sdo]")
{
	// 0x6081 profile velocity, 32 bit: without -t the size comes from an upload
	auto r = run("download -p 0 0x6081 5000");
	CHECK(r.status == 0);
	CHECK(r.out.empty());
	CHECK(r.err.empty());
	r = run("download -p 0 0x6081 5000 -t uint32");
	CHECK(r.status == 0);
	// strict length: a 16-bit write to a 32-bit entry is 0x06070010
	r = run("download -p 0 0x6081 5000 -t uint16");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: download: SDO download 0x6081:00 to slave 0 aborted: 0x06070010 Parameter length error\n");
	// 0x1008 is a 7-byte string: needs -t
	r = run("download -p 0 0x1008 x");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: download: slave 0 0x1008:00 has 7 bytes: give its type with -t (e.g. -t string or -t octet_string)\n");
	r = run("download -p 0 0x6081");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: download: needs INDEX[:SUB] VALUE (download -p N INDEX[:SUB] VALUE)\n");
	r = run("download -p 0 0x6060 300 -t int8");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: download: VALUE: 300 is out of range -128..127\n");
}

// -------------------------------------------------------------------- pdos

TEST_CASE("pdos -p 0: the EST-584's default mapping 0x1600 / 0x1A00 (manual 5.4.1)", "[cli][pdos]")
{
	const auto r = run("pdos -p 0");
	REQUIRE(r.status == 0);
	const auto l = lines(r.out);
	REQUIRE(l.size() == 15); // title, 2 x (SM, PDO), 4 + 6 entries
	CHECK(l[0] == "Slave 0 (EST-584)");
	CHECK(l[1] == "  SM2 outputs (RxPDO), 12 bytes");
	CHECK(l[2] == "    PDO 0x1600");
	CHECK(l[3] == "      0x6040:00  16 bit  offset    0  Controlword");
	CHECK(l[4] == "      0x607a:00  32 bit  offset   16  Target position");
	CHECK_THAT(l[5], StartsWith("      0x60b0:00  32 bit  offset   48"));
	CHECK_THAT(l[6], StartsWith("      0x60b8:00  16 bit  offset   80"));
	CHECK(l[7] == "  SM3 inputs (TxPDO), 17 bytes");
	CHECK(l[8] == "    PDO 0x1a00");
	CHECK(l[9] == "      0x6041:00  16 bit  offset    0  Statusword");
	CHECK_THAT(l[10], StartsWith("      0x6061:00   8 bit  offset   16"));
	CHECK(l[11] == "      0x6064:00  32 bit  offset   24  Position actual value");
	CHECK_THAT(l[12], StartsWith("      0x60b9:00  16 bit  offset   56"));
	CHECK_THAT(l[13], StartsWith("      0x60ba:00  32 bit  offset   72"));
	CHECK_THAT(l[14], StartsWith("      0x60fd:00  32 bit  offset  104"));
}

TEST_CASE("pdos --json: the dio uses SM0/SM1 (no mailbox), the drives SM2/SM3", "[cli][pdos][json]")
{
	const auto r = run("pdos --json");
	REQUIRE(r.status == 0);
	const Json j = testjson::parse(r.out);
	REQUIRE(j.size() == 3);
	CHECK(j[0]["name"].str == "EST-584");
	CHECK(j[0]["output_bytes"].num == 12);
	CHECK(j[0]["input_bytes"].num == 17);
	CHECK(j[0]["sync_managers"][0]["sm"].num == 2);
	CHECK(j[0]["sync_managers"][0]["direction"].str == "outputs");
	CHECK(j[0]["sync_managers"][0]["pdos"][0]["index"].num == 0x1600);
	const Json &e = j[0]["sync_managers"][0]["pdos"][0]["entries"][1];
	CHECK(e["index"].num == 0x607A);
	CHECK(e["bit_length"].num == 32);
	CHECK(e["bit_offset"].num == 16);
	CHECK(j[0]["sync_managers"][1]["sm"].num == 3);
	CHECK(j[2]["output_bytes"].num == 1);
	CHECK(j[2]["sync_managers"][0]["sm"].num == 0);
	CHECK(j[2]["sync_managers"][1]["sm"].num == 1);
	CHECK(j[2]["sync_managers"][1]["direction"].str == "inputs");
}

// ------------------------------------------------------------ SII / EEPROM

TEST_CASE("sii_read -v decodes the identity words of the SII image", "[cli][sii]")
{
	const auto r = run("sii_read -p 0 -v");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("vendor id:             0x00000e5c\n"));
	CHECK_THAT(r.out, Contains("product code:          0x00000584\n"));
	CHECK_THAT(r.out, Contains("revision:              0x00010000\n"));
	CHECK_THAT(r.out, Contains("standard mailbox out:  0x1000, 128 bytes\n"));
	CHECK_THAT(r.out, Contains("standard mailbox in:   0x1080, 128 bytes\n"));
	CHECK_THAT(r.out, Contains("mailbox protocols:     0x0004 (CoE)\n"));
	CHECK_THAT(r.out, Contains("EEPROM size:           15 (2 KiB)\n"));
	const auto s = run(kServo + "sii_read -p 0 -v");
	REQUIRE(s.status == 0);
	CHECK_THAT(s.out, Contains("bootstrap mailbox out: 0x1000, 512 bytes\n"));
	CHECK_THAT(s.out, Contains("mailbox protocols:     0x000c (CoE, FoE)\n"));
}

TEST_CASE("sii_read: hex dump, end of the category list, --raw, --json", "[cli][sii]")
{
	// stdout is a pipe here: the hex dump needs --hex (binary by default)
	auto r = run("sii_read -p 2 --offset 8 --length 6 --hex");
	REQUIRE(r.status == 0);
	CHECK(r.out == "0x0008: 0e5c 0000 1088 0000 0000 0001\n");
	r = run("sii_read -p 0 --hex");
	REQUIRE(r.status == 0);
	const auto l = lines(r.out);
	REQUIRE(l.size() > 8);
	CHECK_THAT(l[0], StartsWith("0x0000: "));
	CHECK_THAT(l[1], StartsWith("0x0008: 0e5c 0000 0584 0000"));
	CHECK_THAT(l.back(), Contains("ffff")); // the category end marker ends the dump
	r = run("sii_read -p 0 --offset 8 --length 2 --raw");
	REQUIRE(r.status == 0);
	CHECK(r.out == std::string("\x5c\x0e\x00\x00", 4));
	r = run("sii_read -p 0 --offset 0x0a --length 2 --json");
	REQUIRE(r.status == 0);
	const Json j = testjson::parse(r.out);
	CHECK(j["offset"].num == 10);
	REQUIRE(j["words"].size() == 2);
	CHECK(j["words"][0].num == 0x0584);
	CHECK(j["words"][1].num == 0);
}

TEST_CASE("eeprom read / write, and write without --force", "[cli][eeprom]")
{
	auto r = run("eeprom -p 0 read 8 4");
	REQUIRE(r.status == 0);
	CHECK(r.out == "0x0008: 0e5c 0000 0584 0000\n");
	r = run("eeprom -p 1 read 0x0a --json");
	REQUIRE(r.status == 0);
	CHECK(testjson::parse(r.out)["words"][0].num == 0x0584);
	r = run("eeprom -p 0 write 4 1");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: eeprom: write changes the slave's SII EEPROM (its identity and configuration): "
		       "add --force to do it\n");
	r = run("eeprom -p 0 write 4 1 --force");
	CHECK(r.status == 0);
	CHECK(r.out.empty());
	r = run("eeprom -p 0 frob 4");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: eeprom: unknown operation 'frob' (read or write)\n");
	r = run("eeprom -p 0 write 0xffff 1 2 --force");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: eeprom: write: 2 words from 0xffff pass word 0xffff\n");
	r = run("eeprom -p 9 read 0");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: eeprom: slave position 9 out of range: the bus has 3 slaves (0..2)\n");
}

// --------------------------------------------------------------------- FoE

TEST_CASE("foe_read of the servo's log.txt, to stdout and to a file", "[cli][foe]")
{
	auto r = run(kServo + "foe_read -p 0 log.txt");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("power on"));
	CHECK_THAT(r.out, Contains("AL INIT -> PREOP"));
	const auto file = std::filesystem::temp_directory_path() /
			  ("ecmxf-test-cli-bus-" + std::to_string(getpid()) + ".log");
	r = run(kServo + "foe_read -p 1 -o " + file.string() + " log.txt");
	REQUIRE(r.status == 0);
	CHECK(r.out.empty());
	std::ifstream f(file);
	const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
	CHECK_THAT(text, Contains("power on"));
	std::filesystem::remove(file);
	// -o -: standard output, no file named '-' (issue 29; the program runs
	// in this test's working directory)
	REQUIRE_FALSE(std::filesystem::exists("-"));
	r = run(kServo + "foe_read -p 0 -o - log.txt");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("power on"));
	CHECK_FALSE(std::filesystem::exists("-"));
}

TEST_CASE("foe errors name the FoE error code and its text", "[cli][foe][errors]")
{
	// unknown name: 0x8001 not found; EST-584: no FoE
	auto r = run(kServo + "foe_read -p 0 nothing.bin");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, StartsWith("ecmxf-util: foe_read: "));
	CHECK_THAT(r.err, Contains("FoE error 0x00008001 (file not found)"));
	r = run("foe_read -p 0 log.txt");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("FoE error 0x08000000"));
	// firmware.bin is writable in BOOT only: 0x8008 in PRE-OP
	const auto dir = std::filesystem::temp_directory_path() / ("ecmxf-test-cli-bus-" + std::to_string(getpid()));
	std::filesystem::create_directories(dir);
	{
		std::ofstream f(dir / "firmware.bin");
		f << "firmware";
	}
	r = run(kServo + "foe_write -p 0 " + (dir / "firmware.bin").string());
	CHECK(r.status == 1);
	CHECK_THAT(r.err, StartsWith("ecmxf-util: foe_write: FoE write of \"firmware.bin\" to slave 0"));
	CHECK_THAT(r.err, Contains("FoE error 0x00008008"));
	std::filesystem::remove_all(dir);
	r = run("foe_write -p 0 /nonexistent/file");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: foe_write: cannot open \"/nonexistent/file\": No such file or directory\n");
}

// ------------------------------------------------------------- peripherals

TEST_CASE("gpio get: 20 input lines low at power-on, errors", "[cli][gpio]")
{
	auto r = run("gpio get");
	REQUIRE(r.status == 0);
	const auto l = lines(r.out);
	REQUIRE(l.size() == 3);
	CHECK(l[0] == "GPIO 0..19: 0x00000");
	r = run("gpio get 7");
	CHECK(r.out == "0\n");
	r = run("--json gpio get");
	const Json j = testjson::parse(r.out);
	CHECK(j["value"].num == 0);
	CHECK(j["lines"].size() == 20);
	CHECK(run("gpio set 3 1").status == 0);
	CHECK(run("gpio config 3 out --pull up --irq rising --debounce on").status == 0);
	r = run("gpio get 20");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: gpio: LINE: 20 is out of range 0..19\n");
	r = run("gpio set 3 2");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: gpio: VALUE: 2 is out of range 0..1\n");
	r = run("gpio config 3 sideways");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: gpio: config: unknown mode 'sideways' (in, out, open-drain, quasi)\n");
}

TEST_CASE("qei, adc, dac on a power-on chip", "[cli][periph]")
{
	auto r = run("qei count");
	REQUIRE(r.status == 0);
	CHECK(r.out == "count: 0 (0x00000000), position 0\n");
	r = run("qei count 0 --json");
	CHECK(testjson::parse(r.out)["count"].num == 0);
	CHECK(run("qei open --mode x2").status == 0);
	r = run("qei count 1");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: qei: CH (the ECM-XF has one encoder, channel 0): 1 is out of range 0..0\n");
	// analog inputs at 0 V read 0
	r = run("adc read 3");
	REQUIRE(r.status == 0);
	CHECK(r.out == "0 (0.0000 V)\n");
	r = run("adc read --json");
	REQUIRE(r.status == 0);
	CHECK(testjson::parse(r.out).size() == 16);
	// differential: 0 V difference reads 2048 (sim-peripherals.rst)
	r = run("adc read 4 --differential --json");
	REQUIRE(r.status == 0);
	CHECK(testjson::parse(r.out)["raw"].num == 2048);
	CHECK(run("dac write 0 2048").status == 0);
	r = run("dac write 0 4096");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: dac: VALUE: 4096 is out of range 0..4095\n");
}

TEST_CASE("emergency: none on a fresh chip, reset", "[cli][emergency][reset]")
{
	auto r = run("emergency");
	REQUIRE(r.status == 0);
	CHECK(r.out == "no emergencies\n");
	r = run("-q emergency");
	CHECK(r.out.empty());
	r = run("emergency -p 0 --json");
	REQUIRE(r.status == 0);
	CHECK(testjson::parse(r.out).size() == 0);
	r = run("reset");
	REQUIRE(r.status == 0);
	CHECK(r.out == "ASYNCCMD_RESET 0x05: async busy flag cleared, last async command abandoned\n");
	r = run("reset --warm");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: reset: --warm restarts the chip and stops the EtherCAT bus: add --force to do it\n");
	r = run("reset --warm --force");
	CHECK(r.status == 0);
	CHECK(r.out == "WARM_RESET: the chip restarted with its power-on settings\n");
}

// ------------------------------------------------------------------ cia402

TEST_CASE("cia402 status: SWITCH ON DISABLED after power-on", "[cli][cia402]")
{
	// 0x40 switch on disabled + bit 4 voltage enabled + bit 9 remote
	auto r = run("cia402 -p 0 status");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, StartsWith("statusword:  0x0250\nstate:       SWITCH ON DISABLED\n"));
	CHECK_THAT(r.out, Contains("position:    0\nvelocity:    0\n"));
	r = run("cia402 -p 1 status --json");
	REQUIRE(r.status == 0);
	const Json j = testjson::parse(r.out);
	CHECK(j["statusword"].num == 0x0250);
	CHECK(j["state"].str == "SWITCH ON DISABLED");
	CHECK(j["position_actual"].num == 0);
}

TEST_CASE("cia402 enable, disable, quick-stop, fault-reset walk the state machine", "[cli][cia402]")
{
	auto r = run("cia402 -p 0 enable --json");
	REQUIRE(r.status == 0);
	Json j = testjson::parse(r.out);
	CHECK(j["state"].str == "OPERATION ENABLED");
	CHECK((static_cast<unsigned>(j["statusword"].num) & 0x6F) == 0x27);
	r = run("cia402 -p 0 enable");
	CHECK_THAT(r.out, StartsWith("OPERATION ENABLED (statusword 0x"));
	r = run("cia402 -p 1 disable");
	REQUIRE(r.status == 0);
	CHECK(r.out == "SWITCH ON DISABLED (statusword 0x0250)\n");
	r = run("cia402 -p 0 quick-stop --json");
	REQUIRE(r.status == 0);
	j = testjson::parse(r.out);
	CHECK(j["state"].str == "QUICK STOP ACTIVE");
	CHECK((static_cast<unsigned>(j["statusword"].num) & 0x6F) == 0x07);
	// no fault: left as it is
	r = run("cia402 -p 0 fault-reset");
	REQUIRE(r.status == 0);
	CHECK(r.out == "SWITCH ON DISABLED (statusword 0x0250)\n");
}

TEST_CASE("cia402 errors: no object dictionary, unknown operation, no drive to move", "[cli][cia402][errors]")
{
	auto r = run("cia402 -p 2 status");
	CHECK(r.status == 1);
	// said as what it is not (issue 29), the abort after it
	CHECK_THAT(r.err, StartsWith("ecmxf-util: cia402: slave 2 is not a CiA-402 drive: it has no statusword "
				     "0x6041 (SDO upload 0x6041:00 from slave 2 aborted: 0x08000023"));
	r = run("cia402 -p 2 enable");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, StartsWith("ecmxf-util: cia402: slave 2 is not a CiA-402 drive"));
	r = run("cia402 -p 0 dance");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: cia402: unknown operation 'dance' (status, enable, disable, fault-reset, "
		       "quick-stop, move, home)\n");
	r = run("cia402 status");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: cia402: which slave? -p/--position N is required (try 'ecmxf-util cia402 --help')\n");
	// the I/O terminal maps no CiA-402 objects (sim-slaves.rst)
	r = run("cia402 -p 2 move --pp 1000");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, StartsWith("ecmxf-util: cia402: slave 2: Cia402Axis: not mapped: 0x6040:00 (controlword) "
				     "as an output, 0x6041:00 (statusword) as an input"));
}

// -------------------------------------------------------------------- help

TEST_CASE("every contract command is listed and has help, help COMMAND = COMMAND --help", "[cli][help]")
{
	const auto list = run("--help");
	REQUIRE(list.status == 0);
	for (const char *c : { "adc", "cia402", "dac", "download", "eeprom", "emergency", "foe_read", "foe_write",
			       "gpio", "pdos", "qei", "reset", "sii_read", "states", "upload", "master", "reg_read",
			       "reg_write", "sii_write" }) {
		CHECK_THAT(list.out, Contains(std::string("\n  ") + c + " "));
		const auto h = run(std::string(c) + " --help");
		CHECK(h.status == 0);
		CHECK_THAT(h.out, StartsWith("Usage: ecmxf-util [global options] " + std::string(c)));
		CHECK(run(std::string("help ") + c).out == h.out);
	}
	// a unique prefix; "sii" is sii_read or sii_write (as in IgH's tool)
	CHECK(run("sii_r --help").out == run("sii_read --help").out);
	const auto amb = run("sii --help");
	CHECK(amb.status == 2);
	CHECK(amb.err == "ecmxf-util: ambiguous command 'sii': sii_read, sii_write\n");
	// -q before the command
	CHECK(run("-q reset").out.empty());
}
