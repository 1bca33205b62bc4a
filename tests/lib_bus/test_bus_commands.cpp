// SPDX-License-Identifier: MIT
// The typed bus commands of Device against the simulator: INIT_OP with DC,
// slave information, states (per slave and all), STATE_CHECK/UPDATE, the
// 3x8 PDO configuration, CONFIG_SM/FMMU/MAP, RECONFIG_OP, DCSYNC +
// INIT_DC_OP, ENABLE_LRW; and each failure with the text the user reads.
// Expected values: EST-584 manual (seed 004) PDO sizes, AKD2G AL status
// table (seed 003), the simulator's documented identities
// (Documentation/sim-slaves.rst) and station addresses (0x1001 + position,
// the simulated chip's choice).

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdint>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/model/types_bus.hpp>

#include "rig.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using ecmxf::AlStatusError;
using ecmxf::Error;
using ecmxf::kAllSlaves;
using ecmxf::PdoConfig;
using ecmxf::PdoDef;
using ecmxf::PdoMapEntry;
using ecmxf::SdoError;
using ecmxf::State;
using bustest::Rig;

TEST_CASE("bus: state names and AL status texts (AKD2G table)", "[bus]")
{
	CHECK(ecmxf::stateName(State::Init) == "INIT");
	CHECK(ecmxf::stateName(State::PreOp) == "PRE-OP");
	CHECK(ecmxf::stateName(State::Boot) == "BOOT");
	CHECK(ecmxf::stateName(State::SafeOp) == "SAFE-OP");
	CHECK(ecmxf::stateName(State::Op) == "OP");
	CHECK(ecmxf::alStatusText(0x0011) == "Invalid requested state change");
	CHECK(ecmxf::alStatusText(0x001D) == "Invalid output configuration SM2 (Rx)");
	CHECK(ecmxf::alStatusText(0x001B) == "Sync manager watchdog");
	CHECK(ecmxf::alStatusText(0x0030) ==
	      "Invalid DC sync error (cycle time via register 0x9A0 is not an allowed value)");
	CHECK(ecmxf::alStatusText(0x0099) == "unknown AL status code");
	CHECK(ecmxf::StateReading{ 0x14 }.state() == State::SafeOp);
	CHECK(ecmxf::StateReading{ 0x14 }.error());
	CHECK(ecmxf::StateReading{ 0x10 }.state() == State::None);
}

TEST_CASE("bus: INIT_OP, SLV_CNT_GET and SLV_INFO_GET of every slave", "[bus]")
{
	Rig r;
	auto &d = r.d();
	CHECK(d.bus().stateGet(kAllSlaves).raw == 0); // nothing initialised yet
	d.bus().initNetwork();
	CHECK(d.bus().slaveCount() == 3);
	CHECK(d.bus().stateGet(kAllSlaves).state() == State::Init);

	for (std::uint8_t p = 0; p < 2; p++) {
		const ecmxf::SlaveInfo s = d.bus().slaveInfo(p);
		CHECK(s.position == p);
		CHECK(s.vendorId == 0x00000E5Cu);
		CHECK(s.productCode == 0x00000584u);
		CHECK(s.revision == 0x00010000u);
		CHECK(s.name == "EST-584");
		CHECK(s.stationAddress == 0x1001 + p);
		CHECK(s.alias == 0);
		CHECK(s.state == State::Init);
		CHECK(s.alStatusCode == 0);
		// manual 5.4.1: RxPDO1 16+32+32+16 bits, TxPDO1 16+8+32+16+32+32 bits
		CHECK(s.outputBytes == 12);
		CHECK(s.inputBytes == 17);
	}
	const ecmxf::SlaveInfo io = d.bus().slaveInfo(2);
	CHECK(io.productCode == 0x00001088u);
	CHECK(io.name == "Digital I/O 8 out / 8 in");
	CHECK(io.stationAddress == 0x1003);
	CHECK(io.outputBytes == 1);
	CHECK(io.inputBytes == 1);
	CHECK(d.bus().slaveInfoRaw(0, ecmxf::SlaveInfoCode::Vendor) == std::vector<std::uint8_t>{ 0x5C, 0x0E, 0, 0 });

	try {
		(void)d.bus().slaveInfo(3);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("ECAT_SLV_INFO_GET code 0 of slave 3: the chip refused the command (error "
					    "status bit 7, command error)"));
	}
	try {
		(void)d.bus().slaveInfoRaw(0, static_cast<ecmxf::SlaveInfoCode>(14));
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("ECAT_SLV_INFO_GET: information code 14 out of range (0..13)"));
	}
}

TEST_CASE("bus: slaveDc reads the DC information codes 10..13", "[bus]")
{
	Rig r("servo-io.net");
	auto &d = r.d();
	ecmxf::InitConfig cfg;
	cfg.dc.sync0Ns = 250'000;
	cfg.dc.shiftNs = -12'500;
	d.bus().initNetwork(cfg);
	const ecmxf::SlaveDc servo = d.bus().slaveDc(0);
	CHECK(servo.hasDc);
	CHECK(servo.cycleNs == 250'000);
	CHECK(servo.shiftNs == -12'500);
	CHECK(servo.active);
	const ecmxf::SlaveDc io = d.bus().slaveDc(2);
	CHECK_FALSE(io.hasDc);
	CHECK(io.cycleNs == 0);
	CHECK_FALSE(io.active);
	CHECK(d.bus().slaveInfoRaw(0, ecmxf::SlaveInfoCode::DcCycle) == std::vector<std::uint8_t>{ 0x90, 0xD0, 0x03, 0 });
	// DC off on the bus: the servo keeps its ESC feature, nothing runs
	cfg.dc.assignActivate = 0;
	d.bus().initNetwork(cfg);
	const ecmxf::SlaveDc off = d.bus().slaveDc(1);
	CHECK(off.hasDc);
	CHECK(off.cycleNs == 0);
	CHECK_FALSE(off.active);
	try {
		(void)d.bus().slaveDc(3);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Contains("code 10 of slave 3"));
	}
}

TEST_CASE("bus: STATE_SET per slave and for all, STATE_GET, STATE_UPDATE, STATE_CHECK", "[bus]")
{
	Rig r;
	auto &d = r.d();
	d.bus().initNetwork();
	d.bus().stateSet(1, State::PreOp);
	CHECK(d.bus().stateGet(1).state() == State::PreOp);
	CHECK(d.bus().stateGet(0).state() == State::Init);
	CHECK(d.bus().slaveInfo(1).state == State::PreOp);
	d.bus().stateSet(kAllSlaves, State::PreOp);
	d.bus().stateSet(kAllSlaves, State::SafeOp);
	CHECK(d.bus().stateGet(kAllSlaves).state() == State::SafeOp);
	CHECK(d.lastHeader().ecatState == 4);
	d.bus().stateSet(kAllSlaves, State::Op);
	CHECK(d.bus().stateGet(kAllSlaves).state() == State::Op);
	CHECK_FALSE(d.bus().stateGet(kAllSlaves).error());
	for (std::uint8_t p = 0; p < 3; p++)
		CHECK(d.bus().stateGet(p).state() == State::Op);

	// STATE_CHECK = SET + UPDATE + GET
	const ecmxf::StateReading s = d.bus().stateCheck(2, State::SafeOp);
	CHECK(s.state() == State::SafeOp);
	CHECK(d.bus().stateGet(kAllSlaves).state() == State::SafeOp);
	d.bus().stateUpdate();
	CHECK(d.bus().stateGet(2).state() == State::SafeOp);
	CHECK(d.bus().stateCheck(kAllSlaves, State::PreOp).state() == State::PreOp);
}

TEST_CASE("bus: a state skip is refused with AL status 0x0011", "[bus][errors]")
{
	Rig r;
	r.d().bus().initNetwork();
	try {
		r.d().bus().stateSet(0, State::SafeOp);
		FAIL("no error");
	} catch (const AlStatusError &e) {
		CHECK(e.slave() == 0);
		CHECK(e.requested() == State::SafeOp);
		CHECK(e.reached() == State::Init);
		CHECK(e.alStatusCode() == 0x0011);
		CHECK(e.errnoValue() == EREMOTEIO);
		CHECK_THAT(e.what(), Equals("slave 0 (EST-584): ECAT_STATE_SET SAFE-OP failed: stays in INIT, AL status "
					    "0x0011 Invalid requested state change"));
	}
	// STATE_CHECK reports the same way, for all slaves: each one named
	try {
		(void)r.d().bus().stateCheck(kAllSlaves, State::Op);
		FAIL("no error");
	} catch (const AlStatusError &e) {
		CHECK(e.slave() == 0);
		CHECK(e.alStatusCode() == 0x0011);
		CHECK_THAT(e.what(),
			   Equals("slave 0 (EST-584): ECAT_STATE_CHECK OP (all slaves) failed: stays in INIT, AL status "
				  "0x0011 Invalid requested state change; slave 1 (EST-584): stays in INIT, AL status "
				  "0x0011 Invalid requested state change; slave 2 (Digital I/O 8 out / 8 in): stays in "
				  "INIT, AL status 0x0011 Invalid requested state change"));
	}
	// the error is acknowledged by the next request
	r.d().bus().stateSet(kAllSlaves, State::PreOp);
	CHECK(r.d().bus().slaveInfo(0).alStatusCode == 0);
}

TEST_CASE("bus: OP on the servo without DC gives its AL status code 0x0030", "[bus][errors]")
{
	Rig r("servo-io.net");
	ecmxf::InitConfig cfg;
	cfg.dc.assignActivate = 0; // no SYNC0 on the slaves
	r.d().bus().initNetwork(cfg);
	r.d().bus().stateSet(kAllSlaves, State::PreOp);
	r.d().bus().stateSet(kAllSlaves, State::SafeOp);
	try {
		r.d().bus().stateSet(0, State::Op);
		FAIL("no error");
	} catch (const AlStatusError &e) {
		CHECK(e.reached() == State::SafeOp);
		CHECK(e.alStatusCode() == 0x0030);
		CHECK_THAT(e.what(), Equals("slave 0 (AKD2G-like servo): ECAT_STATE_SET OP failed: stays in SAFE-OP, AL "
					    "status 0x0030 Invalid DC sync error (cycle time via register 0x9A0 is not "
					    "an allowed value)"));
	}
}

TEST_CASE("bus: STATE_SET BOOT sets up the bootstrap mailbox, PRE-OP after it the standard one", "[bus]")
{
	// the servo's SII has a bootstrap mailbox (sim-slaves.rst); the
	// EST-584 has none and refuses BOOT with 0x0015 (AKD2G table)
	Rig r("servo-io.net");
	r.d().bus().initNetwork();
	r.d().bus().stateSet(0, State::Boot);
	CHECK(r.d().bus().stateGet(0).state() == State::Boot);
	r.d().bus().stateSet(0, State::Init);
	r.d().bus().stateSet(0, State::PreOp);
	CHECK(r.d().bus().stateGet(0).state() == State::PreOp);
	CHECK(r.d().sdo().read<std::uint32_t>(0, 0x1018, 1) == 0x00000E5Cu); // vendor id, sim-slaves.rst

	Rig e("est584x2-io.net");
	e.d().bus().initNetwork();
	try {
		e.d().bus().stateSet(0, State::Boot);
		FAIL("no error");
	} catch (const AlStatusError &ex) {
		CHECK(ex.alStatusCode() == 0x0015);
		CHECK_THAT(ex.what(), Contains("AL status 0x0015 Invalid mailbox boot configuration"));
	}
}

TEST_CASE("bus: the servo reaches OP with DC from INIT_OP", "[bus]")
{
	Rig r("servo-io.net");
	r.d().bus().initNetwork(); // SYNC0 1 ms, AssignActivate 0x0300
	r.d().bus().stateSet(kAllSlaves, State::PreOp);
	r.d().bus().stateSet(kAllSlaves, State::SafeOp);
	r.d().bus().stateSet(kAllSlaves, State::Op);
	CHECK(r.d().bus().stateGet(kAllSlaves).state() == State::Op);
}

TEST_CASE("bus: INIT_OP and DCSYNC + INIT_DC_OP configure DC on the slaves", "[bus]")
{
	simtest::SlaveConfig sc;
	sc.dcAssign = 0x0300;
	Rig r(bustest::testSlaves(2, sc));
	ecmxf::InitConfig cfg;
	cfg.dc.sync0Ns = 500'000;
	cfg.dc.sync1Ns = 250'000;
	cfg.dc.shiftNs = -20'000;
	cfg.dc.assignActivate = 0x0700;
	cfg.lrw = false;
	cfg.busShift = true;
	r.d().bus().initNetwork(cfg);
	CHECK(r.test(0).dcAssign == 0x0700);
	CHECK(r.test(0).dcSync0 == 500'000u);
	CHECK(r.test(0).dcSync1 == 250'000u);
	CHECK(r.test(0).dcShift == -20'000);

	ecmxf::DcConfig one;
	one.sync0Ns = 1'000'000;
	one.sync1Ns = 0;
	one.shiftNs = 12'345;
	one.assignActivate = 0x0300;
	r.d().bus().dcSync(1, one);
	CHECK(r.test(1).dcSync0 == 500'000u); // applied by INIT_DC_OP only
	r.d().bus().initDc();
	CHECK(r.test(1).dcSync0 == 1'000'000u);
	CHECK(r.test(1).dcShift == 12'345);
	CHECK(r.test(1).dcAssign == 0x0300);
	CHECK(r.test(0).dcSync0 == 500'000u);
	r.d().bus().enableLrw(true);
	r.d().bus().enableLrw(false);
}

TEST_CASE("bus: PDO_CONFIG_SET / REQ / GET with the EST-584's RxPDO2, then CONFIG_MAP", "[bus][pdo]")
{
	Rig r;
	r.d().bus().initNetwork();
	r.d().bus().stateSet(kAllSlaves, State::PreOp);

	// manual 5.4.1 RXPDO2 (0x1601): controlword, target position, max.
	// speed, acceleration, deceleration, operation mode = 19 bytes
	PdoConfig c;
	c.slave = 1;
	c.assignIndex = 0x1C12;
	c.pdos.push_back(PdoDef{ 0x1601,
				 { { 0x6040, 0, 16 }, { 0x607A, 0, 32 }, { 0x6081, 0, 32 }, { 0x6083, 0, 32 },
				   { 0x6084, 0, 32 }, { 0x6060, 0, 8 } } });
	r.d().bus().pdoConfigSet(c);
	CHECK(r.d().sdo().read<std::uint16_t>(1, 0x1C12, 1) == 0x1601);
	CHECK(r.d().sdo().read<std::uint32_t>(1, 0x1601, 6) == 0x60600008u);

	const PdoConfig back = r.d().bus().pdoConfigRead(1, 0x1C12);
	CHECK(back.slave == 1);
	CHECK(back.assignIndex == 0x1C12);
	CHECK(back.pdoCount == 1);
	CHECK(back.entryCounts[0] == 6);
	CHECK(back.complete());
	REQUIRE(back.pdos.size() == 1);
	CHECK(back.pdos[0] == c.pdos[0]);
	CHECK(r.d().bus().pdoConfigGet().pdos == back.pdos);

	// the TxPDO side keeps the default 0x1A00 (6 entries)
	const PdoConfig tx = r.d().bus().pdoConfigRead(0, 0x1C13);
	REQUIRE(tx.pdos.size() == 1);
	CHECK(tx.pdos[0].index == 0x1A00);
	CHECK(tx.pdos[0].entries.front() == PdoMapEntry{ 0x6041, 0, 16 });
	CHECK(tx.pdos[0].entries.back() == PdoMapEntry{ 0x60FD, 0, 32 });

	CHECK(r.d().bus().slaveInfo(1).outputBytes == 12); // not yet applied
	r.d().bus().configMap();
	CHECK(r.d().bus().slaveInfo(1).outputBytes == 19);
	CHECK(r.d().bus().slaveInfo(0).outputBytes == 12);
	r.d().bus().stateSet(kAllSlaves, State::SafeOp);
	r.d().bus().stateSet(kAllSlaves, State::Op);

	// RECONFIG_OP does the same; the header reads INIT until STATE_UPDATE
	r.d().bus().reconfigure();
	CHECK(r.d().lastHeader().ecatState == 1);
	r.d().bus().stateUpdate();
	CHECK(r.d().bus().stateGet(kAllSlaves).state() == State::Op);
}

TEST_CASE("bus: PDO configuration errors", "[bus][pdo][errors]")
{
	Rig r;
	r.d().bus().initNetwork();
	r.d().bus().stateSet(kAllSlaves, State::PreOp);
	PdoConfig c;
	c.slave = 0;
	c.pdos.assign(4, PdoDef{ 0x1600, { { 0x6040, 0, 16 } } });
	try {
		r.d().bus().pdoConfigSet(c);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("ECAT_PDO_CONFIG_SET 0x1C12 of slave 0: 4 PDOs, the command holds at most 3 "
					    "(assign more through SDO)"));
	}
	c.pdos.assign(1, PdoDef{ 0x1600, std::vector<PdoMapEntry>(9, PdoMapEntry{ 0x6040, 0, 16 }) });
	try {
		r.d().bus().pdoConfigSet(c);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("ECAT_PDO_CONFIG_SET 0x1C12 of slave 0: PDO 0x1600 has 9 entries, the "
					    "command holds at most 8 per PDO (map it through SDO)"));
	}
	// the device type is not mappable: the slave aborts
	c.pdos.assign(1, PdoDef{ 0x1600, { { 0x6040, 0, 16 }, { 0x1000, 0, 32 } } });
	try {
		r.d().bus().pdoConfigSet(c);
		FAIL("no error");
	} catch (const SdoError &e) {
		CHECK(e.abortCode() == 0x06040041u);
		CHECK_THAT(e.what(), Equals("ECAT_PDO_CONFIG_SET 0x1C12 of slave 0 aborted: 0x06040041 Object can not be "
					    "mapped to PDO"));
	}
	r.chip->faults().forcedSdoAbort = 0x08000000;
	try {
		(void)r.d().bus().pdoConfigRead(0, 0x1C13);
		FAIL("no error");
	} catch (const SdoError &e) {
		CHECK(e.abortCode() == 0x08000000u);
		CHECK_THAT(e.what(), Equals("ECAT_PDO_CONFIG_REQ 0x1C13 of slave 0 aborted: 0x08000000 General error"));
	}
}

TEST_CASE("bus: a wrong SM2 length from CONFIG_SM gives AL status 0x001D at SAFE-OP", "[bus][errors]")
{
	Rig r;
	r.d().bus().initNetwork();
	r.d().bus().stateSet(kAllSlaves, State::PreOp);
	ecmxf::SmConfig sm;
	sm.startAddress = 0x1100; // SII: SM2 outputs at 0x1100
	sm.length = 5;            // the mapping has 12 bytes
	sm.control = 0x64;
	sm.activate = 1;
	r.d().bus().configSm(1, 2, sm);
	try {
		r.d().bus().stateSet(kAllSlaves, State::SafeOp);
		FAIL("no error");
	} catch (const AlStatusError &e) {
		CHECK(e.slave() == 1);
		CHECK(e.reached() == State::PreOp);
		CHECK(e.alStatusCode() == 0x001D);
		CHECK_THAT(e.what(), Equals("slave 1 (EST-584): ECAT_STATE_SET SAFE-OP (all slaves) failed: stays in "
					    "PRE-OP, AL status 0x001D Invalid output configuration SM2 (Rx)"));
	}
	try {
		r.d().bus().configSm(1, 16, sm);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK_THAT(e.what(), Equals("ECAT_CONFIG_SM: sync manager 16 out of range (0..15)"));
	}
	try {
		r.d().bus().configSm(7, 2, sm);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EINVAL);
		CHECK_THAT(e.what(), Equals("ECAT_CONFIG_SM 2 of slave 7: the chip refused the command (error status bit "
					    "7, command error: is the slave on the bus?); the command exists only in "
					    "firmware of manual ver. 050"));
	}
	// obsolete CONFIG_FMMU: accepted and ignored for a slave on the bus
	r.d().bus().configFmmu(0, { 1, 2, 0, 0 });
	CHECK_THROWS_WITH(r.d().bus().configFmmu(9, { 1, 2, 0, 0 }),
			  Contains("ECAT_CONFIG_FMMU of slave 9: the chip refused the command (error status bit 7, "
				   "command error: is the slave on the bus?)"));
}

TEST_CASE("bus: a lost slave and a stuck chip are reported with what was awaited", "[bus][errors]")
{
	Rig r;
	r.d().bus().initNetwork();
	r.d().bus().stateSet(kAllSlaves, State::PreOp);
	r.chip->faults().slaveDropped = 1;
	try {
		r.d().bus().stateSet(kAllSlaves, State::SafeOp);
		FAIL("no error");
	} catch (const AlStatusError &e) {
		CHECK(e.slave() == 1);
		CHECK(e.errnoValue() == EHOSTUNREACH);
		CHECK_THAT(e.what(), Equals("slave 1 (EST-584): ECAT_STATE_SET SAFE-OP (all slaves) failed: the slave "
					    "does not answer (not reachable on the bus); slave 2 (Digital I/O 8 out / 8 in): "
					    "stays in PRE-OP (AL status 0x0000 No error: the request did not reach it or it "
					    "did not finish in the chip's time)"));
	}
	r.chip->faults().slaveDropped = -1;

	r.chip->faults().asyncStuckBusy = true;
	try {
		r.d().bus().stateSet(kAllSlaves, State::PreOp);
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == ETIMEDOUT);
		CHECK_THAT(e.what(), Equals("ECAT_STATE_SET PRE-OP for all slaves: ECAT_STATE_SET: timed out after "
					    "10000 ms waiting for the async command to complete"));
	}
	// the chip still runs the stuck command: the next async one is refused
	try {
		r.d().bus().stateUpdate();
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EBUSY);
		CHECK_THAT(e.what(), Equals("ECAT_STATE_UPDATE: the chip refused the command (error status bit 7, command "
					    "error: another async command is still running on the chip)"));
	}
}

TEST_CASE("bus: bad arguments name the argument and its range", "[bus][errors]")
{
	Rig r;
	r.d().bus().initNetwork();
	CHECK_THROWS_WITH(r.d().bus().stateSet(128, State::PreOp),
			  Equals("ECAT_STATE_SET: slave 128 out of range (0..127, or 0xFF for all slaves)"));
	CHECK_THROWS_WITH(r.d().bus().stateSet(0, State::None),
			  Equals("ECAT_STATE_SET: state 0x00 is not one of INIT (1), PRE-OP (2), BOOT (3), SAFE-OP "
				 "(4), OP (8)"));
	CHECK_THROWS_WITH(r.d().bus().stateSet(0, static_cast<State>(5)),
			  Contains("state 0x05 is not one of INIT (1)"));
	CHECK_THROWS_WITH(r.d().bus().slaveInfo(200), Equals("ECAT_SLV_INFO_GET: slave 200 out of range (0..127)"));
	CHECK_THROWS_WITH(r.d().bus().stateSet(4, State::PreOp),
			  Equals("ECAT_STATE_SET PRE-OP for slave 4: the chip refused the command (error status bit "
				 "7, command error: slave 4 is not on the bus (3 slaves found by ECAT_INIT_OP))"));
	CHECK_THROWS_WITH(r.d().bus().stateGet(4), Equals("ECAT_STATE_GET for slave 4: the chip refused the command (error "
						    "status bit 7, command error)"));
}

TEST_CASE("bus: INIT_OP without link fails naming the link", "[bus][errors]")
{
	Rig r;
	r.chip->faults().linkLost = true;
	try {
		r.d().bus().initNetwork();
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EREMOTEIO);
		CHECK_THAT(e.what(), Equals("ECAT_INIT_OP: the network scan failed: no Ethernet link (error status bit 0 "
					    "clear)"));
	}
}
