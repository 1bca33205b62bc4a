// SPDX-License-Identifier: MIT
// Cyclic::waitInputs() over the FIFO commands (the simulator): an
// application clocked by its inputs. With the chip's lock-step bus every
// output frame makes exactly one bus cycle and every input frame comes
// back once, in order; without it waitInputs() returns within a bus cycle.

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <vector>

#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/link/sim_channel.hpp>

#include "bus.hpp"

using namespace std::chrono_literals;
using pdotest::Bus;

namespace {

/// The loopback network's bus over a chip with @p lockstep.
void useChip(Bus &bus, bool lockstep)
{
	ecmxf::sim::ChipConfig cfg;
	cfg.lockstep = lockstep;
	auto t = std::make_unique<ecmxf::SimChannel>(pdotest::network("loopback.net"), cfg);
	bus.sim = t.get();
	bus.dev = std::make_unique<ecmxf::Device>(std::move(t));
}

/// The I/O terminal's 32-bit input (its outputs looped back) of a TxPDO
/// frame: bytes 34..37 (two EST-584 of 17 input bytes before it).
void record(void *ctx, std::span<const std::uint8_t> f) noexcept
{
	const std::uint32_t v = static_cast<std::uint32_t>(f[34]) | static_cast<std::uint32_t>(f[35]) << 8 |
				static_cast<std::uint32_t>(f[36]) << 16 | static_cast<std::uint32_t>(f[37]) << 24;
	static_cast<std::vector<std::uint32_t> *>(ctx)->push_back(v);
}

} // namespace

TEST_CASE("Cyclic::waitInputs: in lock-step every output frame makes one bus cycle and comes back once",
	  "[lib][pdo][cyclic][lockstep]")
{
	Bus bus;
	useChip(bus, true);
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::loopbackPdos());
	auto counter = image.output<std::uint32_t>(2, 0x7000, 1);
	std::vector<std::uint32_t> seen;
	seen.reserve(600);
	ecmxf::CyclicConfig cfg;
	cfg.period = 1ms;
	cfg.busCycle = 1ms;
	cfg.rxFill = 1; // one frame per cycle(): no copies to top the FIFO up
	cfg.wkcEvery = 1;
	cfg.onInputFrame = &record;
	cfg.context = &seen;
	ecmxf::Cyclic cyc(*bus.dev, image, cfg);
	CHECK(cyc.waitInputs(1ms) == EINVAL); // before start()
	cyc.start();

	const ecmxf::sim::ChipStats &st = bus.chip().stats();
	const std::uint64_t cycles0 = st.busCycles, under0 = st.rxUnderruns;
	// no output frame yet: the bus waits, no input comes
	const auto t0 = bus.chip().now();
	CHECK(cyc.waitInputs(20ms) == ETIMEDOUT);
	CHECK(bus.chip().now() - t0 >= 20ms);
	CHECK(st.busCycles == cycles0);

	const std::uint32_t n = 500;
	for (std::uint32_t i = 1; i <= n; i++) {
		counter.set(i);
		const ecmxf::CycleResult &r = cyc.cycle();
		INFO("cycle " << i << ": " << r.message);
		REQUIRE(r.error == 0);
		REQUIRE(r.framesPushed == 1);
		// the inputs of the previous cycle's frame, exactly one
		REQUIRE(r.framesPopped == (i == 1 ? 0u : 1u));
		REQUIRE(r.wkc == 9); // the chip's last cycle (OP since toOp())
		REQUIRE(cyc.waitInputs(100ms) == 0);
	}
	// one bus cycle per frame so far: each of the n frames made one
	const std::uint64_t made = st.busCycles - cycles0;
	CHECK(made == n);
	CHECK(cyc.cycle().framesPopped == 1); // the last one's inputs
	// the frame this last cycle() pushed makes at most one more, if the
	// next bus cycle fell due during its exchanges (where it falls
	// depends on how many exchanges a cycle takes, not on the frames)
	CHECK(st.busCycles - cycles0 - made <= 1);
	// each value once, in order
	REQUIRE(seen.size() == n);
	for (std::uint32_t i = 0; i < n; i++) {
		INFO("input frame " << i);
		REQUIRE(seen[i] == i + 1);
	}
	CHECK(st.rxUnderruns == under0);
	CHECK(st.txDropped == 0);
	CHECK(st.rxRefused == 0);
	CHECK(cyc.stats().wkcMismatches == 0);
	cyc.stop();
}

TEST_CASE("Cyclic::waitInputs: without lock-step the next bus cycle's frame wakes it", "[lib][pdo][cyclic][lockstep]")
{
	Bus bus;
	useChip(bus, false);
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::loopbackPdos());
	ecmxf::CyclicConfig cfg;
	cfg.period = 1ms;
	cfg.busCycle = 1ms;
	ecmxf::Cyclic cyc(*bus.dev, image, cfg);
	cyc.start();
	for (int i = 0; i < 20; i++) {
		const ecmxf::CycleResult &r = cyc.cycle();
		REQUIRE(r.error == 0);
		const auto t0 = bus.chip().now();
		REQUIRE(cyc.waitInputs(100ms) == 0);
		// the bus runs every 1 ms of virtual time: found within two polls
		CHECK(bus.chip().now() - t0 <= 2ms);
	}
	cyc.stop();
}
