// SPDX-License-Identifier: MIT
// The EtherCAT master inside the simulated chip: INIT_OP (scan, station
// addresses, SII, DC, bus cycle), the AL states (STATE_SET/GET/CHECK/
// UPDATE), slave information, the process image layout (RECONFIG_OP,
// CONFIG_MAP, DIRECT_ASSIGN), DC commands, sync manager configuration.

#include <catch2/catch.hpp>

#include "host.hpp"

using namespace simtest;
namespace sim = ecmxf::sim;
using namespace std::chrono_literals;

// ---------------------------------------------------------------------------
// ECAT_INIT_OP
// ---------------------------------------------------------------------------

TEST_CASE("chip: INIT_OP without the fixed bytes 0xFF 0x81 is a command error", "[chip][master]")
{
	Rig rig(1);
	Cmd c = initOp();
	c.data[1] = 0x80;
	const Rsp r = rig.host.cmd(c);
	CHECK(r.cmdError());
	CHECK_FALSE(r.busy());
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET)).h.ret == 0);
}

TEST_CASE("chip: INIT_OP scans the network, assigns station addresses and leaves the slaves in INIT",
	  "[chip][master]")
{
	SlaveConfig dc;
	dc.dcAssign = 0x0300;
	SlaveList l;
	l.push_back(std::make_unique<TestSlave>(dc));
	l.push_back(std::make_unique<TestSlave>());
	l.push_back(std::make_unique<TestSlave>(dc));
	Rig rig(std::move(l));
	// slaves left in PRE-OP with an error by an earlier master
	rig.s(1).state = ECMXF_ECAT_PREOP;
	rig.s(1).error = true;
	rig.s(1).code = sim::alcode::InvalidStateChange;

	const Rsp a = rig.host.cmd(initOp(500'000, 0x0300, 0, -20'000));
	CHECK(a.busy());
	CHECK(a.h.ecat_state == ECMXF_ECAT_NONE);
	const Rsp r = rig.host.waitIdle();
	CHECK_FALSE(r.asyncError());
	CHECK(r.h.ecat_state == ECMXF_ECAT_INIT);
	CHECK((r.h.err_status & 0x03) == 0x03);	// link (hw) and link at init (sw)
	CHECK(r.h.ecm_status & ECMXF_STS_ETH_INIT);
	CHECK(r.h.ecm_status & ECMXF_STS_PDO_CONFIGURED);
	CHECK_FALSE(r.h.ecm_status & ECMXF_STS_FIFO_EN); // 0x81: FIFO off
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SLV_CNT_GET)).h.ret == 3);
	for (std::size_t i = 0; i < 3; i++) {
		INFO("slave " << i);
		TestSlave &s = rig.s(i);
		CHECK(s.state == ECMXF_ECAT_INIT);
		CHECK_FALSE(s.error);
		const auto station = static_cast<unsigned>(s.regs[0x10] | (s.regs[0x11] << 8));
		CHECK(station == 0x1001 + i);
		REQUIRE(s.dcConfigured);
		CHECK(s.dcSync0 == 500'000);
		CHECK(s.dcShift == -20'000);
	}
	// the error was acknowledged: AL control INIT with bit 4
	CHECK(rig.s(1).alWrites.back() == 0x11);
	CHECK(rig.s(0).alWrites.back() == 0x01);
	// DC only where the slave uses it
	CHECK(rig.s(0).dcAssign == 0x0300);
	CHECK(rig.s(1).dcAssign == 0);
	// the mailbox sync managers from the SII: SM0 at 0x1000, 128 bytes
	CHECK(rig.s(0).regs[0x800] == 0x00);
	CHECK(rig.s(0).regs[0x801] == 0x10);
	CHECK(rig.s(0).regs[0x802] == 128);
	CHECK(rig.s(0).regs[0x804] == 0x26);
}

TEST_CASE("chip: the bus cycle runs at the SYNC0 cycle time, at least 125 us, 1 ms without DC",
	  "[chip][master]")
{
	for (auto [sync0, cycle] : { std::pair<std::uint32_t, long>{ 500'000, 500'000 },
				     { 250'000, 250'000 }, { 100'000, 125'000 }, { 0, 1'000'000 } }) {
		INFO("SYNC0 " << sync0);
		Rig rig(2);
		// before INIT_OP: no bus cycles, only idle time
		rig.run(10ms);
		CHECK(rig.s(0).cycles == 0);
		CHECK(rig.s(0).idleTime >= 10ms);
		rig.init(sync0);
		const auto c0 = rig.s(0).cycles;
		rig.run(std::chrono::nanoseconds(cycle * 40));
		CHECK(rig.s(0).cycles - c0 == 40);
		CHECK(rig.s(0).lastDt == std::chrono::nanoseconds(cycle));
		CHECK(rig.s(1).cycles - c0 == 40);
	}
}

TEST_CASE("chip: DC stable (ECM status bit 2) follows a DC configuration with SYNC0", "[chip][master]")
{
	SlaveConfig dc;
	dc.dcAssign = 0x0300;
	Rig rig(2, dc);
	rig.init(1'000'000, 0x0300);
	CHECK_FALSE(rig.host.info().h.ecm_status & ECMXF_STS_DC_STABLE);
	rig.run(150ms);
	CHECK(rig.host.info().h.ecm_status & ECMXF_STS_DC_STABLE);
	CHECK(rig.s(0).sync0Cycles > 100);

	Rig free(2, dc);
	free.init(1'000'000, 0); // AssignActivate 0: no SYNC0
	free.run(150ms);
	CHECK_FALSE(free.host.info().h.ecm_status & ECMXF_STS_DC_STABLE);
	CHECK(free.s(0).sync0Cycles == 0);
}

TEST_CASE("chip: INIT_OP with the link down waits for it, then fails, ASYNCCMD_RESET 2 ends the wait",
	  "[chip][master]")
{
	Rig rig(2);
	rig.chip->faults().linkLost = true;
	const Rsp a = rig.host.cmd(initOp());
	CHECK(a.busy());
	CHECK_FALSE(a.h.err_status & ECMXF_ERR_LINK_HW);
	rig.run(1s);
	CHECK(rig.host.info().busy());
	const Rsp r = rig.host.waitIdle(10ms);
	CHECK(r.asyncError());
	CHECK(r.h.ecat_state == ECMXF_ECAT_NONE);
	CHECK(rig.chip->now() > 3s);

	rig.host.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).control(ECMXF_CTL_CLR_ASYNC_ERR));
	REQUIRE(rig.host.cmd(initOp()).busy());
	const auto t0 = rig.chip->now();
	rig.host.cmd(Cmd(ECMXF_CMD_ASYNCCMD_RESET, 2));
	const Rsp s = rig.host.waitIdle();
	CHECK(s.asyncError());
	CHECK(rig.chip->now() - t0 < 100ms);
}

// ---------------------------------------------------------------------------
// AL states
// ---------------------------------------------------------------------------

TEST_CASE("chip: STATE_SET 0xFF moves every slave, STATE_GET reports the common and per-slave state",
	  "[chip][master]")
{
	Rig rig(3);
	rig.init();
	Rsp r = rig.state(ECMXF_ECAT_PREOP);
	CHECK(r.h.ecat_state == ECMXF_ECAT_PREOP);
	for (std::size_t i = 0; i < 3; i++)
		CHECK(rig.s(i).state == ECMXF_ECAT_PREOP);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_STATE_GET, 0xFF)).h.ret == ECMXF_ECAT_PREOP);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_STATE_GET, 1)).h.ret == ECMXF_ECAT_PREOP);
	rig.state(ECMXF_ECAT_SAFEOP);
	r = rig.state(ECMXF_ECAT_OP);
	CHECK(r.h.ecat_state == ECMXF_ECAT_OP);
	r = rig.state(ECMXF_ECAT_INIT);
	CHECK(r.h.ecat_state == ECMXF_ECAT_INIT);
	CHECK(rig.s(2).state == ECMXF_ECAT_INIT);
}

TEST_CASE("chip: STATE_SET for one slave, the header shows the lowest state", "[chip][master]")
{
	Rig rig(3);
	rig.init();
	rig.state(ECMXF_ECAT_PREOP);
	const Rsp r = rig.host.async(stateSet(1, ECMXF_ECAT_SAFEOP));
	CHECK_FALSE(r.asyncError());
	CHECK(rig.s(0).state == ECMXF_ECAT_PREOP);
	CHECK(rig.s(1).state == ECMXF_ECAT_SAFEOP);
	CHECK(rig.s(2).state == ECMXF_ECAT_PREOP);
	CHECK(r.h.ecat_state == ECMXF_ECAT_PREOP);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_STATE_GET, 1)).h.ret == ECMXF_ECAT_SAFEOP);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_STATE_GET, 0)).h.ret == ECMXF_ECAT_PREOP);
}

TEST_CASE("chip: an invalid state change fails with the async error and the slave's AL status code",
	  "[chip][master]")
{
	Rig rig(2);
	rig.init();
	const Rsp r = rig.host.async(stateSet(0xFF, ECMXF_ECAT_OP)); // INIT -> OP
	CHECK(r.asyncError());
	CHECK(r.h.ecat_state == ECMXF_ECAT_ERROR);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_STATE_GET, 0)).h.ret == (ECMXF_ECAT_INIT | 0x10));
	const Rsp code = rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, 0).d(7));
	CHECK(code.u16() == sim::alcode::InvalidStateChange);
	// the next request acknowledges the error (AL control bit 4)
	rig.host.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).control(ECMXF_CTL_CLR_ASYNC_ERR));
	const Rsp ok = rig.host.async(stateSet(0xFF, ECMXF_ECAT_PREOP));
	CHECK_FALSE(ok.asyncError());
	CHECK(rig.s(0).alWrites.back() == (ECMXF_ECAT_PREOP | 0x10));
	CHECK(ok.h.ecat_state == ECMXF_ECAT_PREOP);
}

TEST_CASE("chip: STATE_SET with a bad state, a bad slave or before INIT_OP is a command error",
	  "[chip][master]")
{
	Rig rig(2);
	CHECK(rig.host.cmd(stateSet(0xFF, ECMXF_ECAT_PREOP)).cmdError());
	rig.init();
	for (unsigned bad : { 0u, 5u, 6u, 7u, 9u, 0x10u }) {
		const Rsp r = rig.host.cmd(stateSet(0xFF, static_cast<std::uint8_t>(bad)).control(ECMXF_CTL_CLR_CMD_ERR));
		CHECK(r.cmdError());
		CHECK_FALSE(r.busy());
	}
	CHECK(rig.host.cmd(stateSet(2, ECMXF_ECAT_PREOP).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_STATE_GET, 2).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}

TEST_CASE("chip: the master's view of the states is refreshed by STATE_UPDATE or control bit 0",
	  "[chip][master]")
{
	Rig rig(2);
	rig.init();
	rig.state(ECMXF_ECAT_PREOP);
	// a slave changes state behind the master's back
	rig.s(0).state = ECMXF_ECAT_INIT;
	CHECK(rig.host.info().h.ecat_state == ECMXF_ECAT_PREOP);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_STATE_GET, 0xFF)).h.ret == ECMXF_ECAT_PREOP);
	const Rsp u = rig.host.async(Cmd(ECMXF_CMD_ECAT_STATE_UPDATE));
	CHECK(u.h.ecat_state == ECMXF_ECAT_INIT);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_STATE_GET, 0)).h.ret == ECMXF_ECAT_INIT);
	rig.s(0).state = ECMXF_ECAT_PREOP;
	const Rsp c = rig.host.cmd(Cmd(ECMXF_CMD_INFO_UPDATE_OP).control(ECMXF_CTL_REFRESH_STATE));
	CHECK(c.h.ecat_state == ECMXF_ECAT_PREOP);
}

TEST_CASE("chip: ECAT_STATE_CHECK sets the state and refreshes the master's view", "[chip][master]")
{
	Rig rig(2);
	rig.init();
	const Rsp a = rig.host.cmd(Cmd(ECMXF_CMD_ECAT_STATE_CHECK, 0xFF).d(ECMXF_ECAT_PREOP));
	CHECK(a.busy());
	const Rsp r = rig.host.waitIdle();
	CHECK_FALSE(r.asyncError());
	CHECK(r.h.ecat_state == ECMXF_ECAT_PREOP);
	CHECK(rig.s(1).state == ECMXF_ECAT_PREOP);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_STATE_GET, 0xFF)).h.ret == ECMXF_ECAT_PREOP);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_STATE_CHECK, 0xFF).d(5)).cmdError());
}

// ---------------------------------------------------------------------------
// slave information, WKC counts
// ---------------------------------------------------------------------------

TEST_CASE("chip: SLV_INFO_GET returns the slave information items 0..9", "[chip][master]")
{
	SlaveConfig sc;
	sc.vendor = 0x00000A09;
	sc.product = 0x00584001;
	sc.revision = 0x00020003;
	sc.alias = 0x0042;
	sc.name = "EST-584 like";
	sc.outBytes = 10;
	sc.inBytes = 14;
	Rig rig(2, sc);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, 0).d(0)).cmdError());
	rig.init();
	rig.state(ECMXF_ECAT_PREOP);
	Host &h = rig.host;
	auto info = [&](std::uint8_t code) { return h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, 1).d(code)); };
	CHECK(info(0).u32() == 0x00000A09);
	CHECK(info(1).u32() == 0x00584001);
	CHECK(info(2).u32() == 0x00020003);
	const Rsp name = info(3);
	CHECK(std::string(name.data.begin(), name.data.end()) == "EST-584 like");
	CHECK(info(4).u16() == 0x1002);
	CHECK(info(5).u16() == 0x0042);
	const Rsp st = info(6);
	REQUIRE(st.h.len == 1);
	CHECK(st.data[0] == ECMXF_ECAT_PREOP);
	CHECK(info(7).u16() == 0);
	CHECK(info(8).u16() == 10);
	CHECK(info(9).u16() == 14);
	CHECK_FALSE(info(10).cmdError()); // DC codes 10..13: test_chip_variants.cpp
	CHECK(info(14).cmdError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, 2).d(0).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}

TEST_CASE("chip: PDO_WC_GET counts input and output slaves and reports the working counter",
	  "[chip][master]")
{
	SlaveConfig inOnly;
	inOnly.outBytes = 0;
	inOnly.inBytes = 3;
	SlaveConfig none;
	none.outBytes = 0;
	none.inBytes = 0;
	SlaveList l;
	l.push_back(std::make_unique<TestSlave>());
	l.push_back(std::make_unique<TestSlave>(inOnly));
	l.push_back(std::make_unique<TestSlave>());
	l.push_back(std::make_unique<TestSlave>(none));
	Rig rig(std::move(l));
	rig.toOp();
	Host &h = rig.host;
	const Rsp in = h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_WC_GET, 1));
	REQUIRE(in.h.len == 4);
	CHECK(in.u32() == 3);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_WC_GET, 2)).u32() == 2);
	rig.run(3ms);
	// expected = inputs * 1 + outputs * 2
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_WC_GET, 3)).u32() == 3 * 1 + 2 * 2);
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_WC_GET, 0)).cmdError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_PDO_WC_GET, 4).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}

// ---------------------------------------------------------------------------
// layout: RECONFIG_OP, CONFIG_MAP, DIRECT_ASSIGN
// ---------------------------------------------------------------------------

TEST_CASE("chip: RECONFIG_OP re-reads the PDO sizes and sets the header's ECAT state to 1",
	  "[chip][master]")
{
	Rig rig(2);
	rig.init();
	rig.state(ECMXF_ECAT_PREOP);
	Host &h = rig.host;
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0)).u16() == 4);
	rig.s(1).cfg.outBytes = 8;
	rig.s(1).cfg.inBytes = 6;
	// not before the layout is rebuilt
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0)).u16() == 4);
	const Rsp r = h.async(Cmd(ECMXF_CMD_ECAT_RECONFIG_OP));
	CHECK_FALSE(r.asyncError());
	CHECK(r.h.ecat_state == ECMXF_ECAT_INIT); // ver. 050: "cleared to 1"
	CHECK(rig.s(0).state == ECMXF_ECAT_PREOP); // the slaves stay where they are
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0)).u16() == 2 + 8);
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 1)).u16() == 2 + 6);
	CHECK(h.async(Cmd(ECMXF_CMD_ECAT_STATE_UPDATE)).h.ecat_state == ECMXF_ECAT_PREOP);
	// the process data sync managers follow the new sizes (SM2 length)
	CHECK(rig.s(1).regs[0x0800 + 2 * 8 + 2] == 8);
}

TEST_CASE("chip: CONFIG_MAP rebuilds the layout and keeps the ECAT state", "[chip][master]")
{
	Rig rig(2);
	rig.init();
	rig.state(ECMXF_ECAT_PREOP);
	rig.s(0).cfg.inBytes = 9;
	const Rsp r = rig.host.async(Cmd(ECMXF_CMD_ECAT_CONFIG_MAP));
	CHECK_FALSE(r.asyncError());
	CHECK(r.h.ecat_state == ECMXF_ECAT_PREOP);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 1)).u16() == 9 + 2);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_SLV_INFO_GET, 0).d(9)).u16() == 9);
}

TEST_CASE("chip: DIRECT_ASSIGN sets process data lengths by hand, from the next layout on",
	  "[chip][master]")
{
	Rig rig(2);
	rig.init();
	Host &h = rig.host;
	REQUIRE_FALSE(h.cmd(Cmd(ECMXF_CMD_DIRECT_ASSIGN, 1).d(1, 0, 12, 0)).cmdError()); // outputs 12
	REQUIRE_FALSE(h.cmd(Cmd(ECMXF_CMD_DIRECT_ASSIGN, 1).d(1, 1, 0, 1)).cmdError());  // inputs 256
	REQUIRE_FALSE(h.cmd(Cmd(ECMXF_CMD_DIRECT_ASSIGN, 0).d(1, 1)).cmdError());	 // enable
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0)).u16() == 4);
	h.async(Cmd(ECMXF_CMD_ECAT_CONFIG_MAP));
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0)).u16() == 2 + 12);
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 1)).u16() == 2 + 256);
	h.cmd(Cmd(ECMXF_CMD_DIRECT_ASSIGN, 0).d(1, 0));
	h.async(Cmd(ECMXF_CMD_ECAT_CONFIG_MAP));
	CHECK(h.cmd(Cmd(ECMXF_CMD_FIFO_PACK_SIZE_GET, 0)).u16() == 4);
	CHECK(h.cmd(Cmd(ECMXF_CMD_DIRECT_ASSIGN, 2).d(1, 0)).cmdError());
	CHECK(h.cmd(Cmd(ECMXF_CMD_DIRECT_ASSIGN, 0).d(2, 1).control(ECMXF_CTL_CLR_CMD_ERR)).cmdError());
}

// ---------------------------------------------------------------------------
// DC, sync managers, FMMU, LRW
// ---------------------------------------------------------------------------

TEST_CASE("chip: ECAT_DCSYNC stores one slave's DC setting, ECAT_INIT_DC_OP applies it", "[chip][master]")
{
	SlaveConfig dc;
	dc.dcAssign = 0x0300;
	Rig rig(2, dc);
	rig.init(1'000'000, 0x0300);
	std::vector<std::uint8_t> d{ 1, 0 };
	append16(d, 0x0700);
	append32(d, 2'000'000);
	append32(d, 500'000);
	append32(d, 12'345);
	Host &h = rig.host;
	const Rsp a = h.async(Cmd(ECMXF_CMD_ECAT_DCSYNC).payload(d));
	CHECK_FALSE(a.asyncError());
	CHECK(rig.s(1).dcSync0 == 1'000'000); // not yet applied
	const Rsp b = h.async(Cmd(ECMXF_CMD_ECAT_INIT_DC_OP));
	CHECK_FALSE(b.asyncError());
	CHECK(rig.s(1).dcAssign == 0x0700);
	CHECK(rig.s(1).dcSync0 == 2'000'000);
	CHECK(rig.s(1).dcSync1 == 500'000);
	CHECK(rig.s(1).dcShift == 12'345);
	CHECK(rig.s(0).dcSync0 == 1'000'000);
	d[0] = 2;
	CHECK(h.cmd(Cmd(ECMXF_CMD_ECAT_DCSYNC).payload(d)).cmdError());
}

TEST_CASE("chip: ECAT_CONFIG_SM writes a sync manager of the slave", "[chip][master]")
{
	Rig rig(2);
	rig.init();
	std::vector<std::uint8_t> d{ 1, 2 };
	append16(d, 0x1800);
	append16(d, 0x0030);
	append(d, { 0x64, 0x01 });
	const Rsp r = rig.host.cmd(Cmd(ECMXF_CMD_ECAT_CONFIG_SM).payload(d));
	CHECK_FALSE(r.cmdError());
	const TestSlave &s = rig.s(1);
	CHECK(s.regs[0x0810] == 0x00);
	CHECK(s.regs[0x0811] == 0x18);
	CHECK(s.regs[0x0812] == 0x30);
	CHECK(s.regs[0x0813] == 0x00);
	CHECK(s.regs[0x0814] == 0x64);
	CHECK(s.regs[0x0816] == 0x01);
	// the setting survives a layout rebuild
	rig.host.async(Cmd(ECMXF_CMD_ECAT_CONFIG_MAP));
	CHECK(rig.s(1).regs[0x0811] == 0x18);
	d[1] = 16;
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_CONFIG_SM).payload(d)).cmdError());
}

TEST_CASE("chip: ECAT_CONFIG_FMMU is accepted and has no effect (obsolete)", "[chip][master]")
{
	Rig rig(1);
	rig.init();
	const auto regs = rig.s(0).regs;
	const Rsp r = rig.host.cmd(Cmd(ECMXF_CMD_ECAT_CONFIG_FMMU).payload({ 0, 1, 2, 3, 4 }));
	CHECK_FALSE(r.cmdError());
	CHECK(rig.s(0).regs == regs);
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ECAT_CONFIG_FMMU).payload({ 1, 1, 2, 3, 4 })).cmdError());
}

TEST_CASE("chip: ENABLE_LRW accepts 0 and 1 only", "[chip][master]")
{
	Rig rig(1);
	CHECK_FALSE(rig.host.cmd(Cmd(ECMXF_CMD_ENABLE_LRW, 0)).cmdError());
	CHECK_FALSE(rig.host.cmd(Cmd(ECMXF_CMD_ENABLE_LRW, 1)).cmdError());
	CHECK(rig.host.cmd(Cmd(ECMXF_CMD_ENABLE_LRW, 2)).cmdError());
}

TEST_CASE("chip: INIT_OP accepts the special-slave parameter and the LRW and bus-shift header bits",
	  "[chip][master]")
{
	Rig rig(1);
	Cmd c = initOp();
	c.h.param = 48;
	c.reserved(ECMXF_RSV_LRW | ECMXF_RSV_BUS_SHIFT);
	const Rsp r = rig.host.async(c);
	CHECK_FALSE(r.asyncError());
	CHECK(r.h.ecat_state == ECMXF_ECAT_INIT);
}
