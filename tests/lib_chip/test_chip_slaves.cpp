// SPDX-License-Identifier: MIT
// The slave-facing chip services through the typed calls: the SII EEPROM
// (EEPROM_REQ/GET), raw datagrams (RAW_ECAT_FUNC_REQ/GET), FoE and the
// staging flash (FOE_FUNC_REQ/GET), CoE emergencies, the receive mailbox
// (RECV_MAILBOX, MBX_STAT) and DIRECT_ASSIGN, against the simulator's slave
// models (Documentation/simulator.rst, sim-slaves.rst).

#include "helpers.hpp"
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/bus/slave_access.hpp>

#include <cerrno>
#include <string>

#include <ecmxf/sim/slaves.hpp>

using namespace chiptest;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using ecmxf::Datagram;
using ecmxf::DatagramCommand;
namespace model = ecmxf::sim::model;

namespace {

Datagram datagram(DatagramCommand cmd, std::uint16_t adp, std::uint16_t ado, std::vector<std::uint8_t> data)
{
	Datagram d;
	d.command = cmd;
	d.adp = adp;
	d.ado = ado;
	d.data = std::move(data);
	return d;
}

std::vector<std::uint8_t> pattern(std::size_t n)
{
	std::vector<std::uint8_t> v(n);
	for (std::size_t i = 0; i < n; i++)
		v[i] = static_cast<std::uint8_t>(i * 7 + 3);
	return v;
}

} // namespace

// ---------------------------------------------------------------------------
// EEPROM
// ---------------------------------------------------------------------------

TEST_CASE("EEPROM: the words are the SII the network defines (no INIT_OP needed)", "[lib][chip][eeprom]")
{
	SimDevice s;
	auto &d = *s.dev;
	// identity words 0x08..0x0F: vendor, product code (sim_slaves.hpp)
	CHECK(d.slaves().eepromRead(0, 0x0008) == (model::kVendorId & 0xFFFF));
	CHECK(d.slaves().eepromRead(0, 0x0009) == (model::kVendorId >> 16));
	CHECK(d.slaves().eepromRead(0, 0x000A) == (model::kEst584Product & 0xFFFF));
	CHECK(d.slaves().eepromRead(1, 0x000A) == (model::kEst584Product & 0xFFFF));
	CHECK(d.slaves().eepromRead(2, 0x000A) == (model::kDioProduct & 0xFFFF));
	CHECK(d.slaves().eepromRead(2, 0x000C) == (model::kDioRevision & 0xFFFF));
	CHECK(d.slaves().eepromRead(2, 0x000D) == (model::kDioRevision >> 16));

	const std::vector<std::uint16_t> sii = s.chip().network().at(1).sii();
	REQUIRE(sii.size() >= 64);
	CHECK(d.slaves().eepromReadWords(1, 0, 64) == std::vector<std::uint16_t>(sii.begin(), sii.begin() + 64));
}

TEST_CASE("EEPROM: a written word is read back and becomes the alias at the next INIT_OP",
	  "[lib][chip][eeprom]")
{
	SimDevice s;
	auto &d = *s.dev;
	d.slaves().eepromWrite(1, 0x0004, 0x1234); // station alias
	CHECK(d.slaves().eepromRead(1, 0x0004) == 0x1234);
	s.initOp();
	CHECK(s.slaveInfo16(1, 5) == 0x1234); // SLV_INFO_GET item 5: alias
}

TEST_CASE("EEPROM: failures name the slave, the word and the chip's error code", "[lib][chip][eeprom]")
{
	SimDevice s;
	auto &d = *s.dev;
	auto e = thrown([&] { (void)d.slaves().eepromRead(0, 0xFFFF); });
	CHECK(e.errnoValue() == EREMOTEIO);
	CHECK_THAT(e.what(), Equals("EEPROM read of slave 0, word 0xFFFF: EEPROM_REQ: the async command failed: "
				    "EEPROM_GET error code 1 (address beyond the slave's EEPROM)"));
	REQUIRE(e.errorStatus());
	CHECK((*e.errorStatus() & 0x08) == 0x08);

	s.chip().faults().slaveDropped = 1;
	e = thrown([&] { d.slaves().eepromWrite(1, 0x0004, 1); });
	CHECK(e.errnoValue() == EREMOTEIO);
	CHECK_THAT(e.what(), Equals("EEPROM write of slave 1, word 0x0004: EEPROM_REQ: the async command failed: "
				    "EEPROM_GET error code 2 (no answer from the slave)"));
	s.chip().faults().slaveDropped = -1;

	e = thrown([&] { (void)d.slaves().eepromRead(5, 0); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("EEPROM read of slave 5, word 0x0000: EEPROM_REQ: the chip refused the command "
				    "(error status bit 7, command error: slave 5 does not exist)"));
	e = thrown([&] { (void)d.slaves().eepromRead(128, 0); });
	CHECK_THAT(e.what(), Equals("EEPROM read of slave 128, word 0x0000: slave position 128 is out of range "
				    "(0..127)"));
	e = thrown([&] { (void)d.slaves().eepromReadWords(0, 0xFFFF, 2); });
	CHECK_THAT(e.what(), Equals("EEPROM read of slave 0: 2 words from word 0xFFFF do not fit the EEPROM's "
				    "address space (1..65536 words up to word 0xFFFF)"));
	// the chip works on
	CHECK(d.slaves().eepromRead(0, 0x0008) == (model::kVendorId & 0xFFFF));
}

// ---------------------------------------------------------------------------
// raw datagrams
// ---------------------------------------------------------------------------

TEST_CASE("raw datagrams: FPRD of AL status, APRD of station addresses, BRD, LRD", "[lib][chip][raw]")
{
	SimDevice s;
	auto &d = *s.dev;
	s.toPreOp();
	// station addresses 0x1001 + position; AL status 0x0130 = PRE-OP
	ecmxf::DatagramResult r = d.slaves().rawDatagram(datagram(DatagramCommand::FPRD, 0x1001, 0x0130, { 0, 0 }));
	CHECK(r.workingCounter == 1);
	CHECK(r.data == std::vector<std::uint8_t>{ 0x02, 0x00 });
	r = d.slaves().rawDatagram(datagram(DatagramCommand::APRD, ecmxf::autoIncrementAddress(2), 0x0010, { 0, 0 }));
	CHECK(r.workingCounter == 1);
	CHECK(r.data == std::vector<std::uint8_t>{ 0x03, 0x10 });
	CHECK(ecmxf::autoIncrementAddress(0) == 0x0000);
	CHECK(ecmxf::autoIncrementAddress(2) == 0xFFFE);
	r = d.slaves().rawDatagram(datagram(DatagramCommand::BRD, 0, 0x0130, { 0 }));
	CHECK(r.workingCounter == 3);
	CHECK(r.data == std::vector<std::uint8_t>{ 0x02 });
	r = d.slaves().rawDatagram(datagram(DatagramCommand::LRD, 0, 0, { 0, 0, 0, 0 }));
	CHECK(r.workingCounter == 0); // no FMMU maps the logical space
	// no slave at that station address
	r = d.slaves().rawDatagram(datagram(DatagramCommand::FPRD, 0x2000, 0x0130, { 0xAA }));
	CHECK(r.workingCounter == 0);
	CHECK(r.data == std::vector<std::uint8_t>{ 0xAA });

	// FPWR of AL control: slave 0 back to INIT
	r = d.slaves().rawDatagram(datagram(DatagramCommand::FPWR, 0x1001, 0x0120, { 0x01, 0x00 }));
	CHECK(r.workingCounter == 1);
	r = d.slaves().rawDatagram(datagram(DatagramCommand::FPRD, 0x1001, 0x0130, { 0 }));
	CHECK(r.data == std::vector<std::uint8_t>{ 0x01 });
	r = d.slaves().rawDatagram(datagram(DatagramCommand::FPRD, 0x1002, 0x0130, { 0 }));
	CHECK(r.data == std::vector<std::uint8_t>{ 0x02 });
}

TEST_CASE("raw datagrams: lengths and commands are checked, long ones need a larger data section",
	  "[lib][chip][raw]")
{
	SimDevice s;
	auto &d = *s.dev;
	auto e = thrown([&] { d.slaves().rawDatagram(datagram(DatagramCommand::APRD, 0, 0x0130, {})); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(),
		   Equals("APRD ADP 0x0000 ADO 0x0130: datagram length 0 is out of range (1..256 bytes)"));
	e = thrown([&] { d.slaves().rawDatagram(datagram(static_cast<DatagramCommand>(3), 0, 0, { 0 })); });
	CHECK_THAT(e.what(), Equals("RAW_ECAT_FUNC_REQ: datagram command 3 is not one the chip sends (1 APRD, 2 "
				    "APWR, 4 FPRD, 5 FPWR, 7 BRD, 8 BWR, 10 LRD, 11 LWR, 12 LRW, 13 ARMW, 14 FRMW)"));
	e = thrown([&] { d.slaves().rawDatagram(datagram(DatagramCommand::BRD, 0, 0, std::vector<std::uint8_t>(257))); });
	CHECK_THAT(e.what(), Contains("datagram length 257 is out of range (1..256 bytes)"));
	e = thrown([&] { d.slaves().rawDatagram(datagram(DatagramCommand::BRD, 0, 0x1000, std::vector<std::uint8_t>(100))); });
	CHECK(e.errnoValue() == EMSGSIZE);
	CHECK_THAT(e.what(), Equals("BRD ADP 0x0000 ADO 0x1000: RAW_ECAT_FUNC_REQ: 100 data bytes need a data "
				    "section of 120 bytes, the link has 112 (setDataSize())"));

	s.initOp();
	d.chip().setDataSize(512);
	const ecmxf::DatagramResult r =
		d.slaves().rawDatagram(datagram(DatagramCommand::BRD, 0, 0x0130, std::vector<std::uint8_t>(256)));
	CHECK(r.workingCounter == 3);
	REQUIRE(r.data.size() == 256);
	CHECK(r.data[0] == 0x01); // all in INIT
}

// ---------------------------------------------------------------------------
// FoE and the staging flash
// ---------------------------------------------------------------------------

TEST_CASE("FoE round trip on the servo network: firmware.bin in BOOT, then the log", "[lib][chip][foe]")
{
	SimDevice s("servo-io.net");
	auto &d = *s.dev;
	s.initOp();
	// servo 0 to BOOT the way a master does it: SM0/SM1 to the bootstrap
	// mailbox of the SII (words 0x14..0x17), then AL control INIT -> BOOT
	const std::vector<std::uint16_t> boot = d.slaves().eepromReadWords(0, 0x0014, 4);
	REQUIRE(boot == std::vector<std::uint16_t>{ 0x1000, 512, 0x1200, 512 });
	std::vector<std::uint8_t> sm;
	put16(sm, boot[0]);
	put16(sm, boot[1]);
	sm.insert(sm.end(), { 0x26, 0x00, 0x01, 0x00 });
	put16(sm, boot[2]);
	put16(sm, boot[3]);
	sm.insert(sm.end(), { 0x22, 0x00, 0x01, 0x00 });
	CHECK(d.slaves().rawDatagram(datagram(DatagramCommand::FPWR, 0x1001, 0x0800, sm)).workingCounter == 1);
	d.slaves().rawDatagram(datagram(DatagramCommand::FPWR, 0x1001, 0x0120, { 0x03, 0x00 }));
	REQUIRE(d.slaves().rawDatagram(datagram(DatagramCommand::FPRD, 0x1001, 0x0130, { 0 })).data[0] == 0x03);

	const std::vector<std::uint8_t> fw = pattern(1000); // 11 flash chunks at 112 bytes
	d.slaves().foeWrite(0, "firmware.bin", fw);
	auto *servo = dynamic_cast<ecmxf::sim::ServoModel *>(&s.chip().network().at(0));
	REQUIRE(servo);
	CHECK(servo->firmware() == fw);
	// the staged bytes are in the chip's flash at address 0
	CHECK(d.slaves().flashRead(0, 1000) == fw);

	const std::vector<std::uint8_t> log = d.slaves().foeRead(0, "log.txt", { 0, 0x2000, {} });
	const std::string text(log.begin(), log.end());
	CHECK_THAT(text, Contains("firmware.bin written (1000 bytes)\n"));
	CHECK(d.slaves().flashRead(0x2000, static_cast<std::uint32_t>(log.size())) == log);

	// with a larger data section the chunks are 256 bytes; same result
	d.chip().setDataSize(1408);
	const std::vector<std::uint8_t> fw2 = pattern(3000);
	d.slaves().foeWrite(0, "firmware.bin", fw2, { 0x1234, 0x10000, std::chrono::microseconds(500000) });
	CHECK(servo->firmware() == fw2);
}

TEST_CASE("FoE failures carry the FoE error code, arguments are checked", "[lib][chip][foe]")
{
	SimDevice s("servo-io.net");
	auto &d = *s.dev;
	auto e = thrown([&] { (void)d.slaves().foeRead(0, "log.txt"); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("FoE read of \"log.txt\" from slave 0: FOE_FUNC_REQ: the chip refused the command "
				    "(error status bit 7, command error: slave 0 does not exist or the bus is not "
				    "initialised (ECAT_INIT_OP)); the command exists only in firmware of manual "
				    "ver. 050"));
	s.toPreOp();
	e = thrown([&] { (void)d.slaves().foeRead(0, "firmware.bin"); });
	CHECK(e.errnoValue() == EREMOTEIO);
	CHECK_THAT(e.what(), Equals("FoE read of \"firmware.bin\" from slave 0: FOE_FUNC_REQ: the async command "
				    "failed: FoE error 0x00008002 (access denied)"));
	e = thrown([&] { (void)d.slaves().foeRead(1, "nothing.txt"); });
	CHECK_THAT(e.what(), Contains("FoE error 0x00008001 (file not found)"));
	const std::vector<std::uint8_t> fw = pattern(10);
	e = thrown([&] { d.slaves().foeWrite(1, "firmware.bin", fw); });
	CHECK(e.errnoValue() == EREMOTEIO);
	CHECK_THAT(e.what(), Equals("FoE write of \"firmware.bin\" to slave 1: FOE_FUNC_REQ: the async command "
				    "failed: FoE error 0x00008008 (bootstrap only)"));
	e = thrown([&] { (void)d.slaves().foeRead(2, "log.txt"); }); // the digital I/O has no FoE
	CHECK_THAT(e.what(), Contains("FoE error 0x08000000 (general error (e.g. the slave has no FoE))"));

	e = thrown([&] { (void)d.slaves().foeRead(0, std::string(93, 'x')); });
	CHECK(e.errnoValue() == EMSGSIZE);
	CHECK_THAT(e.what(), Contains(": the file name (93 bytes) does not fit the data section (at most 92 bytes "
				      "now; setDataSize())"));
	e = thrown([&] { (void)d.slaves().foeRead(0, ""); });
	CHECK_THAT(e.what(), Equals("FoE read of \"\" from slave 0: empty file name"));
	e = thrown([&] { (void)d.slaves().foeRead(0, "log.txt", { 0, 0x40000, {} }); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("FoE read of \"log.txt\" from slave 0: flash address 0x40000 is out of range "
				    "(0..0x3FFFF)"));
	e = thrown([&] { d.slaves().foeWrite(0, "a.bin", fw, { 0, 0x3FFFA, {} }); });
	CHECK_THAT(e.what(), Equals("FoE write of \"a.bin\" to slave 0: 10 bytes from flash address 0x3FFFA run past "
				    "the end of the 256 KiB flash (0x40000)"));
}

TEST_CASE("staging flash: erased 0xFF, chunked writes and reads round trip", "[lib][chip][foe]")
{
	SimDevice s;
	auto &d = *s.dev;
	CHECK(d.slaves().flashRead(0x3FFF0, 16) == std::vector<std::uint8_t>(16, 0xFF));
	const std::vector<std::uint8_t> v = pattern(300);
	d.slaves().flashWrite(0x100, v);
	CHECK(d.slaves().flashRead(0x100, 300) == v);
	CHECK(d.slaves().flashRead(0xFF, 1) == std::vector<std::uint8_t>{ 0xFF });
	const auto e = thrown([&] { (void)d.slaves().flashRead(0x3FFFF, 2); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Equals("FOE_FUNC_REQ flash read: 2 bytes from flash address 0x3FFFF run past the end "
				    "of the 256 KiB flash (0x40000)"));
}

// ---------------------------------------------------------------------------
// emergencies, receive mailbox
// ---------------------------------------------------------------------------

TEST_CASE("COE_EMERGENCY: a drive fault's emergency, read by the polling master", "[lib][chip][mailbox]")
{
	SimDevice s;
	auto &d = *s.dev;
	CHECK(d.slaves().coeEmergencies().empty());
	s.toPreOp();
	auto *drive = dynamic_cast<ecmxf::sim::Cia402Model *>(&s.chip().network().at(1));
	REQUIRE(drive);
	drive->injectFault(0x4310); // temperature: error register 0x01 | 0x08
	d.link().sleepFor(std::chrono::milliseconds(2));
	const std::vector<ecmxf::CoeEmergency> e = d.slaves().coeEmergencies(8);
	REQUIRE(e.size() == 1);
	CHECK(e[0].entry == 0);
	CHECK(e[0].slave == 1);
	CHECK(e[0].sequence == 1);
	CHECK(e[0].errorCode == 0x4310);
	CHECK(e[0].errorRegister == 0x09);
	CHECK(e[0].data == std::array<std::uint8_t, 5>{});

	auto err = thrown([&] { (void)d.slaves().coeEmergencies(0); });
	CHECK(err.errnoValue() == EINVAL);
	CHECK_THAT(err.what(), Equals("COE_EMERGENCY: count 0 is out of range (1..8)"));
	err = thrown([&] { (void)d.slaves().coeEmergencies(9); });
	CHECK_THAT(err.what(), Equals("COE_EMERGENCY: count 9 is out of range (1..8)"));
	d.chip().setDataSize(32);
	err = thrown([&] { (void)d.slaves().coeEmergencies(3); });
	CHECK(err.errnoValue() == EMSGSIZE);
	CHECK_THAT(err.what(), Equals("COE_EMERGENCY: 3 entries need 36 data bytes, the data section has 32"));
	CHECK(d.slaves().coeEmergencies(2).size() == 1);
}

TEST_CASE("receive mailbox: polling off, MBX_STAT shows the waiting message, RECV_MAILBOX reads it",
	  "[lib][chip][mailbox]")
{
	SimDevice s;
	auto &d = *s.dev;
	s.toPreOp();
	// the master polls the CoE slaves by default; the digital I/O has no mailbox
	CHECK(d.slaves().mailboxPolling() == std::vector<bool>{ true, true, false });
	d.slaves().setMailboxPolling({ false, false, false });
	CHECK(d.slaves().mailboxPolling() == std::vector<bool>{ true, true, false }); // from the next RECONFIG_OP
	s.reconfig();
	CHECK(d.slaves().mailboxPolling() == std::vector<bool>{ false, false, false });
	CHECK(d.slaves().mailboxPending().empty());

	auto *drive = dynamic_cast<ecmxf::sim::Cia402Model *>(&s.chip().network().at(0));
	REQUIRE(drive);
	drive->injectFault(0x2310); // current: error register 0x01 | 0x02
	d.link().sleepFor(std::chrono::milliseconds(2));
	CHECK(d.slaves().mailboxPending() == std::vector<unsigned>{ 0 });
	CHECK(d.slaves().coeEmergencies().empty()); // not polled: not read yet

	// mailbox header (length 10, type CoE), CoE header (service 1), emergency
	const std::vector<std::uint8_t> msg = d.slaves().receiveMailbox(0);
	CHECK(msg == std::vector<std::uint8_t>{ 10, 0, 0, 0, 0, 0x03, 0x00, 0x10, 0x10, 0x23, 0x03, 0, 0, 0, 0, 0 });
	CHECK(d.slaves().mailboxPending().empty());
	// reading it logged it
	const std::vector<ecmxf::CoeEmergency> e = d.slaves().coeEmergencies(1);
	REQUIRE(e.size() == 1);
	CHECK(e[0].slave == 0);
	CHECK(e[0].errorCode == 0x2310);
	CHECK(e[0].errorRegister == 0x03);
	// an empty mailbox
	CHECK(d.slaves().receiveMailbox(0).empty());
	// parts of the last message, at offsets
	CHECK(d.slaves().readMailbox(0, 4) == std::vector<std::uint8_t>(4, 0));

	auto err = thrown([&] { (void)d.slaves().readMailbox(0, 0); });
	CHECK(err.errnoValue() == EINVAL);
	CHECK_THAT(err.what(), Equals("RECV_MAILBOX (read): length 0 is out of range (1..112, the data section)"));
	err = thrown([&] { d.slaves().setMailboxPolling({ true, true }); });
	CHECK_THAT(err.what(), Equals("MBX_STAT (set polling): 2 polling flags given for 3 slaves (one per slave "
				      "found by ECAT_INIT_OP)"));
	s.chip().faults().slaveDropped = 1;
	err = thrown([&] { d.slaves().fetchMailbox(1); });
	CHECK(err.errnoValue() == EREMOTEIO);
	CHECK_THAT(err.what(), Equals("RECV_MAILBOX of slave 1: the async command failed: slave 1 did not answer"));
	s.chip().faults().slaveDropped = -1;
	err = thrown([&] { d.slaves().fetchMailbox(3); });
	CHECK(err.errnoValue() == EINVAL);
	CHECK_THAT(err.what(), Equals("RECV_MAILBOX of slave 3: the chip refused the command (error "
				      "status bit 7, command error: slave 3 does not exist or the bus is not "
				      "initialised (ECAT_INIT_OP)); the command exists only in firmware of manual "
				      "ver. 050"));
}

TEST_CASE("DIRECT_ASSIGN: lengths used instead of the slave's from the next layout", "[lib][chip][mailbox]")
{
	SimDevice s;
	auto &d = *s.dev;
	s.initOp();
	const std::uint16_t outBefore = s.slaveInfo16(2, 8);
	d.slaves().setDirectAssignLength(2, ecmxf::ProcessDataSide::Output, 4);
	d.slaves().setDirectAssignLength(2, ecmxf::ProcessDataSide::Input, 6);
	d.slaves().setDirectAssign(2, true);
	CHECK(s.slaveInfo16(2, 8) == outBefore); // not before the next layout
	s.reconfig();
	CHECK(s.slaveInfo16(2, 8) == 4);
	CHECK(s.slaveInfo16(2, 9) == 6);
	d.slaves().setDirectAssign(2, false);
	s.reconfig();
	CHECK(s.slaveInfo16(2, 8) == outBefore);

	const auto e = thrown([&] { d.slaves().setDirectAssign(3, true); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK_THAT(e.what(), Contains("DIRECT_ASSIGN: the chip refused the command (error status bit 7, command "
				      "error: slave 3 does not exist"));
}
