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

// The schedule (lib/core/ecmxf-pump-sched.c), with the pump of standard()
// (fill level 8, 9 frames per write, 5 per read, TxFIFO depth 10: read-only
// commands per cycle 10 / 5 + 2 = 4): which command goes next, two FIFO
// commands in flight, answers and losses, the estimate and the library's
// cycle; values worked out by hand from the FIFO rules (protocol-core.rst,
// "The PDO pump"; process-data.rst, "One cycle" and "The answer in the
// next cycle").

namespace {

ecmxf_pump_sched sched(unsigned flags, std::uint64_t poll, std::uint64_t wkc)
{
	ecmxf_pump_sched s;
	ecmxf_pump_sched_init(&s, flags, poll, wkc);
	return s;
}

/// An answer's reading: @p refused of as many taken, @p popped frames.
ecmxf_pump_result result(std::uint32_t popped, std::uint32_t refused = 0, bool txOverrun = false)
{
	return ecmxf_pump_result{ refused, refused, popped, txOverrun, false };
}

} // namespace

TEST_CASE("pump schedule: read-only commands per cycle, TxFIFO depth / frames per read + 2", "[pump][sched]")
{
	ecmxf_pump p = standard();
	CHECK(ecmxf_pump_max_reads(&p) == 4);	// 10 / 5 + 2
	ecmxf_pump_init(&p, 12, 20, 112, 10, 0, 64);
	CHECK(ecmxf_pump_max_reads(&p) == 14);	// 64 / 5 + 2
	ecmxf_pump_init(&p, 1, 1, 1024, 64, 0, 64);
	CHECK(ecmxf_pump_max_reads(&p) == 2);	// 64 / 1024 + 2
	ecmxf_pump_init(&p, 12, 0, 112, 10, 0, 10);
	CHECK(ecmxf_pump_max_reads(&p) == 0);	// no inputs
}

TEST_CASE("pump schedule: which command goes next", "[pump][sched]")
{
	ecmxf_pump_flight f{};
	const ecmxf_rsp_hdr on = answer(1, 0, 0);
	const ecmxf_rsp_hdr off = answer(1, 0, 0, 0);

	SECTION("nothing while the chip's FIFOs are off, or before a header")
	{
		ecmxf_pump_sched s = sched(0, 1000, 500);
		CHECK(ecmxf_pump_sched_pick(&s, &f, &off, 10, true, false) == ECMXF_PUMP_PICK_NONE);
		CHECK(ecmxf_pump_sched_pick(&s, &f, nullptr, 10, true, false) == ECMXF_PUMP_PICK_NONE);
		CHECK(ecmxf_pump_sched_deadline(&s, &off) == 0);
		CHECK(ecmxf_pump_sched_deadline(&s, nullptr) == 0);
	}
	SECTION("the FIFO command is due by its timer, INT1 or work left")
	{
		ecmxf_pump_sched s = sched(0, 1000, 0);
		s.next_tick_ns = 5000;
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 4999, false, false) == ECMXF_PUMP_PICK_NONE);
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 5000, false, false) == ECMXF_PUMP_PICK_FIFO);
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 4000, true, false) == ECMXF_PUMP_PICK_FIFO);
		s.again = true;
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 4000, false, false) == ECMXF_PUMP_PICK_FIFO);
	}
	SECTION("both due and nothing in flight: the FIFO command first")
	{
		ecmxf_pump_sched s = sched(0, 1000, 500);
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 0, false, false) == ECMXF_PUMP_PICK_FIFO);
		s.next_tick_ns = 9000;
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 0, false, false) == ECMXF_PUMP_PICK_WKC);
	}
	SECTION("one FIFO command at a time without FIFO_NEXT: the read rides behind it")
	{
		ecmxf_pump_sched s = sched(0, 1000, 500);
		f.busy[0] = true;
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 0, true, true) == ECMXF_PUMP_PICK_WKC);
		f.busy[ECMXF_PUMP_SLOT_WKC] = true;
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 0, true, true) == ECMXF_PUMP_PICK_NONE);
	}
	SECTION("FIFO_NEXT: a second FIFO command once the first has gone out")
	{
		ecmxf_pump_sched s = sched(ECMXF_PUMP_S_FIFO_NEXT, 1000, 0);
		f.busy[0] = true;
		f.newest = 0;
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 0, false, false) == ECMXF_PUMP_PICK_NONE);
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 0, false, true) == ECMXF_PUMP_PICK_FIFO);
		// two in flight: no third
		f.busy[1] = true;
		f.newest = 1;
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 0, true, true) == ECMXF_PUMP_PICK_NONE);
	}
	SECTION("FIFO_NEXT with a read due: the read goes in the exchange that fetches the answer")
	{
		ecmxf_pump_sched s = sched(ECMXF_PUMP_S_FIFO_NEXT, 1000, 500);
		f.busy[0] = true;
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 0, true, true) == ECMXF_PUMP_PICK_WKC);
	}
	SECTION("the deadline: the earlier timer, 1 for a timer at 0")
	{
		ecmxf_pump_sched s = sched(0, 1000, 0);
		CHECK(ecmxf_pump_sched_deadline(&s, &on) == 1);
		s.next_tick_ns = 5000;
		CHECK(ecmxf_pump_sched_deadline(&s, &on) == 5000);
		s.next_wkc_ns = 3000;	// no read period: ignored
		CHECK(ecmxf_pump_sched_deadline(&s, &on) == 5000);
		s.wkc_ns = 2000;
		CHECK(ecmxf_pump_sched_deadline(&s, &on) == 3000);
		s.next_wkc_ns = 7000;
		CHECK(ecmxf_pump_sched_deadline(&s, &on) == 5000);
	}
}

// A level INT1 that a source the pump does not clear holds asserted fires
// again as soon as the worker unmasks it after each FIFO command's clear;
// were every INT1 a reason to send, the pump would run at the link's rate.
// The rule (worked out by hand, period 1000): INT1 brings one command
// forward; the next INT1 before the timer is held; the timer's command (or
// one that work left) frees INT1 again.
TEST_CASE("pump schedule: INT1 brings at most one FIFO command forward per period", "[pump][sched]")
{
	ecmxf_pump_flight f{};
	const ecmxf_rsp_hdr on = answer(1, 0, 0);
	ecmxf_pump_sched s = sched(0, 1000, 0);

	// t=0: the timer's first command
	REQUIRE(ecmxf_pump_sched_pick(&s, &f, &on, 0, true, false) == ECMXF_PUMP_PICK_FIFO);
	(void)ecmxf_pump_sched_fifo(&s, &f, 0);
	CHECK(s.next_tick_ns == 1000);
	CHECK_FALSE(s.kicked);
	CHECK_FALSE(ecmxf_pump_sched_kick_held(&s, 10));
	// t=100: INT1 brings the next one forward
	REQUIRE(ecmxf_pump_sched_pick(&s, &f, &on, 100, true, false) == ECMXF_PUMP_PICK_FIFO);
	(void)ecmxf_pump_sched_fifo(&s, &f, 100);
	CHECK(s.kicked);
	CHECK(s.next_tick_ns == 1100);
	// t=150..1099: INT1 again and again: held, nothing is due
	for (u64 t : { 150u, 500u, 1099u }) {
		CHECK(ecmxf_pump_sched_kick_held(&s, t));
		CHECK(ecmxf_pump_sched_pick(&s, &f, &on, t, true, false) == ECMXF_PUMP_PICK_NONE);
	}
	// work left by an answer is no INT1: due at once, and frees INT1
	s.again = true;
	CHECK_FALSE(ecmxf_pump_sched_kick_held(&s, 600));
	REQUIRE(ecmxf_pump_sched_pick(&s, &f, &on, 600, false, false) == ECMXF_PUMP_PICK_FIFO);
	(void)ecmxf_pump_sched_fifo(&s, &f, 600);
	CHECK_FALSE(s.kicked);
	CHECK(s.next_tick_ns == 1600);
	// INT1 brings one forward again (t=700), then is held until the timer
	REQUIRE(ecmxf_pump_sched_pick(&s, &f, &on, 700, true, false) == ECMXF_PUMP_PICK_FIFO);
	(void)ecmxf_pump_sched_fifo(&s, &f, 700);
	CHECK(s.kicked);
	CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 1699, true, false) == ECMXF_PUMP_PICK_NONE);
	// t=1700: the timer; its command frees INT1
	REQUIRE(ecmxf_pump_sched_pick(&s, &f, &on, 1700, true, false) == ECMXF_PUMP_PICK_FIFO);
	CHECK_FALSE(ecmxf_pump_sched_kick_held(&s, 1700));
	(void)ecmxf_pump_sched_fifo(&s, &f, 1700);
	CHECK_FALSE(s.kicked);
	REQUIRE(ecmxf_pump_sched_pick(&s, &f, &on, 1701, true, false) == ECMXF_PUMP_PICK_FIFO);

	// over 10 periods of INT1 at every 10 ns: at most 2 commands a period
	ecmxf_pump_sched s2 = sched(0, 1000, 0);
	unsigned sent = 0;
	for (u64 t = 0; t < 10000; t += 10) {
		if (ecmxf_pump_sched_pick(&s2, &f, &on, t, true, false) == ECMXF_PUMP_PICK_FIFO) {
			(void)ecmxf_pump_sched_fifo(&s2, &f, t);
			sent++;
		}
	}
	CHECK(sent <= 20);
	CHECK(sent >= 10);
}

TEST_CASE("pump schedule: a pump cycle with FIFO_NEXT and a read every 500 ns, step by step", "[pump][sched]")
{
	// poll 1000 ns, read period 500 ns; times in ns
	ecmxf_pump_sched s = sched(ECMXF_PUMP_S_FIFO_NEXT | ECMXF_PUMP_S_WKC_NEXT, 1000, 500);
	ecmxf_pump_flight f{};
	const ecmxf_rsp_hdr on = answer(1, 0, 0);

	// t = 0: both due, the FIFO command goes; slot 0, the next tick at 1000
	REQUIRE(ecmxf_pump_sched_pick(&s, &f, &on, 0, false, false) == ECMXF_PUMP_PICK_FIFO);
	CHECK(ecmxf_pump_sched_fifo(&s, &f, 0) == 0);
	CHECK(s.next_tick_ns == 1000);
	CHECK(f.released[0]);
	ecmxf_pump_sched_sent(&f, 0, s.next_tick_ns);

	// t = 10: the FIFO command is not due (tick at 1000), the read is: it
	// rides in the exchange that fetches the FIFO answer; next read at 500
	REQUIRE(ecmxf_pump_sched_pick(&s, &f, &on, 10, false, true) == ECMXF_PUMP_PICK_WKC);
	ecmxf_pump_sched_wkc(&s, 10);
	CHECK(s.next_wkc_ns == 500);
	ecmxf_pump_sched_sent(&f, ECMXF_PUMP_SLOT_WKC, s.next_tick_ns);

	// both answers may wait for the next FIFO command until 1000 (the
	// commands are allowed 2000 ns: two periods fit)
	CHECK(ecmxf_pump_sched_waits(&s, &f, 0, 2000, 999));
	CHECK_FALSE(ecmxf_pump_sched_waits(&s, &f, 0, 2000, 1000));
	CHECK_FALSE(ecmxf_pump_sched_waits(&s, &f, 0, 1999, 999));
	CHECK(ecmxf_pump_sched_waits(&s, &f, ECMXF_PUMP_SLOT_WKC, 2000, 999));

	// t = 1000: the tick; slot 0 in flight and sent, slot 1 free: the next
	// FIFO command goes in slot 1
	REQUIRE(ecmxf_pump_sched_pick(&s, &f, &on, 1000, false, true) == ECMXF_PUMP_PICK_FIFO);
	CHECK(ecmxf_pump_sched_fifo(&s, &f, 1000) == 1);
	CHECK(s.next_tick_ns == 2000);
	ecmxf_pump_sched_sent(&f, 1, s.next_tick_ns);

	// t = 1001: two FIFO commands and the read in flight: nothing
	CHECK(ecmxf_pump_sched_pick(&s, &f, &on, 1001, true, true) == ECMXF_PUMP_PICK_NONE);

	// slot 0 answered: the older is free; slot 1, the newest, in flight
	std::uint32_t skipped = 9;
	CHECK(ecmxf_pump_sched_finish(&f, 0, 0, &skipped) == ECMXF_PUMP_DONE_ANSWER);
	CHECK(skipped == 0);
	ecmxf_pump_sched_finish(&f, ECMXF_PUMP_SLOT_WKC, 0, &skipped);
	// t = 1200: the read is due again (500 then 1000 passed: next at 1700)
	REQUIRE(ecmxf_pump_sched_pick(&s, &f, &on, 1200, false, true) == ECMXF_PUMP_PICK_WKC);
	ecmxf_pump_sched_wkc(&s, 1200);
	CHECK(s.next_wkc_ns == 1700);
	// t = 2000: the tick: slot 1 is the newest, in flight: slot 0
	ecmxf_pump_sched_sent(&f, ECMXF_PUMP_SLOT_WKC, s.next_tick_ns);
	REQUIRE(ecmxf_pump_sched_pick(&s, &f, &on, 2000, false, true) == ECMXF_PUMP_PICK_FIFO);
	CHECK(ecmxf_pump_sched_fifo(&s, &f, 2000) == 0);
	CHECK(f.newest == 0);
}

TEST_CASE("pump schedule: the read timer keeps its period and does not burst", "[pump][sched]")
{
	ecmxf_pump_sched s = sched(0, 1000, 1000);
	ecmxf_pump_sched_wkc(&s, 500);
	CHECK(s.next_wkc_ns == 1000);	// 0 + 1000
	ecmxf_pump_sched_wkc(&s, 1200);
	CHECK(s.next_wkc_ns == 2000);	// 1000 + 1000: a late wake-up does not stretch it
	ecmxf_pump_sched_wkc(&s, 5500);
	CHECK(s.next_wkc_ns == 6500);	// 3000 <= 5500: one read, then a period from now
	ecmxf_pump_sched_wkc(&s, 7500);
	CHECK(s.next_wkc_ns == 8500);	// 7500 is not after 7500
}

TEST_CASE("pump schedule: frames in flight count in the level", "[pump][sched]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_flight f{};
	const ecmxf_rsp_hdr h = answer(1, 3, 0);

	f.plan[0].push = 2;
	f.plan[1].push = 5;
	CHECK(ecmxf_pump_flight_pushed(&f) == 0);
	CHECK_FALSE(ecmxf_pump_flight_busy(&f));
	f.busy[0] = true;
	CHECK(ecmxf_pump_flight_pushed(&f) == 2);
	CHECK(ecmxf_pump_sched_level(&p, &f, &h) == 5);	// 3 + 2
	f.busy[1] = true;
	CHECK(ecmxf_pump_flight_pushed(&f) == 7);
	CHECK(ecmxf_pump_sched_level(&p, &f, nullptr) == 7);
	// a command answered with 4 pushed: its frames may not show yet
	ecmxf_pump_plan pl{};
	pl.push = 4;
	ecmxf_pump_result res;
	const ecmxf_rsp_hdr a = answer(1, 3, 0);
	REQUIRE(ecmxf_pump_answer(&p, &pl, &a, 0, &res) == 0);
	CHECK(ecmxf_pump_sched_level(&p, &f, &h) == 14);	// 3 + 4 + 2 + 5
	f.busy[0] = f.busy[1] = false;
	f.busy[ECMXF_PUMP_SLOT_WKC] = true;
	CHECK(ecmxf_pump_flight_busy(&f));
	CHECK(ecmxf_pump_flight_pushed(&f) == 0);
}

TEST_CASE("pump schedule: the kernel's two FIFO commands in flight, 20 frames ready", "[pump][sched]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_sched s = sched(ECMXF_PUMP_S_FIFO_NEXT, 1000, 0);
	ecmxf_pump_flight f{};
	ecmxf_pump_acct a;
	std::uint32_t skipped = 0;
	const ecmxf_rsp_hdr first = answer(1, 0, 0);

	// command A, slot 0: level 0, room 8; 20 ready is more than room 8 +
	// fill 8 = 16, so the oldest 4 are skipped; 8 pushed, a read
	const unsigned sa = ecmxf_pump_sched_fifo(&s, &f, 0);
	REQUIRE(sa == 0);
	REQUIRE(ecmxf_pump_sched_plan(&p, &f, sa, ecmxf_pump_sched_level(&p, &f, &first), 20, ECMXF_PUMP_F_READ));
	CHECK(f.plan[sa].skip == 4);
	CHECK(f.plan[sa].push == 8);
	CHECK(f.plan[sa].read);
	// its answer waits for the next command: its 8 frames leave the ring now
	CHECK(ecmxf_pump_sched_sent(&f, sa, 1000) == 8);

	// command B, slot 1: no header shows A's 8 yet, the level is 0 + 8:
	// no room; 20 - 4 - 8 = 8 ready, not more than 0 + 8: no skip; a read
	const unsigned sb = ecmxf_pump_sched_fifo(&s, &f, 1000);
	REQUIRE(sb == 1);
	CHECK(ecmxf_pump_sched_level(&p, &f, &first) == 8);
	REQUIRE(ecmxf_pump_sched_plan(&p, &f, sb, ecmxf_pump_sched_level(&p, &f, &first), 8, ECMXF_PUMP_F_READ));
	CHECK(f.plan[sb].skip == 0);
	CHECK(f.plan[sb].push == 0);
	CHECK(f.plan[sb].read);
	CHECK(ecmxf_pump_sched_sent(&f, sb, 2000) == 0);

	// A's answer (fetched by B's exchange): taken, RxFIFO 8, TxFIFO 3 left,
	// 2 frames (40 bytes); the 4 skipped are counted now
	REQUIRE(ecmxf_pump_sched_finish(&f, sa, 0, &skipped) == ECMXF_PUMP_DONE_ANSWER);
	CHECK(skipped == 4);
	const ecmxf_rsp_hdr ha = answer(1, 8, 3);
	REQUIRE(ecmxf_pump_sched_answer(&p, &f, sa, &ha, 40, &a) == 0);
	CHECK(a.ops == 1);
	CHECK(a.free == 0);	// left the ring when sent
	CHECK(a.dropped == 0);
	CHECK(a.refusals == 0);
	CHECK(a.store == 2);
	CHECK(a.tx_overruns == 0);	// 2 + 3 < 10
	CHECK(a.rx_underruns == 0);
	CHECK_FALSE(a.wake_out);
	CHECK(a.answered);
	// 3 left in the TxFIFO, but B (in flight) pops them; 8 outputs ready
	ecmxf_pump_sched_left(&s, &f, sa, &ha, 8, &a);
	CHECK(s.again);
	s.again = false;
	ecmxf_pump_sched_left(&s, &f, sa, &ha, 0, &a);
	CHECK_FALSE(s.again);	// B pops the 3, nothing to push

	// B's answer: 3 frames (60 bytes), nothing left, RxFIFO 7
	REQUIRE(ecmxf_pump_sched_finish(&f, sb, 0, &skipped) == ECMXF_PUMP_DONE_ANSWER);
	CHECK(skipped == 0);
	const ecmxf_rsp_hdr hb = answer(0, 7, 0);
	REQUIRE(ecmxf_pump_sched_answer(&p, &f, sb, &hb, 60, &a) == 0);
	CHECK(a.store == 3);
	CHECK(a.refusals == 0);	// nothing pushed: bit 0 means nothing
	ecmxf_pump_sched_left(&s, &f, sb, &hb, 0, &a);
	CHECK_FALSE(s.again);
	ecmxf_pump_sched_left(&s, &f, sb, &hb, 8, &a);
	CHECK(s.again);
	CHECK_FALSE(ecmxf_pump_flight_busy(&f));
}

TEST_CASE("pump schedule: refusals, command errors, bad answers, failures", "[pump][sched]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_flight f{};
	ecmxf_pump_acct a;
	f.plan[0].push = 5;
	f.plan[0].read = true;

	SECTION("refused by a full RxFIFO: the frames leave the ring as dropped")
	{
		const ecmxf_rsp_hdr h = answer(0, 8, 0);
		REQUIRE(ecmxf_pump_sched_answer(&p, &f, 0, &h, 0, &a) == 0);
		CHECK(a.free == 5);
		CHECK(a.dropped == 5);
		CHECK(a.refusals == 1);
		CHECK(a.wake_out);
		f.released[0] = true;	// freed when sent: only counted
		REQUIRE(ecmxf_pump_sched_answer(&p, &f, 0, &h, 0, &a) == 0);
		CHECK(a.free == 0);
		CHECK(a.dropped == 5);
		CHECK(a.refusals == 1);
		CHECK_FALSE(a.wake_out);
	}
	SECTION("a command error takes nothing: frames in the ring go again, those freed are dropped")
	{
		const ecmxf_rsp_hdr h = answer(1, 8, 0, ECMXF_STS_FIFO_EN, ECMXF_ERR_CMD);
		CHECK(ecmxf_pump_sched_answer(&p, &f, 0, &h, 0, &a) == -EREMOTEIO);
		CHECK(a.ops == 1);
		CHECK(a.free == 0);
		CHECK(a.dropped == 0);
		CHECK_FALSE(a.answered);
		f.released[0] = true;
		CHECK(ecmxf_pump_sched_answer(&p, &f, 0, &h, 0, &a) == -EREMOTEIO);
		CHECK(a.free == 0);
		CHECK(a.dropped == 5);
	}
	SECTION("30 bytes of 20-byte frames: -EPROTO, the pushed frames are taken, no input stored")
	{
		ecmxf_pump_sched s = sched(0, 1000, 0);
		const ecmxf_rsp_hdr h = answer(1, 3, 4);
		CHECK(ecmxf_pump_sched_answer(&p, &f, 0, &h, 30, &a) == -EPROTO);
		CHECK(a.free == 5);
		CHECK(a.dropped == 0);
		CHECK(a.store == 0);
		CHECK_FALSE(a.answered);
		ecmxf_pump_sched_left(&s, &f, 0, &h, 8, &a);
		CHECK_FALSE(s.again);
	}
	SECTION("an RxFIFO empty while the FIFOs run, after a push: underrun; the ring's too when it is empty")
	{
		ecmxf_pump_sched s = sched(0, 1000, 0);
		const ecmxf_rsp_hdr h = answer(1, 0, 0);
		REQUIRE(ecmxf_pump_sched_answer(&p, &f, 0, &h, 0, &a) == 0);
		CHECK(a.rx_underruns == 1);
		ecmxf_pump_sched_left(&s, &f, 0, &h, 0, &a);
		CHECK(a.out_underruns == 1);
		CHECK_FALSE(s.again);	// 5 taken, but no frame ready and none queued
	}
	SECTION("a full TxFIFO: 5 popped + 5 left reach the depth 10")
	{
		const ecmxf_rsp_hdr h = answer(1, 4, 5);
		REQUIRE(ecmxf_pump_sched_answer(&p, &f, 0, &h, 100, &a) == 0);
		CHECK(a.store == 5);
		CHECK(a.tx_overruns == 1);
	}
	SECTION("no answer: the frames are lost, never sent again; the read counts a failure only")
	{
		f.busy[0] = true;
		std::uint32_t skipped = 0;
		f.skipped[0] = 2;
		CHECK(ecmxf_pump_sched_finish(&f, 0, -ETIMEDOUT, &skipped) == ECMXF_PUMP_DONE_FAILED);
		CHECK(skipped == 2);
		CHECK_FALSE(f.busy[0]);
		ecmxf_pump_sched_failed(&p, &f, 0, &a);
		CHECK(a.failures == 1);
		CHECK(a.free == 5);
		CHECK(a.dropped == 5);
		CHECK(a.wake_out);
		CHECK(p.unconfirmed == 5);	// they may be in the RxFIFO
		f.released[0] = true;
		ecmxf_pump_sched_failed(&p, &f, 0, &a);
		CHECK(a.free == 0);
		CHECK(a.dropped == 5);
		CHECK_FALSE(a.wake_out);
		ecmxf_pump_sched_failed(&p, &f, ECMXF_PUMP_SLOT_WKC, &a);
		CHECK(a.failures == 1);
		CHECK(a.free == 0);
		CHECK(a.dropped == 0);
	}
	SECTION("a chip reset stops the pump; a command not sent counts its skipped frames once")
	{
		std::uint32_t skipped = 0;
		f.busy[1] = true;
		CHECK(ecmxf_pump_sched_finish(&f, 1, -ECONNRESET, &skipped) == ECMXF_PUMP_DONE_STOP);
		f.skipped[0] = 3;
		CHECK(ecmxf_pump_sched_unsent(&f, 0) == 3);
		CHECK(ecmxf_pump_sched_unsent(&f, 0) == 0);
		CHECK(ecmxf_pump_sched_unsent(&f, ECMXF_PUMP_SLOT_WKC) == 0);
		f.busy[0] = true;
		f.skipped[0] = 3;
		ecmxf_pump_sched_cancel(&f, 0);
		CHECK_FALSE(f.busy[0]);
		CHECK(f.skipped[0] == 0);
	}
}

TEST_CASE("pump schedule: work left after an answer", "[pump][sched]")
{
	ecmxf_pump_sched s = sched(0, 1000, 0);
	ecmxf_pump_flight f{};
	ecmxf_pump_acct a{};
	a.answered = true;
	const ecmxf_rsp_hdr queued = answer(1, 2, 4);
	const ecmxf_rsp_hdr empty = answer(1, 2, 0);

	a.moved = true;
	ecmxf_pump_sched_left(&s, &f, 0, &queued, 0, &a);
	CHECK(s.again);	// 4 TxPDO frames queued, no later command in flight
	s.again = false;
	f.busy[1] = true;
	ecmxf_pump_sched_left(&s, &f, 0, &queued, 0, &a);
	CHECK_FALSE(s.again);	// the later command pops them
	ecmxf_pump_sched_left(&s, &f, 0, &empty, -EFAULT, &a);
	CHECK_FALSE(s.again);	// a broken ring is no work
	a.moved = false;
	ecmxf_pump_sched_left(&s, &f, 0, &empty, 5, &a);
	CHECK_FALSE(s.again);	// a command that moved nothing: wait for the timer
	a.moved = true;
	ecmxf_pump_sched_left(&s, &f, 0, &empty, 5, &a);
	CHECK(s.again);
}

TEST_CASE("pump schedule: the RxFIFO estimate of a host that keeps time", "[pump][sched]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_est e;
	ecmxf_pump_plan push8{};
	push8.push = 8;
	const ecmxf_pump_plan none{};

	SECTION("bus cycle 1000 ns: one frame gone per bus cycle since the chip ran the write")
	{
		ecmxf_pump_est_start(&e, 1000, 10000);
		CHECK(ecmxf_pump_est_cycle(&e, &p, 0, 10500) == 0);
		ecmxf_pump_est_pushed(&e, &push8, 6, 10500, e.cycles);
		CHECK(ecmxf_pump_est_cycle(&e, &p, 0, 13700) == 3);	// 6 - 3200 / 1000
		CHECK(ecmxf_pump_est_cycle(&e, &p, 4, 13700) == 7);	// 6 + 4 in flight - 3
		CHECK(ecmxf_pump_est_cycle(&e, &p, 0, 30000) == 0);	// 19 gone, not below 0
		CHECK(ecmxf_pump_est_cycle(&e, &p, 0, 9000) == 6);	// a clock before the write: none gone
		// a command that pushed nothing tells nothing about the level
		ecmxf_pump_est_pushed(&e, &none, 0, 20000, e.cycles);
		CHECK(ecmxf_pump_est_cycle(&e, &p, 0, 13700) == 3);
	}
	SECTION("bus cycle unknown: one frame gone per cycle")
	{
		ecmxf_pump_est_start(&e, 0, 0);
		CHECK(ecmxf_pump_est_cycle(&e, &p, 0, 0) == 0);	// cycle 1
		ecmxf_pump_est_pushed(&e, &push8, 5, 0, e.cycles);
		CHECK(ecmxf_pump_est_cycle(&e, &p, 0, 0) == 4);	// cycle 2: 5 - 1
		CHECK(ecmxf_pump_est_cycle(&e, &p, 2, 0) == 5);	// cycle 3: 5 + 2 - 2
		CHECK(e.cycles == 3);
	}
	SECTION("without outputs the level is 0, and the cycles count")
	{
		ecmxf_pump_init(&p, 0, 20, 112, 10, 0, 10);
		ecmxf_pump_est_start(&e, 0, 0);
		e.rx_level = 5;
		CHECK(ecmxf_pump_est_cycle(&e, &p, 3, 0) == 0);
		CHECK(e.cycles == 1);
	}
}

TEST_CASE("pump schedule: the TxFIFO loss estimate", "[pump][sched]")
{
	ecmxf_pump_est e;
	ecmxf_pump_plan rd{};
	rd.read = true;
	const ecmxf_pump_plan write{};
	std::uint32_t dropped = 99;

	ecmxf_pump_est_start(&e, 1000, 0);
	// at 2000: 3 popped, 1 left: 4 < depth 10, no overrun
	ecmxf_pump_result r1 = result(3);
	CHECK_FALSE(ecmxf_pump_est_popped(&e, &rd, &r1, 1, 2000, &dropped));
	CHECK(dropped == 0);
	CHECK(e.tx_level == 1);
	CHECK(e.tx_ns == 2000);
	// at 14500: 5 popped + 5 left = 10 queued, the depth: 1 left then + 12
	// bus cycles = 13 made, 3 dropped
	ecmxf_pump_result r2 = result(5, 0, true);
	CHECK(ecmxf_pump_est_popped(&e, &rd, &r2, 5, 14500, &dropped));
	CHECK(dropped == 3);
	// a command without a read changes nothing
	CHECK_FALSE(ecmxf_pump_est_popped(&e, &write, &r2, 0, 20000, &dropped));
	CHECK(dropped == 0);
	CHECK(e.tx_level == 5);
	CHECK(e.tx_ns == 14500);
	// no bus cycle: the overrun is known, the loss is not
	ecmxf_pump_est_start(&e, 0, 0);
	CHECK(ecmxf_pump_est_popped(&e, &rd, &r2, 5, 14500, &dropped));
	CHECK(dropped == 0);
}

TEST_CASE("pump schedule: the commands of a synchronous cycle", "[pump][sched]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_est e;
	ecmxf_pump_est_start(&e, 0, 0);
	ecmxf_pump_cycle c;
	ecmxf_pump_plan pl;
	bool wkc = false;
	std::uint32_t dropped = 0;

	SECTION("level 3: write 5 and read with the WKC read; a backlog of 7 then 2; nothing more to write")
	{
		ecmxf_pump_cycle_start(&c, 3, true);
		REQUIRE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));
		CHECK(pl.push == 5);	// room 8 - 3
		CHECK(pl.read);
		CHECK(wkc);
		ecmxf_pump_result r = result(5);
		ecmxf_pump_cycle_answer(&p, &c, &e, &pl, &r, 7, 0, &dropped);
		REQUIRE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));	// 7 left: read on
		CHECK(pl.push == 0);
		CHECK(pl.read);
		CHECK_FALSE(wkc);
		ecmxf_pump_cycle_answer(&p, &c, &e, &pl, &r, 2, 0, &dropped);
		REQUIRE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));	// 2 left
		CHECK(pl.read);
		r = result(2);
		ecmxf_pump_cycle_answer(&p, &c, &e, &pl, &r, 0, 0, &dropped);
		CHECK(e.tx_level == 0);
		// writes: level 3 + 5 pushed = the fill level: nothing
		CHECK_FALSE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));
		CHECK_FALSE(ecmxf_pump_cycle_wkc_alone(&c));
		CHECK(c.pushed == 5);
		CHECK(c.reads == 2);
		CHECK_FALSE(c.refused);
	}
	SECTION("a refused write ends the writes")
	{
		ecmxf_pump_cycle_start(&c, 0, false);
		REQUIRE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));
		CHECK(pl.push == 8);
		ecmxf_pump_result r = result(0, 8);
		ecmxf_pump_cycle_answer(&p, &c, &e, &pl, &r, 0, 0, &dropped);
		CHECK(c.refused);
		CHECK_FALSE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));
	}
	SECTION("a fill level of 20 from 0: writes of 9, 9 and 2")
	{
		ecmxf_pump_init(&p, 12, 20, 112, 64, 20, 64);
		ecmxf_pump_cycle_start(&c, 0, false);
		const unsigned want[] = { 9, 9, 2 };
		for (unsigned n : want) {
			REQUIRE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));
			CHECK(pl.push == n);
			ecmxf_pump_result r = result(0);
			ecmxf_pump_cycle_answer(&p, &c, &e, &pl, &r, 0, 0, &dropped);
		}
		CHECK_FALSE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));
		CHECK(c.pushed == 20);
	}
	SECTION("a full TxFIFO: four read-only commands at most (10 / 5 + 2)")
	{
		ecmxf_pump_cycle_start(&c, 8, false);
		REQUIRE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));
		CHECK(pl.push == 1);	// at the fill level: the cycle's outputs all the same
		ecmxf_pump_result r = result(5);
		ecmxf_pump_cycle_answer(&p, &c, &e, &pl, &r, 10, 0, &dropped);
		unsigned reads = 0;
		while (ecmxf_pump_cycle_next(&p, &c, &pl, &wkc) && pl.read && !pl.push) {
			reads++;
			ecmxf_pump_cycle_answer(&p, &c, &e, &pl, &r, 10, 0, &dropped);
		}
		CHECK(reads == 4);
		CHECK(c.reads == 4);
	}
	SECTION("a read that pops nothing ends the reads")
	{
		ecmxf_pump_cycle_start(&c, 8, false);
		REQUIRE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));
		ecmxf_pump_result r = result(5);
		ecmxf_pump_cycle_answer(&p, &c, &e, &pl, &r, 3, 0, &dropped);
		REQUIRE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));
		r = result(0);
		ecmxf_pump_cycle_answer(&p, &c, &e, &pl, &r, 3, 0, &dropped);
		CHECK(c.state == ECMXF_PUMP_C_WRITE);
	}
	SECTION("the first read's overrun is reported with the estimate")
	{
		ecmxf_pump_est_start(&e, 1000, 0);
		ecmxf_pump_cycle_start(&c, 0, false);
		REQUIRE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));
		ecmxf_pump_result r = result(5, 0, true);
		// 0 left at 0, 12 bus cycles: 12 made, 5 + 5 queued: 2 dropped
		CHECK(ecmxf_pump_cycle_answer(&p, &c, &e, &pl, &r, 5, 12000, &dropped));
		CHECK(dropped == 2);
	}
	SECTION("no command can go (a data section below a frame): the WKC read goes alone")
	{
		ecmxf_pump_init(&p, 12, 0, 112, 10, 0, 10);
		p.data_size = 10;
		ecmxf_pump_cycle_start(&c, 0, true);
		CHECK_FALSE(ecmxf_pump_cycle_next(&p, &c, &pl, &wkc));
		CHECK_FALSE(wkc);
		CHECK(ecmxf_pump_cycle_wkc_alone(&c));
	}
}

TEST_CASE("pump schedule: the one command of a cycle whose answer the next cycle takes", "[pump][sched]")
{
	ecmxf_pump p = standard();
	ecmxf_pump_sched s = sched(ECMXF_PUMP_S_FIFO_NEXT, 0, 0);
	ecmxf_pump_flight f{};
	ecmxf_pump_est e;
	ecmxf_pump_est_start(&e, 0, 0);

	// cycle 1: level 0: 8 copies, a read
	unsigned slot = ecmxf_pump_sched_fifo(&s, &f, 0);
	REQUIRE(ecmxf_pump_cycle_ahead(&p, &f, slot, ecmxf_pump_est_cycle(&e, &p, ecmxf_pump_flight_pushed(&f), 0)));
	CHECK(f.plan[slot].push == 8);
	CHECK(f.plan[slot].read);
	ecmxf_pump_sched_sent(&f, slot, 0);
	// cycle 2, in the other slot: no answer taken yet, so the count is 0
	// from the start, plus the 8 in flight, less the 2 cycles since the
	// start (no bus cycle: one frame per cycle): level 6, 2 copies
	const unsigned next = ecmxf_pump_sched_fifo(&s, &f, 0);
	CHECK(next == (slot ^ 1U));
	REQUIRE(ecmxf_pump_cycle_ahead(&p, &f, next, ecmxf_pump_est_cycle(&e, &p, ecmxf_pump_flight_pushed(&f), 0)));
	CHECK(f.plan[next].push == 2);
	CHECK(f.plan[next].read);
	CHECK(f.skipped[next] == 0);
	// at or above the fill level the cycle's outputs go all the same
	REQUIRE(ecmxf_pump_cycle_ahead(&p, &f, next, 8));
	CHECK(f.plan[next].push == 1);
	REQUIRE(ecmxf_pump_cycle_ahead(&p, &f, next, 30));
	CHECK(f.plan[next].push == 1);
}
