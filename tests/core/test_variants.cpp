// SPDX-License-Identifier: MIT
// Firmware variants (Documentation/protocol-core.rst, "Firmware variants"):
// the two CRC coverages of the codec against golden values computed
// independently (Python's zlib.crc32 over hand-built bytes), the engine's
// detection of the chip's coverage, and CRC_TYPE_SET that a chip drops or
// refuses without the host getting stuck in either check type.

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdint>
#include <vector>

#include "ecmxf-proto.h"
#include "fake_chip.hpp"

namespace {

constexpr std::uint64_t kStepNs = 100'000;

const ecmxf_check kValid32 =
	static_cast<ecmxf_check>(ECMXF_CHECK_CRC32 | ECMXF_CHECK_COVER_VALID);

std::uint32_t le32(const std::vector<std::uint8_t> &p, std::size_t off)
{
	return static_cast<std::uint32_t>(p[off]) | static_cast<std::uint32_t>(p[off + 1]) << 8 |
	       static_cast<std::uint32_t>(p[off + 2]) << 16 |
	       static_cast<std::uint32_t>(p[off + 3]) << 24;
}

// A command packet of a 32-byte data section, built by hand: SLV_INFO_GET
// (15), index 0x21, param 1, data0 10, data length @len, data @data.
std::vector<std::uint8_t> handCmd(std::uint16_t len, const std::vector<std::uint8_t> &data)
{
	std::vector<std::uint8_t> p(ECMXF_PKT_SIZE(32), 0);
	const std::uint8_t hdr[24] = { 0xA4, 0xA3, 0xA2, 0xA1, 10, 0, 0, 0, 0, 0, 0, 0x21, 15, 1,
				       static_cast<std::uint8_t>(len), static_cast<std::uint8_t>(len >> 8) };
	for (std::size_t i = 0; i < 24; i++)
		p[i] = hdr[i];
	for (std::size_t i = 0; i < data.size(); i++)
		p[24 + i] = data[i];
	return p;
}

ecmxf_cmd_hdr handHdr(std::uint16_t len)
{
	ecmxf_cmd_hdr h{};
	h.data[0] = 10;
	h.index = 0x21;
	h.code = 15;
	h.param = 1;
	h.len = len;
	return h;
}

struct Link : fake::Link {
	Link() : fake::Link(kStepNs) {}
};

} // namespace

TEST_CASE("codec: CRC-32 over the whole frame (050) and over header + valid length (example code)",
	  "[codec][variants]")
{
	// golden values: Python zlib.crc32 over the hand-built bytes
	struct Vec {
		std::uint16_t len;
		std::vector<std::uint8_t> data;
		std::uint32_t frame;
		std::uint32_t valid;
	};
	const Vec vecs[] = {
		{ 5, { 1, 2, 3, 4, 5 }, 0x84041BA9u, 0x14DC4B2Du }, // covers 24 + 8 bytes
		{ 0, {}, 0x34F01C94u, 0x5F580B3Cu },                // covers the header only
		{ 30, { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21,
			22, 23, 24, 25, 26, 27, 28, 29 },
		  0x8F4F4EA6u, 0x8F4F4EA6u }, // rounded up to 32 = the data section
		{ 33, {}, 0xB3A54AA6u, 0xB3A54AA6u }, // beyond the section: clipped to it
	};
	for (const Vec &v : vecs) {
		INFO("data length " << v.len);
		const std::vector<std::uint8_t> hand = handCmd(v.len, v.data);
		for (const bool valid : { false, true }) {
			const ecmxf_check ck = valid ? kValid32 : ECMXF_CHECK_CRC32;
			const std::uint32_t want = valid ? v.valid : v.frame;
			std::vector<std::uint8_t> pkt(ECMXF_PKT_SIZE(32), 0xEE);
			const ecmxf_cmd_hdr h = handHdr(v.len);
			REQUIRE(ecmxf_encode_cmd(pkt.data(), pkt.size(), ck, &h, v.data.data(),
						 v.data.size()) == 0);
			CHECK(std::vector<std::uint8_t>(pkt.begin(), pkt.begin() + 56) ==
			      std::vector<std::uint8_t>(hand.begin(), hand.begin() + 56));
			CHECK(le32(pkt, 56) == want);
			CHECK(le32(pkt, 60) == ECMXF_END_WORD);
			ecmxf_cmd_hdr got{};
			CHECK(ecmxf_decode_cmd(pkt.data(), pkt.size(), ck, &got, nullptr) ==
			      ECMXF_FAULT_NONE);
			CHECK(got.len == v.len);
		}
		// the two rules differ exactly where their values do
		std::vector<std::uint8_t> pkt(ECMXF_PKT_SIZE(32));
		const ecmxf_cmd_hdr h = handHdr(v.len);
		REQUIRE(ecmxf_encode_cmd(pkt.data(), pkt.size(), ECMXF_CHECK_CRC32, &h, v.data.data(),
					 v.data.size()) == 0);
		CHECK((ecmxf_decode_cmd(pkt.data(), pkt.size(), kValid32, nullptr, nullptr) ==
		       ECMXF_FAULT_NONE) == (v.frame == v.valid));
	}
}

TEST_CASE("codec: a response under the example code's coverage, golden and cross-checked",
	  "[codec][variants]")
{
	// SLV_INFO_GET answer, index 0x21, 4 data bytes 11 22 33 44, ECAT
	// state INIT, ECM status CRC-32; zlib.crc32 over 28 / 56 bytes
	ecmxf_rsp_hdr h{};
	h.ecat_state = ECMXF_ECAT_INIT;
	h.ecm_status = ECMXF_CHECK_CRC32;
	h.index = 0x21;
	h.code = 15;
	h.len = 4;
	const std::uint8_t data[4] = { 0x11, 0x22, 0x33, 0x44 };
	std::vector<std::uint8_t> pkt(ECMXF_PKT_SIZE(32));
	REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), kValid32, &h, data, 4) == 0);
	CHECK(le32(pkt, 56) == 0x6C6CEC76u);
	REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), ECMXF_CHECK_CRC32, &h, data, 4) == 0);
	CHECK(le32(pkt, 56) == 0x0EEB3C15u);
	// each rule refuses the other's packet
	CHECK(ecmxf_decode_rsp(pkt.data(), pkt.size(), kValid32, nullptr, nullptr) ==
	      ECMXF_FAULT_CHECK);
	REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), kValid32, &h, data, 4) == 0);
	CHECK(ecmxf_decode_rsp(pkt.data(), pkt.size(), ECMXF_CHECK_CRC32, nullptr, nullptr) ==
	      ECMXF_FAULT_CHECK);
	// bytes past the valid data are not covered by the example code's rule
	pkt[24 + 4] ^= 0xFF;
	CHECK(ecmxf_decode_rsp(pkt.data(), pkt.size(), kValid32, nullptr, nullptr) ==
	      ECMXF_FAULT_NONE);
	pkt[24 + 3] ^= 0xFF;
	CHECK(ecmxf_decode_rsp(pkt.data(), pkt.size(), kValid32, nullptr, nullptr) ==
	      ECMXF_FAULT_CHECK);
}

TEST_CASE("codec: coverage spans, and bad check arguments", "[codec][variants]")
{
	std::vector<std::uint8_t> pkt(ECMXF_PKT_SIZE(112), 0);
	CHECK(ecmxf_check_span(pkt.data(), pkt.size(), ECMXF_CHECK_CRC32) == 24 + 112);
	for (const auto &[len, span] : { std::pair{ 0u, 24u }, { 1u, 28u }, { 4u, 28u }, { 5u, 32u },
					 { 111u, 136u }, { 112u, 136u }, { 1408u, 136u },
					 { 0xFFFFu, 136u } }) {
		pkt[0x0E] = static_cast<std::uint8_t>(len);
		pkt[0x0F] = static_cast<std::uint8_t>(len >> 8);
		CHECK(ecmxf_check_span(pkt.data(), pkt.size(), kValid32) == span);
	}
	CHECK(ecmxf_check_span(pkt.data(), 55, ECMXF_CHECK_CRC32) == 0);
	CHECK(ecmxf_check_span(nullptr, pkt.size(), ECMXF_CHECK_CRC32) == 0);
	// the fixed word ignores the flag; unknown bits are refused
	ecmxf_cmd_hdr h{};
	const auto fixedValid = static_cast<ecmxf_check>(ECMXF_CHECK_FIXED | ECMXF_CHECK_COVER_VALID);
	REQUIRE(ecmxf_encode_cmd(pkt.data(), pkt.size(), fixedValid, &h, nullptr, 0) == 0);
	CHECK(le32(pkt, 24 + 112) == ECMXF_FIXED_CHECK);
	for (const unsigned bad : { 0x04u, 0x08u, 0x20u, 0x13u | 0x80u }) {
		CHECK(ecmxf_encode_cmd(pkt.data(), pkt.size(), static_cast<ecmxf_check>(bad), &h, nullptr,
				       0) == -EINVAL);
		CHECK(ecmxf_decode_rsp(pkt.data(), pkt.size(), static_cast<ecmxf_check>(bad), nullptr,
				       nullptr) == ECMXF_FAULT_SIZE);
	}
	CHECK(std::string(ecmxf_cover_name(ECMXF_COVER_FRAME)) == "frame");
	CHECK(std::string(ecmxf_cover_name(ECMXF_COVER_VALID)) == "valid");
	CHECK(std::string(ecmxf_cover_name(ECMXF_COVER_UNKNOWN)) == "unknown");
	CHECK(std::string(ecmxf_cover_name(static_cast<ecmxf_cover>(3))) == "unknown");
}

TEST_CASE("engine: finds the chip's CRC coverage when CRC-32 comes into force, without a CRC error",
	  "[engine][variants]")
{
	for (const bool valid : { false, true }) {
		INFO((valid ? "example-code coverage" : "manual 050 coverage"));
		Link l;
		l.chip.validCover = valid;
		l.chip.fixedForAll = false;
		CHECK(ecmxf_engine_cover(&l.e) == ECMXF_COVER_UNKNOWN);
		REQUIRE(l.cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC32) == 0);
		CHECK(ecmxf_engine_check(&l.e) == ECMXF_CHECK_CRC32);
		// a command with data: its check word follows the chip's rule
		const std::vector<std::uint8_t> tx = { 1, 2, 3, 4, 5 };
		REQUIRE(l.cmd(ECMXF_CMD_ECAT_SLV_CNT_GET, 0, tx) == 0);
		CHECK(ecmxf_engine_cover(&l.e) == (valid ? ECMXF_COVER_VALID : ECMXF_COVER_FRAME));
		CHECK(l.chip.mosiBad == 0);
		CHECK(l.e.stats.faults[ECMXF_FAULT_CHECK] == 0);
		const ecmxf_cmd_hdr &last = l.chip.executed.back();
		CHECK(last.code == ECMXF_CMD_ECAT_SLV_CNT_GET);
		CHECK(last.len == 5);
		// the probes that waited for the answer carried the whole data
		// section as length, so both rules covered the same bytes
		bool probed = false;
		for (const ecmxf_cmd_hdr &c : l.chip.cmdLog)
			probed |= c.code == ECMXF_CMD_INFO_UPDATE_OP && c.len == ECMXF_DATA_DEFAULT;
		CHECK(probed);
		// and the packet sent: CRC over 24 + 8 bytes, or over all of them
		const auto &p = l.chip.mosiLog.back();
		const std::size_t n = p.size() - 8;
		CHECK(le32(p, n) == ecmxf_crc32(p.data(), valid ? 24 + 8 : n));
		// switching back and forth keeps it and stays clean
		REQUIRE(l.cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_FIXED) == 0);
		REQUIRE(l.cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC32) == 0);
		REQUIRE(l.cmd(ECMXF_CMD_ECAT_SLV_CNT_GET, 0, tx) == 0);
		CHECK(ecmxf_engine_cover(&l.e) == (valid ? ECMXF_COVER_VALID : ECMXF_COVER_FRAME));
		CHECK(l.chip.mosiBad == 0);
	}
}

TEST_CASE("engine: a response both rules verify decides nothing, the next one that tells them apart does",
	  "[engine][variants]")
{
	ecmxf_engine e;
	ecmxf_engine_init(&e, 32, ECMXF_CHECK_CRC32);
	std::vector<std::uint8_t> pkt(ECMXF_PKT_SIZE(32));
	ecmxf_rsp_hdr h{};
	h.ecm_status = ECMXF_CHECK_CRC32;
	h.code = ECMXF_CMD_FW_VERSION_GET;
	h.len = 32; // the whole data section: the rules agree
	const std::vector<std::uint8_t> data(32, 0x5A);
	for (const ecmxf_check ck : { kValid32, ECMXF_CHECK_CRC32 }) {
		REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), ck, &h, data.data(), 32) == 0);
		CHECK((ecmxf_engine_input(&e, 1, pkt.data(), pkt.size()) & ECMXF_EV_BAD_PACKET) == 0);
		CHECK(ecmxf_engine_cover(&e) == ECMXF_COVER_UNKNOWN);
	}
	h.len = 29; // rounds up to 32: the same bytes again
	REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), kValid32, &h, data.data(), 29) == 0);
	CHECK((ecmxf_engine_input(&e, 2, pkt.data(), pkt.size()) & ECMXF_EV_BAD_PACKET) == 0);
	CHECK(ecmxf_engine_cover(&e) == ECMXF_COVER_UNKNOWN);
	h.len = 4; // 24 + 4 bytes against 24 + 32: decides
	REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), kValid32, &h, data.data(), 4) == 0);
	CHECK((ecmxf_engine_input(&e, 3, pkt.data(), pkt.size()) & ECMXF_EV_BAD_PACKET) == 0);
	CHECK(ecmxf_engine_cover(&e) == ECMXF_COVER_VALID);
	// from then on only that rule is accepted
	REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), ECMXF_CHECK_CRC32, &h, data.data(), 4) == 0);
	CHECK((ecmxf_engine_input(&e, 4, pkt.data(), pkt.size()) & ECMXF_EV_BAD_PACKET) != 0);
	CHECK(e.stats.faults[ECMXF_FAULT_CHECK] == 1);
	CHECK(ecmxf_engine_cover(&e) == ECMXF_COVER_VALID);
	// a packet neither rule verifies decides nothing either
	ecmxf_engine f;
	ecmxf_engine_init(&f, 32, ECMXF_CHECK_CRC32);
	REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), ECMXF_CHECK_CRC32, &h, data.data(), 4) == 0);
	pkt[24] ^= 1;
	CHECK((ecmxf_engine_input(&f, 1, pkt.data(), pkt.size()) & ECMXF_EV_BAD_PACKET) != 0);
	CHECK(ecmxf_engine_cover(&f) == ECMXF_COVER_UNKNOWN);
	// with the fixed word in force nothing is decided
	ecmxf_engine g;
	ecmxf_engine_init(&g, 32, ECMXF_CHECK_FIXED);
	REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), ECMXF_CHECK_FIXED, &h, data.data(), 4) == 0);
	CHECK((ecmxf_engine_input(&g, 1, pkt.data(), pkt.size()) & ECMXF_EV_BAD_PACKET) == 0);
	CHECK(ecmxf_engine_cover(&g) == ECMXF_COVER_UNKNOWN);
}

TEST_CASE("engine: CRC_TYPE_SET the chip dropped is sent again, with the fixed word every other time",
	  "[engine][variants]")
{
	for (const bool crcSetFixed : { false, true }) {
		for (const bool valid : { false, true }) {
			INFO((crcSetFixed ? "chip takes CRC_TYPE_SET with the fixed word"
					  : "chip drops it") << ", "
							     << (valid ? "valid" : "frame") << " coverage");
			Link l;
			l.chip.validCover = valid;
			l.chip.fixedForAll = false;
			l.chip.crcSetFixed = crcSetFixed;
			// fixed -> CRC-32, the first send lost on the wire
			int drops = 1;
			l.chip.dropCmd = [&](const ecmxf_cmd_hdr &c) {
				return c.code == ECMXF_CMD_CRC_TYPE_SET && drops-- > 0;
			};
			REQUIRE(l.cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC32) == 0);
			CHECK(l.chip.check == ECMXF_CHECK_CRC32);
			CHECK(ecmxf_engine_check(&l.e) == ECMXF_CHECK_CRC32);
			REQUIRE(l.cmd(ECMXF_CMD_ECAT_SLV_CNT_GET) == 0);

			// CRC-32 -> fixed, the first send lost: the second try goes
			// out with the fixed word, which only one variant takes
			drops = 1;
			const int before = l.chip.mosiBad;
			REQUIRE(l.cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_FIXED) == 0);
			CHECK(l.chip.check == ECMXF_CHECK_FIXED);
			CHECK(ecmxf_engine_check(&l.e) == ECMXF_CHECK_FIXED);
			// taking the fixed word: the lost send and nothing else; a chip
			// that drops it: the lost send and its re-send in the new type,
			// the fixed-word try and its re-send, then the try in force
			CHECK(l.chip.mosiBad - before == (crcSetFixed ? 1 : 4));
			REQUIRE(l.cmd(ECMXF_CMD_ECAT_SLV_CNT_GET) == 0);
			// and once more to CRC-32, undisturbed
			REQUIRE(l.cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC32) == 0);
			REQUIRE(l.cmd(ECMXF_CMD_ECAT_SLV_CNT_GET) == 0);
			CHECK(ecmxf_engine_cover(&l.e) == (valid ? ECMXF_COVER_VALID : ECMXF_COVER_FRAME));
		}
	}
}

TEST_CASE("engine: a chip that never takes CRC_TYPE_SET, or refuses the type, leaves the host in its type",
	  "[engine][variants]")
{
	SECTION("never taken: the command times out, the link keeps working")
	{
		Link l;
		l.chip.fixedForAll = false;
		REQUIRE(l.cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC32) == 0);
		l.chip.dropCmd = [](const ecmxf_cmd_hdr &c) { return c.code == ECMXF_CMD_CRC_TYPE_SET; };
		CHECK(l.cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_FIXED) == -ETIMEDOUT);
		l.chip.dropCmd = nullptr;
		CHECK(l.cmd(ECMXF_CMD_ECAT_SLV_CNT_GET) == 0);
		CHECK(ecmxf_engine_check(&l.e) == ECMXF_CHECK_CRC32);
		CHECK(l.chip.check == ECMXF_CHECK_CRC32);
	}
	SECTION("refused (an undefined type of manual 050): back to the chip's type")
	{
		Link l;
		l.chip.fixedForAll = false;
		l.chip.refuseTypes = 1u << ECMXF_CHECK_CRC8;
		CHECK(l.cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC8) == 0);
		// the answer came; the next ones show the chip kept the fixed word
		CHECK(l.cmd(ECMXF_CMD_ECAT_SLV_CNT_GET) == 0);
		CHECK(l.cmd(ECMXF_CMD_ECAT_SLV_CNT_GET) == 0);
		CHECK(ecmxf_engine_check(&l.e) == ECMXF_CHECK_FIXED);
		CHECK(l.chip.check == ECMXF_CHECK_FIXED);
		const int bad = l.chip.mosiBad;
		CHECK(l.cmd(ECMXF_CMD_ECAT_SLV_CNT_GET) == 0);
		CHECK(l.chip.mosiBad == bad);
	}
}
