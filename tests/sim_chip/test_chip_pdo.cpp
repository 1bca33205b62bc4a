// SPDX-License-Identifier: MIT
// Process data in the simulated chip: FIFO sizes, depths and the 0x4000
// byte budget, PDO_DATA_FIFO_OP (write to the RxFIFO, read the TxFIFO),
// the drop rules, FIFO thresholds raising INT1, PDO_DATA_OP, the working
// counter and the continuous-error limit, and the speed of the bus cycle.

#include <catch2/catch.hpp>

#include <chrono>
#include <ctime>

#include "host.hpp"

using namespace simtest;
namespace sim = ecmxf::sim;
using namespace std::chrono_literals;

namespace {

Cmd fifoWrite(std::vector<std::vector<std::uint8_t>> frames, bool alsoRead = false)
{
	std::vector<std::uint8_t> d;
	for (const auto &f : frames)
		d.insert(d.end(), f.begin(), f.end());
	return Cmd(ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP, static_cast<std::uint8_t>(frames.size()))
		.d(alsoRead ? 0x03 : 0x01)
		.payload(d);
}

Cmd fifoRead()
{
	return Cmd(ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP, 0).d(0x02);
}

} // namespace

TEST_CASE("chip: FIFO_PACK_SIZE_GET reports the RxPDO and TxPDO frame sizes", "[chip][pdo]")
{
	SlaveConfig a;
	a.outBytes = 6;
	a.inBytes = 10;
	Rig rig(3, a);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0)).u16() == 0);
	rig.init();
	const Rsp rx = rig.host.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0));
	REQUIRE(rx.h.len == 2);
	CHECK(rx.u16() == 18);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 1)).u16() == 30);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 2)).cmdError());
}

TEST_CASE("chip: FIFO_ENABLE switches ECM status bit 6", "[chip][pdo]")
{
	Rig rig(1);
	rig.init();
	CHECK_FALSE(rig.host.info().h.ecm_status & ECMXF_STS_FIFO_EN);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1)).h.ecm_status & ECMXF_STS_FIFO_EN);
	CHECK_FALSE(rig.host.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 0)).h.ecm_status & ECMXF_STS_FIFO_EN);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 2)).cmdError());
}

TEST_CASE("chip: RxPDO frames go out one per bus cycle in order, then the last outputs are kept",
	  "[chip][pdo]")
{
	Rig rig(2);
	rig.toOp();
	rig.s(0).logOutputs = true;
	rig.s(1).logOutputs = true;
	Host &h = rig.host;
	// pre-stored while the FIFO is off: nothing is consumed
	const Rsp w = h.cmd(fifoWrite({ { 1, 11, 21, 31 }, { 2, 12, 22, 32 }, { 3, 13, 23, 33 } }));
	CHECK(w.h.ret & 0x01);
	CHECK(w.h.rx_fifo_cnt == 3);
	rig.run(5ms);
	CHECK(h.info().h.rx_fifo_cnt == 3);
	CHECK(rig.s(0).lastOutputs == std::vector<std::uint8_t>{ 0, 0 });
	rig.s(0).outLog.clear();
	rig.s(1).outLog.clear();
	const auto under0 = rig.chip->stats().rxUnderruns;
	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
	rig.run(6ms);
	const auto &log0 = rig.s(0).outLog;
	const auto &log1 = rig.s(1).outLog;
	REQUIRE(log0.size() >= 6);
	// frames before the first popped one are the old (zero) outputs
	std::size_t k = 0;
	while (k < log0.size() && log0[k] == std::vector<std::uint8_t>{ 0, 0 })
		k++;
	REQUIRE(k + 5 <= log0.size());
	CHECK(log0[k] == std::vector<std::uint8_t>{ 1, 11 });
	CHECK(log1[k] == std::vector<std::uint8_t>{ 21, 31 });
	CHECK(log0[k + 1] == std::vector<std::uint8_t>{ 2, 12 });
	CHECK(log0[k + 2] == std::vector<std::uint8_t>{ 3, 13 });
	CHECK(log0[k + 3] == std::vector<std::uint8_t>{ 3, 13 }); // FIFO empty: kept
	CHECK(log1[k + 4] == std::vector<std::uint8_t>{ 23, 33 });
	CHECK(h.info().h.rx_fifo_cnt == 0);
	CHECK(rig.chip->stats().rxUnderruns > under0);
}

TEST_CASE("chip: TxPDO frames are queued one per cycle and read oldest first, as many as fit",
	  "[chip][pdo]")
{
	Rig rig(2);
	rig.toOp();
	rig.s(0).counterInput = true;
	rig.s(1).inputPattern = { 0xAB, 0xCD };
	Host &h = rig.host;
	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
	rig.run(40ms);
	const Rsp hdr = h.info();
	CHECK(hdr.h.tx_fifo_cnt >= 40);
	const Rsp r = h.cmd(fifoRead());
	CHECK(r.h.ret & 0x02);
	// 112 data bytes hold 28 frames of 4 bytes
	REQUIRE(r.h.len == 28 * 4);
	for (std::size_t f = 0; f < 28; f++) {
		INFO("frame " << f);
		CHECK(r.data[4 * f + 2] == 0xAB);
		CHECK(r.data[4 * f + 3] == 0xCD);
		if (f)
			CHECK(r.data[4 * f] == static_cast<std::uint8_t>(r.data[4 * (f - 1)] + 1));
	}
	// the header of the same answer already counts the 28 frames out
	CHECK(r.h.tx_fifo_cnt <= hdr.h.tx_fifo_cnt - 28 + 2);
	const Rsp rest = h.cmd(fifoRead());
	CHECK(rest.h.len % 4 == 0);
	CHECK(rest.h.len >= 4 * 12);
	CHECK(rest.data[0] == static_cast<std::uint8_t>(r.data[4 * 27] + 1));
	// nothing queued: no data and bit 1 clear
	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 0));
	h.cmd(Cmd(ECMXF_CMD_FIFO_CLR_OP, 1));
	const Rsp none = h.cmd(fifoRead());
	CHECK(none.h.len == 0);
	CHECK_FALSE(none.h.ret & 0x02);
}

TEST_CASE("chip: a full RxFIFO refuses the newest frames and sets the FIFO error bit", "[chip][pdo]")
{
	Rig rig(2);
	rig.toOp();
	Host &h = rig.host;
	REQUIRE_FALSE(h.cmd(Cmd(ECMXF_CMD_FIFO_SET_RX_CNT, 4)).cmdError());
	std::vector<std::vector<std::uint8_t>> frames;
	for (std::uint8_t i = 1; i <= 6; i++)
		frames.push_back({ i, i, i, i });
	const Rsp r = h.cmd(fifoWrite(frames));
	CHECK_FALSE(r.h.ret & 0x01);
	CHECK(r.h.err_status & ECMXF_ERR_FIFO);
	CHECK(r.h.rx_fifo_cnt == 4);
	CHECK(rig.chip->stats().rxRefused == 2);
	// the oldest four are kept: 1, 2, 3, 4 go out
	rig.s(0).logOutputs = true;
	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
	rig.run(6ms);
	const auto &log = rig.s(0).outLog;
	std::vector<std::uint8_t> firsts;
	for (const auto &o : log)
		if (firsts.empty() || firsts.back() != o[0])
			firsts.push_back(o[0]);
	if (!firsts.empty() && firsts.front() == 0)
		firsts.erase(firsts.begin()); // cycles before the FIFO was switched on
	CHECK(firsts == std::vector<std::uint8_t>{ 1, 2, 3, 4 });
}

TEST_CASE("chip: a full TxFIFO drops the oldest frame and keeps the newest", "[chip][pdo]")
{
	Rig rig(1);
	rig.toOp();
	rig.s(0).counterInput = true;
	Host &h = rig.host;
	REQUIRE_FALSE(h.cmd(Cmd(ECMXF_CMD_FIFO_SET_TX_CNT, 3)).cmdError());
	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
	rig.run(10ms);
	const Rsp r = h.cmd(fifoRead());
	REQUIRE(r.h.len == 3 * 2);
	CHECK(r.data[2] == static_cast<std::uint8_t>(r.data[0] + 1));
	CHECK(r.data[4] == static_cast<std::uint8_t>(r.data[2] + 1));
	// the newest: the last cycle before the read (at most one cycle ago)
	CHECK(static_cast<std::uint8_t>(rig.s(0).cycles - r.data[4]) <= 1);
	CHECK(rig.chip->stats().txDropped >= 7);
	CHECK_FALSE(r.h.err_status & ECMXF_ERR_FIFO); // dropping old inputs is not an error
}

TEST_CASE("chip: FIFO_CLR_OP clears both FIFOs, the TxFIFO or the RxFIFO", "[chip][pdo]")
{
	Rig rig(1);
	rig.toOp();
	Host &h = rig.host;
	auto fill = [&] {
		h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
		rig.run(5ms);
		h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 0));
		h.cmd(fifoWrite({ { 1, 1 }, { 2, 2 }, { 3, 3 } }));
		const Rsp r = h.info();
		REQUIRE(r.h.tx_fifo_cnt >= 5);
		REQUIRE(r.h.rx_fifo_cnt == 3);
	};
	fill();
	Rsp r = h.cmd(Cmd(ECMXF_CMD_FIFO_CLR_OP, 1));
	CHECK(r.h.tx_fifo_cnt == 0);
	CHECK(r.h.rx_fifo_cnt == 3);
	r = h.cmd(Cmd(ECMXF_CMD_FIFO_CLR_OP, 2));
	CHECK(r.h.rx_fifo_cnt == 0);
	fill();
	r = h.cmd(Cmd(ECMXF_CMD_FIFO_CLR_OP, 0));
	CHECK(r.h.tx_fifo_cnt == 0);
	CHECK(r.h.rx_fifo_cnt == 0);
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_CLR_OP, 3)).cmdError());
}

TEST_CASE("chip: FIFO depths are set within RxCount*RxSize + TxCount*TxSize <= 0x4000", "[chip][pdo]")
{
	SlaveConfig big;
	big.outBytes = 100;
	big.inBytes = 100;
	Rig rig(1, big);
	rig.init();
	Host &h = rig.host;
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_GET_RX_CNT)).h.ret == 64);
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_GET_TX_CNT)).h.ret == 64);
	// 100 * 100 + 64 * 100 = 16400 > 16384
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_SET_RX_CNT, 100)).cmdError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_GET_RX_CNT).control(ECMXF_CTL_CLR_CMD_ERR)).h.ret == 64);
	// 99 * 100 + 64 * 100 = 16300
	CHECK_FALSE(h.cmd(Cmd(ECMXF_CMD_FIFO_SET_RX_CNT, 99)).cmdError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_GET_RX_CNT)).h.ret == 99);
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_SET_TX_CNT, 65)).cmdError());
	CHECK_FALSE(h.cmd(Cmd(ECMXF_CMD_FIFO_SET_TX_CNT, 10).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_GET_TX_CNT)).h.ret == 10);
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_SET_TX_CNT, 0)).cmdError());
	// the RxFIFO really holds 99 frames
	std::vector<std::vector<std::uint8_t>> f(1, std::vector<std::uint8_t>(100, 5));
	h.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).control(ECMXF_CTL_CLR_CMD_ERR));
	for (int i = 0; i < 99; i++)
		REQUIRE(h.cmd(fifoWrite(f)).h.ret & 0x01);
	const Rsp full = h.cmd(fifoWrite(f));
	CHECK_FALSE(full.h.ret & 0x01);
	CHECK(full.h.rx_fifo_cnt == 99);
}

TEST_CASE("chip: FIFO_INIT rebuilds the FIFOs empty with the configured depths", "[chip][pdo]")
{
	Rig rig(1);
	rig.toOp();
	Host &h = rig.host;
	h.cmd(Cmd(ECMXF_CMD_FIFO_SET_RX_CNT, 5));
	h.cmd(fifoWrite({ { 1, 1 }, { 2, 2 } }));
	CHECK(h.info().h.rx_fifo_cnt == 2);
	const Rsp r = h.cmd(Cmd(ECMXF_CMD_FIFO_INIT));
	CHECK(r.h.rx_fifo_cnt == 0);
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_GET_RX_CNT)).h.ret == 5);
}

TEST_CASE("chip: ECAT_SET_FIFO_TH raises the TxFIFO high and RxFIFO low interrupts on INT1",
	  "[chip][pdo][int]")
{
	Rig rig(1);
	rig.toOp();
	Host &h = rig.host;
	sim::Chip &c = *rig.chip;
	h.cmd(Cmd(ECMXF_CMD_ECAT_INT_SET_ENABLE, 0x02)
		      .payload(le32v(ECMXF_INT_TXFIFO_HIGH | ECMXF_INT_RXFIFO_LOW))
		      .len(6));
	SECTION("TxFIFO reaching its high mark")
	{
		REQUIRE_FALSE(h.cmd(Cmd(ECMXF_CMD_ECAT_SET_FIFO_TH, 0x01).d(3, 0)).cmdError());
		h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
		h.cmd(Cmd(ECMXF_CMD_FIFO_CLR_OP, 1).intClear(ECMXF_INT_TXFIFO_HIGH));
		bool seen = false;
		for (int i = 0; i < 20 && !seen; i++) {
			const Rsp r = h.info();
			if (r.h.tx_fifo_cnt < 3) {
				CHECK_FALSE(r.h.int_flags & ECMXF_INT_TXFIFO_HIGH);
			} else {
				CHECK(r.h.int_flags & ECMXF_INT_TXFIFO_HIGH);
				seen = true;
			}
			rig.run(300us);
		}
		CHECK(seen);
		CHECK_FALSE(c.int1()); // active low: asserted
		h.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).intClear(ECMXF_INT_TXFIFO_HIGH));
		CHECK(c.int1());
		// it does not fire again while the count stays above the mark
		rig.run(5ms);
		CHECK_FALSE(h.info().h.int_flags & ECMXF_INT_TXFIFO_HIGH);
	}
	SECTION("RxFIFO falling to its low mark")
	{
		REQUIRE_FALSE(h.cmd(Cmd(ECMXF_CMD_ECAT_SET_FIFO_TH, 0x02).d(0, 2)).cmdError());
		h.cmd(fifoWrite({ { 1, 1 }, { 2, 2 }, { 3, 3 }, { 4, 4 }, { 5, 5 } }));
		CHECK_FALSE(h.info().h.int_flags & ECMXF_INT_RXFIFO_LOW);
		h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
		bool seen = false;
		for (int i = 0; i < 20 && !seen; i++) {
			const Rsp r = h.info();
			if (r.h.rx_fifo_cnt > 2) {
				CHECK_FALSE(r.h.int_flags & ECMXF_INT_RXFIFO_LOW);
			} else {
				CHECK(r.h.int_flags & ECMXF_INT_RXFIFO_LOW);
				seen = true;
			}
			rig.run(300us);
		}
		CHECK(seen);
		CHECK_FALSE(c.int1());
		h.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).intClear(ECMXF_INT_RXFIFO_LOW));
		rig.run(5ms); // 2 -> 1 -> 0: no new edge through the mark
		CHECK_FALSE(h.info().h.int_flags & ECMXF_INT_RXFIFO_LOW);
		CHECK(c.int1());
	}
	SECTION("disabled thresholds raise nothing; bad parameters are refused")
	{
		h.cmd(Cmd(ECMXF_CMD_ECAT_SET_FIFO_TH, 0x00).d(1, 1));
		h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
		rig.run(5ms);
		CHECK_FALSE(h.info().h.int_flags & (ECMXF_INT_TXFIFO_HIGH | ECMXF_INT_RXFIFO_LOW));
		CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SET_FIFO_TH, 0x04)).cmdError());
	}
}

TEST_CASE("chip: PDO_DATA_OP reads the inputs and writes the outputs of the process image",
	  "[chip][pdo]")
{
	Rig rig(2);
	rig.toOp();
	rig.s(0).inputPattern = { 0x10, 0x11 };
	rig.s(1).inputPattern = { 0x20, 0x21 };
	Host &h = rig.host;
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_PDO_DATA_OP).d(0x06)).h.len == 4);
	rig.run(2ms);
	// bit 2 set, bit 1: read only
	const Rsp rd = h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_DATA_OP).d(0x06));
	CHECK(rd.data == std::vector<std::uint8_t>{ 0x10, 0x11, 0x20, 0x21 });
	CHECK(rd.h.ret & 0x02);
	CHECK(rig.s(0).lastOutputs == std::vector<std::uint8_t>{ 0, 0 });
	// bit 2 set, bit 0: write only
	const Rsp wr = h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_DATA_OP).d(0x05).payload({ 9, 8, 7, 6 }));
	CHECK(wr.h.len == 0);
	CHECK(wr.h.ret & 0x01);
	rig.run(2ms);
	CHECK(rig.s(0).lastOutputs == std::vector<std::uint8_t>{ 9, 8 });
	CHECK(rig.s(1).lastOutputs == std::vector<std::uint8_t>{ 7, 6 });
	// bit 2 clear: both
	const Rsp both = h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_DATA_OP).d(0x00).payload({ 1, 2, 3, 4 }));
	CHECK(both.data == std::vector<std::uint8_t>{ 0x10, 0x11, 0x20, 0x21 });
	rig.run(2ms);
	CHECK(rig.s(1).lastOutputs == std::vector<std::uint8_t>{ 3, 4 });
	// bit 2 alone: neither
	const Rsp none = h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_DATA_OP).d(0x04).payload({ 5, 5, 5, 5 }));
	CHECK(none.h.len == 0);
	rig.run(2ms);
	CHECK(rig.s(1).lastOutputs == std::vector<std::uint8_t>{ 3, 4 });
}

TEST_CASE("chip: process data commands before INIT_OP are command errors", "[chip][pdo]")
{
	Rig rig(1);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_PDO_DATA_OP).d(0x06)).cmdError());
	CHECK(rig.host.cmd(fifoRead().control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}

// ---------------------------------------------------------------------------
// working counter
// ---------------------------------------------------------------------------

TEST_CASE("chip: WKC errors in OP are counted in the header, saturating, and flagged", "[chip][pdo][wkc]")
{
	Rig rig(3);
	rig.toOp();
	Host &h = rig.host;
	rig.run(5ms);
	Rsp r = h.info();
	CHECK(r.h.wkc_err_cnt == 0);
	CHECK_FALSE(r.h.int_flags & ECMXF_INT_WKC_ERR);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_CNT_GET)).h.ret == 0);
	rig.chip->faults().slaveDropped = 1;
	rig.run(10ms);
	r = h.info();
	CHECK(r.h.wkc_err_cnt >= 10);
	CHECK(r.h.wkc_err_cnt <= 11);
	CHECK(r.h.int_flags & ECMXF_INT_WKC_ERR);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_WC_GET, 3)).u32() == 2 * 3);
	const unsigned conti = h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_CNT_GET)).h.ret;
	CHECK(conti >= 10);
	rig.run(300ms);
	CHECK(h.info().h.wkc_err_cnt == 255);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_CNT_GET)).h.ret == 255);
	// back: the running count restarts, the header count stays
	rig.chip->faults().slaveDropped = -1;
	rig.run(3ms);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_CNT_GET)).h.ret == 0);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_WC_GET, 3)).u32() == 3 * 3);
	CHECK(h.info().h.wkc_err_cnt == 255);
}

TEST_CASE("chip: no WKC checks before OP", "[chip][pdo][wkc]")
{
	Rig rig(2);
	rig.init();
	rig.state(ECMXF_ECAT_PREOP);
	rig.chip->faults().slaveDropped = 0;
	rig.run(10ms);
	CHECK(rig.host.info().h.wkc_err_cnt == 0);
}

TEST_CASE("chip: after more than WKC_CONTI_ERR_MAX consecutive errors the PDO exchange stops",
	  "[chip][pdo][wkc]")
{
	Rig rig(2);
	rig.toOp();
	Host &h = rig.host;
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET)).h.ret == 255);
	REQUIRE_FALSE(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET, 3)).cmdError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET)).h.ret == 3);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET, 0)).cmdError());
	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1).control(ECMXF_CTL_CLR_CMD_ERR));
	Rsp r = h.info();
	CHECK(r.h.ecm_status & ECMXF_STS_PDO_CONFIGURED);
	CHECK(r.h.ecm_status & ECMXF_STS_FIFO_EN);
	// three errors in a row are tolerated
	rig.chip->faults().slaveDropped = 1;
	rig.run(3ms - 200us);
	rig.chip->faults().slaveDropped = -1;
	rig.run(2ms);
	r = h.info();
	CHECK(r.h.ecm_status & ECMXF_STS_PDO_CONFIGURED);
	// the fourth stops the exchange
	rig.chip->faults().slaveDropped = 1;
	rig.run(6ms);
	rig.chip->faults().slaveDropped = -1;
	r = h.info();
	CHECK_FALSE(r.h.ecm_status & ECMXF_STS_PDO_CONFIGURED);
	CHECK_FALSE(r.h.ecm_status & ECMXF_STS_FIFO_EN);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_CNT_GET)).h.ret == 4);
	const auto cycles = rig.s(0).cycles;
	rig.run(5ms);
	CHECK(rig.s(0).cycles == cycles); // no process data frames any more
	// CONFIG_MAP sets the exchange up again
	r = h.async(Cmd(ECMXF_CMD_ECAT_CONFIG_MAP));
	CHECK(r.h.ecm_status & ECMXF_STS_PDO_CONFIGURED);
	rig.run(3ms);
	CHECK(rig.s(0).cycles > cycles);
}

// ---------------------------------------------------------------------------
// speed
// ---------------------------------------------------------------------------

TEST_CASE("chip: 128 slaves at 8 kHz with a FIFO exchange every ms lose no cycle and no frame",
	  "[chip][pdo][perf]")
{
	SlaveConfig tiny;
	tiny.outBytes = 1;
	tiny.inBytes = 1;
	tiny.mbxLatency = std::chrono::microseconds(500);
	Rig rig(128, tiny);
	rig.toOp(125'000);
	Host &h = rig.host;
	h.send(Cmd(ECMXF_CMD_SPI_RECONFIG_OP).len(1408));
	h.dataSize = 1408;
	h.repeat();
	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
	std::vector<std::vector<std::uint8_t>> frames(8, std::vector<std::uint8_t>(128, 0x5A));
	const Cmd exchange = fifoWrite(frames, true);

	const auto simStart = rig.chip->now();
	const auto cycles0 = rig.chip->stats().busCycles;
	std::size_t inFrames = 0;
	for (int ms = 0; ms < 2000; ms++) {
		const Rsp r = h.cmd(exchange);
		REQUIRE(r.ok());
		inFrames += r.h.len / 128;
		const auto next = simStart + std::chrono::milliseconds(ms + 1);
		if (rig.chip->now() < next)
			rig.chip->advance(next - rig.chip->now());
	}
	const auto simulated = rig.chip->now() - simStart;
	const auto cycles = rig.chip->stats().busCycles - cycles0;
	CHECK(simulated >= std::chrono::milliseconds(2000));
	CHECK(cycles >= 15'990);
	CHECK(inFrames >= 15'900);
	CHECK(rig.host.info().h.wkc_err_cnt == 0);
	// how fast this runs is measured by `make bench` (bench-sim), not here
}
