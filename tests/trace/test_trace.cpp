// SPDX-License-Identifier: MIT
// Packet traces: hand-written traces of the golden packets of
// tests/golden/test_golden.cpp (written from the manuals, not from this
// code) decode to exactly the expected lines; corrupted packets are
// reported BAD; traces recorded from the simulator decode without a fault
// and follow CRC_TYPE_SET and SPI_RECONFIG_OP; bad trace input is refused
// naming the line.

#include <catch2/catch.hpp>

#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/trace/trace.hpp>
#include "../common/thrown.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::Equals;

namespace {

using Bytes = std::vector<std::uint8_t>;

/// A 144-byte packet (N = 112): @p head (24 bytes), @p data then zeros,
/// @p tail (check word, end word).
Bytes packet(const Bytes &head, const Bytes &data, const Bytes &tail)
{
	Bytes p = head;
	p.insert(p.end(), data.begin(), data.end());
	p.resize(24 + 112, 0);
	p.insert(p.end(), tail.begin(), tail.end());
	return p; // 144 bytes (checked in the first test)
}

// The golden vectors of tests/golden/test_golden.cpp, header and trailer
// bytes copied from there (the data sections are zero unless given).
// 2a. INFO_UPDATE_OP, every command header field set, fixed check word
const Bytes kInfoUpdateAllFieldsFixed = packet(
	{ 0xA4, 0xA3, 0xA2, 0xA1, 0x11, 0x22, 0x33, 0x44, 0x00, 0x80, 0xFA, 0x5A,
	  0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xA0, 0x0F, 0x03, 0xA5, 0x0C },
	{}, { 0x78, 0x56, 0x34, 0x12, 0x59, 0x58, 0x57, 0x56 });
// 1b. INFO_UPDATE_OP index 0x01, CRC-32 = 0x5E45867F
const Bytes kInfoUpdateCrc32 = packet(
	{ 0xA4, 0xA3, 0xA2, 0xA1, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01,
	  0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00 },
	{}, { 0x7F, 0x86, 0x45, 0x5E, 0x59, 0x58, 0x57, 0x56 });
// R5. NOP after power-up, fixed check word
const Bytes kRspNopFixed = packet(
	{ 0xA4, 0xA3, 0xA2, 0xA1, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x20, 0x00,
	  0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00 },
	{}, { 0x78, 0x56, 0x34, 0x12, 0x59, 0x58, 0x57, 0x56 });
// R1. ECAT_STATE_GET answer, every header field distinct, CRC-32 = 0x13B46C1C
const Bytes kRspStateGetCrc32 = packet(
	{ 0xA4, 0xA3, 0xA2, 0xA1, 0x01, 0x02, 0x03, 0x04, 0x08, 0x01, 0x1F, 0x07,
	  0x0D, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x01, 0x00, 0x5A, 0x03 },
	{}, { 0x1C, 0x6C, 0xB4, 0x13, 0x59, 0x58, 0x57, 0x56 });
// R2. ECAT_SDO_GET answer with 4 data bytes, CRC-32 = 0x7B398485
const Bytes kRspSdoGetCrc32 = packet(
	{ 0xA4, 0xA3, 0xA2, 0xA1, 0x00, 0x00, 0x00, 0x00, 0x02, 0x01, 0x0B, 0x08,
	  0x0B, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00 },
	{ 0xCD, 0x34, 0xAB, 0x12 }, { 0x85, 0x84, 0x39, 0x7B, 0x59, 0x58, 0x57, 0x56 });
// R3. R2 with the data length field 113, correct CRC-32 = 0x13629B87
const Bytes kRspSdoGetLen113Crc32 = packet(
	{ 0xA4, 0xA3, 0xA2, 0xA1, 0x00, 0x00, 0x00, 0x00, 0x02, 0x01, 0x0B, 0x08,
	  0x0B, 0x00, 0x71, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00 },
	{ 0xCD, 0x34, 0xAB, 0x12 }, { 0x87, 0x9B, 0x62, 0x13, 0x59, 0x58, 0x57, 0x56 });
// R6. "not ready": check word 0x87654321
const Bytes kRspNotReady = packet(
	{ 0xA4, 0xA3, 0xA2, 0xA1, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
	  0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00 },
	{}, { 0x21, 0x43, 0x65, 0x87, 0x59, 0x58, 0x57, 0x56 });

/// One trace line: "<time> <dir> <hex>".
std::string rec(const char *time, char dir, const Bytes &p)
{
	std::string s = std::string(time) + " " + dir + " ";
	char b[3];
	for (const std::uint8_t v : p) {
		std::snprintf(b, sizeof(b), "%02x", v);
		s += b;
	}
	return s + "\n";
}

std::string decode(const std::string &trace, ecmxf::TraceSummary *summary = nullptr, bool json = false)
{
	std::istringstream in(trace);
	std::ostringstream out;
	ecmxf::TraceDecodeOptions o;
	o.json = json;
	const ecmxf::TraceSummary s = ecmxf::decodeTrace(in, out, o);
	if (summary)
		*summary = s;
	return out.str();
}

using ecmxftest::thrown;

std::filesystem::path tempTrace(const char *tag)
{
	return std::filesystem::temp_directory_path() /
	       ("ecmxf-test-trace-" + std::to_string(getpid()) + "-" + tag + ".trace");
}

std::string readFile(const std::filesystem::path &p)
{
	std::ifstream f(p);
	std::stringstream ss;
	ss << f.rdbuf();
	return ss.str();
}

} // namespace

TEST_CASE("golden trace: INFO_UPDATE_OP with every field set and the power-on NOP decode exactly",
	  "[trace][golden]")
{
	const std::string trace = "ecmxf-trace 1\nformat 112 fixed\n" + rec("0.000010000", '>', kInfoUpdateAllFieldsFixed) +
				  rec("0.000013000", '<', kRspNopFixed);
	for (const Bytes *p : { &kInfoUpdateAllFieldsFixed, &kInfoUpdateCrc32, &kRspNopFixed, &kRspStateGetCrc32,
				&kRspSdoGetCrc32, &kRspSdoGetLen113Crc32, &kRspNotReady })
		REQUIRE(p->size() == 144);
	ecmxf::TraceSummary s;
	const std::string out = decode(trace, &s);
	CHECK_THAT(out, Equals(
		"#1 0.000010000 host>chip 144 bytes: INFO_UPDATE_OP (0x00), index 0x5A\n"
		"    param 0x00, len 0, data 11 22 33 44, reserved 0x8000 (GPIO out valid)\n"
		"    control 0xFA (clear CRC count, clear async error, clear SPI error, clear FIFO error, "
		"clear SPI CRC error, clear command error), int clear 0xA0000000 (encoder, EtherCAT packet), "
		"GPIO int clear 0x0F 0x03, GPIO out 0xA5 0x0C\n"
		"    check word 0x12345678: OK (fixed)\n"
		"#1 0.000013000 chip>host 144 bytes: answers nothing (NOP: the chip's first answer after power-on or "
		"reset)\n"
		"    ECAT state NONE (0x00), error status 0x00, ECM status 0x20 (check fixed, NOP)\n"
		"    CRC errors 0, WKC errors 0, TxFIFO 0, RxFIFO 0\n"
		"    index 0x00, code 0x00 INFO_UPDATE_OP, ret 0x00 (0), len 0\n"
		"    int flags 0x00000000, GPIO int flags 0x00 0x00, GPIO in 0x00 0x00\n"
		"    check word 0x12345678: OK (fixed)\n"));
	CHECK(s.packets == 2);
	CHECK(s.commands == 1);
	CHECK(s.responses == 1);
	CHECK(s.bad == 0);
}

TEST_CASE("golden trace: CRC-32 INFO_UPDATE_OP and an ECAT_STATE_GET answer with every field distinct",
	  "[trace][golden]")
{
	const std::string trace = "ecmxf-trace 1\nformat 112 crc32\n" + rec("1.5", '>', kInfoUpdateCrc32) +
				  rec("1.500024", '<', kRspStateGetCrc32);
	CHECK_THAT(decode(trace), Equals(
		"#1 1.500000000 host>chip 144 bytes: INFO_UPDATE_OP (0x00), index 0x01\n"
		"    param 0x00, len 0, data 00 00 00 00, reserved 0x0000\n"
		"    control 0x00, int clear 0x00000000, GPIO int clear 0x00 0x00, GPIO out 0x00 0x00\n"
		"    check word 0x5E45867F: OK (CRC-32)\n"
		"#1 1.500024000 chip>host 144 bytes: answers ECAT_STATE_GET (0x0D), index 0x07 (not sent in this trace)\n"
		"    ECAT state OP (0x08), error status 0x01 (link), ECM status 0x1F (check CRC-32, DC stable, "
		"Ethernet initialised, PDO configured)\n"
		"    CRC errors 1, WKC errors 2, TxFIFO 3, RxFIFO 4\n"
		"    index 0x07, code 0x0D ECAT_STATE_GET, ret 0x08 (8), len 0\n"
		"    int flags 0x80000000 (EtherCAT packet), GPIO int flags 0x01 0x00, GPIO in 0x5A 0x03\n"
		"    check word 0x13B46C1C: OK (CRC-32)\n"));
}

TEST_CASE("golden trace: the ECAT_SDO_GET answer shows its 4 data bytes", "[trace][golden]")
{
	const std::string trace = "ecmxf-trace 1\nformat 112 crc32\n" + rec("0.000100000", '<', kRspSdoGetCrc32);
	CHECK_THAT(decode(trace), Equals(
		"#1 0.000100000 chip>host 144 bytes: answers ECAT_SDO_GET (0x0B), index 0x08 (not sent in this trace)\n"
		"    ECAT state PRE-OP (0x02), error status 0x01 (link), ECM status 0x0B (check CRC-32, Ethernet "
		"initialised)\n"
		"    CRC errors 0, WKC errors 0, TxFIFO 0, RxFIFO 0\n"
		"    index 0x08, code 0x0B ECAT_SDO_GET, ret 0x00 (0), len 4\n"
		"    int flags 0x00000000, GPIO int flags 0x00 0x00, GPIO in 0x00 0x00\n"
		"    data (4 of 112 bytes):\n"
		"      0000: CD 34 AB 12\n"
		"    check word 0x7B398485: OK (CRC-32)\n"));
}

TEST_CASE("a corrupted check word is reported BAD with the expected and the received value",
	  "[trace][golden]")
{
	Bytes cmd = kInfoUpdateCrc32;
	// the fixed word where the CRC-32 belongs
	cmd[136] = 0x78, cmd[137] = 0x56, cmd[138] = 0x34, cmd[139] = 0x12;
	Bytes rsp = kRspSdoGetCrc32;
	rsp[24] = 0xCC; // one data bit flipped: the CRC-32 no longer matches
	ecmxf::TraceSummary s;
	const std::string out = decode("ecmxf-trace 1\nformat 112 crc32\n" + rec("0.1", '>', cmd) + rec("0.2", '<', rsp), &s);
	CHECK_THAT(out, Contains("#1 0.100000000 host>chip 144 bytes: INFO_UPDATE_OP (0x00), index 0x01 [BAD]\n"));
	CHECK_THAT(out, Contains("    check word 0x12345678: BAD (CRC-32 expected 0x5E45867F, got 0x12345678)\n"));
	CHECK_THAT(out, Contains("(not sent in this trace) [BAD]\n"));
	CHECK_THAT(out, Contains("      0000: CC 34 AB 12\n"));
	CHECK_THAT(out, Contains("    check word 0x7B398485: BAD (CRC-32 expected 0x"));
	CHECK_THAT(out, Contains(", got 0x7B398485)\n"));
	CHECK(s.bad == 2);

	// the right packet under the wrong check type is BAD too
	const std::string fixed = decode("ecmxf-trace 1\nformat 112 fixed\n" + rec("0.1", '>', kInfoUpdateCrc32));
	CHECK_THAT(fixed, Contains("    check word 0x5E45867F: BAD (fixed expected 0x12345678, got 0x5E45867F)\n"));
}

TEST_CASE("the not-ready check word, a length beyond the data section and bad frame words are named",
	  "[trace][golden]")
{
	ecmxf::TraceSummary s;
	std::string out = decode("ecmxf-trace 1\n" + rec("0", '<', kRspNotReady), &s);
	CHECK_THAT(out, Equals("#1 0.000000000 chip>host 144 bytes: not ready\n"
			       "    check word 0x87654321: NOT READY (the chip had not processed the previous packet)\n"));
	CHECK(s.notReady == 1);
	CHECK(s.bad == 1);

	out = decode("ecmxf-trace 1\nformat 112 crc32\n" + rec("0", '<', kRspSdoGetLen113Crc32));
	CHECK_THAT(out, Contains("    len 113: BAD (longer than the 112-byte data section)\n"));

	Bytes start = kRspNopFixed;
	start[0] = 0xA5;
	out = decode("ecmxf-trace 1\n" + rec("0", '<', start));
	CHECK_THAT(out, Contains("    start word 0xA1A2A3A5: BAD (expected 0xA1A2A3A4)\n"));
	Bytes end = kRspNopFixed;
	end[143] = 0x00;
	out = decode("ecmxf-trace 1\n" + rec("0", '<', end));
	CHECK_THAT(out, Contains("    end word 0x00575859: BAD (expected 0x56575859)\n"));
}

TEST_CASE("decode --json gives one object per packet", "[trace][json]")
{
	const std::string out = decode("ecmxf-trace 1\nformat 112 crc32\n" + rec("0.5", '<', kRspSdoGetCrc32), nullptr, true);
	CHECK_THAT(out, Equals("[\n  {\"n\": 1, \"line\": 3, \"time\": \"0.500000000\", \"time_ns\": 500000000, "
			       "\"dir\": \"miso\", \"size\": 144, \"check\": \"ok\", \"answers\": null, \"nop\": false, "
			       "\"index\": 8, \"code\": 11, \"name\": \"ECAT_SDO_GET\", \"ret\": 0, \"len\": 4, "
			       "\"crc_err_cnt\": 0, \"wkc_err_cnt\": 0, \"tx_fifo_cnt\": 0, \"rx_fifo_cnt\": 0, "
			       "\"ecat_state\": 2, \"err_status\": 1, \"ecm_status\": 11, \"int_flags\": 0, "
			       "\"gpio_int_flag\": [0, 0], \"gpio_in\": [0, 0], \"data\": \"cd34ab12\"}\n]\n"));
	CHECK(decode("ecmxf-trace 1\n", nullptr, true) == "[]\n");
}

TEST_CASE("bad trace input is refused naming the line", "[trace][errors]")
{
	auto bad = [](const std::string &t) { return thrown([&] { decode(t); }); };
	ecmxf::Error e = bad("hello\n");
	CHECK_THAT(e.what(), Equals("trace line 1: not an ecmxf trace (the first line must be \"ecmxf-trace 1\")"));
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(bad("").what(), Equals("trace line 0: not an ecmxf trace (empty, or no \"ecmxf-trace 1\" line)"));
	CHECK_THAT(bad("ecmxf-trace 1\n# c\n0.1 > a4a3a2a1\n").what(),
		   Equals("trace line 3: a packet of 4 bytes (packets are 64..1440 bytes)"));
	CHECK_THAT(bad("ecmxf-trace 1\nx.1 > 00\n").what(),
		   Equals("trace line 2: bad time \"x.1\" (expected seconds with up to 9 decimals, e.g. 0.000150000)"));
	CHECK_THAT(bad("ecmxf-trace 1\n0.1 > 0g\n").what(), Equals("trace line 2: 'g' is not a hex digit"));
	CHECK_THAT(bad("ecmxf-trace 1\n0.1 > 000\n").what(), Equals("trace line 2: odd number of hex digits"));
	CHECK_THAT(bad("ecmxf-trace 1\n0.1 X 00\n").what(),
		   Equals("trace line 2: unknown record 'X' (expected > < C R)"));
	CHECK_THAT(bad("ecmxf-trace 1\nformat 16 fixed\n").what(),
		   Equals("trace line 2: bad format line \"format 16 fixed\" (expected format <32..1408> "
			  "fixed|crc8|ccitt|crc32, or format ecm-sk 12|16 crc|nocrc|cmdcrc|rspcrc)"));
	CHECK_THAT(bad("ecmxf-trace 1\nformat 112 crc16\n").what(),
		   Equals("trace line 2: unknown check type \"crc16\" (fixed, crc8, ccitt, crc32)"));
	CHECK_THAT(bad("ecmxf-trace 1\n0.1 C 0000\n").what(),
		   Equals("trace line 2: a kernel record needs the 20 header bytes 0x04..0x17, found 2"));
}

TEST_CASE("a trace recorded on the simulator has every exchange and decodes without a fault",
	  "[trace][sim]")
{
	const auto path = tempTrace("sim");
	auto dev = ecmxf::Device::open("sim:?trace=" + path.string());
	auto &chip = *dev->link().simulator();
	CHECK(dev->tracing());
	ecmxf::Command fw;
	fw.code = 56; // FW_VERSION_GET
	ecmxf::Command cnt;
	cnt.code = 16; // ECAT_SLV_CNT_GET
	dev->command(fw);
	dev->command(cnt);
	dev->stopTrace();
	CHECK_FALSE(dev->tracing());
	dev->command(fw); // not recorded

	const std::string text = readFile(path);
	CHECK(text.starts_with("ecmxf-trace 1\n"));
	CHECK_THAT(text, Contains("\nformat 112 fixed\n"));
	std::size_t mosi = 0, miso = 0;
	std::istringstream lines(text);
	for (std::string l; std::getline(lines, l);) {
		mosi += l.find(" > ") != std::string::npos;
		miso += l.find(" < ") != std::string::npos;
	}
	const auto exchanges = chip.stats().exchanges;
	CHECK(mosi + 2 <= exchanges); // the last command's exchanges after stopTrace() are not there
	CHECK(mosi == miso);

	ecmxf::TraceSummary s;
	std::ifstream f(path);
	std::ostringstream out;
	s = ecmxf::decodeTrace(f, out);
	CHECK(s.commands == mosi);
	CHECK(s.responses == miso);
	CHECK(s.bad == 0);
	CHECK_THAT(out.str(), Contains("answers nothing (NOP"));
	CHECK_THAT(out.str(), Contains("host>chip 144 bytes: FW_VERSION_GET (0x38), index 0x01\n"));
	CHECK_THAT(out.str(), Contains("chip>host 144 bytes: answers #2 FW_VERSION_GET (0x38), index 0x01\n"));
	CHECK_THAT(out.str(), Contains(", ret 0x30 (48), len 20\n")); // ChipConfig::fwVersion 0x30
	CHECK_THAT(out.str(), Contains("the re-send of FW_VERSION_GET (0x38) with index 0x01, run as INFO_UPDATE_OP"));
	CHECK_THAT(out.str(), Contains("ECAT_SLV_CNT_GET (0x10), index 0x02\n"));
	std::filesystem::remove(path);
}

TEST_CASE("the decoder follows CRC_TYPE_SET and SPI_RECONFIG_OP recorded on the simulator", "[trace][sim]")
{
	const auto path = tempTrace("format");
	auto dev = ecmxf::Device::open("sim:");
	dev->startTrace(path.string());
	ecmxf::Command crc;
	crc.code = 25; // CRC_TYPE_SET
	crc.param = 3; // CRC-32
	dev->command(crc);
	ecmxf::Command reconf;
	reconf.code = 23; // SPI_RECONFIG_OP
	reconf.len = 32;  // the new data section size is the length field
	dev->command(reconf);
	ecmxf::Command fw;
	fw.code = 56;
	CHECK(dev->command(fw).ret == 0x30);
	dev->stopTrace();

	std::ifstream f(path);
	std::ostringstream out;
	const ecmxf::TraceSummary s = ecmxf::decodeTrace(f, out);
	const std::string log = out.str();
	CHECK(s.bad == 0);
	CHECK_THAT(log, Contains("host>chip 144 bytes: CRC_TYPE_SET (0x19)"));
	CHECK_THAT(log, Contains("OK (CRC-32)"));
	CHECK_THAT(log, Contains("host>chip 144 bytes: SPI_RECONFIG_OP (0x17)"));
	CHECK_THAT(log, Contains("OK (fixed, as SPI_RECONFIG_OP is sent)"));
	CHECK_THAT(log, Contains("(from the next exchange on: data section 32 bytes, packets of 64 bytes)\n"));
	CHECK_THAT(log, Contains("host>chip 64 bytes: FW_VERSION_GET (0x38)"));
	std::filesystem::remove(path);
}

TEST_CASE("startTrace on a path that cannot be created throws with the path and the reason", "[trace][errors]")
{
	auto dev = ecmxf::Device::open("sim:");
	const ecmxf::Error e = thrown([&] { dev->startTrace("/nonexistent-dir/x.trace"); });
	CHECK_THAT(e.what(), Equals(std::string("cannot create the trace file \"/nonexistent-dir/x.trace\": ") +
				    std::strerror(ENOENT)));
	CHECK(e.errnoValue() == ENOENT);
	CHECK_FALSE(dev->tracing());
	const ecmxf::Error u = thrown([&] { (void)ecmxf::Device::open("sim:?trace=/nonexistent-dir/y.trace"); });
	CHECK_THAT(u.what(), Contains("\"/nonexistent-dir/y.trace\""));
	CHECK_NOTHROW(dev->stopTrace()); // nothing running: no-op
}

TEST_CASE("a trace that cannot be written is reported by stopTrace", "[trace][errors]")
{
	REQUIRE(std::filesystem::exists("/dev/full")); // Linux: writes fail with ENOSPC
	auto dev = ecmxf::Device::open("sim:");
	dev->startTrace("/dev/full");
	ecmxf::Command fw;
	fw.code = 56;
	for (int i = 0; i < 40; i++) // more than one stdio buffer of records
		dev->command(fw);
	const ecmxf::Error e = thrown([&] { dev->stopTrace(); });
	CHECK_THAT(e.what(), Equals(std::string("writing the trace file \"/dev/full\" failed: ") + std::strerror(ENOSPC)));
	CHECK(e.errnoValue() == ENOSPC);
}
