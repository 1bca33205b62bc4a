// SPDX-License-Identifier: MIT
// The protocol core's PDO pump (lib/core/ecmxf-pump.c): plans and answers
// with the values worked out by hand from the manual's FIFO rules
// (spec digest, "PDO exchange details" and "The chip's FIFOs"):
// ECAT_PDO_DATA_FIFO_OP's parameter is the RxPDO frame count, data byte 0
// bit 0 pushes, bit 1 pops; the answer's length is a whole number of
// TxPDO frames; a full RxFIFO refuses the newest frames (return value bit
// 0 clear), a full TxFIFO drops its oldest; the header's counts lag by up
// to two exchanges, so the fill level stays two below the depth.

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>

#include "ecmxf-pump.h"

namespace {

// RxPDO 12 bytes, TxPDO 20 bytes, the default 112-byte data section:
// 112 / 12 = 9 frames per write, 112 / 20 = 5 per read.  RxFIFO depth 10:
// fill level 10 - 2 = 8.  TxFIFO depth 10.
ecmxf_pump standard()
{
	ecmxf_pump p;
	ecmxf_pump_init(&p, 12, 20, 112, 10, 0, 10);
	return p;
}

ecmxf_rsp_hdr answer(std::uint8_t ret, std::uint8_t rxCnt, std::uint8_t txCnt,
		     std::uint8_t ecm = ECMXF_STS_FIFO_EN, std::uint8_t err = 0)
{
	ecmxf_rsp_hdr h{};
	h.code = ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP;
	h.ret = ret;
	h.rx_fifo_cnt = rxCnt;
	h.tx_fifo_cnt = txCnt;
	h.ecm_status = ecm;
	h.err_status = err;
	return h;
}

} // namespace

TEST_CASE("pump: the fill level is the depth minus two, at least 1", "[pump]")
{
	CHECK(ecmxf_pump_max_fill(64) == 62);
	CHECK(ecmxf_pump_max_fill(10) == 8);
	CHECK(ecmxf_pump_max_fill(3) == 1);
	CHECK(ecmxf_pump_max_fill(2) == 1);
	CHECK(ecmxf_pump_max_fill(0) == 1);

	ecmxf_pump p = standard();
	CHECK(p.rx_fill == 8);
	ecmxf_pump_init(&p, 12, 20, 112, 10, 3, 10);
	CHECK(p.rx_fill == 3);
}

TEST_CASE("pump: setup checks, in the order the uAPI documents", "[pump]")
{
	CHECK(ecmxf_pump_check(12, 20, 112, 10, 0) == 0);
	CHECK(ecmxf_pump_check(12, 20, 112, 10, 8) == 0);
	CHECK(ecmxf_pump_check(12, 20, 112, 10, 9) == -EINVAL);
	CHECK(ecmxf_pump_check(12, 0, 112, 10, 0) == 0);
	CHECK(ecmxf_pump_check(0, 20, 112, 10, 0) == 0);
	CHECK(ecmxf_pump_check(0, 0, 112, 10, 0) == -ENODATA);
	CHECK(ecmxf_pump_check(113, 20, 112, 10, 0) == -EMSGSIZE);
	CHECK(ecmxf_pump_check(12, 113, 112, 10, 0) == -EMSGSIZE);
	CHECK(ecmxf_pump_check(112, 112, 112, 10, 0) == 0);
	// several wrong: the fill level first, then no frames, then the size
	CHECK(ecmxf_pump_check(0, 0, 112, 10, 9) == -EINVAL);
	CHECK(ecmxf_pump_check(0, 0, 0, 10, 0) == -ENODATA);
}

TEST_CASE("pump: frames per command follow the data section and the byte parameter", "[pump]")
{
	ecmxf_pump p = standard();
	CHECK(ecmxf_pump_per_write(&p) == 9);
	CHECK(ecmxf_pump_per_read(&p) == 5);

	// 1-byte frames in 1024 bytes: 1024 per read, but the parameter is a byte
	ecmxf_pump_init(&p, 1, 1, 1024, 64, 0, 64);
	CHECK(ecmxf_pump_per_write(&p) == 255);
	CHECK(ecmxf_pump_per_read(&p) == 1024);

	// no frames that way
	ecmxf_pump_init(&p, 0, 0, 112, 10, 0, 10);
	CHECK(ecmxf_pump_per_write(&p) == 0);
	CHECK(ecmxf_pump_per_read(&p) == 0);

	// a data section that shrank below a frame (SPI_RECONFIG_OP meanwhile)
	ecmxf_pump_init(&p, 12, 20, 112, 10, 0, 10);
	p.data_size = 10;
	CHECK(ecmxf_pump_per_write(&p) == 0);
	CHECK(ecmxf_pump_per_read(&p) == 0);
}

TEST_CASE("pump: plans fill the RxFIFO up to the fill level", "[pump]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_plan pl;

	SECTION("empty FIFO, 3 frames ready: all 3, and a read")
	{
		CHECK(ecmxf_pump_next(&p, 0, 3, ECMXF_PUMP_F_READ, &pl));
		CHECK(pl.skip == 0);
		CHECK(pl.push == 3);
		CHECK(pl.read);
	}
	SECTION("level 6 of 8: room for 2 of the 5 ready")
	{
		CHECK(ecmxf_pump_next(&p, 6, 5, ECMXF_PUMP_F_READ, &pl));
		CHECK(pl.skip == 0);
		CHECK(pl.push == 2);
	}
	SECTION("at the fill level: a read alone")
	{
		CHECK(ecmxf_pump_next(&p, 8, 5, ECMXF_PUMP_F_READ, &pl));
		CHECK(pl.push == 0);
		CHECK(pl.skip == 0);
		CHECK(pl.read);
	}
	SECTION("above the fill level (a count that lags): no room, no underflow")
	{
		CHECK(ecmxf_pump_next(&p, 200, 5, ECMXF_PUMP_F_READ, &pl));
		CHECK(pl.push == 0);
		CHECK(pl.skip == 0);
	}
	SECTION("at the fill level with nothing to read: nothing to send")
	{
		CHECK_FALSE(ecmxf_pump_next(&p, 8, 5, 0, &pl));
		CHECK(pl.push == 0);
		CHECK_FALSE(pl.read);
	}
	SECTION("nothing ready, no read: nothing to send")
	{
		CHECK_FALSE(ecmxf_pump_next(&p, 0, 0, 0, &pl));
	}
	SECTION("a read is planned only with TxPDO frames")
	{
		ecmxf_pump_init(&p, 12, 0, 112, 10, 0, 10);
		CHECK_FALSE(ecmxf_pump_next(&p, 8, 0, ECMXF_PUMP_F_READ, &pl));
		CHECK_FALSE(pl.read);
		CHECK(ecmxf_pump_next(&p, 0, 1, ECMXF_PUMP_F_READ, &pl));
		CHECK(pl.push == 1);
		CHECK_FALSE(pl.read);
	}
	SECTION("one command carries at most the frames per write")
	{
		ecmxf_pump_init(&p, 12, 20, 112, 64, 0, 64);	// fill 62
		CHECK(ecmxf_pump_next(&p, 0, 40, ECMXF_PUMP_F_READ, &pl));
		CHECK(pl.skip == 0);
		CHECK(pl.push == 9);
	}
	SECTION("no RxPDO frames: nothing is pushed whatever the caller says")
	{
		ecmxf_pump_init(&p, 0, 20, 112, 10, 0, 10);
		CHECK(ecmxf_pump_next(&p, 0, 5, ECMXF_PUMP_F_READ, &pl));
		CHECK(pl.push == 0);
		CHECK(pl.read);
	}
}

TEST_CASE("pump: a caller that fell behind skips its oldest frames", "[pump]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_plan pl;

	// level 2: room 6; more than room + fill = 14 ready: 30 - 14 = 16
	// skipped, then 6 of the remaining 14 pushed
	CHECK(ecmxf_pump_next(&p, 2, 30, ECMXF_PUMP_F_READ, &pl));
	CHECK(pl.skip == 16);
	CHECK(pl.push == 6);

	// exactly room + fill ready: nothing skipped
	CHECK(ecmxf_pump_next(&p, 2, 14, ECMXF_PUMP_F_READ, &pl));
	CHECK(pl.skip == 0);
	CHECK(pl.push == 6);

	// empty FIFO, 20 ready: room 8, 20 - 16 = 4 skipped, 8 pushed
	CHECK(ecmxf_pump_next(&p, 0, 20, 0, &pl));
	CHECK(pl.skip == 4);
	CHECK(pl.push == 8);

	// full FIFO, 20 ready: 20 - 8 = 12 skipped, none pushed, nothing sent
	CHECK_FALSE(ecmxf_pump_next(&p, 8, 20, 0, &pl));
	CHECK(pl.skip == 12);
	CHECK(pl.push == 0);

	// the largest counts do not wrap
	CHECK(ecmxf_pump_next(&p, 0, 0xFFFFFFFFu, 0, &pl));
	CHECK(pl.skip == 0xFFFFFFFFu - 16);
	CHECK(pl.push == 8);
}

TEST_CASE("pump: F_ONE offers one frame even to a full RxFIFO", "[pump]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_plan pl;

	CHECK(ecmxf_pump_next(&p, 8, 1, ECMXF_PUMP_F_ONE, &pl));
	CHECK(pl.push == 1);
	CHECK(ecmxf_pump_next(&p, 50, 8, ECMXF_PUMP_F_ONE, &pl));
	CHECK(pl.push == 1);
	CHECK(pl.skip == 0);
	// with room it changes nothing
	CHECK(ecmxf_pump_next(&p, 5, 8, ECMXF_PUMP_F_ONE, &pl));
	CHECK(pl.push == 3);
	// nothing ready: nothing
	CHECK_FALSE(ecmxf_pump_next(&p, 8, 0, ECMXF_PUMP_F_ONE, &pl));
}

TEST_CASE("pump: the FIFO command's header", "[pump]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_plan pl;
	ecmxf_cmd_hdr h;

	std::memset(&h, 0xA5, sizeof(h));
	REQUIRE(ecmxf_pump_next(&p, 0, 3, ECMXF_PUMP_F_READ, &pl));
	CHECK(ecmxf_pump_fifo_cmd(&p, &pl, false, &h) == 36);	// 3 x 12 bytes
	CHECK(h.code == 5);
	CHECK(h.param == 3);
	CHECK(h.data[0] == 0x03);	// write and read
	CHECK(h.data[1] == 0);
	CHECK(h.data[2] == 0);
	CHECK(h.data[3] == 0);
	CHECK(h.control == 0xA0);	// clear the command error (7) and FIFO error (5)
	CHECK(h.int_clear == 0);
	CHECK(h.len == 0);
	CHECK(h.index == 0);
	CHECK(h.reserved == 0);
	CHECK(h.gpio_int_clear[0] == 0);
	CHECK(h.gpio_out[1] == 0);

	// re-arming INT1: the TxFIFO high (24) and RxFIFO low (25) flags
	CHECK(ecmxf_pump_fifo_cmd(&p, &pl, true, &h) == 36);
	CHECK(h.int_clear == 0x03000000u);

	// a read alone
	REQUIRE(ecmxf_pump_next(&p, 8, 3, ECMXF_PUMP_F_READ, &pl));
	CHECK(ecmxf_pump_fifo_cmd(&p, &pl, false, &h) == 0);
	CHECK(h.param == 0);
	CHECK(h.data[0] == 0x02);

	// a write alone
	REQUIRE(ecmxf_pump_next(&p, 0, 2, 0, &pl));
	CHECK(ecmxf_pump_fifo_cmd(&p, &pl, false, &h) == 24);
	CHECK(h.param == 2);
	CHECK(h.data[0] == 0x01);
}

TEST_CASE("pump: answers", "[pump]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_plan pl;
	ecmxf_pump_result res;
	REQUIRE(ecmxf_pump_next(&p, 0, 3, ECMXF_PUMP_F_READ, &pl));
	REQUIRE(pl.push == 3);

	SECTION("taken, two frames popped")
	{
		const ecmxf_rsp_hdr h = answer(0x03, 4, 1);
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 40, &res) == 0);
		CHECK(res.taken == 3);
		CHECK(res.refused == 0);
		CHECK(res.popped == 2);
		CHECK_FALSE(res.tx_overrun);	// 2 + 1 < 10
		CHECK_FALSE(res.rx_underrun);
		CHECK(p.unconfirmed == 3);
		CHECK(p.pushed_any);
	}
	SECTION("return value bit 0 clear: the RxFIFO refused them")
	{
		const ecmxf_rsp_hdr h = answer(0x02, 8, 0);
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 0, &res) == 0);
		CHECK(res.taken == 3);
		CHECK(res.refused == 3);
		CHECK(res.popped == 0);
	}
	SECTION("command error: nothing taken, the bookkeeping unchanged")
	{
		p.unconfirmed = 7;
		const ecmxf_rsp_hdr h = answer(0x01, 4, 1, ECMXF_STS_FIFO_EN, ECMXF_ERR_CMD);
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 40, &res) == -EREMOTEIO);
		CHECK(res.taken == 0);
		CHECK(res.refused == 0);
		CHECK(res.popped == 0);
		CHECK(p.unconfirmed == 7);
		CHECK_FALSE(p.pushed_any);
	}
	SECTION("a length that is not whole TxPDO frames: EPROTO, the frames pushed are taken")
	{
		const ecmxf_rsp_hdr h = answer(0x01, 4, 1);
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 30, &res) == -EPROTO);
		CHECK(res.taken == 3);
		CHECK(res.popped == 0);
		CHECK(p.unconfirmed == 3);
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 1, &res) == -EPROTO);
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 19, &res) == -EPROTO);
	}
	SECTION("more frames than one answer holds: EPROTO")
	{
		const ecmxf_rsp_hdr h = answer(0x01, 4, 1);
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 100, &res) == 0);	// 5: the most
		CHECK(res.popped == 5);
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 120, &res) == -EPROTO);	// 6
		CHECK(res.popped == 0);
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 0xFFFFFFF0u, &res) == -EPROTO);
	}
	SECTION("popped plus left at the TxFIFO depth: the chip dropped frames")
	{
		ecmxf_rsp_hdr h = answer(0x01, 4, 5);
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 100, &res) == 0);	// 5 + 5
		CHECK(res.tx_overrun);
		h.tx_fifo_cnt = 4;	// 5 + 4 = 9
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 100, &res) == 0);
		CHECK_FALSE(res.tx_overrun);
		h.tx_fifo_cnt = 10;	// nothing popped, a full FIFO left
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 0, &res) == 0);
		CHECK(res.tx_overrun);
	}
	SECTION("TxFIFO depth unknown: no overrun detection")
	{
		ecmxf_pump_init(&p, 12, 20, 112, 10, 0, 0);
		const ecmxf_rsp_hdr h = answer(0x01, 4, 255);
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 100, &res) == 0);
		CHECK_FALSE(res.tx_overrun);
	}
	SECTION("data in the answer to a command without a read is ignored")
	{
		REQUIRE(ecmxf_pump_next(&p, 0, 3, 0, &pl));
		const ecmxf_rsp_hdr h = answer(0x01, 4, 1);
		CHECK(ecmxf_pump_answer(&p, &pl, &h, 30, &res) == 0);
		CHECK(res.popped == 0);
		CHECK(res.taken == 3);
	}
}

TEST_CASE("pump: an empty RxFIFO is an underrun only after a push, with the FIFO on", "[pump]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_plan pl;
	ecmxf_pump_result res;

	// a read before any push: an empty RxFIFO is no underrun
	REQUIRE(ecmxf_pump_next(&p, 0, 0, ECMXF_PUMP_F_READ, &pl));
	ecmxf_rsp_hdr h = answer(0x00, 0, 0);
	CHECK(ecmxf_pump_answer(&p, &pl, &h, 0, &res) == 0);
	CHECK_FALSE(res.rx_underrun);

	// a push, then an empty RxFIFO with the FIFO enabled
	REQUIRE(ecmxf_pump_next(&p, 0, 1, ECMXF_PUMP_F_READ, &pl));
	h = answer(0x01, 0, 0);
	CHECK(ecmxf_pump_answer(&p, &pl, &h, 0, &res) == 0);
	CHECK(res.rx_underrun);
	// the FIFO off: not an underrun
	h = answer(0x01, 0, 0, 0);
	CHECK(ecmxf_pump_answer(&p, &pl, &h, 0, &res) == 0);
	CHECK_FALSE(res.rx_underrun);
	// frames left: not an underrun
	h = answer(0x01, 1, 0);
	CHECK(ecmxf_pump_answer(&p, &pl, &h, 0, &res) == 0);
	CHECK_FALSE(res.rx_underrun);
	// after a push, a later read alone still sees it
	REQUIRE(ecmxf_pump_next(&p, 8, 0, ECMXF_PUMP_F_READ, &pl));
	h = answer(0x00, 0, 0);
	CHECK(ecmxf_pump_answer(&p, &pl, &h, 0, &res) == 0);
	CHECK(res.rx_underrun);
	// but not on an EPROTO answer
	CHECK(ecmxf_pump_answer(&p, &pl, &h, 7, &res) == -EPROTO);
	CHECK_FALSE(res.rx_underrun);

	// no RxPDO frames at all: never
	ecmxf_pump_init(&p, 0, 20, 112, 10, 0, 10);
	p.pushed_any = true;
	REQUIRE(ecmxf_pump_next(&p, 0, 0, ECMXF_PUMP_F_READ, &pl));
	CHECK(ecmxf_pump_answer(&p, &pl, &h, 0, &res) == 0);
	CHECK_FALSE(res.rx_underrun);
}

TEST_CASE("pump: the level counts the frames the header may not show yet", "[pump]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_plan pl;
	ecmxf_pump_result res;

	CHECK(ecmxf_pump_level(&p, nullptr) == 0);

	// exchange 1: empty FIFO, 10 ready: 8 pushed
	REQUIRE(ecmxf_pump_next(&p, ecmxf_pump_level(&p, nullptr), 10, ECMXF_PUMP_F_READ, &pl));
	CHECK(pl.push == 8);
	ecmxf_rsp_hdr h = answer(0x01, 2, 0);	// the count lags: 2
	REQUIRE(ecmxf_pump_answer(&p, &pl, &h, 0, &res) == 0);
	// exchange 2: level 2 + 8 = 10 > 8: no room; 2 ready stay
	CHECK(ecmxf_pump_level(&p, &h) == 10);
	REQUIRE(ecmxf_pump_next(&p, ecmxf_pump_level(&p, &h), 2, ECMXF_PUMP_F_READ, &pl));
	CHECK(pl.push == 0);
	CHECK(pl.skip == 0);
	h = answer(0x00, 6, 1);	// the 8 arrived, 2 went to the bus
	REQUIRE(ecmxf_pump_answer(&p, &pl, &h, 20, &res) == 0);
	CHECK(res.popped == 1);
	// exchange 3: level 6 + 0: room for 2
	CHECK(ecmxf_pump_level(&p, &h) == 6);
	REQUIRE(ecmxf_pump_next(&p, ecmxf_pump_level(&p, &h), 2, ECMXF_PUMP_F_READ, &pl));
	CHECK(pl.push == 2);

	// a command with no answer: its frames are lost and counted as possibly
	// in the FIFO
	CHECK(ecmxf_pump_lost(&p, &pl) == 2);
	CHECK(p.unconfirmed == 2);
	CHECK(ecmxf_pump_level(&p, &h) == 8);
}

TEST_CASE("pump: the working counter", "[pump]")
{
	ecmxf_cmd_hdr c;
	std::memset(&c, 0x5A, sizeof(c));
	ecmxf_pump_wkc_cmd(&c);
	CHECK(c.code == 4);
	CHECK(c.param == 3);
	CHECK(c.control == 0x80);
	CHECK(c.data[0] == 0);
	CHECK(c.int_clear == 0);
	CHECK(c.len == 0);

	const std::uint8_t v[4] = { 0x01, 0x02, 0x03, 0x04 };
	ecmxf_rsp_hdr h{};
	std::uint32_t wkc = 0;
	CHECK(ecmxf_pump_wkc_answer(&h, v, 4, &wkc) == 0);
	CHECK(wkc == 0x04030201u);
	wkc = 7;
	CHECK(ecmxf_pump_wkc_answer(&h, v, 3, &wkc) == -EPROTO);
	CHECK(ecmxf_pump_wkc_answer(&h, v, 0, &wkc) == -EPROTO);
	CHECK(wkc == 7);
	h.err_status = ECMXF_ERR_CMD;
	CHECK(ecmxf_pump_wkc_answer(&h, v, 4, &wkc) == -EREMOTEIO);
	CHECK(wkc == 7);
}
