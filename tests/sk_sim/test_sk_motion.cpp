// SPDX-License-Identifier: MIT
// The simulated ECM-SK board in OP: servo on/off, CSP/CSV/CST through the
// cyclic FIFO (remaining and full counts, threshold, abandon after 100
// cycles), homing (statusword bits 10 and 12), alarm clear.

#include "sk_host.hpp"

#include <ecmxf/model/cia402.hpp>
#include <ecmxf/sim/slaves.hpp>

using namespace skt;
using ecmxf::sk::BoardConfig;

namespace {

const std::vector<std::uint8_t> kTypes = { ECMSK_AXIS_DRIVE, ECMSK_AXIS_STEP, ECMSK_AXIS_IO };

// statusword bits 10 and 12 both set: homing attained (the ECM-SK's "homed")
constexpr std::uint16_t kHomed = ecmxf::cia402::kSwTargetReached | ecmxf::cia402::kSwHomingAttained;

bool enabled(std::uint16_t sw)
{
	return ecmxf::cia402StateFrom(sw) == ecmxf::Cia402State::OperationEnabled;
}

bool faulted(std::uint16_t sw)
{
	const auto s = ecmxf::cia402StateFrom(sw);
	return s == ecmxf::Cia402State::Fault || s == ecmxf::Cia402State::FaultReactionActive;
}

// SV_ON on slaves 1 and 2, then GET_STATUS until both are enabled
void servoOn(Host &h)
{
	h.slave(1, ECMSK_CMD_SV_ON, 1);
	h.slave(2, ECMSK_CMD_SV_ON, 2);
	auto r = h.answer();
	REQUIRE(h.slaveRsp(r, 1).cmd == ECMSK_CMD_SV_ON);
	REQUIRE(h.slaveRsp(r, 2).cmd == ECMSK_CMD_SV_ON);
	for (int i = 0; i < 200; i++) {
		r = h.xfer();
		if (enabled(h.slaveRsp(r, 1).statusword) && enabled(h.slaveRsp(r, 2).statusword))
			return;
		h.b.advance(1ms);
	}
	FAIL("servo on did not enable the drives");
}

} // namespace

TEST_CASE("sk motion: bring-up to OP, SV_ON, a CSP move of the Drive and the STEP slave")
{
	Host h;
	h.toOp(kTypes);
	auto r = h.xfer();
	CHECK(h.ecmRsp(r).cmd == ECMSK_RSP_OP);
	CHECK(h.ecmRsp(r).state == ECMSK_STATE_OP);
	CHECK(h.ecmRsp(r).fifo_remaining == 160);
	servoOn(h);

	// a ramp of 200 targets, one per cycle per slave, streamed with the
	// FIFO kept from running empty
	const auto start1 = static_cast<std::int32_t>(h.slaveRsp(h.xfer(), 1).position);
	const auto start2 = static_cast<std::int32_t>(h.slaveRsp(h.last, 2).position);
	for (int i = 1; i <= 200; i++) {
		h.slave(1, ECMSK_CMD_CSP, static_cast<std::uint8_t>(i), static_cast<std::uint32_t>(start1 + 50 * i));
		h.slave(2, ECMSK_CMD_CSP, static_cast<std::uint8_t>(i), static_cast<std::uint32_t>(start2 + 20 * i));
		r = h.xfer();
		h.b.advance(1ms);
	}
	for (int i = 0; i < 20; i++) {
		r = h.xfer();
		h.b.advance(1ms);
	}
	CHECK(h.ecmRsp(r).fifo_remaining == 160);
	CHECK(h.ecmRsp(r).fifo_full == 0);
	const auto p1 = static_cast<std::int32_t>(h.slaveRsp(r, 1).position);
	const auto p2 = static_cast<std::int32_t>(h.slaveRsp(r, 2).position);
	CHECK(std::abs(p1 - (start1 + 10000)) <= 10);
	CHECK(std::abs(p2 - (start2 + 4000)) <= 10);
	CHECK(h.b.stats().fifoApplied == 400u);
	CHECK(enabled(h.slaveRsp(r, 1).statusword));
}

TEST_CASE("sk motion: the FIFO reports its remaining space, drops and counts what does not fit")
{
	BoardConfig c;
	c.fifoAbandon = false;
	Host h("slave servo\nslave EST-584\nslave dio\n", c);
	h.toOp(kTypes);
	servoOn(h);
	// 200 frames with a CSP for slaves 1 and 2 each: 400 entries, about
	// 2 x 38 applied meanwhile, 160 fit
	const auto p1 = h.slaveRsp(h.xfer(), 1).position, p2 = h.slaveRsp(h.last, 2).position;
	for (int i = 0; i < 200; i++) {
		h.slave(1, ECMSK_CMD_CSP, static_cast<std::uint8_t>(i), p1);
		h.slave(2, ECMSK_CMD_CSP, static_cast<std::uint8_t>(i), p2);
		h.xfer();
	}
	CHECK(h.b.fifoFullCount() >= 40u);
	auto e = h.ecmRsp(h.xfer());
	CHECK(e.fifo_full == h.b.fifoFullCount());
	CHECK(e.fifo_remaining == 160 - h.b.fifoUsed());
	// SET_FIFO clear empties it
	h.ecm(ECMSK_CMD_SET_FIFO, 0, ECMSK_FIFO_CLEAR);
	h.xfer();
	e = h.ecmRsp(h.xfer());
	CHECK(e.fifo_remaining == 160);
	CHECK(h.b.fifoUsed() == 0u);
	// an unknown action is refused
	h.ecm(ECMSK_CMD_SET_FIFO, 5, 3);
	h.xfer();
	CHECK(h.b.stats().refused >= 1u);
}

TEST_CASE("sk motion: a CSP for a slave in CSV mode, or for an IO slave, is refused, not queued")
{
	Host h;
	REQUIRE(h.setState(ECMSK_STATE_PREOP));
	h.slave(1, ECMSK_CMD_DRIVE_MODE, 0, 0, 0); // refused: types not set
	h.toOp(kTypes);
	h.slave(3, ECMSK_CMD_CSP, 1, 5);
	h.slave(1, ECMSK_CMD_CSV, 2, 5); // slave 1 is CSP
	auto r = h.answer();
	CHECK(h.slaveRsp(r, 3).cmd == 0);
	CHECK(h.slaveRsp(r, 1).cmd == 0);
	CHECK(h.b.fifoUsed() == 0u);
}

TEST_CASE("sk motion: SET_FIFO threshold holds the FIFO until its remaining space falls below it")
{
	Host h;
	h.toOp(kTypes);
	servoOn(h);
	CHECK(h.b.fifoThreshold() == 160u); // the default: the depth
	h.ecm(ECMSK_CMD_SET_FIFO, 100, ECMSK_FIFO_THRESHOLD);
	h.xfer();
	CHECK(h.b.fifoThreshold() == 100u);
	const auto p0 = static_cast<std::int32_t>(h.slaveRsp(h.xfer(), 1).position);
	// 60 entries leave 100 free: not below 100, nothing applied
	for (int i = 1; i <= 60; i++) {
		h.slave(1, ECMSK_CMD_CSP, 0, static_cast<std::uint32_t>(p0 + i));
		h.xfer();
	}
	h.b.advance(5ms);
	CHECK(h.b.fifoUsed() == 60u);
	h.slave(1, ECMSK_CMD_CSP, 0, static_cast<std::uint32_t>(p0 + 61));
	h.xfer();
	h.b.advance(5ms);
	CHECK(h.b.fifoUsed() < 61u);
	CHECK(h.b.fifoThreshold() == 160u); // met: back to the default
}

TEST_CASE("sk motion: the FIFO is 160 deep, the threshold's reset value: an explicit 160 holds nothing")
{
	Host h;
	h.toOp(kTypes);
	servoOn(h);
	auto e = h.ecmRsp(h.xfer());
	CHECK(e.fifo_remaining == 160);
	h.ecm(ECMSK_CMD_SET_FIFO, 160, ECMSK_FIFO_THRESHOLD);
	h.xfer();
	CHECK(h.b.fifoThreshold() == 160u);
	const auto p0 = static_cast<std::int32_t>(h.slaveRsp(h.xfer(), 1).position);
	const std::uint64_t applied = h.b.stats().fifoApplied;
	h.slave(1, ECMSK_CMD_CSP, 0, static_cast<std::uint32_t>(p0 + 1));
	h.xfer();
	h.b.advance(2ms); // two cycles
	CHECK(h.b.fifoUsed() == 0u);
	CHECK(h.b.stats().fifoApplied == applied + 1);
	// 0 restores the default
	h.ecm(ECMSK_CMD_SET_FIFO, 0, ECMSK_FIFO_THRESHOLD);
	h.xfer();
	CHECK(h.b.fifoThreshold() == 160u);
}

TEST_CASE("sk motion: entries held by a threshold and abandoned after 100 cycles are counted in the FIFO full count")
{
	Host h;
	h.toOp(kTypes);
	servoOn(h);
	h.ecm(ECMSK_CMD_SET_FIFO, 100, ECMSK_FIFO_THRESHOLD);
	h.xfer();
	const auto p0 = static_cast<std::int32_t>(h.slaveRsp(h.xfer(), 1).position);
	for (int i = 1; i <= 20; i++) { // held: 140 free is not below 100
		h.slave(1, ECMSK_CMD_CSP, 0, static_cast<std::uint32_t>(p0 + i));
		h.xfer();
	}
	CHECK(h.ecmRsp(h.xfer()).fifo_full == 0);
	h.b.advance(150ms); // 150 cycles: every entry waited more than 100
	const auto e = h.ecmRsp(h.xfer());
	CHECK(h.b.fifoUsed() == 0u);
	CHECK(h.b.stats().fifoAbandoned == 20u);
	CHECK(e.fifo_full == 20);
	CHECK(e.fifo_remaining == 160);
}

TEST_CASE("sk motion: CONFIG3 abandons cyclic commands that waited more than 100 cycles")
{
	for (bool abandon : { true, false }) {
		BoardConfig c;
		c.fifoAbandon = abandon;
		Host h("slave servo\nslave EST-584\nslave dio\n", c);
		h.toOp(kTypes);
		servoOn(h);
		const auto p0 = static_cast<std::int32_t>(h.slaveRsp(h.xfer(), 1).position);
		// 150 entries for one slave at once: one is applied per cycle
		for (int i = 1; i <= 150; i++) {
			h.slave(1, ECMSK_CMD_CSP, 0, static_cast<std::uint32_t>(p0 + i));
			h.xfer();
		}
		h.b.advance(200ms);
		INFO("abandon " << abandon);
		CHECK(h.b.fifoUsed() == 0u);
		if (abandon)
			CHECK(h.b.stats().fifoAbandoned > 10u);
		else
			CHECK(h.b.stats().fifoAbandoned == 0u);
		CHECK(h.b.stats().fifoApplied + h.b.stats().fifoAbandoned == 150u);
	}
}

TEST_CASE("sk motion: SV_OFF disables the drive, ALM_CLR resets a fault")
{
	Host h;
	h.toOp(kTypes);
	servoOn(h);
	h.slave(1, ECMSK_CMD_SV_OFF, 4);
	h.answer();
	h.b.advance(20ms);
	auto r = h.xfer();
	CHECK_FALSE(enabled(h.slaveRsp(r, 1).statusword));

	auto *drive = dynamic_cast<ecmxf::sim::Cia402Model *>(&h.b.network().at(0));
	REQUIRE(drive != nullptr);
	drive->injectFault(0x7500);
	h.b.advance(50ms);
	r = h.xfer();
	CHECK(faulted(h.slaveRsp(r, 1).statusword));
	CHECK(h.slaveRsp(r, 1).error_code == 0x7500);
	h.slave(1, ECMSK_CMD_ALM_CLR, 5);
	h.answer();
	h.b.advance(20ms);
	r = h.xfer();
	CHECK_FALSE(faulted(h.slaveRsp(r, 1).statusword));
}

TEST_CASE("sk motion: CSV and CST on the servo")
{
	Host h;
	REQUIRE(h.setState(ECMSK_STATE_PREOP));
	std::uint32_t topo = 0;
	REQUIRE(ecmsk_axis_topology(kTypes.data(), 3, 0, &topo) == 0);
	h.ecm(ECMSK_CMD_SET_AXIS, topo, 0);
	h.answer();
	h.slave(1, ECMSK_CMD_DRIVE_MODE, 1, ECMSK_MODE_CSV, ECMSK_SYNC_DCSYNC);
	h.answer();
	h.toOp(kTypes);
	servoOn(h);
	const auto p0 = static_cast<std::int32_t>(h.slaveRsp(h.xfer(), 1).position);
	h.slave(1, ECMSK_CMD_CSV, 1, 100000);
	h.answer();
	h.b.advance(500ms);
	const auto p1 = static_cast<std::int32_t>(h.slaveRsp(h.xfer(), 1).position);
	CHECK(p1 - p0 > 10000);
}

TEST_CASE("sk motion: GO_HOME needs 0x6060 = 6 and 0x6098 by SDO, bits 10 and 12 say done, one at a time")
{
	Host h;
	h.toOp(kTypes);
	servoOn(h);
	h.slave(2, ECMSK_CMD_GO_HOME, 9);
	CHECK(h.slaveRsp(h.answer(), 2).cmd == 0); // no SDO_WR first
	REQUIRE(h.sdoRun(ECMSK_CMD_SDO_WR, 2, 0x6060, 0, 1, 6).status == ECMSK_SDO_DONE);
	REQUIRE(h.sdoRun(ECMSK_CMD_SDO_WR, 2, 0x607C, 0, 4, 1000).status == ECMSK_SDO_DONE);
	REQUIRE(h.sdoRun(ECMSK_CMD_SDO_WR, 2, 0x6098, 0, 1, 37).status == ECMSK_SDO_DONE);
	h.slave(2, ECMSK_CMD_GO_HOME, 9);
	CHECK(h.slaveRsp(h.answer(), 2).cmd == ECMSK_CMD_GO_HOME);
	bool homed = false;
	for (int i = 0; i < 300 && !homed; i++) {
		auto r = h.xfer();
		const auto sw = h.slaveRsp(r, 2).statusword;
		homed = (sw & kHomed) == kHomed && static_cast<std::int32_t>(h.slaveRsp(r, 2).position) == 1000;
		h.b.advance(1ms);
	}
	CHECK(homed);
	// back in CSP (2.1.18, hint 2)
	h.b.advance(10ms);
	auto *drive = dynamic_cast<ecmxf::sim::Cia402Model *>(&h.b.network().at(1));
	REQUIRE(drive != nullptr);
	CHECK(drive->modeDisplay() == 8);
	// GO_HOME again needs the SDO_WR again
	h.slave(2, ECMSK_CMD_GO_HOME, 10);
	CHECK(h.slaveRsp(h.answer(), 2).cmd == 0);
}

TEST_CASE("sk motion: a 1-channel HSP is typed HSP, runs CSV, and answers its inputs instead of torque")
{
	Host h("slave servo\nslave hsp\nslave dio\n");
	REQUIRE(h.setState(ECMSK_STATE_PREOP));
	std::uint32_t topo = 0;
	const std::uint8_t wrong[3] = { ECMSK_AXIS_DRIVE, ECMSK_AXIS_STEP, ECMSK_AXIS_IO };
	REQUIRE(ecmsk_axis_topology(wrong, 3, 0, &topo) == 0);
	h.ecm(ECMSK_CMD_SET_AXIS, topo, 0);
	CHECK(h.ecmRsp(h.answer()).data2 == 0x2u);
	const std::vector<std::uint8_t> types = { ECMSK_AXIS_DRIVE, ECMSK_AXIS_HSP, ECMSK_AXIS_IO };
	REQUIRE(ecmsk_axis_topology(types.data(), 3, 0, &topo) == 0);
	h.ecm(ECMSK_CMD_SET_AXIS, topo, 0);
	CHECK(h.ecmRsp(h.answer()).data2 == 0u);
	h.slave(2, ECMSK_CMD_DRIVE_MODE, 1, ECMSK_MODE_CST, ECMSK_SYNC_DCSYNC); // HSP: no CST
	CHECK(h.slaveRsp(h.answer(), 2).cmd == 0);
	h.slave(2, ECMSK_CMD_DRIVE_MODE, 1, ECMSK_MODE_CSV, ECMSK_SYNC_DCSYNC);
	CHECK(h.slaveRsp(h.answer(), 2).cmd == ECMSK_CMD_DRIVE_MODE);
	h.toOp(types);
	h.slave(2, ECMSK_CMD_SV_ON, 1);
	h.answer();
	h.b.advance(20ms);
	auto r = h.xfer();
	REQUIRE(enabled(h.slaveRsp(r, 2).statusword));
	const auto p0 = static_cast<std::int32_t>(h.slaveRsp(r, 2).position);
	h.slave(2, ECMSK_CMD_CSV, 2, 20000);
	h.answer();
	h.b.advance(500ms);
	r = h.xfer();
	CHECK(static_cast<std::int32_t>(h.slaveRsp(r, 2).position) - p0 > 5000);
	CHECK(h.slaveRsp(r, 2).error_code == 0); // HSP: no ALM code
}

TEST_CASE("sk motion: a 2-channel HSP with 16-byte slots moves both channels (tables 2.16/2.18)")
{
	BoardConfig c;
	c.slotSize = 16;
	Host h("slave hsp channels=2\nslave dio\n", c);
	h.toOp({ ECMSK_AXIS_HSP, ECMSK_AXIS_IO });
	h.slave(1, ECMSK_CMD_SV_ON, 1);
	h.answer();
	h.b.advance(20ms);
	auto r = h.xfer();
	ecmsk_hsp2 a{};
	REQUIRE(ecmsk_get_hsp2(&h.g, r.data(), 1, &a) == 0);
	REQUIRE(enabled(a.statusword));
	for (int i = 1; i <= 100; i++) {
		ecmsk_hsp2 cmd{ ECMSK_CMD_CSP, static_cast<std::uint8_t>(i), 0, static_cast<std::uint32_t>(10 * i), 0,
				static_cast<std::uint32_t>(-20 * i), 0 };
		REQUIRE(ecmsk_put_hsp2(&h.g, h.cmd.data(), 1, &cmd) == 0);
		h.xfer();
		h.b.advance(1ms);
	}
	h.b.advance(20ms);
	r = h.xfer();
	REQUIRE(ecmsk_get_hsp2(&h.g, r.data(), 1, &a) == 0);
	CHECK(static_cast<std::int32_t>(a.pos1) == 1000);
	CHECK(static_cast<std::int32_t>(a.pos2) == -2000);
	auto *hsp = &h.b.network().at(0);
	std::vector<std::uint8_t> v;
	REQUIRE(hsp->sdoUpload(0x6864, 0, false, v) == 0);
	CHECK(static_cast<std::int32_t>(v[0] | v[1] << 8 | v[2] << 16 | v[3] << 24) == -2000);
}

TEST_CASE("sk motion: with 12-byte slots a 2-channel HSP drives channel 1 only, channels=3 is refused")
{
	Host h("slave hsp channels=2\nslave dio\n");
	h.toOp({ ECMSK_AXIS_HSP, ECMSK_AXIS_IO });
	h.slave(1, ECMSK_CMD_SV_ON, 1);
	h.answer();
	h.b.advance(20ms);
	const auto p0 = static_cast<std::int32_t>(h.slaveRsp(h.xfer(), 1).position);
	h.slave(1, ECMSK_CMD_CSP, 2, static_cast<std::uint32_t>(p0 + 300));
	h.answer();
	h.b.advance(20ms);
	CHECK(static_cast<std::int32_t>(h.slaveRsp(h.xfer(), 1).position) == p0 + 300);
	std::vector<std::uint8_t> v;
	REQUIRE(h.b.network().at(0).sdoUpload(0x6864, 0, false, v) == 0);
	CHECK((v[0] | v[1] | v[2] | v[3]) == 0);
	CHECK_THROWS(net("slave hsp channels=3\n"));
	CHECK_THROWS(net("slave hsp channels=0\n"));
}

TEST_CASE("sk motion: one GO_HOME at a time on the bus, ABORT_HOME stops it and returns to CSP")
{
	Host h("slave EST-584\nslave EST-584\nslave dio\n");
	h.toOp({ ECMSK_AXIS_STEP, ECMSK_AXIS_STEP, ECMSK_AXIS_IO });
	for (unsigned s : { 1u, 2u }) {
		h.slave(s, ECMSK_CMD_SV_ON, 1);
		h.answer();
	}
	h.b.advance(30ms);
	for (int si : { 1, 2 }) {
		const auto s = static_cast<std::uint8_t>(si);
		REQUIRE(h.sdoRun(ECMSK_CMD_SDO_WR, s, 0x6060, 0, 1, 6).status == ECMSK_SDO_DONE);
		REQUIRE(h.sdoRun(ECMSK_CMD_SDO_WR, s, 0x6098, 0, 1, 19).status == ECMSK_SDO_DONE); // switch search
	}
	h.slave(1, ECMSK_CMD_GO_HOME, 1);
	CHECK(h.slaveRsp(h.answer(), 1).cmd == ECMSK_CMD_GO_HOME);
	h.b.advance(50ms);
	h.slave(2, ECMSK_CMD_GO_HOME, 2); // while slave 1 homes
	CHECK(h.slaveRsp(h.answer(), 2).cmd == 0);
	auto *d1 = dynamic_cast<ecmxf::sim::Cia402Model *>(&h.b.network().at(0));
	REQUIRE(d1 != nullptr);
	CHECK(d1->modeDisplay() == 6);
	const auto moving = d1->positionActual();
	h.b.advance(50ms);
	CHECK(d1->positionActual() != moving); // searching for the switch
	h.slave(2, ECMSK_CMD_ABORT_HOME, 3); // from any drive slot: every slave
	CHECK(h.slaveRsp(h.answer(), 2).cmd == ECMSK_CMD_ABORT_HOME);
	h.b.advance(300ms);
	CHECK(d1->modeDisplay() == 8);
	const auto stopped = d1->positionActual();
	h.b.advance(50ms);
	CHECK(d1->positionActual() == stopped); // the search is over
	// now slave 2 may home (its 0x6060 = 6 was written and is kept)
	h.slave(2, ECMSK_CMD_GO_HOME, 4);
	CHECK(h.slaveRsp(h.answer(), 2).cmd == ECMSK_CMD_GO_HOME);
}
