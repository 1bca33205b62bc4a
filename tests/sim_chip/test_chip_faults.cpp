// SPDX-License-Identifier: MIT
// Fault injection of the simulated chip (FaultPlan) and what the host sees:
// MOSI and MISO bit errors, "not ready", INT0 stuck busy, link loss, one
// slave dropping out and coming back, a forced SDO abort, a stuck async
// command.

#include <catch2/catch.hpp>

#include "host.hpp"

using namespace simtest;
namespace sim = ecmxf::sim;
using namespace std::chrono_literals;

TEST_CASE("chip faults: MOSI bit errors make the chip see corrupted packets", "[chip][faults]")
{
	Rig rig(1);
	Host &h = rig.host;
	rig.chip->faults().mosiBitErrors = 2;
	h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET, 5)); // both copies corrupted
	CHECK(rig.chip->faults().mosiBitErrors == 0);
	Rsp r = h.info();
	CHECK(r.h.crc_err_cnt == 2);
	CHECK(r.h.err_status & ECMXF_ERR_SPI_CRC);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET)).h.ret == 255);
	// the host re-sends: now it runs
	h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET, 5));
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET)).h.ret == 5);
}

TEST_CASE("chip faults: MISO bit errors make the host see a bad check word", "[chip][faults]")
{
	Rig rig(1);
	Host &h = rig.host;
	rig.chip->faults().misoBitErrors = 1;
	const Rsp bad = h.send(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET, 6));
	CHECK(bad.fault == ECMXF_FAULT_CHECK);
	// the chip got the command all the same
	const Rsp ans = h.repeat();
	REQUIRE(ans.ok());
	CHECK(ans.h.code == ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET);
	CHECK(ans.h.crc_err_cnt == 0);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET)).h.ret == 6);
	// a lost answer: the repeat is answered as INFO_UPDATE with our index
	h.send(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET));
	rig.chip->faults().misoBitErrors = 1;
	CHECK(h.repeat().fault == ECMXF_FAULT_CHECK);
	const Rsp again = h.repeat();
	CHECK(again.h.index == h.last.h.index);
	CHECK(again.h.code == ECMXF_CMD_INFO_UPDATE_OP);
}

TEST_CASE("chip faults: 'not ready' answers carry 0x87654321 and the packet is not taken in",
	  "[chip][faults]")
{
	Rig rig(1);
	Host &h = rig.host;
	rig.chip->faults().notReady = 2;
	CHECK(h.send(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET, 7)).fault == ECMXF_FAULT_NOT_READY);
	CHECK(h.repeat().fault == ECMXF_FAULT_NOT_READY);
	// the third copy is the first the chip takes in: it runs, and is
	// answered by the next exchange
	const Rsp prev = h.repeat();
	REQUIRE(prev.ok());
	CHECK(prev.h.code != ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET);
	CHECK(h.repeat().h.code == ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_SET);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_MAX_GET)).h.ret == 7);
	CHECK(rig.chip->stats().notReady == 2);
	CHECK(h.info().h.crc_err_cnt == 0);
}

TEST_CASE("chip faults: INT0 stuck busy never signals ready, the chip still works", "[chip][faults]")
{
	Rig rig(1);
	sim::Chip &c = *rig.chip;
	Host &h = rig.host;
	c.faults().int0StuckBusy = true;
	c.advance(10ms);
	CHECK_FALSE(c.ready());
	CHECK_FALSE(c.int0()); // active high: stuck low
	// a host that falls back to waiting 150 us gets its answers
	c.exchange(h.encode(h.fresh(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET))));
	h.last = Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET);
	h.last.h.index = h.index;
	c.advance(150us);
	const Rsp r = h.decode(c.exchange(h.encode(h.last)));
	REQUIRE(r.ok());
	CHECK(r.h.code == ECMXF_CMD_ECAT_SLV_CNT_GET);
	CHECK(r.h.ret == 0); // no INIT_OP yet
	c.faults().int0StuckBusy = false;
	c.advance(150us);
	CHECK(c.ready());
	CHECK(c.int0());
}

TEST_CASE("chip faults: link loss in OP gives WKC errors, ECAT state ERROR and clear link bits",
	  "[chip][faults]")
{
	Rig rig(2);
	rig.toOp();
	Host &h = rig.host;
	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
	rig.run(3ms);
	Rsp r = h.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).intClear(0xFFFFFFFF));
	CHECK((r.h.err_status & 0x03) == 0x03);
	CHECK(r.h.ecat_state == ECMXF_ECAT_OP);

	rig.chip->faults().linkLost = true;
	h.cmd(Cmd(ECMXF_CMD_FIFO_CLR_OP, 1).intClear(0xFFFFFFFF));
	const auto cycles = rig.s(0).cycles;
	rig.run(5ms);
	r = h.info();
	CHECK(r.h.ecat_state == ECMXF_ECAT_ERROR);
	CHECK((r.h.err_status & 0x03) == 0);
	CHECK(r.h.wkc_err_cnt >= 5);
	CHECK(r.h.int_flags & ECMXF_INT_WKC_ERR);
	CHECK_FALSE(r.h.int_flags & ECMXF_INT_ECAT_PKT); // no frame came back
	CHECK(r.h.tx_fifo_cnt == 0);			   // so no inputs either
	CHECK(rig.s(0).cycles == cycles);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_WC_GET, 3)).u32() == 0);
	// mailbox traffic fails too
	CHECK(h.async(sdoReq(1, 0, 0x2000, 0, {}, 0, 5000)).asyncError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET)).u32() == sim::abort::Timeout);
	CHECK(h.async(Cmd(ECMXF_CMD_ECAT_STATE_UPDATE)).h.ecat_state == ECMXF_ECAT_ERROR);

	// the link returns: bit 0 at once, bit 1 with the next INIT_OP
	rig.chip->faults().linkLost = false;
	rig.run(3ms);
	r = h.info();
	CHECK((r.h.err_status & 0x03) == ECMXF_ERR_LINK_HW);
	CHECK(r.h.int_flags & ECMXF_INT_ECAT_PKT);
	// the master's view is refreshed on request
	CHECK(h.async(Cmd(ECMXF_CMD_ECAT_STATE_UPDATE)).h.ecat_state == ECMXF_ECAT_OP);
	const auto errs = h.info().h.wkc_err_cnt;
	rig.run(3ms);
	CHECK(h.info().h.wkc_err_cnt == errs);
	rig.init();
	CHECK((h.info().h.err_status & 0x03) == 0x03);
}

TEST_CASE("chip faults: a slave that drops out and comes back", "[chip][faults]")
{
	Rig rig(3);
	rig.toOp();
	Host &h = rig.host;
	rig.chip->faults().slaveDropped = 1;
	rig.run(5ms);
	Rsp r = h.info();
	CHECK(r.h.ecat_state == ECMXF_ECAT_ERROR);
	CHECK(r.h.wkc_err_cnt >= 4);
	CHECK((r.h.err_status & 0x03) == 0x03); // the link is fine
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_WC_GET, 3)).u32() == 2 * 3);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_STATE_GET, 1)).h.ret == ECMXF_ECAT_ERROR);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_STATE_GET, 0)).h.ret == ECMXF_ECAT_OP);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, 1).d(6)).cmdError());
	// SDO to it times out; to the others it works
	CHECK(h.async(sdoReq(1, 1, 0x2000, 0, {}, 0, 20'000)).asyncError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET)).u32() == sim::abort::Timeout);
	CHECK_FALSE(h.async(sdoReq(1, 2, 0x2000, 0)).asyncError());
	// the slave got no frames meanwhile
	CHECK(rig.s(1).idleTime > 5ms);

	rig.chip->faults().slaveDropped = -1;
	rig.run(3ms);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_WKC_CONTI_ERR_CNT_GET)).h.ret == 0);
	CHECK(h.info().h.ecat_state == ECMXF_ECAT_ERROR); // until refreshed
	CHECK(h.async(Cmd(ECMXF_CMD_ECAT_STATE_UPDATE)).h.ecat_state == ECMXF_ECAT_OP);

	// a scan while a slave is missing finds the slaves before it
	rig.chip->faults().slaveDropped = 2;
	rig.init();
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET)).h.ret == 2);
}

TEST_CASE("chip faults: a forced SDO abort fails the next SDO with that code", "[chip][faults]")
{
	Rig rig(1);
	rig.init();
	rig.state(ECMXF_ECAT_PREOP);
	Host &h = rig.host;
	rig.chip->faults().forcedSdoAbort = sim::abort::ValueRange;
	CHECK(h.async(sdoReq(0, 0, 0x2000, 0, { 1, 2, 3, 4 })).asyncError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SDO_ABORTCODE_GET)).u32() == sim::abort::ValueRange);
	CHECK(rig.chip->faults().forcedSdoAbort == 0);
	CHECK(rig.s(0).downloads.empty());
	CHECK_FALSE(h.async(sdoReq(0, 0, 0x2000, 0, { 1, 2, 3, 4 })).asyncError());
	CHECK(rig.s(0).downloads.size() == 1);
}

TEST_CASE("chip faults: a stuck async command stays busy until ASYNCCMD_RESET", "[chip][faults]")
{
	Rig rig(1);
	rig.init();
	Host &h = rig.host;
	rig.chip->faults().asyncStuckBusy = true;
	REQUIRE(h.cmd(stateSet(0xFF, ECMXF_ECAT_PREOP)).busy());
	CHECK_FALSE(rig.chip->faults().asyncStuckBusy); // "the next async command"
	rig.run(30s);
	const Rsp r = h.info();
	CHECK(r.busy());
	CHECK_FALSE(r.asyncError());
	CHECK(rig.s(0).state == ECMXF_ECAT_INIT);
	// other async commands are refused meanwhile
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_STATE_UPDATE)).cmdError());
	const Rsp cleared = h.cmd(Cmd(ECMXF_CMD_ASYNCCMD_RESET, 1));
	CHECK_FALSE(cleared.busy());
	CHECK_FALSE(rig.host.async(stateSet(0xFF, ECMXF_ECAT_PREOP)).asyncError());
	CHECK(rig.s(0).state == ECMXF_ECAT_PREOP);
}
