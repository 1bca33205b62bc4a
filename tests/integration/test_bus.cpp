// SPDX-License-Identifier: MIT
// Bus bring-up through Master, the slaves as scanned, EtherCAT states with
// their AL status, SDO, the SII EEPROM, raw datagrams, the mailbox and the
// chip's staging flash, on the device of ECMXF_TEST_URI.
//
// Expected values: the simulator's model identities and SII images
// (Documentation/sim-slaves.rst: vendor 0x00000E5C, EST-584 product 0x584
// revision 0x00010000, dio product 0x1088; station addresses 0x1001 + bus
// position; ESC types 0x11 / 0x12), the EST-584 manual (3.5 0x2001 = 50000
// pulses per revolution; 4.3.1 0x2000 peak current 3200 mA, 1..8400; 5.4.1
// default PDOs: 12 output and 17 input bytes), the AL status table (0x0011
// "Invalid requested state change") and the SDO abort table (0x06020000
// "Object not existing", 0x06090031 "Value is too great").

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdint>
#include <string>
#include <vector>

#include "integration.hpp"
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/bus/slave_access.hpp>

using namespace std::chrono_literals;
using Catch::Matchers::Contains;
using ecmxf::kAllSlaves;
using ecmxf::State;
using integ::Rig;

TEST_CASE("bus: Master brings the network to OP and the scan names every slave", "[bus][master]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	ecmxf::Master m(d);
	ecmxf::MasterConfig mc = integ::masterConfig(d);
	std::vector<std::string> steps;
	auto inner = mc.onStep;
	mc.onStep = [&](std::string_view s) {
		steps.emplace_back(s);
		inner(s);
	};
	m.bringUp(mc);
	const std::vector<std::string> want{ "init",	    "scan",		 "states to PRE-OP",
					     "PDO configuration", "start-up SDOs",	 "PDO mapping",
					     "states to SAFE-OP", "states to OP",	 "FIFO enable" };
	CHECK(steps == want);

	REQUIRE(m.slaves().size() == 3);
	for (unsigned i = 0; i < 3; i++) {
		const ecmxf::SlaveInfo &s = m.slaves()[i];
		INFO("slave " << i);
		CHECK(s.position == i);
		CHECK(s.vendorId == 0x00000E5Cu);
		CHECK(s.stationAddress == 0x1001 + i);
		CHECK(s.alias == 0);
		CHECK(s.alStatusCode == 0);
	}
	CHECK(m.slaves()[0].productCode == 0x584u);
	CHECK(m.slaves()[0].revision == 0x00010000u);
	CHECK(m.slaves()[0].name == "EST-584");
	CHECK(m.slaves()[0].outputBytes == 12);
	CHECK(m.slaves()[0].inputBytes == 17);
	CHECK(m.slaves()[1].name == "EST-584");
	CHECK(m.slaves()[2].productCode == 0x1088u);
	CHECK(m.slaves()[2].name == "Digital I/O 8 out / 8 in");
	CHECK(m.slaves()[2].outputBytes == 1);
	CHECK(m.slaves()[2].inputBytes == 1);
	// FIFO_PACK_SIZE_GET: 12 + 12 + 1 output, 17 + 17 + 1 input bytes
	CHECK(m.rxPdoSize() == 25);
	CHECK(m.txPdoSize() == 35);
	CHECK(m.outputOffset(2) == 24);
	CHECK(m.inputOffset(1) == 17);
	// the EST-584's default mapping (5.4.1): 0x1600 and 0x1A00
	REQUIRE(m.pdos().size() == 3);
	REQUIRE(m.pdos()[0].outputs.size() == 4);
	CHECK(m.pdos()[0].outputs[0].index == 0x6040);
	CHECK(m.pdos()[0].outputs[1].index == 0x607A);
	CHECK(m.pdos()[0].outputs[1].bitOffset == 16);
	REQUIRE(m.pdos()[0].inputs.size() == 6);
	CHECK(m.pdos()[0].inputs[2].index == 0x6064);
	CHECK(m.pdos()[0].inputs[2].bitOffset == 24);
	// the dio's, from its SII: 0x7000:01 out, 0x6000:01 in
	REQUIRE(m.pdos()[2].outputs.size() == 1);
	CHECK(m.pdos()[2].outputs[0].index == 0x7000);
	CHECK(m.pdos()[2].outputs[0].sub == 1);
	CHECK(m.pdos()[2].inputs[0].index == 0x6000);

	// every slave in OP, as the chip reads it
	CHECK(d.bus().slaveCount() == 3);
	d.bus().stateUpdate();
	CHECK(d.bus().stateGet(kAllSlaves).state() == State::Op);
	CHECK(d.bus().stateCheck(1, State::Op).state() == State::Op);
	const ecmxf::SlaveInfo s1 = d.bus().slaveInfo(1);
	CHECK(s1.state == State::Op);
	CHECK(s1.productCode == 0x584u);
	CHECK(s1.stationAddress == 0x1002);
	// the raw bytes of one code: the vendor id, little-endian
	CHECK(d.bus().slaveInfoRaw(2, ecmxf::SlaveInfoCode::Vendor) == std::vector<std::uint8_t>{ 0x5C, 0x0E, 0, 0 });
	// ECAT_PDO_WC_GET: 3 slaves with inputs, 3 with outputs: 3 + 2 x 3 = 9
	const ecmxf::PdoSlaveCounts pc = d.pdo().slaveCounts();
	CHECK(pc.inputSlaves == 3);
	CHECK(pc.outputSlaves == 3);
	CHECK(pc.expectedWkc() == 9);
	m.rescan();
	CHECK(m.slaves().size() == 3);
	d.pdo().fifoEnable(false);
}

TEST_CASE("bus: refused state changes report the slave, the state reached and the AL status", "[bus][states]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	integ::initBus(d);
	CHECK(d.bus().stateGet(kAllSlaves).state() == State::Init);
	// INIT -> SAFE-OP skips PRE-OP: 0x0011 (AKD2G table, ETG.1000)
	const auto e = integ::thrown<ecmxf::AlStatusError>([&] { d.bus().stateSet(0, State::SafeOp); });
	CHECK(e.slave() == 0);
	CHECK(e.requested() == State::SafeOp);
	CHECK(e.reached() == State::Init);
	CHECK(e.alStatusCode() == 0x0011);
	CHECK(e.errnoValue() == EREMOTEIO);
	CHECK_THAT(e.what(), Contains("AL status 0x0011 Invalid requested state change"));
	const ecmxf::SlaveInfo s0 = d.bus().slaveInfo(0);
	CHECK(s0.alStatusCode == 0x0011);
	CHECK(s0.state == State::Init);
	// the next request acknowledges the error
	d.bus().stateSet(kAllSlaves, State::PreOp);
	CHECK(d.bus().slaveInfo(0).alStatusCode == 0);
	CHECK(d.bus().stateCheck(kAllSlaves, State::PreOp).state() == State::PreOp);
	CHECK_FALSE(d.bus().stateCheck(kAllSlaves, State::PreOp).error());
}

TEST_CASE("SDO: typed reads and writes, strings, and real aborts", "[bus][sdo]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	integ::initBus(d);
	d.bus().stateSet(kAllSlaves, State::PreOp);
	struct Restore {
		ecmxf::Device &d;
		~Restore()
		{
			try {
				d.sdo().write<std::uint16_t>(1, 0x2000, 0, 3200);
				d.sdo().write<std::uint16_t>(0, 0x2000, 0, 3200);
			} catch (...) {
			}
		}
	} restore{ d };

	CHECK(d.sdo().read<std::uint16_t>(0, 0x2001, 0) == 50000);      // 3.5 pulses/rev
	CHECK(d.sdo().read<std::uint32_t>(1, 0x1000, 0) == 0x00030192u); // CiA 402 stepper
	CHECK(d.sdo().read<std::uint32_t>(1, 0x1018, 1) == 0x00000E5Cu); // vendor
	CHECK(d.sdo().read<std::uint32_t>(1, 0x1018, 2) == 0x584u);      // product
	CHECK(d.sdo().read<std::uint32_t>(1, 0x1018, 4) == 2u);          // serial = position + 1
	CHECK(d.sdo().readString(0, 0x1008, 0) == "EST-584");
	CHECK(d.sdo().upload(0, 0x2001, 0) == std::vector<std::uint8_t>{ 0x50, 0xC3 });

	// 0x2000 peak current: 3200 mA by default, 1..8400
	CHECK(d.sdo().read<std::uint16_t>(1, 0x2000, 0) == 3200);
	d.sdo().write<std::uint16_t>(1, 0x2000, 0, 2000);
	CHECK(d.sdo().read<std::uint16_t>(1, 0x2000, 0) == 2000);
	CHECK(d.sdo().read<std::uint16_t>(0, 0x2000, 0) == 3200); // the other drive keeps its own

	// a missing object: abort 0x06020000
	const auto e = integ::thrown<ecmxf::SdoError>([&] { (void)d.sdo().read<std::uint32_t>(0, 0x2FFF, 0); });
	CHECK(e.abortCode() == 0x06020000u);
	CHECK_THAT(e.what(), Contains("SDO upload 0x2FFF:00 from slave 0 aborted: 0x06020000 Object not existing"));
	CHECK(d.bus().sdoAbortCode() == 0x06020000u);
	// above the range: 0x06090031, and the EST-584 stores the limit (5.3.3)
	const auto hi = integ::thrown<ecmxf::SdoError>([&] { d.sdo().write<std::uint16_t>(0, 0x2000, 0, 9000); });
	CHECK(hi.abortCode() == 0x06090031u);
	CHECK_THAT(hi.what(), Contains("0x06090031 Value is too great"));
	CHECK(d.sdo().read<std::uint16_t>(0, 0x2000, 0) == 8400);
	// a good transfer after the aborts
	CHECK(d.sdo().read<std::uint16_t>(0, 0x2001, 0) == 50000);
}

TEST_CASE("slaves: SII EEPROM words, raw datagrams, mailbox and the staging flash", "[bus][eeprom]")
{
	Rig r;
	ecmxf::Device &d = r.d();
	integ::initBus(d);
	d.bus().stateSet(kAllSlaves, State::PreOp);

	// SII words 0x08..0x0F: vendor, product, revision, serial (ETG.2010)
	CHECK(d.slaves().eepromRead(0, 0x08) == 0x0E5C);
	CHECK(d.slaves().eepromReadWords(2, 0x08, 8) ==
	      std::vector<std::uint16_t>{ 0x0E5C, 0x0000, 0x1088, 0x0000, 0x0000, 0x0001, 0x0003, 0x0000 });
	CHECK(d.slaves().eepromRead(1, 0x0E) == 2); // serial, low word
	// the size word 0x3E: 2 KiB image = 15 (sim-slaves.rst)
	CHECK(d.slaves().eepromRead(0, 0x3E) == 15);

	// raw datagrams: ESC type register 0x0000 (0x11 drives, 0x12 dio)
	ecmxf::Datagram g;
	g.command = ecmxf::DatagramCommand::APRD;
	g.adp = ecmxf::autoIncrementAddress(0);
	g.ado = 0x0000;
	g.data = { 0 };
	ecmxf::DatagramResult res = d.slaves().rawDatagram(g);
	CHECK(res.workingCounter == 1);
	CHECK(res.data == std::vector<std::uint8_t>{ 0x11 });
	g.command = ecmxf::DatagramCommand::FPRD;
	g.adp = 0x1003;
	res = d.slaves().rawDatagram(g);
	CHECK(res.workingCounter == 1);
	CHECK(res.data == std::vector<std::uint8_t>{ 0x12 });
	// BRD of the configured station address: every slave answers
	g.command = ecmxf::DatagramCommand::BRD;
	g.adp = 0;
	g.ado = 0x0010;
	g.data = { 0, 0 };
	CHECK(d.slaves().rawDatagram(g).workingCounter == 3);

	// the mailboxes are empty; the drives' receive mailbox too
	CHECK(d.slaves().mailboxPending().empty());
	CHECK(d.slaves().receiveMailbox(0).empty());
	const std::vector<bool> poll = d.slaves().mailboxPolling();
	CHECK(poll.size() == 3);

	// the staging flash of FOE_FUNC_REQ: written and read back
	std::vector<std::uint8_t> pattern(300);
	for (std::size_t i = 0; i < pattern.size(); i++)
		pattern[i] = static_cast<std::uint8_t>(i * 7 + 1);
	d.slaves().flashWrite(0x100, pattern);
	CHECK(d.slaves().flashRead(0x100, 300) == pattern);
	// the EST-584 has no FoE (SII mailbox protocols: CoE only)
	CHECK_THROWS_AS(d.slaves().foeRead(0, "log.txt"), ecmxf::Error);
}
