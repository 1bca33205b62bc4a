// SPDX-License-Identifier: MIT
// ecmxf-util run as a separate program: global options, command prefixes,
// exit codes, and `info` / `slaves` against the simulator's default
// network (2 x EST-584 + 1 x dio). The expected values come from the
// simulator's documentation and public constants (ChipConfig defaults,
// sim_slaves.hpp identities, Documentation/sim-slaves.rst), not from the
// tool's own output.

#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <ecmxf/protocol.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/slaves.hpp>

#include "cli_run.hpp"
#include "json.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

using clitest::lines;
using clitest::Result;
using clitest::run;

using testjson::Json;

Json parseJson(const std::string &s)
{
	return testjson::parse(s);
}

} // namespace

TEST_CASE("info reports the simulator's power-on firmware, format, status and counters",
	  "[cli][info]")
{
	const Result r = run("info");
	REQUIRE(r.status == 0);
	CHECK(r.err.empty());
	const unsigned fw = ecmxf::sim::ChipConfig{}.fwVersion; // 0x30
	char buf[64];
	std::snprintf(buf, sizeof(buf), "firmware version:  %u (0x%02x)\n", fw, fw);
	CHECK_THAT(r.out, Contains(buf));
	CHECK_THAT(r.out, Contains("series:            0 (ECM-XF)\n"));
	CHECK_THAT(r.out, Contains("build id:          ecmxf-simulator\n"));
	// 112-byte data section; packet = 16-byte header + data + 16-byte trailer
	CHECK_THAT(r.out, Contains("data size:         112 (packet 144 bytes)\n"));
	CHECK_THAT(r.out, Contains("extended version:  0\n"));
	// ECAT_WKC_CONTI_ERR_CNT_GET 0; limit 255 = none (power-on)
	CHECK_THAT(r.out, Contains("WKC continuous:    0 (limit none)\n"));
	CHECK_THAT(r.out, Contains("check type:        fixed\n"));
	// no CRC was ever in force: nothing to tell the coverages apart
	CHECK_THAT(r.out, Contains("CRC coverage:      unknown\n"));
	// before INIT_OP: no network; link present (bit 0); FIFO enabled at power-on
	CHECK_THAT(r.out, Contains("ECAT state:        NONE (0x00)\n"));
	CHECK_THAT(r.out, Contains("error status:      0x01 (link)\n"));
	CHECK_THAT(r.out, Contains("ECM status:        0x40 (FIFO enabled)\n"));
	CHECK_THAT(r.out, Contains("SPI CRC errors:    0\n"));
	CHECK_THAT(r.out, Contains("WKC errors:        0\n"));
	CHECK_THAT(r.out, Contains("slaves:            0\n"));
}

TEST_CASE("info --json (and the global --json) is one JSON object with the same values",
	  "[cli][info][json]")
{
	for (const char *args : { "info --json", "--json info" }) {
		const Result r = run(args);
		REQUIRE(r.status == 0);
		const Json j = parseJson(r.out);
		REQUIRE(j.kind == Json::Object);
		CHECK(j["firmware_version"].num == ecmxf::sim::ChipConfig{}.fwVersion);
		CHECK(j["series"].num == 0);
		CHECK(j["build_id"].str == "ecmxf-simulator");
		CHECK(j["data_size"].num == 112);
		CHECK(j["check_type"].str == "fixed");
		CHECK(j["crc_coverage"].str == "unknown");
		CHECK(j["ecat_state"].num == 0);
		CHECK(j["error_status"].num == 1);
		REQUIRE(j["error_bits"].arr.size() == 1);
		CHECK(j["error_bits"].arr[0].str == "link");
		CHECK(j["ecm_status"].num == 0x40);
		CHECK(j["spi_crc_errors"].num == 0);
		CHECK(j["wkc_errors"].num == 0);
		CHECK(j["slaves"].num == 0);
		CHECK(j["device"].str == "sim:");
	}
}

namespace {

/// The default network with chip lines, in a file removed at the end.
struct NetFile {
	std::string path;
	explicit NetFile(const std::string &chipLines)
	{
		static int serial = 0;
		path = (std::filesystem::temp_directory_path() /
			("ecmxf-test-cli-" + std::to_string(getpid()) + "-" + std::to_string(serial++) + ".net"))
			       .string();
		std::ofstream f(path);
		f << "slave EST-584\nslave EST-584\nslave dio\n" << chipLines;
	}
	~NetFile() { std::filesystem::remove(path); }
	NetFile(const NetFile &) = delete;
	NetFile &operator=(const NetFile &) = delete;
};

} // namespace

TEST_CASE("a sim: URI with check=crc32 switches the chip to CRC-32 at open, under either CRC coverage",
	  "[cli][variants]")
{
	// 0x2001:0 of the EST-584: 50000 (sim-slaves.rst)
	Result r = run("-d 'sim:?check=crc32' upload -p 0 0x2001:0");
	REQUIRE(r.status == 0);
	CHECK(r.err.empty());
	CHECK_THAT(r.out, Contains(" 50000\n"));
	r = run("-d 'sim:?check=crc32' info");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("check type:        CRC-32\n"));
	CHECK_THAT(r.out, Contains("CRC coverage:      frame\n"));
	CHECK_THAT(r.out, Contains("SPI CRC errors:    0\n"));

	for (const char *variant : { "chip crc32-coverage=valid\n",
				     "chip crc32-coverage=valid crc-type-set-fixed=accept\n",
				     "chip crc32-coverage=frame crc-type-set-fixed=accept\n" }) {
		INFO(variant);
		const NetFile net(variant);
		const bool valid = std::string(variant).find("=valid") != std::string::npos;
		r = run("-d 'sim:" + net.path + "?check=crc32' upload -p 0 0x2001:0");
		REQUIRE(r.status == 0);
		CHECK_THAT(r.out, Contains(" 50000\n"));
		r = run("--json -d 'sim:" + net.path + "?check=crc32' info");
		REQUIRE(r.status == 0);
		const Json j = parseJson(r.out);
		CHECK(j["check_type"].str == "CRC-32");
		CHECK(j["crc_coverage"].str == (valid ? "valid" : "frame"));
		CHECK(j["spi_crc_errors"].num == 0);
	}
	// the other check words of the codec
	for (const char *type : { "fixed", "crc8", "ccitt" }) {
		r = run(std::string("-d 'sim:?check=") + type + "' upload -p 1 0x2001:0");
		REQUIRE(r.status == 0);
		CHECK_THAT(r.out, Contains(" 50000\n"));
	}
}

TEST_CASE("a bad check= value or chip line is an error naming the value", "[cli][variants]")
{
	Result r = run("-d 'sim:?check=crc64' info");
	CHECK(r.status != 0);
	CHECK(r.out.empty());
	CHECK_THAT(r.err, Contains("bad check value \"crc64\": expected fixed, crc8, ccitt or crc32"));
	const NetFile net("chip crc32-coverage=half\n");
	r = run("-d 'sim:" + net.path + "?check=crc32' info");
	CHECK(r.status != 0);
	CHECK_THAT(r.err, Contains(net.path + ":4: chip option crc32-coverage: bad value 'half' (expected frame or valid)"));
	r = run("-d '/dev/ecmxf0?check=crc32' info");
	CHECK(r.status != 0);
	CHECK_THAT(r.err, Contains("option \"check\" applies to spidev: URIs only"));
}

TEST_CASE("slaves scans the default network and lists 3 slaves in INIT in bus order",
	  "[cli][slaves]")
{
	const Result r = run("slaves");
	REQUIRE(r.status == 0);
	CHECK(r.err.empty()); // the scan is mentioned only with -v
	const auto l = lines(r.out);
	REQUIRE(l.size() == 3);
	// position, alias:relative position, state, no error, vendor:product, name
	CHECK(l[0] == "0    0:0      INIT   +  0x00000e5c:0x00000584  EST-584");
	CHECK(l[1] == "1    0:1      INIT   +  0x00000e5c:0x00000584  EST-584");
	CHECK(l[2] == "2    0:2      INIT   +  0x00000e5c:0x00001088  Digital I/O 8 out / 8 in");
}

TEST_CASE("slaves -v adds revision, station address, AL status code and process data sizes",
	  "[cli][slaves]")
{
	const Result r = run("slaves -v");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.err, Contains("ECAT_INIT_OP"));
	const auto l = lines(r.out);
	REQUIRE(l.size() == 4);
	CHECK_THAT(l[0], StartsWith("POS  ALIAS"));
	CHECK_THAT(l[0], Contains("REVISION"));
	// stations 0x1001 + position; EST-584 12/17 bytes, dio 1/1; ESC
	// features 0x000C (DC) for the drives, 0 for the dio (sim-slaves.rst)
	// (SLV_INFO_GET 10); the scan ran without DC: SYNC0 cycle and shift 0,
	// not active (SLV_INFO_GET 11..13, commands-bus.rst)
	CHECK_THAT(l[0], Contains("  DC     CYCLE NS    SHIFT NS  ACT  NAME"));
	CHECK(l[1] == "0    0:0      INIT   +  0x00000e5c:0x00000584  0x00010000  0x1001  0x0000     12    17  yes           0           0  no   EST-584");
	CHECK(l[2] == "1    0:1      INIT   +  0x00000e5c:0x00000584  0x00010000  0x1002  0x0000     12    17  yes           0           0  no   EST-584");
	CHECK(l[3] == "2    0:2      INIT   +  0x00000e5c:0x00001088  0x00010000  0x1003  0x0000      1     1  no            0           0  no   Digital I/O 8 out / 8 in");
}

TEST_CASE("slaves --json is an array of 3 objects with the models' identities", "[cli][slaves][json]")
{
	namespace m = ecmxf::sim::model;
	const Result r = run("slaves --json");
	REQUIRE(r.status == 0);
	const Json j = parseJson(r.out);
	REQUIRE(j.kind == Json::Array);
	REQUIRE(j.arr.size() == 3);
	const std::uint32_t product[] = { m::kEst584Product, m::kEst584Product, m::kDioProduct };
	const std::uint32_t revision[] = { m::kEst584Revision, m::kEst584Revision, m::kDioRevision };
	const unsigned out[] = { 12, 12, 1 }, in[] = { 17, 17, 1 };
	for (std::size_t i = 0; i < 3; i++) {
		const Json &s = j.arr[i];
		CHECK(s["position"].num == static_cast<double>(i));
		CHECK(s["vendor_id"].num == m::kVendorId);
		CHECK(s["product_code"].num == product[i]);
		CHECK(s["revision"].num == revision[i]);
		CHECK(s["state"].str == "INIT");
		CHECK(s["al_state"].num == 1);
		CHECK(s["error"].kind == Json::Bool);
		CHECK_FALSE(s["error"].b);
		CHECK(s["alias"].num == 0);
		CHECK(s["station_address"].num == 0x1001 + static_cast<double>(i));
		CHECK(s["al_status_code"].num == 0);
		CHECK(s["output_bytes"].num == out[i]);
		CHECK(s["input_bytes"].num == in[i]);
	}
	CHECK(j.arr[0]["name"].str == "EST-584");
	CHECK(j.arr[2]["name"].str == "Digital I/O 8 out / 8 in");
}

TEST_CASE("a device URI whose network file does not exist fails with exit code 1 naming the file",
	  "[cli][errors]")
{
	const Result r = run("-d sim:/nonexistent.net info");
	CHECK(r.status == 1);
	CHECK(r.out.empty());
	CHECK_THAT(r.err, StartsWith("ecmxf-util: "));
	CHECK_THAT(r.err, Contains("/nonexistent.net"));
}

TEST_CASE("usage errors exit with code 2: unknown command, option or argument", "[cli][errors]")
{
	Result r = run("frobnicate");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, StartsWith("ecmxf-util: unknown command 'frobnicate'"));
	r = run("--frob info");
	CHECK(r.status == 2);
	r = run("info --frob");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("'--frob'"));
	r = run("");
	CHECK(r.status == 2);
}

TEST_CASE("unambiguous prefixes select a command", "[cli]")
{
	const Result full = run("slaves");
	const Result prefix = run("sl");
	REQUIRE(prefix.status == 0);
	CHECK(prefix.out == full.out);
	const Result i = run("in --json");
	REQUIRE(i.status == 0);
	CHECK(parseJson(i.out)["data_size"].num == 112);
}

TEST_CASE("--help and COMMAND --help print usage and exit 0", "[cli][help]")
{
	Result r = run("--help");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, StartsWith("Usage: ecmxf-util"));
	CHECK_THAT(r.out, Contains("info"));
	CHECK_THAT(r.out, Contains("slaves"));
	r = run("info --help");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, StartsWith("Usage: ecmxf-util [global options] info"));
	r = run("slaves --help");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, StartsWith("Usage: ecmxf-util [global options] slaves"));
	r = run("-V");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, StartsWith("ecmxf-util "));
}

// ---------------------------------------------------------------------------
// decode and --trace
// ---------------------------------------------------------------------------

namespace {

/// A 144-byte packet in trace hex: header, 112 zero data bytes, trailer.
std::string tracePacket(const std::string &head, const std::string &tail)
{
	return head + std::string(224, '0') + tail;
}

/// A temporary file with @p text, removed by the destructor.
struct TempFile {
	explicit TempFile(const std::string &tag, const std::string &text = {})
		: path((std::filesystem::temp_directory_path() /
			("ecmxf-test-cli-" + std::to_string(getpid()) + "-" + tag + ".trace"))
			       .string())
	{
		if (!text.empty())
			std::ofstream(path) << text;
	}
	~TempFile() { std::filesystem::remove(path); }
	std::string path;
};

// tests/golden/test_golden.cpp: 1b. INFO_UPDATE_OP index 0x01 CRC-32, and
// R1. the ECAT_STATE_GET answer with every header field distinct, CRC-32
const std::string kGoldenTrace =
	"ecmxf-trace 1\n"
	"format 112 crc32\n"
	"0.000010000 > " +
	tracePacket("a4a3a2a1 00000000 00000001 00000000 00000000 00000000", "7f86455e 59585756") +
	"\n"
	"0.000034000 < " +
	tracePacket("a4a3a2a1 01020304 08011f07 0d080000 00000080 01005a03", "1c6cb413 59585756") + "\n";

} // namespace

TEST_CASE("decode prints a hand-written golden trace as the exact protocol log", "[cli][decode]")
{
	const TempFile f("golden", kGoldenTrace);
	const Result r = run("decode " + f.path);
	REQUIRE(r.status == 0);
	CHECK(r.err.empty());
	CHECK(r.out ==
	      "#1 0.000010000 host>chip 144 bytes: INFO_UPDATE_OP (0x00), index 0x01\n"
	      "    param 0x00, len 0, data 00 00 00 00, reserved 0x0000\n"
	      "    control 0x00, int clear 0x00000000, GPIO int clear 0x00 0x00, GPIO out 0x00 0x00\n"
	      "    check word 0x5E45867F: OK (CRC-32)\n"
	      "#1 0.000034000 chip>host 144 bytes: answers ECAT_STATE_GET (0x0D), index 0x07 (not sent in this trace)\n"
	      "    ECAT state OP (0x08), error status 0x01 (link), ECM status 0x1F (check CRC-32, DC stable, "
	      "Ethernet initialised, PDO configured)\n"
	      "    CRC errors 1, WKC errors 2, TxFIFO 3, RxFIFO 4\n"
	      "    index 0x07, code 0x0D ECAT_STATE_GET, ret 0x08 (8), len 0\n"
	      "    int flags 0x80000000 (EtherCAT packet), GPIO int flags 0x01 0x00, GPIO in 0x5A 0x03\n"
	      "    check word 0x13B46C1C: OK (CRC-32)\n"
	      "2 packets: 1 commands, 1 responses, 0 bad (0 not ready)\n");
}

TEST_CASE("decode --json is a JSON array with one object per packet", "[cli][decode][json]")
{
	const TempFile f("json", kGoldenTrace);
	for (const std::string &args : { "decode --json " + f.path, "--json decode " + f.path }) {
		const Result r = run(args);
		REQUIRE(r.status == 0);
		const Json j = parseJson(r.out);
		REQUIRE(j.kind == Json::Array);
		REQUIRE(j.arr.size() == 2);
		CHECK(j.arr[0]["dir"].str == "mosi");
		CHECK(j.arr[0]["name"].str == "INFO_UPDATE_OP");
		CHECK(j.arr[0]["index"].num == 1);
		CHECK(j.arr[0]["check"].str == "ok");
		CHECK(j.arr[1]["dir"].str == "miso");
		CHECK(j.arr[1]["code"].num == 0x0D);
		CHECK(j.arr[1]["ecat_state"].num == 8);
		CHECK(j.arr[1]["ecm_status"].num == 0x1F);
		CHECK(j.arr[1]["int_flags"].num == 2147483648.0);
		CHECK(j.arr[1]["answers"].kind == Json::Null);
		CHECK(j.arr[1]["time_ns"].num == 34000);
	}
}

TEST_CASE("decode reports a corrupted check word as BAD and counts it", "[cli][decode]")
{
	std::string text = kGoldenTrace;
	const auto at = text.find("7f86455e");
	REQUIRE(at != std::string::npos);
	text.replace(at, 8, "7f86455f");
	const TempFile f("bad", text);
	const Result r = run("decode " + f.path);
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("    check word 0x5F45867F: BAD (CRC-32 expected 0x5E45867F, got 0x5F45867F)\n"));
	CHECK_THAT(r.out, Contains("2 packets: 1 commands, 1 responses, 1 bad (0 not ready)\n"));
}

TEST_CASE("decode errors: no file (usage, 2), a missing file and a non-trace (1)", "[cli][decode][errors]")
{
	Result r = run("decode");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: decode: which trace file? (ecmxf-util decode TRACEFILE)\n");
	r = run("decode --frob x");
	CHECK(r.status == 2);
	CHECK_THAT(r.err, Contains("'--frob'"));
	r = run("decode /nonexistent.trace");
	CHECK(r.status == 1);
	CHECK(r.out.empty());
	CHECK(r.err == "ecmxf-util: cannot open the trace file \"/nonexistent.trace\": No such file or directory\n");
	const TempFile f("notatrace", "hello\n");
	r = run("decode " + f.path);
	CHECK(r.status == 1);
	CHECK(r.out.empty());
	CHECK(r.err == "ecmxf-util: trace line 1: not an ecmxf trace (the first line must be \"ecmxf-trace 1\")\n");
}

TEST_CASE("the global option --trace FILE records the exchanges of a command and decode reads them back", "[cli][decode]")
{
	const TempFile f("recorded");
	Result r = run("--trace " + f.path + " info");
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("firmware version:"));
	r = run("decode " + f.path);
	REQUIRE(r.status == 0);
	CHECK_THAT(r.out, Contains("host>chip 144 bytes: FW_VERSION_GET (0x38)"));
	CHECK_THAT(r.out, Contains("host>chip 144 bytes: SPI_PACK_SIZE_GET (0x14)"));
	CHECK_THAT(r.out, Contains(" bad (0 not ready)\n"));
	CHECK_THAT(r.out, Contains(" 0 bad "));

	r = run("--trace=/nonexistent-dir/x.trace info");
	CHECK(r.status == 1);
	CHECK_THAT(r.err, Contains("cannot create the trace file \"/nonexistent-dir/x.trace\""));
	// a trace that cannot be written fails the run (the command's output
	// stands, the failure is said)
	r = run("--trace /dev/full info");
	CHECK(r.status == 1);
	CHECK_THAT(r.out, Contains("firmware version:"));
	CHECK_THAT(r.err, Contains("ecmxf-util: writing the trace file \"/dev/full\" failed: No space left on device"));
	r = run("info --trace");
	CHECK(r.status == 2);
	r = run("--trace");
	CHECK(r.status == 2);
	CHECK(r.err == "ecmxf-util: option '--trace' needs a file name\n");
}

TEST_CASE("decode --help and the command list mention decode and --trace", "[cli][decode][help]")
{
	Result r = run("--help");
	CHECK_THAT(r.out, Contains("decode"));
	CHECK_THAT(r.out, Contains("--trace FILE"));
	r = run("decode --help");
	CHECK(r.status == 0);
	CHECK_THAT(r.out, StartsWith("Usage: ecmxf-util [global options] decode TRACEFILE [--json | --pcapng OUT]"));
}

TEST_CASE("commands --json is an array with one object per command code", "[cli][commands][json]")
{
	const Result r = run("commands --json");
	REQUIRE(r.status == 0);
	const Json j = parseJson(r.out);
	REQUIRE(j.kind == Json::Array);
	CHECK(j.size() == ecmxf::commandCount());
	std::map<unsigned, const Json *> byCode;
	for (const Json &c : j.arr)
		byCode[static_cast<unsigned>(c["code"].num)] = &c;
	// manual ver. 050 (spec digest): 0 INFO_UPDATE_OP immediate, in both
	// manuals; 10 ECAT_SDO_REQ async, result by 11 ECAT_SDO_GET; 127
	// WARM_RESET async, ver. 050 only
	REQUIRE(byCode.count(0));
	CHECK((*byCode[0])["name"].str == "INFO_UPDATE_OP");
	CHECK_FALSE((*byCode[0])["async"].b);
	CHECK((*byCode[0])["v038"].b);
	CHECK((*byCode[0])["v050"].b);
	CHECK((*byCode[0])["partner"].kind == Json::Null);
	REQUIRE(byCode.count(10));
	CHECK((*byCode[10])["name"].str == "ECAT_SDO_REQ");
	CHECK((*byCode[10])["async"].b);
	CHECK((*byCode[10])["partner"].num == 11);
	REQUIRE(byCode.count(127));
	CHECK((*byCode[127])["name"].str == "WARM_RESET");
	CHECK((*byCode[127])["async"].b);
	CHECK_FALSE((*byCode[127])["v038"].b);
	CHECK((*byCode[127])["v050"].b);
}
