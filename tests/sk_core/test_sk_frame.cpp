// SPDX-License-Identifier: MIT
// The ECM-SK slot protocol core (lib/core/ecmsk-*.c): geometry, CRC-8,
// slot encode/decode for every command of table 1.3 against golden frames
// computed from the quick start by tests/sk_core/make-golden.py (its
// output pasted below, not produced by the code under test).

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "ecmsk-proto.h"

namespace {

struct Golden {
	std::size_t size;
	std::vector<std::pair<std::size_t, std::uint8_t>> bytes;

	[[nodiscard]] std::vector<std::uint8_t> frame() const
	{
		std::vector<std::uint8_t> f(size, 0);
		for (auto [i, b] : bytes)
			f[i] = b;
		return f;
	}
};

// ---- pasted output of make-golden.py ----
// kSetStatePreop: 504 bytes, CRC 0xE7
static const Golden kSetStatePreop{ 504, {
	{ 0, 0x01 }, { 3, 0xE7 }, { 4, 0x02 },
} };
// kSetAxis16: 512 bytes, CRC 0x93
static const Golden kSetAxis16{ 512, {
	{ 0, 0x02 }, { 2, 0x01 }, { 3, 0x93 }, { 4, 0x03 }, { 5, 0x21 }, { 6, 0xFF }, { 7, 0xFF },
} };
// kCspSdoWr: 504 bytes, CRC 0xA2
static const Golden kCspSdoWr{ 504, {
	{ 0, 0x03 }, { 3, 0xA2 }, { 4, 0xF4 }, { 5, 0x01 }, { 8, 0xFF }, { 9, 0xFF }, { 12, 0x15 },
	{ 13, 0x07 }, { 16, 0x18 }, { 17, 0xFC }, { 18, 0xFF }, { 19, 0xFF }, { 20, 0x05 },
	{ 480, 0x14 }, { 481, 0xA5 }, { 484, 0x0F }, { 485, 0x0F }, { 492, 0x08 }, { 494, 0x02 },
	{ 495, 0x01 }, { 498, 0x60 }, { 499, 0x60 }, { 500, 0x06 },
} };
// kOpResponse: 504 bytes, CRC 0x33
static const Golden kOpResponse{ 504, {
	{ 0, 0xBF }, { 1, 0x02 }, { 2, 0x08 }, { 3, 0x33 }, { 8, 0xC8 }, { 10, 0x03 }, { 12, 0x15 },
	{ 13, 0x07 }, { 14, 0x37 }, { 15, 0x12 }, { 16, 0x40 }, { 17, 0xE2 }, { 18, 0x01 },
	{ 20, 0xFB }, { 21, 0xFF }, { 23, 0x75 }, { 492, 0x07 }, { 494, 0x01 }, { 498, 0x41 },
	{ 499, 0x60 }, { 500, 0x37 }, { 501, 0x12 },
} };
// kHsp2Csv: 512 bytes, CRC 0x30
static const Golden kHsp2Csv{ 512, {
	{ 3, 0x30 }, { 48, 0x16 }, { 49, 0x09 }, { 52, 0xE8 }, { 53, 0x03 }, { 56, 0x01 },
	{ 58, 0x30 }, { 59, 0xF8 }, { 60, 0xFF }, { 61, 0xFF }, { 62, 0x02 },
} };
// all-zero 504: 0x59, all-zero 512: 0x60
// '123456789' (byte 3 as 0): 0x59
// ---- end of pasted output ----

ecmsk_geom geom(unsigned slot)
{
	ecmsk_geom g{};
	REQUIRE(ecmsk_geom_init(&g, slot) == 0);
	return g;
}

// CRC-8 as the quick start's 2.2 describes it, one bit at a time.
std::uint8_t crcBitwise(const std::vector<std::uint8_t> &f)
{
	std::uint8_t c = 0x5A;
	for (std::size_t i = 0; i < f.size(); i++) {
		c = static_cast<std::uint8_t>(c ^ (i == 3 ? 0 : f[i]));
		for (int k = 0; k < 8; k++)
			c = (c & 0x80) ? static_cast<std::uint8_t>((c << 1) ^ 0x07)
				       : static_cast<std::uint8_t>(c << 1);
	}
	return c;
}

} // namespace

TEST_CASE("sk geometry: 12-byte slots make 42 slots, 504 bytes, 16-byte slots 32 slots, 512 bytes")
{
	auto g = geom(12);
	CHECK(g.slots == 42);
	CHECK(g.max_slaves == 40);
	CHECK(g.sdo_slot == 41);
	CHECK(g.frame_size == 504);
	g = geom(16);
	CHECK(g.slots == 32);
	CHECK(g.max_slaves == 30);
	CHECK(g.sdo_slot == 31);
	CHECK(g.frame_size == 512);
}

TEST_CASE("sk geometry: slot sizes other than 12 and 16 are refused")
{
	ecmsk_geom g{};
	for (unsigned bad : { 0u, 8u, 11u, 13u, 15u, 17u, 32u, 504u })
		CHECK(ecmsk_geom_init(&g, bad) == -EINVAL);
}

TEST_CASE("sk crc8: golden frames, the bitwise definition and the table agree")
{
	CHECK(ecmsk_crc8(reinterpret_cast<const std::uint8_t *>("123456789"), 9) == 0x59);
	std::vector<std::uint8_t> z504(504, 0), z512(512, 0);
	CHECK(ecmsk_crc8(z504.data(), 504) == 0x59);
	CHECK(ecmsk_crc8(z512.data(), 512) == 0x60);
	for (const Golden *gd : { &kSetStatePreop, &kSetAxis16, &kCspSdoWr, &kOpResponse, &kHsp2Csv }) {
		auto f = gd->frame();
		CHECK(ecmsk_frame_crc_ok(f.data(), f.size()));
		CHECK(ecmsk_crc8(f.data(), f.size()) == f[3]);
		CHECK(crcBitwise(f) == f[3]);
	}
}

TEST_CASE("sk crc8: byte 3 does not enter the CRC, every other byte does")
{
	auto f = kCspSdoWr.frame();
	const std::uint8_t good = f[3];
	f[3] ^= 0xFF;
	CHECK(ecmsk_crc8(f.data(), f.size()) == good);
	CHECK_FALSE(ecmsk_frame_crc_ok(f.data(), f.size()));
	ecmsk_frame_seal(f.data(), f.size());
	CHECK(f[3] == good);
	for (std::size_t i : { 0u, 2u, 4u, 100u, 503u }) {
		auto g = kCspSdoWr.frame();
		g[i] ^= 0x01;
		CHECK_FALSE(ecmsk_frame_crc_ok(g.data(), g.size()));
	}
	std::uint8_t tiny[3] = { 1, 2, 3 };
	CHECK_FALSE(ecmsk_frame_crc_ok(tiny, 3));
}

TEST_CASE("sk encode: SET_STATE PRE-OP in a 504-byte frame is the golden frame")
{
	auto g = geom(12);
	std::vector<std::uint8_t> f(504, 0);
	ecmsk_ecm_cmd c{ ECMSK_CMD_SET_STATE, 0, ECMSK_STATE_PREOP, 0, 0 };
	REQUIRE(ecmsk_put_ecm(&g, f.data(), &c) == 0);
	ecmsk_frame_seal(f.data(), f.size());
	CHECK(f == kSetStatePreop.frame());
}

TEST_CASE("sk encode: SET_AXIS group 1 in a 512-byte frame, topology from slave types")
{
	auto g = geom(16);
	std::uint8_t types[12] = { 0, 0, 0, 0, 0, 0, 0, 0, ECMSK_AXIS_STEP, ECMSK_AXIS_DRIVE,
				   ECMSK_AXIS_IO, ECMSK_AXIS_HSP };
	std::uint32_t topo = 0;
	REQUIRE(ecmsk_axis_topology(types, 12, 1, &topo) == 0);
	CHECK(topo == 0xFFFF2103u);
	std::vector<std::uint8_t> f(512, 0);
	ecmsk_ecm_cmd c{ ECMSK_CMD_SET_AXIS, 1, topo, 0, 0 };
	REQUIRE(ecmsk_put_ecm(&g, f.data(), &c) == 0);
	ecmsk_frame_seal(f.data(), f.size());
	CHECK(f == kSetAxis16.frame());
	// group 0 of the same 12 slaves: 8 drives
	REQUIRE(ecmsk_axis_topology(types, 12, 0, &topo) == 0);
	CHECK(topo == 0u);
	// group 2: nobody
	REQUIRE(ecmsk_axis_topology(types, 12, 2, &topo) == 0);
	CHECK(topo == 0xFFFFFFFFu);
}

TEST_CASE("sk encode: SET_AXIS refuses a group above 4, more than 40 slaves, an unknown type")
{
	std::uint8_t types[41] = {};
	std::uint32_t topo = 0x1234;
	CHECK(ecmsk_axis_topology(types, 8, 5, &topo) == -EINVAL);
	CHECK(ecmsk_axis_topology(types, 41, 0, &topo) == -EINVAL);
	types[3] = 4;
	CHECK(ecmsk_axis_topology(types, 8, 0, &topo) == -EINVAL);
	types[3] = ECMSK_AXIS_NONE;
	CHECK(ecmsk_axis_topology(types, 8, 0, &topo) == -EINVAL);
	CHECK(topo == 0x1234u);
}

TEST_CASE("sk encode: SET_DC, a CSP, an IO_WR in slot 40 and an SDO_WR make the golden frame")
{
	auto g = geom(12);
	std::vector<std::uint8_t> f(504, 0);
	ecmsk_ecm_cmd dc{ ECMSK_CMD_SET_DC, 0, 500, ECMSK_DC_FIX, 0 };
	REQUIRE(ecmsk_put_ecm(&g, f.data(), &dc) == 0);
	ecmsk_slave_cmd csp{ ECMSK_CMD_CSP, 7, static_cast<std::uint32_t>(-1000), 5, 0 };
	REQUIRE(ecmsk_put_slave(&g, f.data(), 1, &csp) == 0);
	ecmsk_slave_cmd io{ ECMSK_CMD_IO_WR, 0xA5, 0x0F0F, 0, 0 };
	REQUIRE(ecmsk_put_slave(&g, f.data(), 40, &io) == 0);
	ecmsk_sdo sdo{ ECMSK_CMD_SDO_WR, 0, 2, 1, 0, 0x6060, 6 };
	REQUIRE(ecmsk_put_sdo(&g, f.data(), &sdo) == 0);
	ecmsk_frame_seal(f.data(), f.size());
	CHECK(f == kCspSdoWr.frame());

	// and the firmware's side reads the same commands back
	ecmsk_ecm_cmd e{};
	ecmsk_get_ecm_cmd(&g, f.data(), &e);
	CHECK(e.cmd == ECMSK_CMD_SET_DC);
	CHECK(e.data1 == 500u);
	CHECK(e.data2 == 0xFFFFu);
	ecmsk_slave_cmd s{};
	REQUIRE(ecmsk_get_slave_cmd(&g, f.data(), 1, &s) == 0);
	CHECK(s.cmd == ECMSK_CMD_CSP);
	CHECK(s.index == 7);
	CHECK(static_cast<std::int32_t>(s.target) == -1000);
	CHECK(s.value == 5u);
	ecmsk_sdo r{};
	ecmsk_get_sdo(&g, f.data(), &r);
	CHECK(r.cmd == ECMSK_CMD_SDO_WR);
	CHECK(r.slave == 2);
	CHECK(r.size == 1);
	CHECK(r.index == 0x6060);
	CHECK(r.value == 6u);
}

TEST_CASE("sk encode: slave slots outside 1..max and 12-byte frames with data3 are refused")
{
	auto g12 = geom(12), g16 = geom(16);
	std::vector<std::uint8_t> f(512, 0), before = f;
	ecmsk_slave_cmd c{ ECMSK_CMD_SV_ON, 1, 0, 0, 0 };
	CHECK(ecmsk_put_slave(&g12, f.data(), 0, &c) == -ERANGE);
	CHECK(ecmsk_put_slave(&g12, f.data(), 41, &c) == -ERANGE);
	CHECK(ecmsk_put_slave(&g16, f.data(), 31, &c) == -ERANGE);
	CHECK(ecmsk_put_slave(&g16, f.data(), 30, &c) == 0);
	ecmsk_slave_cmd wide{ ECMSK_CMD_CSP, 1, 0, 0, 1 };
	f = before;
	CHECK(ecmsk_put_slave(&g12, f.data(), 1, &wide) == -EINVAL);
	ecmsk_ecm_cmd e{ ECMSK_CMD_GET_STATUS, 0, 0, 0, 7 };
	CHECK(ecmsk_put_ecm(&g12, f.data(), &e) == -EINVAL);
	CHECK(f == before);
	ecmsk_slave_rsp r{};
	CHECK(ecmsk_get_slave(&g12, f.data(), 0, &r) == -ERANGE);
	CHECK(ecmsk_get_slave(&g12, f.data(), 41, &r) == -ERANGE);
	ecmsk_slave_cmd rc{};
	CHECK(ecmsk_get_slave_cmd(&g16, f.data(), 31, &rc) == -ERANGE);
}

TEST_CASE("sk encode: SDO_WR sizes other than 1, 2, 4, values too wide, slaves outside 1..max")
{
	auto g = geom(12);
	std::vector<std::uint8_t> f(504, 0);
	for (unsigned size : { 0u, 3u, 5u, 8u }) {
		ecmsk_sdo c{ ECMSK_CMD_SDO_WR, 0, 1, static_cast<std::uint8_t>(size), 0, 0x6060, 1 };
		CHECK(ecmsk_put_sdo(&g, f.data(), &c) == -EINVAL);
	}
	ecmsk_sdo wide1{ ECMSK_CMD_SDO_WR, 0, 1, 1, 0, 0x6060, 0x100 };
	CHECK(ecmsk_put_sdo(&g, f.data(), &wide1) == -EINVAL);
	ecmsk_sdo wide2{ ECMSK_CMD_SDO_WR, 0, 1, 2, 0, 0x6040, 0x10000 };
	CHECK(ecmsk_put_sdo(&g, f.data(), &wide2) == -EINVAL);
	ecmsk_sdo s0{ ECMSK_CMD_SDO_RD, 0, 0, 0, 0, 0x6041, 0 };
	CHECK(ecmsk_put_sdo(&g, f.data(), &s0) == -ERANGE);
	ecmsk_sdo s41{ ECMSK_CMD_SDO_RD, 0, 41, 0, 0, 0x6041, 0 };
	CHECK(ecmsk_put_sdo(&g, f.data(), &s41) == -ERANGE);
	CHECK(f == std::vector<std::uint8_t>(504, 0));
	ecmsk_sdo ok{ ECMSK_CMD_SDO_WR, 0, 40, 4, 2, 0x6099, 0xFFFFFFFF };
	CHECK(ecmsk_put_sdo(&g, f.data(), &ok) == 0);
}

TEST_CASE("sk decode: a response in OP — 0xBF, CRC errors, state, FIFO counts, slave and SDO slots")
{
	auto g = geom(12);
	auto f = kOpResponse.frame();
	ecmsk_ecm_rsp e{};
	ecmsk_get_ecm(&g, f.data(), &e);
	CHECK(e.cmd == ECMSK_RSP_OP);
	CHECK(e.crc_errors == 2);
	CHECK(e.state == ECMSK_STATE_OP);
	CHECK(e.fifo_remaining == 200);
	CHECK(e.fifo_full == 3);
	ecmsk_slave_rsp s{};
	REQUIRE(ecmsk_get_slave(&g, f.data(), 1, &s) == 0);
	CHECK(s.cmd == ECMSK_CMD_CSP);
	CHECK(s.index == 7);
	CHECK(s.statusword == 0x1237);
	CHECK(static_cast<std::int32_t>(s.position) == 123456);
	CHECK(static_cast<std::int16_t>(s.torque) == -5);
	CHECK(s.error_code == 0x7500);
	ecmsk_sdo sdo{};
	ecmsk_get_sdo(&g, f.data(), &sdo);
	CHECK(sdo.cmd == ECMSK_CMD_SDO_RD);
	CHECK(sdo.status == ECMSK_SDO_DONE);
	CHECK(sdo.slave == 1);
	CHECK(sdo.index == 0x6041);
	CHECK(sdo.value == 0x1237u);

	// the firmware's encoder makes the same frame
	std::vector<std::uint8_t> out(504, 0);
	ecmsk_ecm_rsp er{ ECMSK_RSP_OP, 2, ECMSK_STATE_OP, 0, 0, 0xDEAD, 0, 200, 3 };
	REQUIRE(ecmsk_put_ecm_rsp(&g, out.data(), &er) == 0);
	ecmsk_slave_rsp sr{ ECMSK_CMD_CSP, 7, 0x1237, 123456, static_cast<std::uint16_t>(-5), 0x7500, 0 };
	REQUIRE(ecmsk_put_slave_rsp(&g, out.data(), 1, &sr) == 0);
	ecmsk_sdo sdr{ ECMSK_CMD_SDO_RD, ECMSK_SDO_DONE, 1, 0, 0, 0x6041, 0x1237 };
	REQUIRE(ecmsk_put_sdo_rsp(&g, out.data(), &sdr) == 0);
	ecmsk_frame_seal(out.data(), out.size());
	CHECK(out == f);
}

TEST_CASE("sk decode: outside OP, bytes 8-11 of slot 0 are Data2, not FIFO counts")
{
	auto g = geom(12);
	std::vector<std::uint8_t> out(504, 0);
	ecmsk_ecm_rsp er{ ECMSK_CMD_SET_AXIS, 0, ECMSK_STATE_PREOP, 0, 3, 0x11223344, 0, 9, 9 };
	REQUIRE(ecmsk_put_ecm_rsp(&g, out.data(), &er) == 0);
	CHECK(out[0] == 0x02);
	CHECK(out[2] == 0x02);
	CHECK(out[4] == 3);
	CHECK(out[8] == 0x44);
	CHECK(out[11] == 0x11);
}

TEST_CASE("sk encode/decode: a 2-channel HSP uses the 16-byte layout of tables 2.16/2.18")
{
	auto g = geom(16);
	std::vector<std::uint8_t> f(512, 0);
	ecmsk_hsp2 c{ ECMSK_CMD_CSV, 9, 0xFFFF, 1000, 1, static_cast<std::uint32_t>(-2000), 2 };
	REQUIRE(ecmsk_put_hsp2(&g, f.data(), 3, &c) == 0);
	ecmsk_frame_seal(f.data(), f.size());
	CHECK(f == kHsp2Csv.frame());	// statusword is not sent
	ecmsk_hsp2 r{};
	REQUIRE(ecmsk_get_hsp2(&g, f.data(), 3, &r) == 0);
	CHECK(r.pos1 == 1000u);
	CHECK(static_cast<std::int32_t>(r.pos2) == -2000);
	CHECK(r.io2 == 2);
	auto g12 = geom(12);
	CHECK(ecmsk_put_hsp2(&g12, f.data(), 3, &c) == -EINVAL);
	CHECK(ecmsk_get_hsp2(&g12, f.data(), 3, &r) == -EINVAL);
	CHECK(ecmsk_put_hsp2(&g, f.data(), 31, &c) == -ERANGE);
}

TEST_CASE("sk commands: table 1.3's ids, names, slots and states")
{
	struct Row {
		std::uint16_t id;
		const char *name;
		unsigned states;
		bool slave;
	};
	const unsigned all = 0x0F, i = 1, p = 2, s = 4, o = 8;
	const Row rows[] = {
		{ 0x00, "GET_STATUS", all, false }, { 0x01, "SET_STATE", all, false },
		{ 0x02, "SET_AXIS", i | p, false }, { 0x03, "SET_DC", i | p, false },
		{ 0x04, "SET_EX", i | p | s, false }, { 0x05, "SET_FIFO", o, false },
		{ 0x06, "DRIVE_MODE", i | p, true }, { 0x07, "SDO_RD", p | s | o, false },
		{ 0x08, "SDO_WR", p | s | o, false }, { 0x10, "ALM_CLR", o, true },
		{ 0x11, "SV_ON", o, true }, { 0x12, "SV_OFF", o, true }, { 0x13, "IO_RD", o, true },
		{ 0x14, "IO_WR", o, true }, { 0x15, "CSP", o, true }, { 0x16, "CSV", o, true },
		{ 0x17, "CST", o, true }, { 0x18, "GO_HOME", o, true }, { 0x19, "ABORT_HOME", o, true },
		{ 0x21, "LIO_RD", all, false }, { 0x22, "LIO_WR", all, false },
		{ 0xBB, "SW_RESET", all, false },
	};
	for (const auto &r : rows) {
		INFO(r.name);
		CHECK(ecmsk_cmd_known(r.id));
		CHECK(std::string(ecmsk_cmd_name(r.id)) == r.name);
		CHECK(ecmsk_cmd_states(r.id) == r.states);
		CHECK(ecmsk_cmd_is_slave(static_cast<std::uint8_t>(r.id)) == r.slave);
		CHECK(ecmsk_cmd_is_cyclic(static_cast<std::uint8_t>(r.id)) ==
		      (r.id >= 0x15 && r.id <= 0x17));
	}
	for (unsigned bad : { 0x09u, 0x0Fu, 0x1Au, 0x20u, 0x23u, 0xBAu, 0xBFu, 0x100u, 0x0121u }) {
		CHECK_FALSE(ecmsk_cmd_known(static_cast<std::uint16_t>(bad)));
		CHECK(ecmsk_cmd_states(static_cast<std::uint16_t>(bad)) == 0u);
		CHECK(std::string(ecmsk_cmd_name(static_cast<std::uint16_t>(bad))) == "?");
	}
}

TEST_CASE("sk commands: SET_DC cycle times are 250 * 2^n us, states are the four of 1.8")
{
	for (std::uint32_t us : { 250u, 500u, 1000u, 2000u, 4000u, 8000u, 250u << 20 })
		CHECK(ecmsk_dc_cycle_valid(us));
	for (std::uint32_t us : { 0u, 125u, 249u, 251u, 750u, 1500u, 3000u, 250u << 21, 0xFFFFFFFFu })
		CHECK_FALSE(ecmsk_dc_cycle_valid(us));
	for (std::uint32_t st : { 1u, 2u, 4u, 8u })
		CHECK(ecmsk_state_valid(st));
	for (std::uint32_t st : { 0u, 3u, 5u, 6u, 7u, 9u, 0x10u, 0x108u })
		CHECK_FALSE(ecmsk_state_valid(st));
}

TEST_CASE("sk crc8: eight bytes per step agrees with the bitwise definition at every length")
{
	std::uint32_t x = 12345;
	for (std::size_t len = 0; len <= 600; len++) {
		std::vector<std::uint8_t> f(len);
		for (auto &b : f) {
			x = x * 1103515245u + 12345u;
			b = static_cast<std::uint8_t>(x >> 16);
		}
		INFO("length " << len);
		CHECK(ecmsk_crc8(f.data(), f.size()) == crcBitwise(f));
	}
}

TEST_CASE("sk encode: a 2-channel HSP response carries the statusword, 12-byte slots refuse it")
{
	auto g = geom(16);
	std::vector<std::uint8_t> f(512, 0);
	ecmsk_hsp2 r{ ECMSK_CMD_CSP, 4, 0x1237, 1000, 0x0003, static_cast<std::uint32_t>(-2000), 0x0100 };
	REQUIRE(ecmsk_put_hsp2_rsp(&g, f.data(), 2, &r) == 0);
	// slot 2 = bytes 32..47, tables 2.16/2.18
	CHECK(f[32] == 0x15);
	CHECK(f[33] == 4);
	CHECK(f[34] == 0x37);
	CHECK(f[35] == 0x12);
	CHECK(f[36] == 0xE8);
	CHECK(f[37] == 0x03);
	CHECK(f[40] == 0x03);
	CHECK(f[42] == 0x30);
	CHECK(f[43] == 0xF8);
	CHECK(f[44] == 0xFF);
	CHECK(f[45] == 0xFF);
	CHECK(f[47] == 0x01);
	auto g12 = geom(12);
	CHECK(ecmsk_put_hsp2_rsp(&g12, f.data(), 2, &r) == -EINVAL);
	CHECK(ecmsk_put_hsp2_rsp(&g, f.data(), 31, &r) == -ERANGE);
}
