// SPDX-License-Identifier: MIT
// Packet traces of the ECM-SK (Documentation/trace.rst): a hand-built
// frame decodes to exactly the expected lines (its CRC-8 computed by hand,
// outside this code: tests/trace/test_trace_sk.cpp's comment below), bad
// "format ecm-sk" lines and frames of the wrong size are refused naming
// the line, trace= on the ECM-SK's URIs starts a trace that decodes with
// every frame, and the trace's errors name the option, the path or the
// failed write.

#include <catch2/catch.hpp>

#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <ecmxf/error.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/trace/trace.hpp>
#include "../common/thrown.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using ecmxftest::thrown;

namespace {

using Frame = std::vector<std::uint8_t>;

/// A trace record: "<time> <dir>" and the bytes in groups of 4.
std::string rec(const char *time, char dir, const Frame &f)
{
	std::string s = std::string(time) + ' ' + dir;
	char b[3];
	for (std::size_t i = 0; i < f.size(); i++) {
		if (i % 4 == 0)
			s += ' ';
		std::snprintf(b, sizeof(b), "%02x", f[i]);
		s += b;
	}
	return s + '\n';
}

std::string decode(const std::string &text, ecmxf::TraceSummary *sum = nullptr, bool json = false)
{
	std::istringstream in(text);
	std::ostringstream out;
	ecmxf::TraceDecodeOptions o;
	o.json = json;
	const ecmxf::TraceSummary s = ecmxf::decodeTrace(in, out, o);
	if (sum)
		*sum = s;
	return out.str();
}

// The hand-built frames (12-byte slots, 504 bytes). Their CRC-8s
// (x^8 + x^2 + x + 1, initial value 0x5A, not reflected, no final xor,
// byte 3 counted as 0; quick start 2.2) were computed with a separate
// ten-line Python loop, which gives 0xF4 for "123456789" with initial
// value 0 (the CRC-8's published check value):
//  - kCmd: SET_STATE (0x0001) to PRE-OP (data1 2); slot 3 (slave 2)
//    DRIVE_MODE (0x06) index 0x07, mode 8, sync 1: CRC-8 0xFE; with
//    byte 5 flipped (data1 0x00000102) it should be 0x12;
//  - kRsp: byte 0 SET_STATE answered, 0 CRC errors, INIT: CRC-8 0xC0.
Frame cmdFrame()
{
	Frame f(504, 0);
	f[0] = 0x01; // SET_STATE
	f[4] = 0x02; // PRE-OP
	f[36] = 0x06; // slot 3: DRIVE_MODE
	f[37] = 0x07;
	f[40] = 8;    // CSP
	f[44] = 1;    // DC sync
	f[3] = 0xFE;
	return f;
}

Frame rspFrame()
{
	Frame f(504, 0);
	f[0] = 0x01;
	f[2] = 0x01; // INIT
	f[3] = 0xC0;
	return f;
}

const std::string kSdoZero = "00 00 00 00 00 00 00 00 00 00 00 00";

std::filesystem::path tempPath(const char *tag, const char *ext = ".trace")
{
	return std::filesystem::temp_directory_path() /
	       ("ecmxf-test-sktrace-" + std::to_string(getpid()) + "-" + tag + ext);
}

} // namespace

TEST_CASE("sk trace: a hand-built frame decodes to the expected lines", "[trace][sk]")
{
	ecmxf::TraceSummary s;
	const std::string out = decode("ecmxf-trace 1\nformat ecm-sk 12 crc\n" + rec("0.000001000", '>', cmdFrame()) +
					       rec("0.000002000", '<', rspFrame()),
				       &s);
	CHECK_THAT(out, Equals("#1 0.000001000 host>board 504 bytes (12-byte slots): SET_STATE (0x0001)\n"
			       "    CRC-8 (byte 3) 0xFE: OK\n"
			       "    slot 0 (ECM): SET_STATE (0x0001), param 0x00, data1 0x00000002, data2 0x00000000\n"
			       "    slot 3 (slave 2): DRIVE_MODE (0x06), index 0x07, target 0x00000008, value 0x00000001\n"
			       "    slot 41 (SDO): " +
			       kSdoZero +
			       "\n"
			       "#1 0.000002000 board>host 504 bytes (12-byte slots): SET_STATE (0x01), state INIT (0x01)\n"
			       "    CRC-8 (byte 3) 0xC0: OK\n"
			       "    slot 0 (ECM): SET_STATE (0x01), CRC errors 0, state INIT (0x01), data1 0x00000000, "
			       "data2 0x00000000\n"
			       "    slot 41 (SDO): " +
			       kSdoZero + "\n"));
	CHECK(s.packets == 2);
	CHECK(s.commands == 1);
	CHECK(s.responses == 1);
	CHECK(s.skFrames == 2);
	CHECK(s.bad == 0);
}

TEST_CASE("sk trace: a flipped byte is a bad CRC-8, nocrc and one-way settings are not checked", "[trace][sk]")
{
	Frame bad = cmdFrame();
	bad[5] ^= 0x01;
	ecmxf::TraceSummary s;
	std::string out = decode("ecmxf-trace 1\nformat ecm-sk 12 crc\n" + rec("1", '>', bad), &s);
	CHECK_THAT(out, Contains("#1 1.000000000 host>board 504 bytes (12-byte slots): SET_STATE (0x0001) [BAD]\n"
				 "    CRC-8 (byte 3) 0xFE: BAD (expected 0x12, got 0xFE)\n"
				 "    slot 0 (ECM): SET_STATE (0x0001), param 0x00, data1 0x00000102,"));
	CHECK(s.bad == 1);
	out = decode("ecmxf-trace 1\nformat ecm-sk 12 nocrc\n" + rec("1", '>', bad), &s);
	CHECK_THAT(out, Contains("    CRC-8 (byte 3) 0xFE: not checked (nocrc)\n"));
	CHECK(s.bad == 0);
	// rspcrc: the commands are not sealed, the answers are
	Frame rsp = rspFrame();
	rsp[3] = 0;
	out = decode("ecmxf-trace 1\nformat ecm-sk 12 rspcrc\n" + rec("1", '>', bad) + rec("2", '<', rsp), &s);
	CHECK_THAT(out, Contains("    CRC-8 (byte 3) 0xFE: not checked (rspcrc)\n"));
	CHECK_THAT(out, Contains("    CRC-8 (byte 3) 0x00: BAD (expected 0xC0, got 0x00)\n"));
	CHECK(s.bad == 1);
	out = decode("ecmxf-trace 1\nformat ecm-sk 12 cmdcrc\n" + rec("2", '<', rsp), &s);
	CHECK_THAT(out, Contains("    CRC-8 (byte 3) 0x00: not checked (cmdcrc)\n"));
}

TEST_CASE("sk trace: --json gives the dissector's fields", "[trace][sk]")
{
	const std::string out = decode("ecmxf-trace 1\nformat ecm-sk 12 crc\n" + rec("0.000001000", '>', cmdFrame()) +
					       rec("0.000002000", '<', rspFrame()),
				       nullptr, true);
	CHECK_THAT(out,
		   Equals("[\n  {\"n\": 1, \"line\": 3, \"time\": \"0.000001000\", \"time_ns\": 1000, \"dir\": \"mosi\", "
			  "\"sk\": true, \"size\": 504, \"slot_size\": 12, \"crc\": \"ok\", \"crc_byte\": 254, "
			  "\"crc_expected\": 254, \"cmd\": 1, \"name\": \"SET_STATE\", \"param\": 0, \"data1\": 2, "
			  "\"data2\": 0, \"slaves\": [{\"slot\": 3, \"slave\": 2, \"cmd\": 6, \"name\": \"DRIVE_MODE\", "
			  "\"index\": 7, \"target\": 8, \"value\": 1}], \"sdo\": \"000000000000000000000000\"},\n"
			  "  {\"n\": 1, \"line\": 4, \"time\": \"0.000002000\", \"time_ns\": 2000, \"dir\": \"miso\", "
			  "\"sk\": true, \"size\": 504, \"slot_size\": 12, \"crc\": \"ok\", \"crc_byte\": 192, "
			  "\"crc_expected\": 192, \"cmd\": 1, \"name\": \"SET_STATE\", \"crc_errors\": 0, \"state\": 1, "
			  "\"data1\": 0, \"data2\": 0, \"slaves\": [], \"sdo\": \"000000000000000000000000\"}\n]\n"));
}

TEST_CASE("sk trace: bad format lines and frames are refused naming the line", "[trace][sk][errors]")
{
	auto bad = [](const std::string &t) { return thrown([&] { decode(t); }); };
	const std::string head = "ecmxf-trace 1\n";
	const std::string expected =
		"\" (expected format ecm-sk 12|16 crc|nocrc|cmdcrc|rspcrc: the slot size and the CRC-8 in force)";
	for (const char *l : { "format ecm-sk 14 crc", "format ecm-sk 12", "format ecm-sk", "format ecm-sk 16 crc x",
			       "format ecm-sk twelve crc" }) {
		const ecmxf::Error e = bad(head + l + "\n");
		CHECK_THAT(e.what(), Equals("trace line 2: bad format line \"" + std::string(l) + expected));
		CHECK(e.errnoValue() == EINVAL);
	}
	CHECK_THAT(bad(head + "format ecm-sk 12 crc8\n").what(),
		   Equals("trace line 2: unknown ECM-SK CRC setting \"crc8\" (crc: both directions, nocrc, cmdcrc: "
			  "host to board only, rspcrc: board to host only)"));
	// a 512-byte frame under 12-byte slots, a 504-byte one under 16
	Frame f16(512, 0);
	CHECK_THAT(bad(head + "format ecm-sk 12 nocrc\n# c\n" + rec("1", '>', f16)).what(),
		   Equals("trace line 4: an ECM-SK frame of 512 bytes (the format ecm-sk 12 line 2 takes 504-byte "
			  "frames)"));
	CHECK_THAT(bad(head + "format ecm-sk 16 nocrc\n" + rec("1", '<', cmdFrame())).what(),
		   Equals("trace line 3: an ECM-SK frame of 504 bytes (the format ecm-sk 16 line 2 takes 512-byte "
			  "frames)"));
	CHECK_THAT(bad(head + "format ecm-sk 12 nocrc\n1 C " + std::string(40, '0') + "\n").what(),
		   Equals("trace line 3: a kernel record 'C' in ECM-SK frames (the format ecm-sk line 2 is in force; "
			  "expected > or <)"));
	// an ECM-XF format line switches back: a 144-byte packet is an ECM-XF one
	ecmxf::TraceSummary s;
	Frame xf(144, 0);
	(void)decode(head + "format ecm-sk 16 crc\nformat 112 fixed\n" + rec("1", '>', xf), &s);
	CHECK(s.skFrames == 0);
	CHECK(s.commands == 1);
	CHECK_THAT(bad(head + "format ecm-sk 16 crc\n" + rec("1", '>', xf)).what(),
		   Contains("trace line 3: an ECM-SK frame of 144 bytes"));
}

TEST_CASE("sk trace: trace= on sk-sim: records every frame, text and pcapng", "[trace][sk][sim]")
{
	const auto path = tempPath("sim");
	{
		auto b = ecmxf::sk::Board::open("sk-sim:?ex=3&trace=" + path.string());
		REQUIRE(b->tracing());
		b->states().set(ecmxf::State::PreOp);
		(void)b->setup().detectAxes();
		(void)b->sdo().read(1, 0x1018, 1);
		b->stopTrace();
		CHECK_FALSE(b->tracing());
		CHECK_NOTHROW(b->stopTrace()); // nothing running: no-op
	}
	std::ifstream f(path);
	std::string first, format;
	std::getline(f, first);
	std::string l;
	while (std::getline(f, l))
		if (l.starts_with("format")) {
			format = l;
			break;
		}
	CHECK(first == "ecmxf-trace 1");
	CHECK(format == "format ecm-sk 12 crc");
	f.clear();
	f.seekg(0);
	std::ostringstream out;
	const ecmxf::TraceSummary s = ecmxf::decodeTrace(f, out);
	CHECK(s.skFrames > 6);
	CHECK(s.skFrames == s.packets);
	CHECK(s.commands == s.responses);
	CHECK(s.bad == 0);
	CHECK_THAT(out.str(), Contains("host>board 504 bytes (12-byte slots): SET_STATE (0x0001)\n"));
	CHECK_THAT(out.str(), Contains("host>board 504 bytes (12-byte slots): SET_AXIS (0x0002)\n"));
	CHECK_THAT(out.str(), Contains(": OK\n"));
	std::filesystem::remove(path);

	// the 16-byte slots, without CRCs, to pcapng
	const auto pcap = tempPath("sim16", ".pcapng");
	{
		auto b = ecmxf::sk::Board::open("sk-sim:?slot=16&trace=" + pcap.string());
		b->states().set(ecmxf::State::PreOp);
		b->stopTrace();
	}
	std::ifstream p(pcap, std::ios::binary);
	const std::string bytes((std::istreambuf_iterator<char>(p)), std::istreambuf_iterator<char>());
	REQUIRE(bytes.size() > 28);
	CHECK(bytes.substr(0, 4) == std::string("\x0A\x0D\x0D\x0A", 4));
	CHECK(bytes.find("ecmsk frames") != std::string::npos); // the USER2 interface's name
	std::filesystem::remove(pcap);
}

TEST_CASE("sk trace: the URI's trace= errors name the option, the path and the failed write", "[trace][sk][errors]")
{
	ecmxf::Error e = thrown([] { (void)ecmxf::sk::Board::open("sk-sim:?trace="); });
	CHECK_THAT(e.what(), Contains("cannot open \"sk-sim:?trace=\": option \"trace\" needs a file name (trace=<file>)"));
	CHECK(e.errnoValue() == EINVAL);
	e = thrown([] { (void)ecmxf::sk::Board::open("sk-unix:/tmp/x.sock?slot=12&trace="); });
	CHECK_THAT(e.what(), Contains("option \"trace\" needs a file name"));
	e = thrown([] { (void)ecmxf::sk::Board::open("sk-sim:?ex=1&trace=/nonexistent-dir/x.trace"); });
	CHECK_THAT(e.what(), Equals(std::string("cannot create the trace file \"/nonexistent-dir/x.trace\": ") +
				    std::strerror(ENOENT)));
	CHECK(e.errnoValue() == ENOENT);
	auto b = ecmxf::sk::Board::open("sk-sim:");
	e = thrown([&] { b->startTrace("/nonexistent-dir/y.pcapng"); });
	CHECK_THAT(e.what(), Contains("\"/nonexistent-dir/y.pcapng\""));
	CHECK_FALSE(b->tracing());

	REQUIRE(std::filesystem::exists("/dev/full")); // Linux: writes fail with ENOSPC
	for (const char *name : { "/dev/full", "sk-sim:?trace=/dev/full" }) {
		auto d = std::string(name).starts_with("sk-") ? ecmxf::sk::Board::open(name) : ecmxf::sk::Board::open("sk-sim:");
		if (!d->tracing())
			d->startTrace(name);
		for (int i = 0; i < 20; i++) // more than one stdio buffer of frames
			(void)d->states().status();
		e = thrown([&] { d->stopTrace(); });
		CHECK_THAT(e.what(),
			   Equals(std::string("writing the trace file \"/dev/full\" failed: ") + std::strerror(ENOSPC)));
		CHECK(e.errnoValue() == ENOSPC);
		CHECK_FALSE(d->tracing());
	}
}
