// SPDX-License-Identifier: MIT
// Master: the bring-up of each bundled network to OP, the scanned slaves,
// the PDO mappings it reads back (expected values: EST-584 manual 5.4.1,
// the servo and dio models of Documentation/sim-slaves.rst and the network
// files), PDO configuration through the 3x8 command and through SDO,
// start-up SDOs, and each step's failure in words.

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdint>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/bus/master.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/model/types_bus.hpp>

#include "rig.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using ecmxf::AlStatusError;
using ecmxf::Error;
using ecmxf::Master;
using ecmxf::MasterConfig;
using ecmxf::PdoDef;
using ecmxf::PdoEntryInfo;
using ecmxf::SdoError;
using ecmxf::State;
using bustest::Rig;

namespace {

struct E {
	std::uint16_t index;
	std::uint8_t sub;
	std::uint8_t bits;
	std::uint32_t offset;
};

void checkEntries(const std::vector<PdoEntryInfo> &got, std::uint16_t pdo, const std::vector<E> &want)
{
	REQUIRE(got.size() == want.size());
	for (std::size_t i = 0; i < want.size(); i++) {
		INFO("entry " << i);
		CHECK(got[i].pdo == pdo);
		CHECK(got[i].index == want[i].index);
		CHECK(got[i].sub == want[i].sub);
		CHECK(got[i].bitLength == want[i].bits);
		CHECK(got[i].bitOffset == want[i].offset);
	}
}

// EST-584 manual 5.4.1, RXPDO1 (0x1600) and TXPDO1 (0x1A00)
const std::vector<E> kEstRx{ { 0x6040, 0, 16, 0 }, { 0x607A, 0, 32, 16 }, { 0x60B0, 0, 32, 48 }, { 0x60B8, 0, 16, 80 } };
const std::vector<E> kEstTx{ { 0x6041, 0, 16, 0 },   { 0x6061, 0, 8, 16 },   { 0x6064, 0, 32, 24 },
			     { 0x60B9, 0, 16, 56 }, { 0x60BA, 0, 32, 72 }, { 0x60FD, 0, 32, 104 } };

} // namespace

TEST_CASE("master: est584x2-io.net to OP with its PDO mappings", "[master]")
{
	Rig r("est584x2-io.net");
	Master m(r.d());
	MasterConfig cfg;
	cfg.expectedSlaves = 3;
	m.bringUp(cfg);

	CHECK(r.d().lastHeader().ecatState == 8);
	CHECK((r.d().lastHeader().ecmStatus & 0x40) != 0); // FIFO enabled
	REQUIRE(m.slaves().size() == 3);
	CHECK(m.slaves()[0].name == "EST-584");
	CHECK(m.slaves()[1].productCode == 0x584u);
	CHECK(m.slaves()[2].name == "Digital I/O 8 out / 8 in");
	REQUIRE(m.pdos().size() == 3);
	for (std::size_t p = 0; p < 2; p++) {
		INFO("slave " << p);
		checkEntries(m.pdos()[p].outputs, 0x1600, kEstRx);
		checkEntries(m.pdos()[p].inputs, 0x1A00, kEstTx);
		CHECK(m.pdos()[p].outputBytes == 12);
		CHECK(m.pdos()[p].inputBytes == 17);
	}
	CHECK(m.pdos()[0].outputs[0].name == "Controlword");
	CHECK(m.pdos()[0].inputs[2].name == "Position actual value");
	// the dio (no mailbox): from its SII, 0x7000:01 out, 0x6000:01 in
	checkEntries(m.pdos()[2].outputs, 0x1600, { { 0x7000, 1, 8, 0 } });
	checkEntries(m.pdos()[2].inputs, 0x1A00, { { 0x6000, 1, 8, 0 } });
	CHECK(m.rxPdoSize() == 25);
	CHECK(m.txPdoSize() == 35);
	CHECK(m.outputOffset(2) == 24);
	CHECK(m.inputOffset(1) == 17);
	CHECK(m.inputOffset(2) == 34);
	CHECK_THROWS_WITH(m.outputOffset(3), Contains("slave 3 out of range"));
	CHECK(r.d().bus().stateGet(ecmxf::kAllSlaves).state() == State::Op);
}

TEST_CASE("master: servo-io.net to OP (DC SYNC0 1 ms)", "[master]")
{
	Rig r("servo-io.net");
	Master m(r.d());
	m.bringUp(MasterConfig{});
	CHECK(r.d().lastHeader().ecatState == 8);
	REQUIRE(m.slaves().size() == 3);
	CHECK(m.slaves()[0].name == "AKD2G-like servo");
	CHECK(m.slaves()[0].productCode == 0x0000A2D2u);
	// the servo model's defaults: RxPDO 13 bytes, TxPDO 15 bytes
	checkEntries(m.pdos()[0].outputs, 0x1600,
		     { { 0x6040, 0, 16, 0 }, { 0x607A, 0, 32, 16 }, { 0x60FF, 0, 32, 48 }, { 0x6071, 0, 16, 80 },
		       { 0x6060, 0, 8, 96 } });
	checkEntries(m.pdos()[1].inputs, 0x1A00,
		     { { 0x6041, 0, 16, 0 }, { 0x6064, 0, 32, 16 }, { 0x606C, 0, 32, 48 }, { 0x6077, 0, 16, 80 },
		       { 0x603F, 0, 16, 96 }, { 0x6061, 0, 8, 112 } });
	CHECK(m.pdos()[0].outputBytes == 13);
	CHECK(m.pdos()[0].inputBytes == 15);
	CHECK(m.rxPdoSize() == 13 + 13 + 1);
	CHECK(m.txPdoSize() == 15 + 15 + 1);
}

TEST_CASE("master: slaves128.net to OP", "[master]")
{
	Rig r("slaves128.net");
	Master m(r.d());
	MasterConfig cfg;
	cfg.expectedSlaves = 128;
	m.bringUp(cfg);
	CHECK(r.d().lastHeader().ecatState == 8);
	REQUIRE(m.slaves().size() == 128);
	// 64 x EST-584 (12/17) + 64 x dio (1/1): 832 / 1152 bytes (network file)
	CHECK(m.rxPdoSize() == 832);
	CHECK(m.txPdoSize() == 1152);
	REQUIRE(m.pdos().size() == 128);
	checkEntries(m.pdos()[63].outputs, 0x1600, kEstRx);
	checkEntries(m.pdos()[63].inputs, 0x1A00, kEstTx);
	checkEntries(m.pdos()[127].outputs, 0x1600, { { 0x7000, 1, 8, 0 } });
	CHECK(m.slaves()[127].stationAddress == 0x1001 + 127);
	CHECK(m.outputOffset(64) == 64u * 12u);
	CHECK(m.inputOffset(127) == 64u * 17u + 63u);
}

TEST_CASE("master: PDO assignment through the 3x8 command and through SDO, start-up SDOs", "[master][pdo]")
{
	Rig r;
	Master m(r.d());
	MasterConfig cfg;
	// slave 0: manual RXPDO2 (0x1601) through PDO_CONFIG_SET
	ecmxf::SlavePdoAssignment a0;
	a0.slave = 0;
	a0.rxPdos = std::vector<PdoDef>{ PdoDef{ 0x1601,
						 { { 0x6040, 0, 16 }, { 0x607A, 0, 32 }, { 0x6081, 0, 32 },
						   { 0x6083, 0, 32 }, { 0x6084, 0, 32 }, { 0x6060, 0, 8 } } } };
	// slave 1: four RxPDOs (more than the command's 3): through SDO
	ecmxf::SlavePdoAssignment a1;
	a1.slave = 1;
	a1.rxPdos = std::vector<PdoDef>{ PdoDef{ 0x1600, { { 0x6040, 0, 16 } } },
					 PdoDef{ 0x1601, { { 0x607A, 0, 32 } } },
					 PdoDef{ 0x1602, { { 0x6060, 0, 8 }, { 0x0000, 0, 8 } } },
					 PdoDef{ 0x1603, { { 0x60FF, 0, 32 } } } };
	a1.txPdos = std::vector<PdoDef>{ PdoDef{ 0x1A00, { { 0x6041, 0, 16 }, { 0x6064, 0, 32 } } } };
	cfg.pdoAssignments = { a0, a1 };
	// (not 0x6060: slave 0 maps it, so in OP the outputs own it)
	cfg.startupSdos.push_back({ 0, 0x2030, 0, { 0xD0, 0x07 } }); // 2000
	cfg.startupSdos.push_back({ 1, 0x2001, 0, { 0x10, 0x27 } }); // 10000
	m.bringUp(cfg);
	CHECK(r.d().lastHeader().ecatState == 8);

	checkEntries(m.pdos()[0].outputs, 0x1601,
		     { { 0x6040, 0, 16, 0 }, { 0x607A, 0, 32, 16 }, { 0x6081, 0, 32, 48 }, { 0x6083, 0, 32, 80 },
		       { 0x6084, 0, 32, 112 }, { 0x6060, 0, 8, 144 } });
	CHECK(m.pdos()[0].outputBytes == 19);
	checkEntries(m.pdos()[0].inputs, 0x1A00, kEstTx);
	const auto &o1 = m.pdos()[1].outputs;
	REQUIRE(o1.size() == 5);
	CHECK(o1[0].pdo == 0x1600);
	CHECK(o1[1].pdo == 0x1601);
	CHECK(o1[1].bitOffset == 16);
	CHECK(o1[2].pdo == 0x1602);
	CHECK(o1[2].index == 0x6060);
	CHECK(o1[2].bitOffset == 48);
	CHECK(o1[3].index == 0); // the 8-bit gap
	CHECK(o1[3].bitOffset == 56);
	CHECK(o1[4].pdo == 0x1603);
	CHECK(o1[4].bitOffset == 64);
	CHECK(m.pdos()[1].outputBytes == 12);
	checkEntries(m.pdos()[1].inputs, 0x1A00, { { 0x6041, 0, 16, 0 }, { 0x6064, 0, 32, 16 } });
	CHECK(m.pdos()[1].inputBytes == 6);
	CHECK(m.rxPdoSize() == 19 + 12 + 1);
	CHECK(m.txPdoSize() == 17 + 6 + 1);

	CHECK(r.d().sdo().read<std::uint16_t>(0, 0x2030, 0) == 2000);
	CHECK(r.d().sdo().read<std::uint16_t>(1, 0x2001, 0) == 10000);
}

TEST_CASE("master: RECONFIG_OP instead of CONFIG_MAP, and stopping in SAFE-OP", "[master][pdo]")
{
	Rig r;
	Master m(r.d());
	MasterConfig cfg;
	ecmxf::SlavePdoAssignment a;
	a.slave = 1;
	a.txPdos = std::vector<PdoDef>{ PdoDef{ 0x1A00, { { 0x6041, 0, 16 } } } };
	cfg.pdoAssignments = { a };
	cfg.remap = ecmxf::RemapCommand::Reconfig;
	cfg.target = State::SafeOp;
	cfg.enableFifo = false;
	m.bringUp(cfg);
	CHECK(r.d().bus().stateGet(ecmxf::kAllSlaves).state() == State::SafeOp);
	CHECK(m.slaves()[1].inputBytes == 2);
	CHECK((r.d().lastHeader().ecmStatus & 0x40) == 0);
}

TEST_CASE("master: each step's failure names the step", "[master][errors]")
{
	SECTION("scan: another slave count than expected")
	{
		Rig r;
		Master m(r.d());
		MasterConfig cfg;
		cfg.expectedSlaves = 4;
		try {
			m.bringUp(cfg);
			FAIL("no error");
		} catch (const Error &e) {
			CHECK(e.errnoValue() == ENODEV);
			CHECK_THAT(e.what(), Equals("bring-up step 'scan' failed: found 3 slaves, expected 4"));
		}
	}
	SECTION("init: the chip stays busy")
	{
		Rig r;
		r.chip->faults().asyncStuckBusy = true;
		Master m(r.d());
		try {
			m.bringUp(MasterConfig{});
			FAIL("no error");
		} catch (const Error &e) {
			CHECK(e.errnoValue() == ETIMEDOUT);
			CHECK_THAT(e.what(), Equals("bring-up step 'init' failed: ECAT_INIT_OP: timed out after 10000 ms "
						    "waiting for the async command to complete"));
		}
	}
	SECTION("start-up SDOs: a read-only object")
	{
		Rig r;
		Master m(r.d());
		MasterConfig cfg;
		cfg.startupSdos.push_back({ 1, 0x1000, 0, { 1, 0, 0, 0 } });
		try {
			m.bringUp(cfg);
			FAIL("no error");
		} catch (const SdoError &e) {
			CHECK(e.abortCode() == 0x06010002u);
			CHECK_THAT(e.what(), Equals("bring-up step 'start-up SDOs' failed: SDO download 0x1000:00 to slave 1 "
						    "aborted: 0x06010002 Read only entry"));
		}
	}
	SECTION("PDO configuration: an object that cannot be mapped")
	{
		Rig r;
		Master m(r.d());
		MasterConfig cfg;
		ecmxf::SlavePdoAssignment a;
		a.slave = 0;
		a.rxPdos = std::vector<PdoDef>{ PdoDef{ 0x1600, { { 0x6041, 0, 16 } } } }; // statusword is TxPDO only
		cfg.pdoAssignments = { a };
		try {
			m.bringUp(cfg);
			FAIL("no error");
		} catch (const SdoError &e) {
			CHECK(e.abortCode() == 0x06040041u);
			CHECK_THAT(e.what(), Equals("bring-up step 'PDO configuration' failed: ECAT_PDO_CONFIG_SET 0x1C12 "
						    "of slave 0 aborted: 0x06040041 Object can not be mapped to PDO"));
		}
	}
	SECTION("PDO configuration: a slave that is not there")
	{
		Rig r;
		Master m(r.d());
		MasterConfig cfg;
		ecmxf::SlavePdoAssignment a;
		a.slave = 5;
		a.rxPdos = std::vector<PdoDef>{};
		cfg.pdoAssignments = { a };
		CHECK_THROWS_WITH(m.bringUp(cfg), Equals("bring-up step 'PDO configuration' failed: PDO assignment for "
							 "slave 5: only 3 slaves on the bus"));
	}
	SECTION("states to SAFE-OP: an output mapping over the EST-584's 64 bytes")
	{
		Rig r;
		Master m(r.d());
		MasterConfig cfg;
		ecmxf::SlavePdoAssignment a;
		a.slave = 1;
		std::vector<ecmxf::PdoMapEntry> eight(8, ecmxf::PdoMapEntry{ 0x607A, 0, 32 });
		a.rxPdos = std::vector<PdoDef>{ PdoDef{ 0x1600, eight }, PdoDef{ 0x1601, eight }, PdoDef{ 0x1602, eight } };
		cfg.pdoAssignments = { a };
		try {
			m.bringUp(cfg);
			FAIL("no error");
		} catch (const AlStatusError &e) {
			CHECK(e.slave() == 1);
			CHECK(e.alStatusCode() == 0x0025);
			CHECK_THAT(e.what(), Equals("bring-up step 'states to SAFE-OP' failed: slave 1 (EST-584): "
						    "ECAT_STATE_SET SAFE-OP (all slaves) failed: stays in PRE-OP, AL status "
						    "0x0025 Invalid output mapping (too many PDO entries)"));
		}
	}
	SECTION("states to OP: the servo without DC")
	{
		Rig r("servo-io.net");
		Master m(r.d());
		MasterConfig cfg;
		cfg.init.dc.assignActivate = 0;
		try {
			m.bringUp(cfg);
			FAIL("no error");
		} catch (const AlStatusError &e) {
			CHECK(e.alStatusCode() == 0x0030);
			CHECK(e.reached() == State::SafeOp);
			CHECK_THAT(e.what(), Equals("bring-up step 'states to OP' failed: slave 0 (AKD2G-like servo): "
						    "ECAT_STATE_SET OP (all slaves) failed: stays in SAFE-OP, AL status 0x0030 "
						    "Invalid DC sync error (cycle time via register 0x9A0 is not an allowed "
						    "value); slave 1 (AKD2G-like servo): stays in SAFE-OP, AL status 0x0030 "
						    "Invalid DC sync error (cycle time via register 0x9A0 is not an allowed "
						    "value)"));
		}
	}
	SECTION("bad configuration")
	{
		Rig r;
		Master m(r.d());
		MasterConfig cfg;
		cfg.target = State::Init;
		CHECK_THROWS_WITH(m.bringUp(cfg),
				  Equals("Master::bringUp: target state INIT not one of PRE-OP, SAFE-OP, OP"));
		cfg.target = State::SafeOp;
		CHECK_THROWS_WITH(m.bringUp(cfg), Equals("Master::bringUp: enableFifo needs target state OP (the manual "
							 "enables the FIFO in OP), target is SAFE-OP"));
	}
}
