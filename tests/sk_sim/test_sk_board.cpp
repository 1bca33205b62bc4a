// SPDX-License-Identifier: MIT
// The simulated ECM-SK board: board settings, the frame, Busy, the
// commands of the ECM slot and the SDO slot, and where table 1.3 refuses
// them.  Every check reads the board's answers through the frame.

#include "sk_host.hpp"

#include <stdexcept>

#include <ecmxf/sim/slaves.hpp>

using namespace skt;
using ecmxf::sk::BoardConfig;

TEST_CASE("sk board settings: parse the keys, refuse unknown keys and bad values")
{
	auto c = BoardConfig::parse("slot=16&test=1,abandon=0&ex=3&fifo=512&busy_us=50&spi_hz=6000000&lio=0x3F");
	CHECK(c.slotSize == 16);
	CHECK(c.testMode);
	CHECK_FALSE(c.fifoAbandon);
	CHECK(c.extensions == 3u);
	CHECK(c.fifoDepth == 512u);
	CHECK(c.busyTime == 50us);
	CHECK(c.spiHz == 6000000u);
	CHECK(c.lioInputs == 0x3Fu);
	CHECK(BoardConfig::parse("").slotSize == 12);
	for (const char *bad : { "slot=14", "slot=", "slot=twelve", "test=2", "abandon=-1", "ex=4",
				 "fifo=159", "fifo=5000", "paced=2", "paced=", "busy_us=0", "spi_hz=1", "lio=64", "colour=red",
				 "slot", "=12", "slot=12x" }) {
		INFO(bad);
		CHECK_THROWS_AS(BoardConfig::parse(bad), std::invalid_argument);
	}
}

TEST_CASE("sk board: more slaves than the frame has slots for is refused")
{
	std::string n41, n31;
	for (int i = 0; i < 41; i++)
		n41 += "slave dio\n";
	for (int i = 0; i < 31; i++)
		n31 += "slave dio\n";
	CHECK_THROWS_AS(ecmxf::sk::SimBoard(net(n41)), std::invalid_argument);
	BoardConfig c16;
	c16.slotSize = 16;
	CHECK_THROWS_AS(ecmxf::sk::SimBoard(net(n31), c16), std::invalid_argument);
	CHECK_NOTHROW(ecmxf::sk::SimBoard(net(n31)));
	BoardConfig bad;
	bad.slotSize = 13;
	CHECK_THROWS_AS(ecmxf::sk::SimBoard(net("slave dio\n"), bad), std::invalid_argument);
}

TEST_CASE("sk board: powers on in INIT, frames are 504 or 512 bytes")
{
	Host h;
	CHECK(h.b.frameSize() == 504);
	auto r = h.ecmRsp(h.xfer());
	CHECK(r.cmd == 0);
	CHECK(r.state == ECMSK_STATE_INIT);
	BoardConfig c;
	c.slotSize = 16;
	Host h16("slave dio\n", c);
	CHECK(h16.b.frameSize() == 512);
}

TEST_CASE("sk board: a command's answer comes with the next exchange (LIO_RD)")
{
	Host h;
	h.b.setLioInputs(0x15);
	h.ecm(ECMSK_CMD_LIO_RD);
	auto first = h.ecmRsp(h.xfer());
	CHECK(first.cmd == 0);
	CHECK(first.data1 == 0u);
	auto second = h.ecmRsp(h.xfer());
	CHECK(second.cmd == ECMSK_CMD_LIO_RD);
	CHECK(second.data1 == 0x15u);
	// GET_STATUS keeps the last result outside OP (2.1.1)
	auto third = h.ecmRsp(h.xfer());
	CHECK(third.cmd == 0);
	CHECK(third.data1 == 0x15u);
}

TEST_CASE("sk board: LIO_WR sets the ECM IC's outputs in any state, values above 6 bits are refused")
{
	Host h;
	h.ecm(ECMSK_CMD_LIO_WR, 0x2A);
	CHECK(h.ecmRsp(h.answer()).cmd == ECMSK_CMD_LIO_WR);
	CHECK(h.b.lioOutputs() == 0x2Au);
	h.ecm(ECMSK_CMD_LIO_WR, 0x40);
	CHECK(h.ecmRsp(h.answer()).cmd == 0);
	CHECK(h.b.lioOutputs() == 0x2Au);
	REQUIRE(h.setState(ECMSK_STATE_PREOP));
	h.ecm(ECMSK_CMD_LIO_WR, 0x01);
	h.answer();
	CHECK(h.b.lioOutputs() == 0x01u);
}

TEST_CASE("sk board: Busy rises with a transfer and falls after the frame is processed")
{
	BoardConfig c;
	c.busyTime = 40us;
	Host h("slave dio\n", c);
	CHECK_FALSE(h.b.busy());
	const auto t0 = h.b.now();
	h.xfer();
	CHECK(h.b.now() - t0 == h.b.wireTime());
	CHECK(h.b.wireTime() == 168us); // 504 bytes at 24 MHz
	CHECK(h.b.busy());
	h.b.advance(39us);
	CHECK(h.b.busy());
	h.b.advance(1us);
	CHECK_FALSE(h.b.busy());
}

TEST_CASE("sk board: a transfer while Busy is high, or of another length, is not processed")
{
	Host h;
	h.xfer();
	REQUIRE(h.b.busy());
	Frame mosi(504, 0), miso(504, 0xEE);
	mosi[0] = ECMSK_CMD_LIO_WR;
	mosi[4] = 7;
	h.b.exchange(mosi, miso);
	CHECK(miso == Frame(504, 0));
	CHECK(h.b.stats().whileBusy == 1u);
	h.waitReady();
	CHECK(h.b.lioOutputs() == 0u);
	Frame shortMosi(503, 0), shortMiso(503, 0xEE);
	shortMosi[0] = ECMSK_CMD_LIO_WR;
	shortMosi[4] = 7;
	h.b.exchange(shortMosi, shortMiso);
	CHECK(shortMiso == Frame(503, 0));
	CHECK(h.b.stats().badLength == 1u);
	h.waitReady();
	CHECK(h.b.lioOutputs() == 0u);
}

TEST_CASE("sk board: SET_STATE takes several cycles, Current State follows INIT -> PRE-OP -> SAFE-OP")
{
	Host h;
	h.ecm(ECMSK_CMD_SET_STATE, ECMSK_STATE_PREOP);
	h.xfer();
	auto r = h.ecmRsp(h.xfer());
	CHECK(r.cmd == ECMSK_CMD_SET_STATE);
	CHECK(r.state == ECMSK_STATE_INIT); // not yet
	CHECK(h.reach(ECMSK_STATE_PREOP));
	// default types (IO) do not match the servo: SAFE-OP is refused
	h.ecm(ECMSK_CMD_SET_STATE, ECMSK_STATE_SAFEOP);
	h.xfer();
	CHECK_FALSE(h.reach(ECMSK_STATE_SAFEOP, 50ms));
	CHECK(h.b.state() == ECMSK_STATE_PREOP);
	CHECK(h.b.lastError().find("SET_AXIS") != std::string::npos);
	// SET_STATE with a value that is no state is refused
	h.ecm(ECMSK_CMD_SET_STATE, 3);
	CHECK(h.ecmRsp(h.answer()).cmd == 0);
}

TEST_CASE("sk board: SET_AXIS answers the slave count in PRE-OP (0 in INIT) and checks the types")
{
	Host h;
	std::uint8_t types[3] = { ECMSK_AXIS_DRIVE, ECMSK_AXIS_STEP, ECMSK_AXIS_IO };
	std::uint32_t topo = 0;
	REQUIRE(ecmsk_axis_topology(types, 3, 0, &topo) == 0);
	h.ecm(ECMSK_CMD_SET_AXIS, topo, 0);
	auto r = h.ecmRsp(h.answer());
	CHECK(r.cmd == ECMSK_CMD_SET_AXIS);
	CHECK(r.data1 == 0u); // INIT
	REQUIRE(h.setState(ECMSK_STATE_PREOP));

	SECTION("matching types are taken") {
		h.ecm(ECMSK_CMD_SET_AXIS, topo, 0);
		r = h.ecmRsp(h.answer());
		CHECK(r.data1 == 3u);
		CHECK(r.data2 == 0u);
		CHECK(h.b.slaveType(1) == ECMSK_AXIS_DRIVE);
		CHECK(h.b.slaveType(2) == ECMSK_AXIS_STEP);
	}
	SECTION("a type that is not the slave's: the group is refused, the mask says which") {
		std::uint8_t wrong[3] = { ECMSK_AXIS_STEP, ECMSK_AXIS_STEP, ECMSK_AXIS_HSP };
		REQUIRE(ecmsk_axis_topology(wrong, 3, 0, &topo) == 0);
		h.ecm(ECMSK_CMD_SET_AXIS, topo, 0);
		r = h.ecmRsp(h.answer());
		CHECK(r.cmd == ECMSK_CMD_SET_AXIS);
		CHECK(r.data2 == 0x5u); // slaves 1 and 3
		CHECK(h.b.slaveType(1) == ECMSK_AXIS_DRIVE); // as set in INIT
		CHECK(h.b.slaveType(3) == ECMSK_AXIS_IO);
	}
	SECTION("a type for a slave that is not there") {
		h.ecm(ECMSK_CMD_SET_AXIS, 0xFFFF3130u, 0); // 1 Drive, 2 STEP, 3 IO, 4 STEP
		r = h.ecmRsp(h.answer());
		CHECK(r.data2 == 0x8u);
	}
	SECTION("zero nibbles (Drive, the default value) for the slaves that are not there: taken") {
		// as a host that fills the whole word sends it: 1 Drive, 2 STEP,
		// 3 IO, 4..8 zero (table 2.3)
		h.ecm(ECMSK_CMD_SET_AXIS, 0x00000130u, 0);
		r = h.ecmRsp(h.answer());
		CHECK(r.cmd == ECMSK_CMD_SET_AXIS);
		CHECK(r.data1 == 3u);
		CHECK(r.data2 == 0u);
		CHECK(h.b.slaveType(1) == ECMSK_AXIS_DRIVE);
		CHECK(h.b.slaveType(2) == ECMSK_AXIS_STEP);
		CHECK(h.b.slaveType(3) == ECMSK_AXIS_IO);
		// then DRIVE_MODE is taken and SAFE-OP comes
		h.slave(1, ECMSK_CMD_DRIVE_MODE, 1, ECMSK_MODE_CSP, ECMSK_SYNC_DCSYNC);
		h.slave(2, ECMSK_CMD_DRIVE_MODE, 2, ECMSK_MODE_CSP, ECMSK_SYNC_DCSYNC);
		const auto &a = h.answer();
		CHECK(h.slaveRsp(a, 1).cmd == ECMSK_CMD_DRIVE_MODE);
		CHECK(h.slaveRsp(a, 2).cmd == ECMSK_CMD_DRIVE_MODE);
		CHECK(h.setState(ECMSK_STATE_SAFEOP));
		// the other groups: all zero, no slave there, nothing refused
		h.ecm(ECMSK_CMD_SET_STATE, ECMSK_STATE_PREOP);
		h.xfer();
		REQUIRE(h.reach(ECMSK_STATE_PREOP));
		h.ecm(ECMSK_CMD_SET_AXIS, 0u, 1);
		r = h.ecmRsp(h.answer());
		CHECK(r.cmd == ECMSK_CMD_SET_AXIS);
		CHECK(r.data2 == 0u);
	}
	SECTION("group 5 and unknown types are refused") {
		h.ecm(ECMSK_CMD_SET_AXIS, 0xFFFFFFFFu, 5);
		CHECK(h.ecmRsp(h.answer()).cmd == 0);
		h.ecm(ECMSK_CMD_SET_AXIS, 0xFFFFFF4Fu, 0);
		CHECK(h.ecmRsp(h.answer()).data2 == 0x2u);
	}
}

TEST_CASE("sk board: SET_DC takes 250 * 2^n us with FIX 0xFFFF, in INIT and PRE-OP only")
{
	Host h("slave dio\n");
	for (std::uint32_t us : { 250u, 500u, 2000u, 1000u }) {
		h.ecm(ECMSK_CMD_SET_DC, us, 0, ECMSK_DC_FIX);
		CHECK(h.ecmRsp(h.answer()).cmd == ECMSK_CMD_SET_DC);
		CHECK(h.b.cycleUs() == us);
	}
	for (std::uint32_t us : { 0u, 125u, 750u, 1500u }) {
		h.ecm(ECMSK_CMD_SET_DC, us, 0, ECMSK_DC_FIX);
		CHECK(h.ecmRsp(h.answer()).cmd == 0);
		CHECK(h.b.cycleUs() == 1000u);
	}
	h.ecm(ECMSK_CMD_SET_DC, 500, 0, 0x1234);
	CHECK(h.ecmRsp(h.answer()).cmd == 0);
	REQUIRE(h.setState(ECMSK_STATE_SAFEOP));
	h.ecm(ECMSK_CMD_SET_DC, 500, 0, ECMSK_DC_FIX);
	CHECK(h.ecmRsp(h.answer()).cmd == 0);
	CHECK(h.b.cycleUs() == 1000u);
}

TEST_CASE("sk board: SET_EX is saved and takes effect at the next power-on")
{
	Host h("slave dio\n");
	h.ecm(ECMSK_CMD_SET_EX, ECMSK_EX_CMD_CRC | ECMSK_EX_RSP_CRC);
	CHECK(h.ecmRsp(h.answer()).cmd == ECMSK_CMD_SET_EX);
	CHECK(h.b.extensionsSaved() == 3u);
	CHECK(h.b.extensionsInForce() == 0u);
	auto r = h.xfer();
	CHECK(r[3] == 0); // no response CRC yet
	h.ecm(ECMSK_CMD_SET_EX, 4);
	CHECK(h.ecmRsp(h.answer()).cmd == 0);
	CHECK(h.b.extensionsSaved() == 3u);

	h.b.powerCycle();
	CHECK(h.b.extensionsInForce() == 3u);
	r = h.xfer();
	CHECK(ecmsk_frame_crc_ok(r.data(), r.size()));
	CHECK(r[3] != 0);
	// a command frame with a bad CRC is refused and counted
	h.waitReady();
	Frame mosi(504, 0), miso(504, 0);
	mosi[0] = ECMSK_CMD_LIO_WR;
	mosi[4] = 5;
	ecmsk_frame_seal(mosi.data(), mosi.size());
	mosi[3] ^= 0x01;
	h.b.exchange(mosi, miso);
	h.waitReady();
	CHECK(h.b.lioOutputs() == 0u);
	CHECK(h.b.crcErrors() == 1);
	CHECK(h.ecmRsp(h.xfer()).crc_errors == 1);
	// the same frame with its CRC is carried out
	h.ecm(ECMSK_CMD_LIO_WR, 5);
	h.answer();
	CHECK(h.b.lioOutputs() == 5u);
}

TEST_CASE("sk board: SET_EX is refused in OP")
{
	Host h("slave dio\n");
	h.toOp({ ECMSK_AXIS_IO });
	h.ecm(ECMSK_CMD_SET_EX, 1);
	h.xfer();
	CHECK(h.b.extensionsSaved() == 0u);
	CHECK(h.b.stats().refused >= 1u);
}

TEST_CASE("sk board: SW_RESET goes back to INIT, holds Busy, forgets the settings")
{
	Host h("slave dio\n");
	h.toOp({ ECMSK_AXIS_IO }, 500);
	h.ecm(ECMSK_CMD_LIO_WR, 3);
	h.answer();
	h.ecm(ECMSK_CMD_SW_RESET);
	h.xfer();
	CHECK(h.b.busy());
	h.b.advance(9ms);
	CHECK(h.b.busy());
	h.waitReady();
	CHECK(h.b.state() == ECMSK_STATE_INIT);
	CHECK(h.b.cycleUs() == 1000u);
	CHECK(h.b.lioOutputs() == 0u);
	auto r = h.ecmRsp(h.xfer());
	CHECK(r.state == ECMSK_STATE_INIT);
	CHECK(r.cmd == 0);
}

TEST_CASE("sk board: SDO_RD and SDO_WR through the SDO slot, fetched with GET_STATUS")
{
	Host h;
	SECTION("refused in INIT") {
		auto r = h.sdoRun(ECMSK_CMD_SDO_RD, 1, 0x1000, 0);
		CHECK(r.cmd == 0);
	}
	SECTION("in PRE-OP") {
		REQUIRE(h.setState(ECMSK_STATE_PREOP));
		h.sdo(ECMSK_CMD_SDO_RD, 1, 0x1018, 1);
		h.xfer();
		auto busy = h.sdoRsp(h.xfer());
		CHECK(busy.cmd == ECMSK_CMD_SDO_RD);
		CHECK(busy.status == ECMSK_SDO_BUSY);
		auto r = h.sdoRun(ECMSK_CMD_SDO_RD, 1, 0x1018, 1);
		CHECK(r.status == ECMSK_SDO_DONE);
		CHECK(r.value == 0x00000E5Cu);
		CHECK(r.size == 4);
		CHECK(r.index == 0x1018);
		CHECK(r.subindex == 1);

		r = h.sdoRun(ECMSK_CMD_SDO_WR, 2, 0x6098, 0, 1, 37);
		CHECK(r.status == ECMSK_SDO_DONE);
		CHECK(r.value == 37u); // the object value echoed (table 2.9)
		CHECK(r.index == 0x6098);
		r = h.sdoRun(ECMSK_CMD_SDO_WR, 1, 0x607A, 0, 4, 0x12345678u);
		CHECK(r.status == ECMSK_SDO_DONE);
		CHECK(r.value == 0x12345678u);
		r = h.sdoRun(ECMSK_CMD_SDO_WR, 1, 0x5FFF, 0, 4, 7); // failed: the abort code
		CHECK(r.status == ECMSK_SDO_FAILED);
		CHECK(r.value == 0x06020000u);
		r = h.sdoRun(ECMSK_CMD_SDO_RD, 2, 0x6098, 0);
		CHECK(r.value == 37u);
		CHECK(r.size == 1);

		r = h.sdoRun(ECMSK_CMD_SDO_RD, 1, 0x5FFF, 0);
		CHECK(r.status == ECMSK_SDO_FAILED);
		CHECK(r.value == 0x06020000u);
		r = h.sdoRun(ECMSK_CMD_SDO_RD, 1, 0x1008, 0); // a string: longer than 4 bytes
		CHECK(r.status == ECMSK_SDO_FAILED);
		CHECK(r.value == 0x06070012u);
		r = h.sdoRun(ECMSK_CMD_SDO_RD, 7, 0x1000, 0); // no slave 7
		CHECK(r.status == ECMSK_SDO_FAILED);
		CHECK(r.value == 0x08000000u);
	}
}

TEST_CASE("sk board: DRIVE_MODE in PRE-OP for drives only, modes the drive supports, not in OP")
{
	Host h;
	REQUIRE(h.setState(ECMSK_STATE_PREOP));
	std::uint8_t types[3] = { ECMSK_AXIS_DRIVE, ECMSK_AXIS_STEP, ECMSK_AXIS_IO };
	std::uint32_t topo = 0;
	REQUIRE(ecmsk_axis_topology(types, 3, 0, &topo) == 0);
	h.ecm(ECMSK_CMD_SET_AXIS, topo, 0);
	h.answer();
	h.slave(1, ECMSK_CMD_DRIVE_MODE, 9, ECMSK_MODE_CSV, ECMSK_SYNC_DCSYNC);
	h.slave(2, ECMSK_CMD_DRIVE_MODE, 8, ECMSK_MODE_CSV, ECMSK_SYNC_DCSYNC); // EST-584: CSP only
	h.slave(3, ECMSK_CMD_DRIVE_MODE, 7, ECMSK_MODE_CSP, ECMSK_SYNC_DCSYNC); // IO
	auto r = h.answer();
	CHECK(h.slaveRsp(r, 1).cmd == ECMSK_CMD_DRIVE_MODE);
	CHECK(h.slaveRsp(r, 1).index == 9);
	CHECK(h.slaveRsp(r, 2).cmd == 0);
	CHECK(h.slaveRsp(r, 3).cmd == 0);
	CHECK(h.b.driveMode(1) == ECMSK_MODE_CSV);
	CHECK(h.b.driveMode(2) == ECMSK_MODE_CSP);
	for (std::uint32_t bad : { 0u, 1u, 7u, 11u }) {
		h.slave(1, ECMSK_CMD_DRIVE_MODE, 1, bad, 0);
		CHECK(h.slaveRsp(h.answer(), 1).cmd == 0);
	}
	h.slave(1, ECMSK_CMD_DRIVE_MODE, 1, ECMSK_MODE_CST, 2); // sync type 2
	CHECK(h.slaveRsp(h.answer(), 1).cmd == 0);
	CHECK(h.b.driveMode(1) == ECMSK_MODE_CSV);
	h.slave(1, ECMSK_CMD_DRIVE_MODE, 1, ECMSK_MODE_CSP, ECMSK_SYNC_DCSYNC);
	h.answer();
	REQUIRE(h.setState(ECMSK_STATE_OP));
	h.slave(1, ECMSK_CMD_DRIVE_MODE, 1, ECMSK_MODE_CST, ECMSK_SYNC_DCSYNC);
	CHECK(h.slaveRsp(h.answer(), 1).cmd == 0);
	CHECK(h.b.driveMode(1) == ECMSK_MODE_CSP);
}

TEST_CASE("sk board: slave commands of OP are refused in PRE-OP and SAFE-OP")
{
	Host h;
	REQUIRE(h.setState(ECMSK_STATE_PREOP));
	for (int c : { ECMSK_CMD_SV_ON, ECMSK_CMD_CSP, ECMSK_CMD_ALM_CLR, ECMSK_CMD_GO_HOME }) {
		h.slave(1, static_cast<std::uint8_t>(c), 3);
		CHECK(h.slaveRsp(h.answer(), 1).cmd == 0);
	}
	h.slave(3, ECMSK_CMD_IO_WR, 3, 0xFF);
	CHECK(h.slaveRsp(h.answer(), 3).cmd == 0);
	h.ecm(ECMSK_CMD_SET_FIFO, 0, ECMSK_FIFO_CLEAR);
	CHECK(h.ecmRsp(h.answer()).cmd == 0);
}

TEST_CASE("sk board: test mode (CONFIG1) goes to OP by itself at 1 ms and walks the outputs")
{
	BoardConfig c;
	c.testMode = true;
	Host h("slave dio\nslave dio\n", c);
	CHECK(h.reach(ECMSK_STATE_OP, 200ms));
	CHECK(h.b.cycleUs() == 1000u);
	auto *io = dynamic_cast<ecmxf::sim::DioModel *>(&h.b.network().at(0));
	REQUIRE(io != nullptr);
	h.b.advance(10ms);
	const auto a = io->outputs()[0];
	h.b.advance(100ms);
	const auto b = io->outputs()[0];
	CHECK(a != 0);
	CHECK(b != 0);
	CHECK(a != b);
}

TEST_CASE("sk board: IO_WR and IO_RD on an IO slave in OP, refused on a drive")
{
	Host h;
	h.toOp({ ECMSK_AXIS_DRIVE, ECMSK_AXIS_STEP, ECMSK_AXIS_IO });
	auto *io = dynamic_cast<ecmxf::sim::DioModel *>(&h.b.network().at(2));
	REQUIRE(io != nullptr);
	h.slave(3, ECMSK_CMD_IO_WR, 0x11, 0xA5);
	auto r = h.answer();
	CHECK(h.slaveRsp(r, 3).cmd == ECMSK_CMD_IO_WR);
	CHECK(h.slaveRsp(r, 3).index == 0x11);
	h.b.advance(3ms);
	CHECK(io->outputs()[0] == 0xA5);
	io->setInput(1, true);
	io->setInput(3, true);
	h.b.advance(3ms);
	h.slave(3, ECMSK_CMD_IO_RD, 0x12);
	r = h.answer();
	CHECK(h.slaveRsp(r, 3).cmd == ECMSK_CMD_IO_RD);
	CHECK((h.slaveRsp(r, 3).position & 0x0Au) == 0x0Au);
	h.slave(1, ECMSK_CMD_IO_WR, 0x13, 1);
	CHECK(h.slaveRsp(h.answer(), 1).cmd == 0);
}

TEST_CASE("sk board settings: fifo= is the depth FIFO remaining reports, spi_hz= the wire time, lio= the inputs")
{
	BoardConfig c = BoardConfig::parse("fifo=300&spi_hz=6000000&lio=0x21&slot=16");
	Host h("slave dio\n", c);
	CHECK(h.b.wireTime() == 682666ns); // 512 bytes at 6 MHz
	const auto t0 = h.b.now();
	h.xfer();
	CHECK(h.b.now() - t0 == h.b.wireTime());
	h.ecm(ECMSK_CMD_LIO_RD);
	CHECK(h.ecmRsp(h.answer()).data1 == 0x21u);
	h.toOp({ ECMSK_AXIS_IO });
	CHECK(h.ecmRsp(h.xfer()).fifo_remaining == 300);
}

TEST_CASE("sk board settings: paced=1 keeps virtual time from running ahead of the wall clock")
{
	CHECK_FALSE(BoardConfig::parse("").paced);
	BoardConfig c = BoardConfig::parse("paced=1");
	REQUIRE(c.paced);
	const auto t0 = std::chrono::steady_clock::now();
	Host h("slave dio\n", c);
	h.b.advance(30ms);
	// a lower bound only: the board slept at least that long
	CHECK(std::chrono::steady_clock::now() - t0 >= 30ms);
	CHECK(h.b.now() >= 30ms);
	for (int i = 0; i < 20; i++)
		h.xfer();
	CHECK(h.b.now() <= std::chrono::steady_clock::now() - t0 + h.b.wireTime());
	// cycles ran in that time, as at the board's rate
	CHECK(h.b.stats().cycles >= 30u);
}
