// SPDX-License-Identifier: MIT
/*
 * fuzz_diff.cpp - differential: one command, three views.
 *
 * Input: data size selector (u16), check type (u8), the command header
 * fields (24 bytes) and data bytes. Checks:
 *  1. the core's encoder and decoder round-trip: ecmxf_encode_cmd() at
 *     the chosen data size and check type, ecmxf_decode_cmd() gives back
 *     every header field and data byte; a wrong check type (other than a
 *     CRC that happens to agree) or one flipped bit makes it fail;
 *  2. the simulator's view of the same header at its size (112 bytes,
 *     fixed check word; the code replaced by one of the read-only
 *     commands, so that the shared chip keeps its format): the chip takes
 *     the packet in (no bad packet counted) and its answer, read with the
 *     next exchange, decodes with the core's response decoder and carries
 *     the command's index and code, a length inside the data section.
 * One simulated chip serves every input (only read-only commands reach it).
 */
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include <ecmxf/sim/chip.hpp>

#include "ecmxf-proto.h"
#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

namespace {

bool sameHeader(const ecmxf_cmd_hdr &a, const ecmxf_cmd_hdr &b)
{
	return std::memcmp(a.data, b.data, 4) == 0 && a.reserved == b.reserved && a.control == b.control &&
	       a.index == b.index && a.code == b.code && a.param == b.param && a.len == b.len &&
	       a.int_clear == b.int_clear && std::memcmp(a.gpio_int_clear, b.gpio_int_clear, 2) == 0 &&
	       std::memcmp(a.gpio_out, b.gpio_out, 2) == 0;
}

constexpr std::uint8_t kReadOnly[] = { ECMXF_CMD_INFO_UPDATE_OP,     ECMXF_CMD_ECAT_PDO_WC_GET,
				       ECMXF_CMD_ECAT_STATE_GET,     ECMXF_CMD_ECAT_SLV_CNT_GET,
				       ECMXF_CMD_FIFO_PACK_SIZE_GET, ECMXF_CMD_SPI_PACK_SIZE_GET };

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 27)
		return 0;
	const auto le16 = [](const std::uint8_t *p) { return static_cast<std::uint16_t>(p[0] | unsigned{ p[1] } << 8); };
	const unsigned ds = ECMXF_DATA_MIN + le16(data) % (ECMXF_DATA_MAX - ECMXF_DATA_MIN + 1);
	const auto check = static_cast<ecmxf_check>(data[2] & 3);
	ecmxf_cmd_hdr h{};
	const std::uint8_t *f = data + 3;
	std::memcpy(h.data, f, 4);
	h.reserved = le16(f + 4);
	h.control = f[6];
	h.index = f[7];
	h.code = f[8];
	h.param = f[9];
	h.len = le16(f + 10);
	h.int_clear = le16(f + 12) | static_cast<std::uint32_t>(le16(f + 14)) << 16;
	h.gpio_int_clear[0] = f[16];
	h.gpio_int_clear[1] = f[17];
	h.gpio_out[0] = f[18];
	h.gpio_out[1] = f[19];
	const std::uint8_t *payload = data + 27;
	const std::size_t plen = size - 27;

	// 1. the core's round trip
	const std::size_t n = ECMXF_PKT_SIZE(ds);
	std::vector<std::uint8_t> pkt(n);
	const int enc = ecmxf_encode_cmd(pkt.data(), n, check, &h, payload, plen);
	FUZZ_ASSERT(enc == 0 || plen > ds);
	if (enc == 0) {
		ecmxf_cmd_hdr back{};
		const std::uint8_t *d = nullptr;
		FUZZ_ASSERT(ecmxf_decode_cmd(pkt.data(), n, check, &back, &d) == ECMXF_FAULT_NONE);
		FUZZ_ASSERT(sameHeader(h, back));
		FUZZ_ASSERT(d == pkt.data() + ECMXF_HDR_SIZE);
		FUZZ_ASSERT(plen == 0 || std::memcmp(d, payload, plen) == 0);
		for (std::size_t i = plen; i < ds; i++)
			FUZZ_ASSERT(d[i] == 0);
		// one flipped bit anywhere is seen (every check type covers the
		// header and the data; the words frame it)
		const std::size_t bit = (static_cast<std::size_t>(f[0]) * 131 + plen * 7) % (n * 8);
		std::vector<std::uint8_t> bad = pkt;
		bad[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
		if (check != ECMXF_CHECK_FIXED || bit / 8 < 4 || bit / 8 >= n - ECMXF_TRAILER_SIZE)
			FUZZ_ASSERT(ecmxf_decode_cmd(bad.data(), n, check, nullptr, nullptr) != ECMXF_FAULT_NONE);
	}

	// 2. the simulator's view (its format: 112 bytes, fixed check word)
	static std::unique_ptr<ecmxf::sim::Chip> chip = std::make_unique<ecmxf::sim::Chip>();
	static std::uint8_t index = 0;
	ecmxf_cmd_hdr c = h;
	c.code = kReadOnly[h.code % sizeof(kReadOnly)];
	c.control &= static_cast<std::uint8_t>(~ECMXF_CTL_CLR_CRC_CNT); // keep the chip's counts
	c.index = ++index;
	const std::size_t sn = chip->packetSize();
	FUZZ_ASSERT(sn == ECMXF_PKT_SIZE(ECMXF_DATA_DEFAULT));
	std::vector<std::uint8_t> mosi(sn), miso(sn);
	FUZZ_ASSERT(ecmxf_encode_cmd(mosi.data(), sn, ECMXF_CHECK_FIXED, &c, payload,
				     plen < ECMXF_DATA_DEFAULT ? plen : ECMXF_DATA_DEFAULT) == 0);
	const std::uint64_t bad0 = chip->stats().badPackets;
	chip->exchange(mosi, miso);
	FUZZ_ASSERT(chip->stats().badPackets == bad0);
	// the answer comes with the next exchange (an INFO_UPDATE)
	ecmxf_cmd_hdr nop{};
	nop.index = ++index;
	FUZZ_ASSERT(ecmxf_encode_cmd(mosi.data(), sn, ECMXF_CHECK_FIXED, &nop, nullptr, 0) == 0);
	chip->exchange(mosi, miso);
	ecmxf_rsp_hdr r{};
	FUZZ_ASSERT(ecmxf_decode_rsp(miso.data(), sn, ECMXF_CHECK_FIXED, &r, nullptr) == ECMXF_FAULT_NONE);
	FUZZ_ASSERT(r.index == c.index && r.code == c.code);
	FUZZ_ASSERT(r.len <= ECMXF_DATA_DEFAULT);
	return 0;
}
