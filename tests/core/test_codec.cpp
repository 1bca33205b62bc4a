// SPDX-License-Identifier: MIT
// Codec round trips for every data size and check type, and rejection of
// every kind of bad packet.  The byte-exact golden vectors are in
// tests/golden/; here the codec is checked against itself and the layout.

#include <catch2/catch.hpp>

#include <cstdint>
#include <vector>

#include "ecmxf-proto.h"

namespace {

const ecmxf_check kChecks[] = { ECMXF_CHECK_FIXED, ECMXF_CHECK_CRC8, ECMXF_CHECK_CCITT,
				ECMXF_CHECK_CRC32 };

ecmxf_rsp_hdr sampleRsp(std::uint16_t len)
{
	ecmxf_rsp_hdr h{};
	h.crc_err_cnt = 1;
	h.wkc_err_cnt = 2;
	h.tx_fifo_cnt = 3;
	h.rx_fifo_cnt = 4;
	h.ecat_state = ECMXF_ECAT_OP;
	h.err_status = ECMXF_ERR_LINK_HW;
	h.ecm_status = ECMXF_STS_FIFO_EN;
	h.index = 0x5A;
	h.code = ECMXF_CMD_ECAT_SDO_GET;
	h.ret = 0x77;
	h.len = len;
	h.int_flags = ECMXF_INT_ECAT_PKT | 0x00ABCDEFu;
	h.gpio_int_flag[0] = 0x11;
	h.gpio_int_flag[1] = 0x22;
	h.gpio_in[0] = 0x33;
	h.gpio_in[1] = 0x44;
	return h;
}

std::uint32_t le32(const std::vector<std::uint8_t> &p, std::size_t off)
{
	return static_cast<std::uint32_t>(p[off]) | static_cast<std::uint32_t>(p[off + 1]) << 8 |
	       static_cast<std::uint32_t>(p[off + 2]) << 16 |
	       static_cast<std::uint32_t>(p[off + 3]) << 24;
}

} // namespace

TEST_CASE("codec: command packets round-trip at every data size 32..1408 with every check type",
	  "[codec]")
{
	for (unsigned n = ECMXF_DATA_MIN; n <= ECMXF_DATA_MAX; n++) {
		for (ecmxf_check check : kChecks) {
			std::vector<std::uint8_t> pkt(ECMXF_PKT_SIZE(n), 0xEE);
			std::vector<std::uint8_t> data(n);
			for (unsigned i = 0; i < n; i++)
				data[i] = static_cast<std::uint8_t>(i * 7 + n);
			ecmxf_cmd_hdr h{};
			h.data[0] = 0xFF;
			h.data[3] = 0x81;
			h.reserved = ECMXF_RSV_GPIO_OUT | ECMXF_RSV_LRW;
			h.control = ECMXF_CTL_CLR_CMD_ERR;
			h.index = static_cast<std::uint8_t>(n);
			h.code = ECMXF_CMD_ECAT_SDO_REQ;
			h.param = 9;
			h.len = static_cast<std::uint16_t>(n);
			h.int_clear = ECMXF_INT_ECAT_PKT;
			h.gpio_int_clear[1] = 0x0F;
			h.gpio_out[0] = 0xA5;
			REQUIRE(ecmxf_encode_cmd(pkt.data(), pkt.size(), check, &h, data.data(), n) == 0);

			ecmxf_cmd_hdr got{};
			const std::uint8_t *d = nullptr;
			REQUIRE(ecmxf_decode_cmd(pkt.data(), pkt.size(), check, &got, &d) ==
				ECMXF_FAULT_NONE);
			CHECK(got.index == h.index);
			CHECK(got.code == h.code);
			CHECK(got.reserved == h.reserved);
			CHECK(got.int_clear == h.int_clear);
			CHECK(got.gpio_out[0] == 0xA5);
			CHECK(d == pkt.data() + ECMXF_HDR_SIZE);
			CHECK(std::equal(data.begin(), data.end(), d));
			CHECK(le32(pkt, 0) == ECMXF_START_WORD);
			CHECK(le32(pkt, ECMXF_HDR_SIZE + n + 4) == ECMXF_END_WORD);
			CHECK(le32(pkt, ECMXF_HDR_SIZE + n) ==
			      ecmxf_check_word(check, pkt.data(), ECMXF_HDR_SIZE + n));
		}
	}
}

TEST_CASE("codec: response packets round-trip and every header field is read back",
	  "[codec]")
{
	for (unsigned n : { 32u, 112u, 1000u, 1408u }) {
		for (ecmxf_check check : kChecks) {
			std::vector<std::uint8_t> pkt(ECMXF_PKT_SIZE(n));
			const std::uint8_t data[4] = { 0xDE, 0xAD, 0xBE, 0xEF };
			const ecmxf_rsp_hdr h = sampleRsp(4);
			REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), check, &h, data, 4) == 0);
			ecmxf_rsp_hdr got{};
			const std::uint8_t *d = nullptr;
			REQUIRE(ecmxf_decode_rsp(pkt.data(), pkt.size(), check, &got, &d) ==
				ECMXF_FAULT_NONE);
			CHECK(got.crc_err_cnt == 1);
			CHECK(got.wkc_err_cnt == 2);
			CHECK(got.tx_fifo_cnt == 3);
			CHECK(got.rx_fifo_cnt == 4);
			CHECK(got.ecat_state == ECMXF_ECAT_OP);
			CHECK(got.err_status == ECMXF_ERR_LINK_HW);
			CHECK(got.ecm_status == ECMXF_STS_FIFO_EN);
			CHECK(got.index == 0x5A);
			CHECK(got.code == ECMXF_CMD_ECAT_SDO_GET);
			CHECK(got.ret == 0x77);
			CHECK(got.len == 4);
			CHECK(got.int_flags == (ECMXF_INT_ECAT_PKT | 0x00ABCDEFu));
			CHECK(got.gpio_int_flag[0] == 0x11);
			CHECK(got.gpio_int_flag[1] == 0x22);
			CHECK(got.gpio_in[0] == 0x33);
			CHECK(got.gpio_in[1] == 0x44);
			CHECK(d[3] == 0xEF);
		}
	}
}

TEST_CASE("codec: a response data length beyond the data section is rejected", "[codec]")
{
	const unsigned n = 112;
	std::vector<std::uint8_t> pkt(ECMXF_PKT_SIZE(n));
	ecmxf_rsp_hdr h = sampleRsp(static_cast<std::uint16_t>(n));
	REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), ECMXF_CHECK_CRC32, &h, nullptr, 0) == 0);
	CHECK(ecmxf_decode_rsp(pkt.data(), pkt.size(), ECMXF_CHECK_CRC32, nullptr, nullptr) ==
	      ECMXF_FAULT_NONE);
	h.len = static_cast<std::uint16_t>(n + 1);
	REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), ECMXF_CHECK_CRC32, &h, nullptr, 0) == 0);
	CHECK(ecmxf_decode_rsp(pkt.data(), pkt.size(), ECMXF_CHECK_CRC32, nullptr, nullptr) ==
	      ECMXF_FAULT_LENGTH);
	h.len = 0xFFFF;
	REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), ECMXF_CHECK_CRC32, &h, nullptr, 0) == 0);
	ecmxf_rsp_hdr got{};
	CHECK(ecmxf_decode_rsp(pkt.data(), pkt.size(), ECMXF_CHECK_CRC32, &got, nullptr) ==
	      ECMXF_FAULT_LENGTH);
}

TEST_CASE("codec: every single-bit error is caught by the CRC check types", "[codec]")
{
	const unsigned n = 32;
	for (ecmxf_check check : { ECMXF_CHECK_CRC8, ECMXF_CHECK_CCITT, ECMXF_CHECK_CRC32 }) {
		std::vector<std::uint8_t> pkt(ECMXF_PKT_SIZE(n));
		const ecmxf_rsp_hdr h = sampleRsp(0);
		REQUIRE(ecmxf_encode_rsp(pkt.data(), pkt.size(), check, &h, nullptr, 0) == 0);
		for (std::size_t bit = 0; bit < pkt.size() * 8; bit++) {
			std::vector<std::uint8_t> bad = pkt;
			bad[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
			const ecmxf_fault f =
				ecmxf_decode_rsp(bad.data(), bad.size(), check, nullptr, nullptr);
			INFO("check " << check << " bit " << bit);
			CHECK(f != ECMXF_FAULT_NONE);
		}
	}
}

TEST_CASE("codec: faults are told apart and mapped to errno values", "[codec]")
{
	const unsigned n = 64;
	std::vector<std::uint8_t> good(ECMXF_PKT_SIZE(n));
	const ecmxf_rsp_hdr h = sampleRsp(0);
	REQUIRE(ecmxf_encode_rsp(good.data(), good.size(), ECMXF_CHECK_FIXED, &h, nullptr, 0) == 0);

	auto decode = [&](const std::vector<std::uint8_t> &p) {
		return ecmxf_decode_rsp(p.data(), p.size(), ECMXF_CHECK_FIXED, nullptr, nullptr);
	};
	auto bad = good;
	bad[1] = 0;
	CHECK(decode(bad) == ECMXF_FAULT_START);
	bad = good;
	bad[bad.size() - 2] = 0;
	CHECK(decode(bad) == ECMXF_FAULT_END);
	bad = good;
	bad[ECMXF_HDR_SIZE + n] = 0x79;
	CHECK(decode(bad) == ECMXF_FAULT_CHECK);
	bad = good;
	bad[ECMXF_HDR_SIZE + n + 0] = 0x21;
	bad[ECMXF_HDR_SIZE + n + 1] = 0x43;
	bad[ECMXF_HDR_SIZE + n + 2] = 0x65;
	bad[ECMXF_HDR_SIZE + n + 3] = 0x87;
	CHECK(decode(bad) == ECMXF_FAULT_NOT_READY);
	// "not ready" wins even over a broken frame
	bad[0] = 0;
	CHECK(decode(bad) == ECMXF_FAULT_NOT_READY);

	CHECK(ecmxf_fault_errno(ECMXF_FAULT_NONE) == 0);
	CHECK(ecmxf_fault_errno(ECMXF_FAULT_CHECK) == -EBADMSG);
	CHECK(ecmxf_fault_errno(ECMXF_FAULT_START) == -EPROTO);
	CHECK(ecmxf_fault_errno(ECMXF_FAULT_END) == -EPROTO);
	CHECK(ecmxf_fault_errno(ECMXF_FAULT_LENGTH) == -EPROTO);
	CHECK(ecmxf_fault_errno(ECMXF_FAULT_NOT_READY) == -EIO);
	CHECK(ecmxf_fault_errno(ECMXF_FAULT_SIZE) == -EINVAL);
	for (int f = 0; f <= ECMXF_FAULT_COUNT; f++)
		CHECK(ecmxf_fault_name(static_cast<ecmxf_fault>(f)) != nullptr);
}

TEST_CASE("codec: sizes outside 56..1440 bytes and bad arguments are refused", "[codec]")
{
	std::vector<std::uint8_t> pkt(ECMXF_PKT_MAX + 8);
	ecmxf_cmd_hdr h{};
	CHECK(ecmxf_encode_cmd(pkt.data(), ECMXF_PKT_SIZE(31), ECMXF_CHECK_FIXED, &h, nullptr, 0) ==
	      -EINVAL);
	CHECK(ecmxf_encode_cmd(pkt.data(), ECMXF_PKT_SIZE(1409), ECMXF_CHECK_FIXED, &h, nullptr, 0) ==
	      -EINVAL);
	volatile int four = 4; // not a check type
	CHECK(ecmxf_encode_cmd(pkt.data(), ECMXF_PKT_SIZE(32), static_cast<ecmxf_check>(four), &h,
			       nullptr, 0) == -EINVAL);
	CHECK(ecmxf_encode_cmd(nullptr, ECMXF_PKT_SIZE(32), ECMXF_CHECK_FIXED, &h, nullptr, 0) ==
	      -EINVAL);
	CHECK(ecmxf_encode_cmd(pkt.data(), ECMXF_PKT_SIZE(32), ECMXF_CHECK_FIXED, nullptr, nullptr,
			       0) == -EINVAL);
	CHECK(ecmxf_encode_cmd(pkt.data(), ECMXF_PKT_SIZE(32), ECMXF_CHECK_FIXED, &h, pkt.data(),
			       33) == -EMSGSIZE);
	CHECK(ecmxf_encode_cmd(pkt.data(), ECMXF_PKT_SIZE(32), ECMXF_CHECK_FIXED, &h, nullptr, 1) ==
	      -EMSGSIZE);
	CHECK(ecmxf_decode_rsp(pkt.data(), 0, ECMXF_CHECK_FIXED, nullptr, nullptr) ==
	      ECMXF_FAULT_SIZE);
	CHECK(ecmxf_decode_rsp(pkt.data(), ECMXF_PKT_SIZE(1409), ECMXF_CHECK_FIXED, nullptr,
			       nullptr) == ECMXF_FAULT_SIZE);
	CHECK(ecmxf_decode_rsp(nullptr, ECMXF_PKT_SIZE(32), ECMXF_CHECK_FIXED, nullptr, nullptr) ==
	      ECMXF_FAULT_SIZE);
	CHECK(ecmxf_data_size_valid(32));
	CHECK(ecmxf_data_size_valid(1408));
	CHECK_FALSE(ecmxf_data_size_valid(31));
	CHECK_FALSE(ecmxf_data_size_valid(1409));
}
