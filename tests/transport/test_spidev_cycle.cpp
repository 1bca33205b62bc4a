// SPDX-License-Identifier: MIT
// The spidev channel's system calls, counted by the fake backend as the
// real one makes them (fake_spidev.hpp): INT0 is waited for by its ready
// edge (no level polling when an edge comes), one transfer per exchange,
// and a steady Cyclic over spidev makes a fixed, small number of system
// calls per cycle (Documentation/process-data.rst "Real time"). Virtual
// time: the counts are exact, not timings.

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/link/spidev_channel.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>

#include "fake_spidev.hpp"
#include "../lib_pdo/bus.hpp"

using namespace std::chrono_literals;

namespace {

using Calls = test::FakeSpidev::Syscalls;

Calls since(const Calls &now, const Calls &before)
{
	Calls d;
	d.ioctlTransfer = now.ioctlTransfer - before.ioctlTransfer;
	d.ioctlLine = now.ioctlLine - before.ioctlLine;
	d.ppoll = now.ppoll - before.ppoll;
	d.read = now.read - before.read;
	d.clock = now.clock - before.clock;
	d.sleep = now.sleep - before.sleep;
	return d;
}

/// What @p cycles steady cycles of a started Cyclic cost (after 50 of
/// warm-up): the backend's system calls and the channel's and link's
/// counts.
struct Steady {
	Calls calls;
	std::uint64_t exchanges = 0;     ///< the channel's
	std::uint64_t linkExchanges = 0; ///< the link's counters
	std::uint64_t levelReads = 0;
};

Steady runSteady(test::FakeSpidev &b, ecmxf::SpidevChannel &ch, ecmxf::Device &dev, ecmxf::Cyclic &cyc,
		 unsigned cycles, bool wantInputs)
{
	cyc.start();
	for (int i = 0; i < 50; i++) {
		REQUIRE(cyc.cycle().error == 0);
		REQUIRE(cyc.waitNextCycle() == 0);
	}
	const Calls before = b.calls;
	const std::uint64_t exchanges = ch.stats().exchanges;
	const std::uint64_t linkExchanges = dev.link().counters().exchanges;
	const std::uint64_t levels = ch.stats().int0LevelReads;
	for (unsigned i = 0; i < cycles; i++) {
		const ecmxf::CycleResult &res = cyc.cycle();
		INFO("cycle " << i << ": " << res.message);
		REQUIRE(res.error == 0);
		if (wantInputs)
			REQUIRE(res.inputsUpdated);
		REQUIRE(cyc.waitNextCycle() == 0);
	}
	Steady st;
	st.calls = since(b.calls, before);
	st.exchanges = ch.stats().exchanges - exchanges;
	st.linkExchanges = dev.link().counters().exchanges - linkExchanges;
	st.levelReads = ch.stats().int0LevelReads - levels;
	const Calls &d = st.calls;
	INFO("per " << cycles << " cycles: transfer " << d.ioctlTransfer << ", line " << d.ioctlLine << ", ppoll "
		    << d.ppoll << ", read " << d.read << ", clock " << d.clock << ", sleep " << d.sleep);
	return st;
}

/// The rig's chip configuration, busy for @p t after each packet (0: INT0
/// never drops, so no edge comes).
ecmxf::sim::ChipConfig busyFor(std::chrono::nanoseconds t)
{
	ecmxf::sim::ChipConfig cfg = test::SpidevRig::defaultConfig();
	cfg.processingTime = t;
	return cfg;
}

/// The first wait for "ready" (the level: nothing is known yet), then one
/// exchange of a zeroed packet.
void firstExchange(test::SpidevRig &r)
{
	std::vector<std::uint8_t> mosi(r.chip.packetSize()), miso(mosi.size());
	REQUIRE(r.transport->waitReady(1ms));
	r.transport->exchange(mosi, miso);
}

} // namespace

TEST_CASE("spidev INT0: the ready edge after an exchange is waited for with one ppoll and one read, "
	  "no level read",
	  "[transport][spidev][rt]")
{
	test::SpidevRig r;
	auto &b = *r.backend;
	std::vector<std::uint8_t> mosi(r.chip.packetSize()), miso(mosi.size());

	// the first wait reads the level once (nothing is known yet)
	REQUIRE(r.transport->waitReady(1ms));
	CHECK(b.calls.ioctlLine == 1);
	CHECK(r.transport->stats().int0LevelReads == 1);

	for (int i = 0; i < 10; i++) {
		r.transport->exchange(mosi, miso);
		const Calls before = b.calls;
		REQUIRE(r.transport->waitReady(1ms));
		const Calls d = since(b.calls, before);
		CHECK(d.ppoll == 1);
		CHECK(d.read == 1);
		CHECK(d.ioctlLine == 0);
		CHECK(d.clock == 0);
		// known ready now: asking again costs nothing
		const Calls again = b.calls;
		REQUIRE(r.transport->waitReady(1ms));
		CHECK(since(b.calls, again).total() == 0);
	}
	// after a sleep the edge has come: one read, no wait
	r.transport->exchange(mosi, miso);
	r.transport->sleepFor(200us);
	const Calls before = b.calls;
	REQUIRE(r.transport->waitReady(1ms));
	const Calls d = since(b.calls, before);
	CHECK(d.ppoll == 0);
	CHECK(d.read == 1);
	CHECK(d.total() == 1);
	CHECK(r.transport->stats().int0LevelReads == 1);
	CHECK(r.transport->stats().int0Unsignalled == 0);
	CHECK(r.chip.stats().notReady == 0);
	CHECK(r.chip.stats().busyExchanges == 0);
}

TEST_CASE("spidev INT0: the coarse clock follows the ready edges and sleeps without reading the clock",
	  "[transport][spidev][rt]")
{
	test::SpidevRig r;
	std::vector<std::uint8_t> mosi(r.chip.packetSize()), miso(mosi.size());
	REQUIRE(r.transport->waitReady(1ms));
	const auto t0 = r.transport->now();
	CHECK(r.transport->coarseNow() == t0);
	r.transport->exchange(mosi, miso);
	REQUIRE(r.transport->waitReady(1ms));
	// the edge's time: later than t0, not later than the chip's clock
	CHECK(r.transport->coarseNow() > t0);
	CHECK(r.transport->coarseNow() <= r.chip.now());
	const unsigned clocks = r.backend->calls.clock;
	r.transport->sleepUntil(r.chip.now() + 700us);
	CHECK(r.transport->coarseNow() == r.chip.now());
	r.transport->sleepFor(300us);
	CHECK(r.transport->coarseNow() == r.chip.now());
	CHECK(r.backend->calls.clock == clocks);
	CHECK(r.backend->calls.sleep == 2);
}

TEST_CASE("spidev INT0: a chip that does not go busy (no edge) is found ready by one level read after the grace",
	  "[transport][spidev][rt]")
{
	test::SpidevRig r(true, false, busyFor(0ns)); // INT0 never drops: no edge
	firstExchange(r);
	const auto t0 = r.chip.now();
	const unsigned lines = r.backend->calls.ioctlLine;
	REQUIRE(r.transport->waitReady(5ms));
	CHECK(r.chip.now() - t0 == ecmxf::SpidevOptions::kEdgeGrace);
	CHECK(r.backend->calls.ioctlLine == lines + 1);
	CHECK(r.transport->stats().int0Unsignalled == 1);
	CHECK(r.transport->stats().int0Timeouts == 0);
}

TEST_CASE("spidev INT0: after a sleep with no edge queued, the level is read at once (no grace)",
	  "[transport][spidev][rt]")
{
	test::SpidevRig r(true, false, busyFor(0ns)); // INT0 never drops: no edge
	firstExchange(r);
	r.transport->sleepFor(700us); // the rest of a cycle
	const auto t0 = r.chip.now();
	const Calls before = r.backend->calls;
	REQUIRE(r.transport->waitReady(5ms));
	const Calls d = since(r.backend->calls, before);
	CHECK(r.chip.now() == t0); // no wait
	CHECK(d.ppoll == 0);
	CHECK(d.ioctlLine == 1);
	CHECK(d.read == 2); // the queue before the level and after it
	CHECK(r.transport->stats().int0Unsignalled == 1);
	// a chip still busy after the sleep: the level says so, the edge is
	// then waited for as usual
	test::SpidevRig s(true, false, busyFor(2ms));
	firstExchange(s);
	s.transport->sleepFor(500us);
	const auto t1 = s.chip.now();
	REQUIRE(s.transport->waitReady(5ms));
	CHECK(s.chip.now() - t1 == 1500us);
	CHECK(s.transport->stats().int0Unsignalled == 0);
	CHECK(s.transport->stats().int0Timeouts == 0);
}

TEST_CASE("spidev INT0 stuck busy after an exchange: one level read after the grace, then the edge wait to "
	  "the timeout",
	  "[transport][spidev][rt]")
{
	test::SpidevRig r;
	firstExchange(r);
	r.chip.faults().int0StuckBusy = true;
	const auto t0 = r.chip.now();
	const Calls before = r.backend->calls;
	CHECK_FALSE(r.transport->waitReady(2ms));
	CHECK(r.chip.now() - t0 == 2ms);
	const Calls d = since(r.backend->calls, before);
	CHECK(d.ppoll == 2); // the grace, then the rest
	CHECK(d.read == 0);
	CHECK(d.ioctlLine == 1);
	CHECK(r.transport->stats().int0Timeouts == 1);
	// the clock is read once the wait has timed out
	CHECK(r.transport->coarseNow() == r.chip.now());
}

TEST_CASE("spidev Cyclic: a steady cycle makes 2 transfers, waits INT0 by its edge and sleeps once: 8 system "
	  "calls",
	  "[transport][spidev][rt][cyclic]")
{
	test::SpidevRig r;
	test::FakeSpidev &b = *r.backend;
	ecmxf::SpidevChannel &ch = *r.transport;
	pdotest::Bus bus(std::move(r.dev), r.chip);
	bus.toOp();
	REQUIRE(bus.dev->link().pipelining());
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	ecmxf::CyclicConfig cc;
	cc.period = 1ms;
	cc.busCycle = 1ms;
	cc.rxFill = 4;
	cc.wkcEvery = 10;
	cc.wkcAnswerNextCycle = true; // the read rides along: 2 exchanges per cycle
	ecmxf::Cyclic cyc(*bus.dev, image, cc);
	constexpr unsigned kCycles = 200;
	const Steady st = runSteady(b, ch, *bus.dev, cyc, kCycles, false);
	const Calls &d = st.calls;
	CHECK(st.exchanges == 2 * kCycles);
	// one SPI transfer ioctl per exchange
	CHECK(d.ioctlTransfer == 2 * kCycles);
	// INT0 by its edge: never its level
	CHECK(d.ioctlLine == 0);
	CHECK(st.levelReads == 0);
	// the first exchange's edge came during the sleep: one read; the
	// second's is waited for: one ppoll and one read
	CHECK(d.ppoll == kCycles);
	CHECK(d.read == 2 * kCycles);
	// the pacing: one clock read (late?) and one absolute sleep; the
	// batch's start: one clock read
	CHECK(d.sleep == kCycles);
	CHECK(d.clock == 2 * kCycles);
	CHECK(d.total() == 8 * kCycles);
	CHECK(cyc.stats().lateCycles == 0);
	CHECK(r.chip.stats().notReady == 0);
	CHECK(r.chip.stats().busyExchanges == 0);
}

TEST_CASE("spidev Cyclic fifoAnswerNextCycle: a steady cycle makes 1 transfer and 5 system calls, a cycle with a "
	  "working counter read 2 transfers and 8",
	  "[transport][spidev][rt][cyclic]")
{
	test::SpidevRig r;
	test::FakeSpidev &b = *r.backend;
	ecmxf::SpidevChannel &ch = *r.transport;
	pdotest::Bus bus(std::move(r.dev), r.chip);
	bus.toOp();
	REQUIRE(bus.dev->link().pipelining());
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	ecmxf::CyclicConfig cc;
	cc.period = 1ms;
	cc.busCycle = 1ms;
	cc.rxFill = 4;
	cc.wkcEvery = 10;
	cc.fifoAnswerNextCycle = true; // the FIFO command's answer comes with the next cycle's exchange
	ecmxf::Cyclic cyc(*bus.dev, image, cc);
	constexpr unsigned kCycles = 200;
	constexpr unsigned kReads = kCycles / 10;
	const Steady st = runSteady(b, ch, *bus.dev, cyc, kCycles, true);
	const Calls &d = st.calls;
	// one exchange per cycle, one more in each of the 20 with a read
	CHECK(st.exchanges == kCycles + kReads);
	CHECK(st.linkExchanges == kCycles + kReads);
	CHECK(cyc.stats().wkcReads == 50 / 10 + kReads);
	CHECK(d.ioctlTransfer == kCycles + kReads);
	CHECK(d.ioctlLine == 0);
	CHECK(st.levelReads == 0);
	// the first exchange's edge came during the sleep: one read; the
	// batch returns once the FIFO command is sent, without waiting for
	// its edge. A read cycle waits for the second exchange's edge: one
	// ppoll and one read more
	CHECK(d.ppoll == kReads);
	CHECK(d.read == kCycles + kReads);
	// the pacing: one clock read and one absolute sleep; the batch's
	// start: one clock read
	CHECK(d.sleep == kCycles);
	CHECK(d.clock == 2 * kCycles);
	// 5 a cycle, 8 in a read cycle
	CHECK(d.total() == 5 * (kCycles - kReads) + 8 * kReads);
	CHECK(cyc.stats().lateCycles == 0);
	CHECK(cyc.stats().rxRefusals == 0);
	CHECK(cyc.stats().txOverflows == 0);
	CHECK(r.chip.stats().notReady == 0);
	CHECK(r.chip.stats().busyExchanges == 0);
	cyc.stop();
	// nothing in flight: the next command gets its own answer
	CHECK(bus.cmd(16).ret == 3); // ECAT_SLV_CNT_GET
}
