// SPDX-License-Identifier: MIT
// The simulated chip's SPI front end: exchange rules, header fields, error
// bits and counters, packet size and check type, INT0/INT1, reset, the
// async-command rules. Expected values come from the manuals (ver. 050
// where they differ) and the decisions of the protocol digest.

#include <catch2/catch.hpp>

#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

#include <unistd.h>

#include "host.hpp"

using namespace simtest;
namespace sim = ecmxf::sim;

namespace {

/// A packet whose check word is wrong.
std::vector<std::uint8_t> corrupt(std::vector<std::uint8_t> p)
{
	p[p.size() - 8] ^= 0x40;
	return p;
}

} // namespace

// ---------------------------------------------------------------------------
// exchange rules
// ---------------------------------------------------------------------------

TEST_CASE("chip: the first response after power-on is a NOP that answers nothing", "[chip][spi]")
{
	sim::Chip chip(sim::Network{});
	Host host(chip);
	CHECK(chip.dataSize() == 112);
	CHECK(chip.packetSize() == 24 + 112 + 8);
	CHECK(chip.ready());
	const Rsp r = host.send(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET));
	REQUIRE(r.ok());
	CHECK(r.nop());
	CHECK(r.h.index == 0);
	CHECK(r.h.code == 0);
	CHECK(r.h.len == 0);
	CHECK((r.h.ecm_status & ECMXF_STS_CHECK_MASK) == ECMXF_CHECK_FIXED);
	CHECK(r.h.ecat_state == ECMXF_ECAT_NONE);
	// link present (bit 0, hardware), not yet checked by INIT_OP (bit 1)
	CHECK(r.h.err_status == ECMXF_ERR_LINK_HW);
	// the next answer is a real one, without the NOP bit
	const Rsp a = host.repeat();
	REQUIRE(a.ok());
	CHECK_FALSE(a.nop());
	CHECK(a.h.code == ECMXF_CMD_ECAT_SLV_CNT_GET);
}

TEST_CASE("chip: each exchange returns the answer to the previous packet", "[chip][spi]")
{
	Rig rig(2);
	Host &h = rig.host;
	const std::uint8_t syncIndex = h.index;
	const Rsp first = h.send(Cmd(ECMXF_CMD_FW_VERSION_GET));
	REQUIRE(first.ok());
	// the answer to the sync INFO_UPDATE
	CHECK(first.h.index == syncIndex);
	CHECK(first.h.code == ECMXF_CMD_INFO_UPDATE_OP);
	const std::uint8_t fwIndex = h.index;
	const Rsp second = h.send(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET));
	REQUIRE(second.ok());
	CHECK(second.h.index == fwIndex);
	CHECK(second.h.code == ECMXF_CMD_FW_VERSION_GET);
	CHECK(second.h.len == 20);
	const Rsp third = h.repeat();
	CHECK(third.h.code == ECMXF_CMD_ECAT_SLV_CNT_GET);
	CHECK(third.h.index == h.index);
}

TEST_CASE("chip: a repeated (index, code) runs as INFO_UPDATE and is answered as one", "[chip][spi]")
{
	Rig rig(1);
	Host &h = rig.host;
	rig.init();
	// an async command: executing it twice would be refused as "busy"
	const Rsp a = h.cmd(stateSet(0xFF, ECMXF_ECAT_PREOP));
	REQUIRE(a.ok());
	CHECK(a.h.code == ECMXF_CMD_ECAT_STATE_SET);
	CHECK(a.busy());
	const Rsp b = h.repeat();
	REQUIRE(b.ok());
	CHECK(b.h.index == h.last.h.index);
	CHECK(b.h.code == ECMXF_CMD_INFO_UPDATE_OP);
	CHECK(b.h.ret == 0);
	CHECK(b.h.len == 0);
	CHECK_FALSE(b.cmdError());
	const Rsp c = h.repeat();
	CHECK(c.h.code == ECMXF_CMD_INFO_UPDATE_OP);
	CHECK_FALSE(c.cmdError());
	// only one AL control write per slave happened
	rig.host.waitIdle();
	CHECK(rig.s(0).state == ECMXF_ECAT_PREOP);
}

TEST_CASE("chip: the same code with a new index is a new command", "[chip][spi]")
{
	Rig rig(3);
	const Rsp a = rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET));
	const Rsp b = rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET));
	CHECK(a.h.code == ECMXF_CMD_ECAT_SLV_CNT_GET);
	CHECK(b.h.code == ECMXF_CMD_ECAT_SLV_CNT_GET);
	CHECK(a.h.index != b.h.index);
}

TEST_CASE("chip: INFO_UPDATE answers with a refreshed header and no data", "[chip][spi]")
{
	Rig rig(1);
	const Rsp r = rig.host.info();
	REQUIRE(r.ok());
	CHECK(r.h.code == ECMXF_CMD_INFO_UPDATE_OP);
	CHECK(r.h.index == rig.host.index);
	CHECK(r.h.ret == 0);
	CHECK(r.h.len == 0);
	CHECK_FALSE(r.nop());
}

// ---------------------------------------------------------------------------
// bad packets, CRC error count, error bits
// ---------------------------------------------------------------------------

TEST_CASE("chip: a command packet with a bad check word is counted and not executed", "[chip][spi]")
{
	Rig rig(1);
	Host &h = rig.host;
	const Rsp ok = h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET));
	const std::uint8_t lastValid = h.index;
	REQUIRE(ok.h.crc_err_cnt == 0);
	CHECK_FALSE(ok.h.err_status & ECMXF_ERR_SPI_CRC);

	// WKC_CONTI_ERR_MAX_SET 5, but corrupted
	Cmd bad = h.fresh(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET, 5));
	const Rsp r1 = h.decode(h.xfer(corrupt(h.encode(bad))));
	REQUIRE(r1.ok());
	// next exchange: an INFO_UPDATE-like refresh for the last valid index
	const Rsp r2 = h.send(Cmd(ECMXF_CMD_INFO_UPDATE_OP));
	REQUIRE(r2.ok());
	CHECK(r2.h.index == lastValid);
	CHECK(r2.h.code == ECMXF_CMD_INFO_UPDATE_OP);
	CHECK(r2.h.crc_err_cnt == 1);
	CHECK(r2.h.err_status & ECMXF_ERR_SPI_CRC);
	CHECK(r2.h.int_flags & ECMXF_INT_CRC_ERR);
	// it was not executed
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET)).h.ret == 255);
	CHECK(rig.chip->stats().badPackets == 1);
}

TEST_CASE("chip: wrong start or end words and wrong packet sizes count as CRC errors", "[chip][spi]")
{
	Rig rig(1);
	Host &h = rig.host;
	auto p = h.encode(h.fresh(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET)));
	p[0] ^= 0xFF; // start word
	h.xfer(p);
	p = h.encode(h.fresh(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET)));
	p.back() ^= 0xFF; // end word
	h.xfer(p);
	// a packet of the wrong size: the chip shifts out its own size's bytes
	std::vector<std::uint8_t> shortPkt(100, 0);
	const auto miso = h.xfer(shortPkt);
	CHECK(miso.size() == 100);
	const Rsp r = h.info();
	CHECK(r.h.crc_err_cnt == 3);
	CHECK(r.h.err_status & ECMXF_ERR_SPI_CRC);
}

TEST_CASE("chip: the SPI CRC error count saturates at 255", "[chip][spi]")
{
	Rig rig(0);
	Host &h = rig.host;
	for (int i = 0; i < 300; i++)
		h.xfer(corrupt(h.encode(h.fresh(Cmd(ECMXF_CMD_INFO_UPDATE_OP)))));
	CHECK(h.info().h.crc_err_cnt == 255);
	CHECK(rig.chip->stats().badPackets == 300);
}

TEST_CASE("chip: control bit 1 and CRC_ERR_CNT_CLR clear the CRC error count", "[chip][spi]")
{
	Rig rig(0);
	Host &h = rig.host;
	for (int i = 0; i < 3; i++)
		h.xfer(corrupt(h.encode(h.fresh(Cmd(ECMXF_CMD_INFO_UPDATE_OP)))));
	// CRC_ERR_CNT_CLR returns the count it cleared
	const Rsp c = h.cmd(Cmd(ECMXF_CMD_CRC_ERR_CNT_CLR));
	CHECK(c.h.ret == 3);
	CHECK(c.h.crc_err_cnt == 0);
	// bit 6 (SPI CRC error) stays until the control byte clears it
	CHECK(c.h.err_status & ECMXF_ERR_SPI_CRC);
	h.xfer(corrupt(h.encode(h.fresh(Cmd(ECMXF_CMD_INFO_UPDATE_OP)))));
	CHECK(h.info().h.crc_err_cnt == 1);
	const Rsp d = h.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).control(ECMXF_CTL_CLR_CRC_CNT | ECMXF_CTL_CLR_SPI_CRC_ERR));
	CHECK(d.h.crc_err_cnt == 0);
	CHECK_FALSE(d.h.err_status & ECMXF_ERR_SPI_CRC);
}

TEST_CASE("chip: unknown command codes are answered with the command error bit", "[chip][spi]")
{
	Rig rig(1);
	Host &h = rig.host;
	for (unsigned code : { 14u, 17u, 21u, 22u, 36u, 37u, 40u, 60u, 100u, 128u, 141u, 145u, 255u }) {
		INFO("code " << code);
		const Rsp r = h.cmd(Cmd(static_cast<std::uint8_t>(code)).control(ECMXF_CTL_CLR_CMD_ERR));
		REQUIRE(r.ok());
		CHECK(r.h.code == code);
		CHECK(r.h.index == h.index);
		CHECK(r.h.ret == 0);
		CHECK(r.h.len == 0);
		CHECK(r.cmdError());
	}
	// control bit 7 clears it (the clear is applied before the command runs)
	CHECK_FALSE(h.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}

TEST_CASE("chip: the error bits persist until the control byte clears each one", "[chip][spi]")
{
	Rig rig(1);
	Host &h = rig.host;
	rig.init();
	const Rsp a = h.async(stateSet(0, ECMXF_ECAT_OP)); // INIT -> OP: refused
	CHECK(a.asyncError());
	// FIFO error: RxFIFO of depth 1 (FIFO off, nothing consumes it), two frames
	REQUIRE_FALSE(h.cmd(Cmd(ECMXF_CMD_FIFO_SET_RX_CNT, 1)).cmdError());
	h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP, 2).d(1).payload(std::vector<std::uint8_t>(4, 7)));
	h.cmd(Cmd(14)); // command error
	Rsp r = h.info();
	CHECK(r.h.err_status & ECMXF_ERR_FIFO);
	CHECK(r.h.err_status & ECMXF_ERR_ASYNC);
	CHECK(r.h.err_status & ECMXF_ERR_CMD);
	// several more exchanges: still set
	for (int i = 0; i < 3; i++)
		r = h.info();
	CHECK((r.h.err_status & 0xA8) == 0xA8);
	r = h.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).control(ECMXF_CTL_CLR_ASYNC_ERR));
	CHECK((r.h.err_status & 0xF8) == (ECMXF_ERR_FIFO | ECMXF_ERR_CMD));
	r = h.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).control(ECMXF_CTL_CLR_FIFO_ERR));
	CHECK((r.h.err_status & 0xF8) == ECMXF_ERR_CMD);
	r = h.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).control(ECMXF_CTL_CLR_CMD_ERR | ECMXF_CTL_CLR_SPI_ERR));
	CHECK((r.h.err_status & 0xF8) == 0);
	// the link bits are not error bits: 0 and 1 still read 1
	CHECK((r.h.err_status & 0x03) == 0x03);
}

// ---------------------------------------------------------------------------
// packet size, check type
// ---------------------------------------------------------------------------

TEST_CASE("chip: SPI_PACK_SIZE_GET returns the data section size", "[chip][spi]")
{
	Rig rig(0);
	const Rsp r = rig.host.cmd(Cmd(ECMXF_CMD_SPI_PACK_SIZE_GET));
	REQUIRE(r.h.len == 2);
	CHECK(r.u16() == 112);
}

TEST_CASE("chip: SPI_RECONFIG_OP switches the size from the next exchange and answers at the new size",
	  "[chip][spi]")
{
	Rig rig(0);
	Host &h = rig.host;
	const Rsp before = h.send(Cmd(ECMXF_CMD_SPI_RECONFIG_OP).len(256));
	REQUIRE(before.ok()); // the previous answer, still at 112
	CHECK(rig.chip->dataSize() == 256);
	CHECK(rig.chip->packetSize() == 24 + 256 + 8);
	// the chip takes time before it accepts the next exchange
	CHECK_FALSE(rig.chip->ready());
	h.dataSize = 256;
	const Rsp r = h.repeat();
	REQUIRE(r.ok());
	CHECK(r.h.code == ECMXF_CMD_SPI_RECONFIG_OP);
	CHECK(r.h.len == 0);
	const Rsp s = h.cmd(Cmd(ECMXF_CMD_SPI_PACK_SIZE_GET));
	CHECK(s.u16() == 256);
}

TEST_CASE("chip: SPI_RECONFIG_OP outside 32..1408 is a command error and keeps the size", "[chip][spi]")
{
	Rig rig(0);
	for (unsigned bad : { 0u, 31u, 1409u, 4000u }) {
		const Rsp r = rig.host.cmd(Cmd(ECMXF_CMD_SPI_RECONFIG_OP).len(static_cast<std::uint16_t>(bad)).control(ECMXF_CTL_CLR_CMD_ERR));
		CHECK(r.cmdError());
		CHECK(rig.chip->dataSize() == 112);
	}
	for (unsigned good : { 32u, 1408u }) {
		rig.host.send(Cmd(ECMXF_CMD_SPI_RECONFIG_OP).len(static_cast<std::uint16_t>(good)).control(ECMXF_CTL_CLR_CMD_ERR));
		rig.host.dataSize = good;
		const Rsp r = rig.host.repeat();
		CHECK_FALSE(r.cmdError());
		CHECK(rig.chip->dataSize() == good);
	}
}

TEST_CASE("chip: SPI_RECONFIG_OP is accepted with the fixed check word under CRC-32, counting a CRC error",
	  "[chip][spi]")
{
	Rig rig(0);
	Host &h = rig.host;
	h.send(Cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC32));
	h.check = ECMXF_CHECK_CRC32;
	h.info();
	REQUIRE(h.info().h.crc_err_cnt == 0);
	// sent with the fixed word, as the manual asks
	Cmd rc = h.fresh(Cmd(ECMXF_CMD_SPI_RECONFIG_OP).len(64));
	h.last = rc;
	h.xfer(h.encode(rc, ECMXF_CHECK_FIXED, 112));
	CHECK(rig.chip->dataSize() == 64);
	h.dataSize = 64;
	const Rsp r = h.repeat(); // the repeat in CRC-32, at the new size
	REQUIRE(r.ok());
	CHECK(r.h.code == ECMXF_CMD_SPI_RECONFIG_OP);
	CHECK(r.h.crc_err_cnt == 1);
	CHECK_FALSE(r.h.err_status & ECMXF_ERR_SPI_CRC);
	CHECK((r.h.ecm_status & ECMXF_STS_CHECK_MASK) == ECMXF_CHECK_CRC32);
}

TEST_CASE("chip: CRC_TYPE_SET answers in the old check type and uses the new one afterwards",
	  "[chip][spi]")
{
	Rig rig(0);
	Host &h = rig.host;
	h.send(Cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC32));
	// from now on the chip checks commands with CRC-32
	h.check = ECMXF_CHECK_CRC32;
	const auto miso = h.xfer(h.encode(h.last));
	// the answer to CRC_TYPE_SET: fixed check word
	const Rsp old = h.decode(miso, ECMXF_CHECK_FIXED);
	REQUIRE(old.ok());
	CHECK(old.h.code == ECMXF_CMD_CRC_TYPE_SET);
	CHECK((old.h.ecm_status & ECMXF_STS_CHECK_MASK) == ECMXF_CHECK_FIXED);
	CHECK(h.decode(miso, ECMXF_CHECK_CRC32).fault == ECMXF_FAULT_CHECK);
	// every later answer: CRC-32
	const Rsp now = h.info();
	REQUIRE(now.ok());
	CHECK((now.h.ecm_status & ECMXF_STS_CHECK_MASK) == ECMXF_CHECK_CRC32);
	CHECK(now.h.crc_err_cnt == 0);
	// a packet with the fixed word is now a CRC error
	h.xfer(h.encode(h.fresh(Cmd(ECMXF_CMD_INFO_UPDATE_OP)), ECMXF_CHECK_FIXED, 112));
	CHECK(h.info().h.crc_err_cnt == 1);
	// ver. 038 types are accepted, 4 is not
	h.send(Cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC8));
	h.check = ECMXF_CHECK_CRC8;
	CHECK(h.decode(h.xfer(h.encode(h.last)), ECMXF_CHECK_CRC32).ok());
	CHECK((h.info().h.ecm_status & ECMXF_STS_CHECK_MASK) == ECMXF_CHECK_CRC8);
	const Rsp bad = h.cmd(Cmd(ECMXF_CMD_CRC_TYPE_SET, 4));
	CHECK(bad.cmdError());
	CHECK((h.info().h.ecm_status & ECMXF_STS_CHECK_MASK) == ECMXF_CHECK_CRC8);
}

// ---------------------------------------------------------------------------
// INT0, ready, not ready
// ---------------------------------------------------------------------------

TEST_CASE("chip: INT0 shows busy for the processing time after each exchange", "[chip][spi][int]")
{
	sim::ChipConfig cfg;
	cfg.processingTime = std::chrono::microseconds(120);
	Rig rig(0, {}, cfg);
	sim::Chip &c = *rig.chip;
	rig.host.waitReady();
	CHECK(c.ready());
	CHECK(c.int0()); // active high = ready (ver. 050 default)
	const auto t0 = c.now();
	c.exchange(rig.host.encode(rig.host.fresh(Cmd(ECMXF_CMD_INFO_UPDATE_OP))));
	// the wire time of 144 bytes at 48 MHz has passed: 24 us
	CHECK(c.now() - t0 == std::chrono::microseconds(24));
	CHECK_FALSE(c.ready());
	CHECK_FALSE(c.int0());
	c.advance(std::chrono::microseconds(119));
	CHECK_FALSE(c.ready());
	c.advance(std::chrono::microseconds(1));
	CHECK(c.ready());
	CHECK(c.int0());
}

TEST_CASE("chip: an exchange while busy is taken in and counted", "[chip][spi][int]")
{
	Rig rig(0);
	Host &h = rig.host;
	h.waitReady();
	const auto busy0 = rig.chip->stats().busyExchanges;
	rig.chip->exchange(h.encode(h.fresh(Cmd(ECMXF_CMD_INFO_UPDATE_OP))));
	REQUIRE_FALSE(rig.chip->ready());
	// no wait: WKC_CONTI_ERR_MAX_SET 7 while the chip still processes
	const auto miso = rig.chip->exchange(h.encode(h.fresh(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET, 7))));
	CHECK(h.decode(miso).ok());
	CHECK(rig.chip->stats().busyExchanges == busy0 + 1);
	CHECK(rig.chip->stats().notReady == 0);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET)).h.ret == 7);
	CHECK(rig.chip->stats().busyExchanges == busy0 + 1); // the host waits again
}

TEST_CASE("chip: with notReadyWhileBusy an exchange while busy is answered 'not ready' and not taken in",
	  "[chip][spi][int]")
{
	sim::ChipConfig cfg;
	cfg.notReadyWhileBusy = true;
	Rig rig(0, {}, cfg);
	Host &h = rig.host;
	h.waitReady();
	rig.chip->exchange(h.encode(h.fresh(Cmd(ECMXF_CMD_INFO_UPDATE_OP))));
	REQUIRE_FALSE(rig.chip->ready());
	// no wait: WKC_CONTI_ERR_MAX_SET 7 while the chip still processes
	const auto miso = rig.chip->exchange(h.encode(h.fresh(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET, 7))));
	CHECK(h.decode(miso).fault == ECMXF_FAULT_NOT_READY);
	CHECK(rig.chip->stats().notReady == 1);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET)).h.ret == 255);
}

TEST_CASE("chip: ECAT_INT_SET_ENABLE parameter bit 1 sets the INT0 polarity, bit 0 the INT1 polarity",
	  "[chip][spi][int]")
{
	Rig rig(0);
	sim::Chip &c = *rig.chip;
	Host &h = rig.host;
	// defaults: INT0 active high (ready = high), INT1 active low (idle = high)
	h.waitReady();
	CHECK(c.int0());
	CHECK(c.int1());
	std::vector<std::uint8_t> en(6, 0);
	h.cmd(Cmd(ECMXF_CMD_ECAT_INT_SET_ENABLE, 0x00).payload(en));
	h.waitReady();
	CHECK_FALSE(c.int0()); // INT0 active low: ready = low
	CHECK(c.int1());
	h.cmd(Cmd(ECMXF_CMD_ECAT_INT_SET_ENABLE, 0x03).payload(en));
	h.waitReady();
	CHECK(c.int0());
	CHECK_FALSE(c.int1()); // INT1 active high: idle = low
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_INT_SET_ENABLE, 0x04).payload(en)).cmdError());
}

TEST_CASE("chip: ECAT_INT_GET_ENABLE returns the polarity and the six enable bytes", "[chip][spi][int]")
{
	Rig rig(0);
	Host &h = rig.host;
	Rsp g = h.cmd(Cmd(ECMXF_CMD_ECAT_INT_GET_ENABLE));
	CHECK(g.h.ret == 0x02); // power-on: INT0 active high, INT1 active low
	REQUIRE(g.h.len == 6);
	CHECK(g.u32() == 0);
	std::vector<std::uint8_t> en = le32v(ECMXF_INT_ECAT_PKT | ECMXF_INT_WKC_ERR);
	append(en, { 0x81, 0x12 });
	h.cmd(Cmd(ECMXF_CMD_ECAT_INT_SET_ENABLE, 0x01).payload(en));
	g = h.cmd(Cmd(ECMXF_CMD_ECAT_INT_GET_ENABLE));
	CHECK(g.h.ret == 0x01);
	CHECK(g.data == en);
}

TEST_CASE("chip: INT1 is asserted while IntFlag & IntEnable, and the interrupt clear resets flags",
	  "[chip][spi][int]")
{
	Rig rig(1);
	sim::Chip &c = *rig.chip;
	Host &h = rig.host;
	rig.init(1'000'000);
	rig.run(std::chrono::milliseconds(3));
	Rsp r = h.info();
	// a frame came back every cycle: bit 31
	CHECK(r.h.int_flags & ECMXF_INT_ECAT_PKT);
	// not enabled: INT1 stays inactive (high)
	CHECK(c.int1());
	h.cmd(Cmd(ECMXF_CMD_ECAT_INT_SET_ENABLE, 0x02).payload(le32v(ECMXF_INT_ECAT_PKT)).len(6));
	CHECK_FALSE(c.int1()); // asserted, active low
	// clear between two bus cycles: the flag is gone until the next cycle
	rig.run(std::chrono::microseconds(500)); // now mid-cycle
	h.waitReady();
	const auto t = c.now();
	r = h.send(Cmd(ECMXF_CMD_INFO_UPDATE_OP).intClear(ECMXF_INT_ECAT_PKT));
	REQUIRE(c.now() - t < std::chrono::microseconds(100));
	CHECK(c.int1());
	r = h.send(Cmd(ECMXF_CMD_INFO_UPDATE_OP));
	CHECK_FALSE(r.h.int_flags & ECMXF_INT_ECAT_PKT); // the answer prepared after the clear
	rig.run(std::chrono::milliseconds(1));
	CHECK_FALSE(c.int1()); // the next cycle set it again
}

// ---------------------------------------------------------------------------
// firmware version, reset
// ---------------------------------------------------------------------------

TEST_CASE("chip: FW_VERSION_GET returns the version and 20 data bytes", "[chip][spi]")
{
	sim::ChipConfig cfg;
	cfg.fwVersion = 0x41;
	cfg.fwVersionData = { 0, 7, 0, 2, 'b', 'u', 'i', 'l', 'd' };
	Rig rig(0, {}, cfg);
	const Rsp r = rig.host.cmd(Cmd(ECMXF_CMD_FW_VERSION_GET));
	CHECK(r.h.ret == 0x41);
	REQUIRE(r.h.len == 20);
	CHECK(r.data[1] == 7);
	CHECK(r.data[3] == 2);
	CHECK(r.data[4] == 'b');
	CHECK(r.data[19] == 0);

	Rig dflt(0);
	const Rsp d = dflt.host.cmd(Cmd(ECMXF_CMD_FW_VERSION_GET));
	CHECK(d.h.ret == sim::ChipConfig{}.fwVersion);
	CHECK(d.h.len == 20);
}

TEST_CASE("chip: WARM_RESET restores every power-on default and answers with a NOP", "[chip][spi]")
{
	Rig rig(2);
	Host &h = rig.host;
	rig.init();
	// change many things
	h.cmd(Cmd(ECMXF_CMD_FIFO_SET_TX_CNT, 10));
	h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET, 9));
	h.cmd(Cmd(ECMXF_CMD_ECAT_INT_SET_ENABLE, 0x01).payload(le32v(0xFFFFFFFF)).len(6));
	h.cmd(Cmd(14)); // command error bit
	h.send(Cmd(ECMXF_CMD_CRC_TYPE_SET, ECMXF_CHECK_CRC32));
	h.check = ECMXF_CHECK_CRC32;
	h.repeat();
	h.send(Cmd(ECMXF_CMD_SPI_RECONFIG_OP).len(400));
	h.dataSize = 400;
	h.repeat();
	REQUIRE(rig.chip->dataSize() == 400);

	const Rsp before = h.send(Cmd(ECMXF_CMD_WARM_RESET));
	REQUIRE(before.ok());
	CHECK(rig.chip->dataSize() == 112);
	h.dataSize = 112;
	h.check = ECMXF_CHECK_FIXED;
	// the chip boots: INT0 busy for a while
	CHECK_FALSE(rig.chip->ready());
	const Rsp nop = h.send(Cmd(ECMXF_CMD_INFO_UPDATE_OP));
	REQUIRE(nop.ok());
	CHECK(nop.nop());
	CHECK(nop.h.index == 0);
	CHECK(nop.h.code == 0);
	CHECK(nop.h.ecat_state == ECMXF_ECAT_NONE);
	CHECK((nop.h.err_status & 0xF8) == 0);
	CHECK((nop.h.ecm_status & ECMXF_STS_CHECK_MASK) == ECMXF_CHECK_FIXED);
	CHECK_FALSE(nop.h.ecm_status & ECMXF_STS_ETH_INIT);
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_GET_TX_CNT)).h.ret == 64);
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_GET_RX_CNT)).h.ret == 64);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET)).h.ret == 255);
	const Rsp ie = h.cmd(Cmd(ECMXF_CMD_ECAT_INT_GET_ENABLE));
	CHECK(ie.h.ret == 0x02);
	CHECK(ie.u32() == 0);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET)).h.ret == 0);
	CHECK(h.cmd(Cmd(ECMXF_CMD_SPI_PACK_SIZE_GET)).u16() == 112);
	// the slaves keep their state: WARM_RESET resets the chip only
	CHECK(rig.s(0).state == ECMXF_ECAT_INIT);
}

// ---------------------------------------------------------------------------
// async commands
// ---------------------------------------------------------------------------

TEST_CASE("chip: an async command is answered at once with busy, which clears when it is done",
	  "[chip][spi][async]")
{
	SlaveConfig sc;
	sc.transitionTime = std::chrono::milliseconds(30);
	Rig rig(2, sc);
	rig.init();
	Host &h = rig.host;
	const auto t0 = rig.chip->now();
	const Rsp a = h.cmd(stateSet(0xFF, ECMXF_ECAT_PREOP));
	CHECK(a.h.code == ECMXF_CMD_ECAT_STATE_SET);
	CHECK(a.h.ret == 0);
	CHECK(a.busy());
	const Rsp done = h.waitIdle(std::chrono::microseconds(500));
	CHECK_FALSE(done.asyncError());
	CHECK(rig.chip->now() - t0 >= std::chrono::milliseconds(30));
	CHECK(rig.chip->now() - t0 < std::chrono::milliseconds(35));
	CHECK(done.h.ecat_state == ECMXF_ECAT_PREOP);
}

TEST_CASE("chip: a second async command while busy is refused with the command error bit",
	  "[chip][spi][async]")
{
	SlaveConfig sc;
	sc.transitionTime = std::chrono::milliseconds(50);
	Rig rig(1, sc);
	rig.init();
	Host &h = rig.host;
	REQUIRE(h.cmd(stateSet(0xFF, ECMXF_ECAT_PREOP)).busy());
	const Rsp second = h.cmd(Cmd(ECMXF_CMD_ECAT_STATE_UPDATE));
	CHECK(second.h.index == h.index);
	CHECK(second.h.code == ECMXF_CMD_ECAT_STATE_UPDATE);
	CHECK(second.h.ret == 0);
	CHECK(second.cmdError());
	CHECK(second.busy()); // the first one still runs
	// immediate commands run meanwhile
	const Rsp imm = h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET));
	CHECK(imm.h.ret == 1);
	CHECK(imm.busy());
	const Rsp done = h.waitIdle();
	CHECK_FALSE(done.asyncError());
	CHECK(rig.s(0).state == ECMXF_ECAT_PREOP);
}

TEST_CASE("chip: an async command that fails sets error bit 3 when busy clears", "[chip][spi][async]")
{
	SlaveConfig sc;
	sc.transitionTime = std::chrono::milliseconds(5);
	Rig rig(1, sc);
	rig.init();
	rig.state(ECMXF_ECAT_PREOP);
	rig.s(0).refuse[ECMXF_ECAT_SAFEOP] = sim::alcode::InvalidOutputConfig;
	const Rsp a = rig.host.cmd(stateSet(0xFF, ECMXF_ECAT_SAFEOP));
	CHECK(a.busy());
	CHECK_FALSE(a.asyncError());
	const Rsp done = rig.host.waitIdle();
	CHECK(done.asyncError());
	CHECK(done.h.ecat_state == ECMXF_ECAT_ERROR);
}

TEST_CASE("chip: ASYNCCMD_RESET clears a busy flag or abandons the async command", "[chip][spi][async]")
{
	SlaveConfig sc;
	sc.transitionTime = std::chrono::seconds(2);
	Rig rig(1, sc);
	rig.init();
	Host &h = rig.host;
	for (unsigned p : { 1u, 4u }) {
		INFO("parameter " << int(p));
		REQUIRE(h.cmd(stateSet(0xFF, rig.s(0).state == 1 ? 2 : 1)).busy());
		const Rsp r = h.cmd(Cmd(ECMXF_CMD_ASYNCCMD_RESET, static_cast<std::uint8_t>(p)));
		CHECK_FALSE(r.cmdError());
		CHECK_FALSE(r.busy());
		CHECK_FALSE(r.asyncError());
		rig.run(std::chrono::seconds(3));
	}
	CHECK(h.cmd(Cmd(ECMXF_CMD_ASYNCCMD_RESET, 0)).cmdError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_ASYNCCMD_RESET, 8).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}

// ---------------------------------------------------------------------------
// time, construction
// ---------------------------------------------------------------------------

TEST_CASE("chip: virtual time moves only by advance() and the wire time of exchanges", "[chip][time]")
{
	sim::ChipConfig cfg;
	cfg.spiClockHz = 8'000'000; // 144 bytes = 144 us on the wire
	sim::Chip chip(sim::Network{}, cfg);
	CHECK(chip.now() == std::chrono::nanoseconds(0));
	chip.advance(std::chrono::milliseconds(3));
	CHECK(chip.now() == std::chrono::milliseconds(3));
	Host h(chip);
	chip.exchange(h.encode(h.fresh(Cmd(ECMXF_CMD_INFO_UPDATE_OP))));
	CHECK(chip.now() == std::chrono::milliseconds(3) + std::chrono::microseconds(144));
	chip.advance(std::chrono::nanoseconds(-5)); // ignored
	CHECK(chip.now() == std::chrono::milliseconds(3) + std::chrono::microseconds(144));
}

TEST_CASE("chip: in paced mode time follows the monotonic clock and the bus cycles with it", "[chip][time]")
{
	sim::ChipConfig cfg;
	cfg.timeMode = sim::TimeMode::Paced;
	sim::Network net;
	net.add(std::make_unique<TestSlave>());
	sim::Chip chip(std::move(net), cfg);
	Host h(chip);
	h.paced = true;
	h.sync();
	const Rsp r = h.async(initOp(1'000'000));
	CHECK_FALSE(r.asyncError());
	const auto &s = dynamic_cast<const TestSlave &>(chip.network().at(0));
	const auto t0 = chip.now();
	const auto c0 = s.cycles;
	chip.advance(std::chrono::seconds(10)); // no effect in paced mode
	CHECK(chip.now() - t0 < std::chrono::seconds(1));
	std::this_thread::sleep_for(std::chrono::milliseconds(30));
	const auto dt = chip.now() - t0;
	CHECK(dt >= std::chrono::milliseconds(30));
	const auto cycles = static_cast<long>(s.cycles - c0);
	const long expect = static_cast<long>(dt / std::chrono::milliseconds(1));
	CHECK(cycles >= expect - 1);
	CHECK(cycles <= expect + 1);
}

TEST_CASE("chip: a chip built from a network file, a bad file is an exception naming it", "[chip][time]")
{
	const std::string path = "/tmp/ecmxf-chip-test-" + std::to_string(::getpid()) + ".net";
	{
		std::ofstream f(path);
		f << "# two digital I/O slaves\nname chip test\nslave dio\nslave dio\n";
	}
	{
		sim::Chip chip(path);
		CHECK(chip.network().size() == 2);
		CHECK(chip.network().name() == "chip test");
	}
	std::remove(path.c_str());
	try {
		sim::Chip chip(path);
		FAIL("no exception for a missing file");
	} catch (const std::exception &e) {
		CHECK(std::string(e.what()).find(path) != std::string::npos);
	}
	sim::ChipConfig bad;
	bad.spiClockHz = 0;
	CHECK_THROWS_AS(sim::Chip(sim::Network{}, bad), std::invalid_argument);
}
