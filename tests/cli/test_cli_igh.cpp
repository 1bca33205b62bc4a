// SPDX-License-Identifier: MIT
// ecmxf-util for someone who knows IgH's `ethercat` tool, and bad input
// (issue 15): IgH's argument forms (-p0, --position=0, INDEX SUB, its
// --type names), reg_read / reg_write / sii_write / master, the answers for
// IgH commands the ECM-XF cannot do, states walking through SAFE-OP,
// sii_read's binary output into a pipe, monitor paced on a simulator, and
// each bad input of the issue with its message. Run as a program against
// the simulator (a fresh chip at every call); the unit part calls the
// type encoder directly. Expected values come from the simulator's
// documentation (sim-slaves.rst: EST-584 identity, AL status register),
// ETG.1000 (register 0x0130 AL status, 0x0000 ESC type) and ETG.2010 (the
// SII checksum), not from the tool's output.

#include <catch2/catch.hpp>

#include <sys/resource.h>
#include <sys/time.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

#include "cli_run.hpp"
#include "ecmxf-util.hpp"
#include "json.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using Catch::Matchers::EndsWith;
using clitest::run;
using testjson::Json;

namespace {

std::string tempPath(const std::string &name)
{
	return (std::filesystem::temp_directory_path() /
		("ecmxf-test-igh-" + std::to_string(getpid()) + "-" + name))
		.string();
}

std::vector<std::uint8_t> readFile(const std::string &path)
{
	std::ifstream f(path, std::ios::binary);
	return { std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>() };
}

void writeFile(const std::string &path, const std::vector<std::uint8_t> &b)
{
	std::ofstream f(path, std::ios::binary | std::ios::trunc);
	f.write(reinterpret_cast<const char *>(b.data()), static_cast<std::streamsize>(b.size()));
}

double childCpuSeconds()
{
	rusage ru{};
	getrusage(RUSAGE_CHILDREN, &ru);
	return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
	       static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) / 1e6;
}

} // namespace

// ------------------------------------------------------- argument forms

TEST_CASE("igh: -p0, --position=0 and -p 0 select the same slave", "[cli][igh]")
{
	// 0x1018:01 vendor id of the EST-584 (sim-slaves.rst): 0x00000e5c
	for (const char *form : { "-p 0", "-p0", "--position=0", "--position 0" }) {
		const auto r = run(std::string("upload ") + form + " 0x1018:1");
		INFO(form);
		REQUIRE(r.status == 0);
		CHECK(r.out == "0x00000e5c 3676\n");
	}
	const auto t = run("upload -p0 -tuint32 0x1018:2");
	REQUIRE(t.status == 0);
	CHECK(t.out == "1412\n"); // product code 0x584
}

TEST_CASE("igh: upload INDEX SUB and download INDEX SUB VALUE as separate arguments", "[cli][igh]")
{
	auto r = run("upload -p 0 0x1018 1");
	REQUIRE(r.status == 0);
	CHECK(r.out == "0x00000e5c 3676\n");
	r = run("upload -p 0 0x1018 2 -t uint32");
	REQUIRE(r.status == 0);
	CHECK(r.out == "1412\n");
	// 0x6081 profile velocity, uint32, writable (sim-slaves.rst)
	r = run("download -p 0 0x6081 0 1000");
	CHECK(r.status == 0);
	CHECK(r.err.empty());
	r = run("download -p 0 0x6081 0 1000 -t uint32");
	CHECK(r.status == 0);
	// the subindex given twice, too many arguments
	r = run("upload -p 0 0x1018:1 1");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: upload: INDEX:SUB '0x1018:1' and a SUB argument: give the subindex once\n");
	r = run("upload -p 0 0x1018 1 2");
	CHECK(r.status == 2);
	r = run("download -p 0 0x6081 0 1 2");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: download: too many arguments (try 'ecmxf-util download --help')\n");
}

TEST_CASE("igh: -a ALIAS [-p N] selects the N-th slave after the one with that alias", "[cli][igh]")
{
	const std::string net = tempPath("alias.net");
	{
		std::ofstream f(net);
		f << "slave dio alias=7\nslave EST-584 alias=4660\nslave EST-584\n";
	}
	const std::string d = "-d sim:" + net + " ";
	// product code: EST-584 0x584 (0x1018:02), digital I/O 0x1088 (sim-slaves.rst)
	auto r = run(d + "upload -a 4660 0x1018:2 -t uint32");
	REQUIRE(r.status == 0);
	CHECK(r.out == "1412\n");
	r = run(d + "upload -a 0x1234 -p 1 0x1018:2 -t uint32");
	REQUIRE(r.status == 0);
	CHECK(r.out == "1412\n");
	// the digital I/O has no mailbox: its product code from SII word 0x0a
	r = run(d + "sii_read -a7 --offset 0x0a --length 1 --hex");
	REQUIRE(r.status == 0);
	CHECK(r.out == "0x000a: 1088\n");
	r = run(d + "reg_read --alias=7 -p 2 -t uint16 0x0130");
	REQUIRE(r.status == 0);
	CHECK(r.out == "1\n");
	// none has it, or -p runs past the bus
	r = run(d + "upload -a 5 0x1018:2");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: upload: no slave has the alias 5 ('ecmxf-util slaves -v' shows each slave's "
		       "alias)\n");
	r = run(d + "upload -a 4660 -p 2 0x1018:2");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: upload: alias 4660 is slave 1: -p 2 after it is beyond the bus (3 slaves)\n");
	// bad values, and commands that take no -a
	r = run(d + "upload -a 0x10000 0x1018:2");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: upload: -a: 0x10000 is out of range 0..65535\n");
	r = run(d + "upload 0x1018:2 -a");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: upload: option '-a' needs a value\n");
	r = run(d + "pdos -a 7");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: -a/--alias is not taken by this command: select the slave with -p N\n");
	r = run("decode -a 7 /dev/null");
	CHECK(r.status == 2);
	std::filesystem::remove(net);
}

TEST_CASE("igh: IgH's --type names: sm8..sm64, unicode_string, raw", "[cli][igh][units]")
{
	using ecmxf_util::DataType;
	using B = std::vector<std::uint8_t>;
	// sign and magnitude: top bit the sign, the rest |value|
	CHECK(ecmxf_util::encodeValue("t", ecmxf_util::parseType("t", "sm32"), "-5") == B{ 5, 0, 0, 0x80 });
	CHECK(ecmxf_util::encodeValue("t", ecmxf_util::parseType("t", "sm16"), "300") == B{ 0x2c, 0x01 });
	CHECK(ecmxf_util::encodeValue("t", ecmxf_util::parseType("t", "sm8"), "-127") == B{ 0xff });
	CHECK_THROWS_AS(ecmxf_util::encodeValue("t", DataType::Sm8, "-128"), ecmxf_util::UsageError);
	CHECK(ecmxf_util::formatValue(DataType::Sm32, B{ 5, 0, 0, 0x80 }) == "-5");
	CHECK(ecmxf_util::formatValue(DataType::Sm16, B{ 0x2c, 0x01 }) == "300");
	CHECK(ecmxf_util::typeSize(DataType::Sm64) == 8);
	CHECK(ecmxf_util::parseType("t", "unicode_string") == DataType::String);
	CHECK(ecmxf_util::parseType("t", "raw") == DataType::OctetString);
	CHECK_THROWS_WITH(ecmxf_util::parseType("t", "int24"), Contains("unknown type 'int24'"));
	// and on the command line
	// (0x607F max profile velocity: 4 bytes, not among the standard objects
	// the tools know a type of, so -t decides)
	const auto r = run("download -p 0 0x607F 0 -5 -t sm32");
	CHECK(r.status == 0);
	CHECK(r.err.empty());
}

// ------------------------------------------------------------ commands

TEST_CASE("igh: reg_read reads ESC registers by APRD, typed or as bytes", "[cli][igh][reg]")
{
	// AL status (0x0130) after the scan: INIT = 1 (ETG.1000.4)
	auto r = run("reg_read -p 0 -t uint16 0x0130");
	REQUIRE(r.status == 0);
	CHECK(r.out == "1\n");
	r = run("reg_read -p 2 0x0130 2");
	REQUIRE(r.status == 0);
	CHECK(r.out == "01 00\n");
	r = run("reg_read -p 1 0x0130 2 --json");
	REQUIRE(r.status == 0);
	const Json j = testjson::parse(r.out);
	CHECK(j["position"].num == 1);
	CHECK(j["address"].num == 0x130);
	CHECK(j["wkc"].num == 1);
	CHECK(j["hex"].str == "0100");
	// bad input
	r = run("reg_read -p 0 0x0130");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: reg_read: how many bytes? give SIZE or -t TYPE\n");
	r = run("reg_read -p 0 0xffff 2");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: reg_read: 2 bytes from 0xffff pass register 0xffff\n");
	r = run("reg_read -p 0 0x0130 257");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: reg_read: SIZE: 257 is out of range 1..256\n");
	r = run("reg_read -p 0 -t uint16 0x0130 4");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: reg_read: SIZE 4 does not match type uint16\n");
	r = run("reg_read -p 7 0x0130 2");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: reg_read: slave position 7 out of range: the bus has 3 slaves (0..2)\n");
}

TEST_CASE("igh: reg_write writes by APWR, bad DATA is refused before the bus", "[cli][igh][reg]")
{
	auto r = run("reg_write -p 0 0x0f80 0a0b");
	CHECK(r.status == 0);
	CHECK(r.out.empty());
	r = run("reg_write -p 0 -t uint16 0x0f80 0x1234");
	CHECK(r.status == 0);
	r = run("reg_write -p 0 0x0f80 zz");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("reg_write: VALUE: 'zz' is not hex bytes"));
	r = run("reg_write -p 0 -t uint8 0x0f80 256");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: reg_write: VALUE: 256 is out of range 0..255\n");
	r = run("reg_write -p 0 0x0f80");
	CHECK(r.status == 2);
}

TEST_CASE("igh: sii_write takes sii_read's binary image, checksum, size and directory errors", "[cli][igh][sii]")
{
	const std::string img = tempPath("sii.bin");
	// sii_read into a file writes the binary image (as IgH's tool)
	auto r = run("sii_read -p 0 >" + img);
	REQUIRE(r.status == 0);
	std::vector<std::uint8_t> b = readFile(img);
	REQUIRE(b.size() >= 16);
	REQUIRE(b.size() % 2 == 0);
	// word 8..9 vendor id 0x00000e5c (ETG.2010, sim-slaves.rst)
	CHECK(b[16] == 0x5c);
	CHECK(b[17] == 0x0e);
	r = run("sii_write -p 1 " + img);
	CHECK(r.status == 0);
	CHECK(r.err == "ecmxf-util: sii_write: " + std::to_string(b.size() / 2) + " words written to slave 1\n");
	// a wrong checksum (word 7) is refused, --force writes it
	b[14] ^= 0xff;
	writeFile(img, b);
	r = run("sii_write -p 1 " + img);
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("configuration area checksum (word 7)"));
	CHECK_THAT(r.err, Contains("--force"));
	r = run("sii_write -p 1 --force -q " + img);
	CHECK(r.status == 0);
	CHECK(r.err.empty());
	// odd size, too short, too large, a directory
	writeFile(img, { 1, 2, 3 });
	r = run("sii_write -p 1 " + img);
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("has 3 bytes: an SII image is whole 16-bit words"));
	writeFile(img, { 1, 2, 3, 4 });
	r = run("sii_write -p 1 " + img);
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("at least the 8 words"));
	r = run("sii_write -p 1 /dev/zero");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: sii_write: \"/dev/zero\" is larger than an SII EEPROM (65536 words)\n");
	r = run("sii_write -p 1 /tmp");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: sii_write: \"/tmp\" is a directory, not a file\n");
	std::filesystem::remove(img);
}

TEST_CASE("igh: master shows phase, slaves, link and counters", "[cli][igh]")
{
	auto r = run("master");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, StartsWith("Master0\n  Device: sim:\n  Phase: Idle (no network initialised)\n"
				     "  Slaves: 0\n  Link: UP\n"));
	// a good link is no error: bits 0 and 1 of the error status are the link
	CHECK_THAT(r.out, Contains("  Link: UP\n  Error status: none\n"));
	CHECK_THAT(r.out, !Contains("(bit 0)"));
	CHECK_THAT(r.out, Contains("    SPI CRC errors: 0\n    WKC errors: 0\n"));
	r = run("master --json");
	REQUIRE(r.status == 0);
	const Json j = testjson::parse(r.out);
	CHECK(j["slaves"].num == 0);
	CHECK(j["link"].b);
	CHECK(j["wkc_errors"].num == 0);
}

TEST_CASE("igh: pdos --cstruct and --xml print the mapping as IgH's cstruct and xml do", "[cli][igh]")
{
	// slave 0 of the default network: an EST-584 (sim-slaves.rst: vendor
	// 0x00000e5c, product 0x00000584; RxPDO 0x1600 of 4 entries from
	// Controlword 0x6040, TxPDO 0x1A00 of 6 from Statusword 0x6041)
	auto r = run("pdos -p 0 --cstruct");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, StartsWith("/* Slave 0, \"EST-584\"\n * Vendor ID:       0x00000e5c\n"
				     " * Product code:    0x00000584\n"));
	CHECK_THAT(r.out, Contains("ec_pdo_entry_info_t slave_0_pdo_entries[] = {\n    {0x6040, 0x00, 16}, /* Controlword */\n"));
	CHECK_THAT(r.out, Contains("ec_pdo_info_t slave_0_pdos[] = {\n    {0x1600, 4, slave_0_pdo_entries + 0},\n"
				   "    {0x1a00, 6, slave_0_pdo_entries + 4},\n};"));
	CHECK_THAT(r.out, Contains("    {2, EC_DIR_OUTPUT, 1, slave_0_pdos + 0, EC_WD_ENABLE},\n"
				   "    {3, EC_DIR_INPUT, 1, slave_0_pdos + 1, EC_WD_DISABLE},\n    {0xff}\n};"));
	r = run("pdos -p 0 --xml");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, StartsWith("<?xml version=\"1.0\" ?>\n<EtherCATInfo>\n"));
	CHECK_THAT(r.out, Contains("<Type ProductCode=\"#x00000584\" RevisionNo=\"#x00010000\">EST-584</Type>"));
	CHECK_THAT(r.out, Contains("<RxPdo Sm=\"2\" Fixed=\"1\" Mandatory=\"1\">\n          <Index>#x1600</Index>\n"
				   "          <Entry>\n            <Index>#x6040</Index>\n            <SubIndex>0</SubIndex>\n"
				   "            <BitLen>16</BitLen>\n            <Name>Controlword</Name>\n"));
	CHECK_THAT(r.out, EndsWith("</EtherCATInfo>\n"));
	// IgH's command names give the same
	auto c = run("cstruct -p 0");
	REQUIRE(c.status == 0);
	CHECK(c.out == run("pdos -p 0 --cstruct").out);
	// without -p: one document, every slave's EtherCATInfo in a list
	{
		const auto all = run("xml");
		REQUIRE(all.status == 0);
		CHECK_THAT(all.out, StartsWith("<?xml version=\"1.0\" ?>\n<EtherCATInfoList>\n<EtherCATInfo>\n"));
		CHECK_THAT(all.out, EndsWith("</EtherCATInfo>\n</EtherCATInfoList>\n"));
		std::size_t decls = 0, infos = 0;
		for (std::size_t at = 0; (at = all.out.find("<?xml", at)) != std::string::npos; at++)
			decls++;
		for (std::size_t at = 0; (at = all.out.find("<EtherCATInfo>", at)) != std::string::npos; at++)
			infos++;
		CHECK(decls == 1);
		CHECK(infos == 3);
	}
	c = run("xml -p 0");
	REQUIRE(c.status == 0);
	CHECK(c.out == run("pdos -p 0 --xml").out);
	for (const char *bad : { "cstruct --xml", "xml --cstruct", "cstruct --bogus", "xml -p 99", "--json xml" }) {
		c = run(bad);
		INFO(bad);
		CHECK(c.status != 0);
		CHECK(c.out.empty());
	}
	// one output form at a time
	for (const char *bad : { "pdos --cstruct --xml", "pdos --json --xml", "pdos --cstruct --json" }) {
		r = run(bad);
		INFO(bad);
		CHECK(r.status == 2);
		CHECK_THAT(r.err, Contains("--json, --cstruct and --xml exclude each other"));
	}
}

TEST_CASE("igh: every IgH command the ECM-XF cannot do says what to use instead", "[cli][igh]")
{
	const std::pair<const char *, const char *> cases[] = {
		{ "sdos", "no SDO information service" }, { "domains", "no domains" },
		{ "alias", "eeprom -p N write 4" },
		{ "config", "ecmxf-util pdos" },	  { "crc", "ecmxf-util master" },
		{ "debug", "--trace FILE" },		  { "eoe", "no Ethernet over EtherCAT" },
		{ "graph", "slaves" },			  { "ip", "no Ethernet over EtherCAT" },
		{ "rescan", "ecmxf-util reset" },	  { "soe_read", "no Servo Drive over EtherCAT" },
		{ "soe_write", "ecmxf-util download" },
	};
	for (const auto &[cmd, hint] : cases) {
		const auto r = run(cmd);
		INFO(cmd);
		CHECK(r.status == 2);
		CHECK_THAT(r.err, StartsWith(std::string("ecmxf-util: '") + cmd +
					     "' is an IgH ethercat command that ecmxf-util does not have: "));
		CHECK_THAT(r.err, Contains(hint));
		CHECK_THAT(r.err, !Contains("unknown command"));
	}
	// a name that is neither ours nor IgH's stays unknown
	const auto r = run("frobnicate");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: unknown command 'frobnicate' (try --help)\n");
}

TEST_CASE("igh: states -p N OP from PRE-OP walks through SAFE-OP", "[cli][igh][states]")
{
	// a fresh bus with -p is brought to PRE-OP; OP straight from PRE-OP
	// is refused by an EtherCAT slave (AL status 0x0011)
	auto r = run("states -p 1 OP");
	REQUIRE(r.status == 0);
	CHECK(r.out == "1    OP     +\n");
	CHECK(r.err.empty());
	r = run("states -p 0 OP --json");
	REQUIRE(r.status == 0);
	const Json j = testjson::parse(r.out);
	REQUIRE(j["slaves"].size() == 1);
	CHECK(j["slaves"][0]["state"].str == "OP");
	CHECK(j["slaves"][0]["al_status_code"].num == 0);
}

TEST_CASE("igh: sii_read writes the binary image into a pipe, --hex the dump", "[cli][igh][sii]")
{
	auto r = run("sii_read -p 0 --offset 8 --length 2");
	REQUIRE(r.status == 0);
	CHECK(r.out == std::string("\x5c\x0e\x00\x00", 4));
	r = run("sii_read -p 0 --offset 8 --length 2 --hex");
	REQUIRE(r.status == 0);
	CHECK(r.out == "0x0008: 0e5c 0000\n");
	r = run("sii_read -p 0 --raw --hex");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: sii_read: --raw and --hex exclude each other\n");
}

namespace {

/// The CPU seconds of a monitor run for a second, then stopped by @p sig
/// (its stderr joins stdout: run()'s 2> redirects the last command only).
std::pair<clitest::Result, double> monitorForASecond(const std::string &options, const char *sig)
{
	const double cpu0 = childCpuSeconds();
	const auto r = run("monitor " + options + " 2>&1 & pid=$!; sleep 1; kill -" + sig + " $pid; wait $pid");
	return { r, childCpuSeconds() - cpu0 };
}

} // namespace

TEST_CASE("igh: monitor on a simulator without a bound is paced to the wall clock", "[cli][igh][monitor]")
{
	const auto [r, cpu] = monitorForASecond("", "INT");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("paced to the wall clock"));
	// spinning in virtual time would take a core for the whole second
	CHECK(cpu < 0.5);
	// with --duration it is paced too, and says nothing
	const auto b = run("monitor --duration 300 --json");
	CHECK(b.status == 0);
	CHECK_THAT(b.err, !Contains("paced"));
}

TEST_CASE("igh: monitor --count on a quiet simulated bus is paced too (issue 29)", "[cli][igh][monitor]")
{
	// --count 1 on a bus where nothing happens: the count is never
	// reached (it used to spin a core polling in virtual time)
	const auto [r, cpu] = monitorForASecond("--count 1", "TERM");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, Contains("paced to the wall clock"));
	CHECK(cpu < 0.5);
}

// ------------------------------------------------------------ bad input

TEST_CASE("bad input: integers out of range, negative into unsigned, nan and inf into integers (issue 29)",
	  "[cli][igh][errors]")
{
	// -t: the type's range, named
	auto r = run("download -p 0 0x2001 0 -30000 -t uint16");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: download: VALUE: -30000 is out of range 0..65535\n");
	r = run("download -p 0 0x2001 0 65536 -t uint16");
	CHECK(r.err == "ecmxf-util: download: VALUE: 65536 is out of range 0..65535\n");
	r = run("download -p 0 0x6060 -129 -t int8");
	CHECK(r.err == "ecmxf-util: download: VALUE: -129 is out of range -128..127\n");
	for (const char *v : { "nan", "inf", "-inf", "1.5", "1e3" }) {
		INFO(v);
		r = run(std::string("download -p 0 0x607F -t uint32 -- ") + v);
		CHECK(r.status == 2);
		CHECK_THAT(r.err, Contains("is not a number"));
		r = run(std::string("download -p 0 0x607F -t int32 -- ") + v);
		CHECK(r.status == 2);
	}
	// without -t, a standard object: its CiA 402 type decides
	r = run("download -p 0 0x6081 0 -5");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: download: VALUE: -5 is out of range 0..4294967295 (0x6081:00 Profile velocity "
		       "is UNSIGNED32)\n");
	r = run("download -p 0 0x6060 200");
	CHECK(r.err == "ecmxf-util: download: VALUE: 200 is out of range -128..127 (0x6060:00 Modes of operation is "
		       "INTEGER8)\n");
	r = run("download -p 0 0x607A -5000"); // INTEGER32: taken (sim: is fresh at every run: no read-back)
	CHECK(r.status == 0);
	CHECK(r.err.empty());
	// with -t too: the value must fit the object's type, and -t be an integer
	r = run("download -p 0 0x6081 -5 -t int32");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("-5 is out of range 0..4294967295 (0x6081:00 Profile velocity is UNSIGNED32)"));
	r = run("download -p 0 0x6081 nan -t float");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: download: -t float: 0x6081:00 Profile velocity is UNSIGNED32 (CiA 402), an "
		       "integer\n");
	// without -t, an object of 2 bytes and no known type: no negative VALUE
	r = run("download -p 0 0x2001 0 -30000");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: download: VALUE -30000: slave 0 0x2001:00 has 2 bytes and a type the master "
		       "cannot learn (no SDO information service): give -t int16 if it is signed\n");
	r = run("download -p 0 0x2001 0 70000");
	CHECK(r.err == "ecmxf-util: download: VALUE: 70000 is out of range 0..65535\n");
	r = run("download -p 0 0x2001 0 51200");
	CHECK(r.status == 0);
	CHECK(r.err.empty());
}

TEST_CASE("bad input: float and double VALUEs out of range, NaN and inf only when spelled", "[cli][igh][errors]")
{
	auto r = run("download -p 0 0x6081 1e99 -t float");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, StartsWith("ecmxf-util: download: VALUE: 1e99 is out of range for float"));
	r = run("download -p 0 0x6081 -1e39 -t float");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("out of range for float"));
	r = run("download -p 0 0x6081 1e-50 -t float");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("out of range for float"));
	r = run("download -p 0 0x6081 1e999 -t double");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("out of range for double"));
	r = run("download -p 0 0x6081 1.5x -t float");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("'1.5x' is not a real number"));
	r = run("download -p 0 0x6081 'nan(1)' -t float");
	CHECK(r.status == 2);
	// spelled out: taken (by an object whose type the tools do not know;
	// 0x6081 is UNSIGNED32 in CiA 402: no float there)
	for (const char *v : { "inf", "-inf", "nan", "-Infinity", "3.4e38", "0", "-1.5" }) {
		r = run(std::string("download -p 0 -t float 0x607F -- ") + v);
		INFO(v);
		CHECK(r.status == 0);
	}
	using ecmxf_util::DataType;
	using B = std::vector<std::uint8_t>;
	CHECK(ecmxf_util::encodeValue("t", DataType::Float, "inf") == B{ 0, 0, 0x80, 0x7f });
	CHECK(ecmxf_util::encodeValue("t", DataType::Float, "-inf") == B{ 0, 0, 0x80, 0xff });
	const B nan = ecmxf_util::encodeValue("t", DataType::Float, "nan");
	float f;
	std::memcpy(&f, nan.data(), 4);
	CHECK(std::isnan(f));
	CHECK_THROWS_AS(ecmxf_util::encodeValue("t", DataType::Float, "1e99"), ecmxf_util::UsageError);
	CHECK(ecmxf_util::encodeValue("t", DataType::Double, "1e99").size() == 8);
}

TEST_CASE("bad input: foe_write of /dev/zero stops at the FoE flash size, a directory is named", "[cli][igh][errors]")
{
	auto r = run("foe_write -p 0 /dev/zero");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: foe_write: \"/dev/zero\" is larger than the chip's FoE staging flash (262144 "
		       "bytes)\n");
	r = run("foe_write -p 0 /tmp");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: foe_write: \"/tmp\" is a directory, not a file\n");
	CHECK_THAT(r.err, !Contains("basic_filebuf"));
}

TEST_CASE("bad input: sim: with a directory or an empty network file says so", "[cli][igh][errors]")
{
	auto r = run("-d sim:/tmp slaves");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: slaves: cannot open \"sim:/tmp\": network file '/tmp' is a directory\n");
	const std::string empty = tempPath("empty.net");
	writeFile(empty, {});
	r = run("-d sim:" + empty + " slaves");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("the network has no slaves"));
	CHECK_THAT(r.err, !Contains("ECAT_INIT_OP"));
	writeFile(empty, { '#', ' ', 'n', 'o', 'n', 'e', '\n' });
	r = run("-d sim:" + empty + " slaves");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("the network has no slaves"));
	std::filesystem::remove(empty);
}

TEST_CASE("bad input: download of a missing object names the download", "[cli][igh][errors]")
{
	const auto r = run("download -p 0 0x7777 5");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, StartsWith("ecmxf-util: download: SDO download 0x7777:00 to slave 0: its size could not "
				     "be read (give -t TYPE to skip that): "));
	CHECK_THAT(r.err, Contains("0x06020000 Object not existing"));
}

TEST_CASE("bad input: output that cannot be written fails with exit 1", "[cli][igh][errors]")
{
	for (const char *cmd : { "slaves", "commands", "version", "master --json", "sii_read -p 0 --hex" }) {
		const auto r = run(std::string(cmd) + " >/dev/full");
		INFO(cmd);
		CHECK(r.status == 1);
		CHECK_THAT(r.err, Contains("ecmxf-util: cannot write to standard output: No space left on device"));
	}
	// --help too, and a usage error keeps its exit code 2
	auto r = run("slaves --help >/dev/full");
	CHECK(r.status == 1);
	r = run("frobnicate >/dev/full");
	CHECK(r.status == 2);
}

TEST_CASE("smaller (issue 29): version --json, decode of a directory", "[cli][igh]")
{
	auto r = run("version --json");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, StartsWith("{\"version\": \""));
	CHECK(testjson::parse(r.out)["version"].str.size() > 0);
	r = run("decode /tmp");
	CHECK(r.status == 1);
	CHECK(r.err == "ecmxf-util: decode: \"/tmp\" is a directory, not a trace file\n");
}
