// SPDX-License-Identifier: MIT
// The lock-step bus of the simulated chip (ChipConfig::lockstep,
// Documentation/simulator.rst "Lock-step bus"): with the FIFO on, a bus
// cycle runs only when the RxFIFO holds its frame and the TxFIFO has room;
// with the FIFO off, or without the option, time runs the bus.

#include <catch2/catch.hpp>

#include <chrono>

#include "host.hpp"

using namespace simtest;
namespace sim = ecmxf::sim;
using namespace std::chrono_literals;

namespace {

Cmd fifoWrite(const std::vector<std::vector<std::uint8_t>> &frames)
{
	std::vector<std::uint8_t> d;
	for (const auto &f : frames)
		d.insert(d.end(), f.begin(), f.end());
	return Cmd(ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP, static_cast<std::uint8_t>(frames.size())).d(0x01).payload(d);
}

Cmd fifoRead()
{
	return Cmd(ECMXF_CMD_ECAT_PDO_DATA_FIFO_OP, 0).d(0x02);
}

sim::ChipConfig lockstep(bool on)
{
	sim::ChipConfig c;
	c.lockstep = on;
	return c;
}

} // namespace

TEST_CASE("chip lock-step: the bus waits for RxPDO frames and runs one cycle per frame, in order",
	  "[chip][pdo][lockstep]")
{
	Rig rig(1, SlaveConfig{}, lockstep(true));
	rig.toOp(); // 1 ms SYNC0
	rig.s(0).logOutputs = true;
	rig.s(0).counterInput = true;
	Host &h = rig.host;
	const sim::ChipStats &st = rig.chip->stats();

	// FIFO off: time runs the bus as without the option (10 ms: 10 cycles)
	std::uint64_t c0 = st.busCycles;
	rig.run(10ms);
	CHECK(st.busCycles == c0 + 10);
	CHECK(rig.chip->nextLockstepCycle() == std::chrono::nanoseconds::max());

	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
	rig.run(2ms); // the cycle due now finds the RxFIFO empty
	c0 = st.busCycles;
	const std::uint64_t under0 = st.rxUnderruns, waits0 = st.busWaits;
	REQUIRE(waits0 >= 1);
	rig.run(50ms);
	CHECK(st.busCycles == c0);         // no frame: no cycle in 50 ms
	CHECK(st.rxUnderruns == under0);   // and no underrun counted
	CHECK(st.busWaits == waits0);      // one wait, counted once
	CHECK(rig.chip->nextLockstepCycle() == std::chrono::nanoseconds::max());
	CHECK(h.info().h.tx_fifo_cnt == 0);

	// three frames: exactly three cycles, each frame once, in order
	rig.s(0).outLog.clear();
	const Rsp w = h.cmd(fifoWrite({ { 1, 11 }, { 2, 12 }, { 3, 13 } }));
	REQUIRE(w.h.ret & 0x01);
	rig.run(20ms);
	CHECK(st.busCycles == c0 + 3);
	CHECK(st.rxUnderruns == under0);
	CHECK(st.busWaits == waits0 + 1);
	REQUIRE(rig.s(0).outLog.size() == 3);
	CHECK(rig.s(0).outLog[0] == std::vector<std::uint8_t>{ 1, 11 });
	CHECK(rig.s(0).outLog[1] == std::vector<std::uint8_t>{ 2, 12 });
	CHECK(rig.s(0).outLog[2] == std::vector<std::uint8_t>{ 3, 13 });
	// their three input frames, consecutive cycle counters, nothing else
	const Rsp r = h.cmd(fifoRead());
	REQUIRE(r.h.len == 3 * 2);
	CHECK(r.data[2] == static_cast<std::uint8_t>(r.data[0] + 1));
	CHECK(r.data[4] == static_cast<std::uint8_t>(r.data[2] + 1));
	CHECK(st.txDropped == 0);
}

TEST_CASE("chip lock-step: a waiting cycle runs at once when its frame comes, the next one a cycle later",
	  "[chip][pdo][lockstep]")
{
	Rig rig(1, SlaveConfig{}, lockstep(true));
	rig.toOp(1'000'000);
	Host &h = rig.host;
	const sim::ChipStats &st = rig.chip->stats();
	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
	rig.run(5ms);
	h.send(fifoWrite({ { 1, 1 }, { 2, 2 } }));
	const std::uint64_t c0 = st.busCycles;
	// the frames are in: the first cycle is due (its time already past)
	const auto due = rig.chip->nextLockstepCycle();
	REQUIRE(due != std::chrono::nanoseconds::max());
	CHECK(due <= rig.chip->now());
	rig.run(1ns);
	CHECK(st.busCycles == c0 + 1);
	// the second one 1 ms (the SYNC0 cycle) after the first
	const auto next = rig.chip->nextLockstepCycle();
	CHECK(next - due == 1ms);
	rig.run(next - rig.chip->now() - 1ns);
	CHECK(st.busCycles == c0 + 1);
	rig.run(1ns);
	CHECK(st.busCycles == c0 + 2);
	CHECK(rig.chip->nextLockstepCycle() == std::chrono::nanoseconds::max());
}

TEST_CASE("chip lock-step: a full TxFIFO holds the bus until the host reads it", "[chip][pdo][lockstep]")
{
	Rig rig(1, SlaveConfig{}, lockstep(true));
	rig.toOp();
	rig.s(0).counterInput = true;
	Host &h = rig.host;
	const sim::ChipStats &st = rig.chip->stats();
	REQUIRE_FALSE(h.cmd(Cmd(ECMXF_CMD_FIFO_SET_TX_CNT, 3)).cmdError());
	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
	const std::uint64_t c0 = st.busCycles;
	h.cmd(fifoWrite({ { 1, 1 }, { 2, 2 }, { 3, 3 }, { 4, 4 }, { 5, 5 } }));
	rig.run(20ms);
	// three cycles filled the TxFIFO; two frames wait in the RxFIFO
	CHECK(st.busCycles == c0 + 3);
	CHECK(st.txDropped == 0);
	const Rsp r = h.cmd(fifoRead());
	REQUIRE(r.h.len == 3 * 2);
	rig.run(20ms);
	CHECK(st.busCycles == c0 + 5);
	const Rsp r2 = h.cmd(fifoRead());
	REQUIRE(r2.h.len == 2 * 2);
	CHECK(r2.data[0] == static_cast<std::uint8_t>(r.data[4] + 1));
	CHECK(r2.data[2] == static_cast<std::uint8_t>(r.data[4] + 2));
	CHECK(st.txDropped == 0);
	CHECK(h.info().h.rx_fifo_cnt == 0);
}

TEST_CASE("chip lock-step off: time runs the bus, an empty RxFIFO is an underrun", "[chip][pdo][lockstep]")
{
	Rig rig(1, SlaveConfig{}, lockstep(false));
	rig.toOp();
	Host &h = rig.host;
	const sim::ChipStats &st = rig.chip->stats();
	h.cmd(Cmd(ECMXF_CMD_FIFO_ENABLE, 1));
	rig.run(1ms);
	const std::uint64_t c0 = st.busCycles, under0 = st.rxUnderruns;
	rig.run(10ms);
	CHECK(st.busCycles == c0 + 10);
	CHECK(st.rxUnderruns == under0 + 10);
	CHECK(st.busWaits == 0);
	CHECK(rig.chip->nextLockstepCycle() == std::chrono::nanoseconds::max());
}
