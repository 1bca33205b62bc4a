// SPDX-License-Identifier: MIT
// Recorder::sample() allocates nothing and throws nothing: next to
// Cyclic::cycle() on the simulated ECM-XF bus in OP (8 signals: process
// data of both drives and cycle figures, through a trigger with
// pre-trigger samples, the ring wrapping), and next to the ECM-SK's
// BoardCyclic::cycle() with its feedback slots; and the live view's frame
// copy (RecorderSnapshot::take() into a SnapshotExchange, publish(),
// pending(), and the drawer's take()) between cycles. Counted by the
// process-wide operator new of tests/common/alloc_counter.cpp; nothing in
// a counted window uses Catch (its macros allocate).

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>

#include <ecmxf/bus/master.hpp>
#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/scope/recorder.hpp>
#include <ecmxf/scope/snapshot.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/sk/board_views.hpp>

#include "../common/alloc_counter.hpp"
#include "../lib_motion/bench.hpp"

using namespace std::chrono_literals;

static_assert(noexcept(std::declval<ecmxf::Recorder &>().sample(std::chrono::nanoseconds{})));
static_assert(noexcept(std::declval<ecmxf::Recorder &>().sample(std::chrono::nanoseconds{},
								    std::declval<const ecmxf::CycleResult &>())));
static_assert(noexcept(std::declval<ecmxf::Recorder &>().sample(std::chrono::nanoseconds{},
								    std::declval<const ecmxf::sk::CycleResult &>())));
static_assert(noexcept(std::declval<ecmxf::RecorderSnapshot &>().take(std::declval<const ecmxf::Recorder &>(), 1)));
static_assert(noexcept(std::declval<ecmxf::SnapshotExchange &>().publish()));
static_assert(noexcept(std::declval<ecmxf::SnapshotExchange &>().pending()));
static_assert(noexcept(std::declval<ecmxf::SnapshotExchange &>().take()));

TEST_CASE("scope alloc: Recorder sample next to Cyclic cycle allocates nothing")
{
	motiontest::Bench b; // the default network in OP, the motion PDOs, a 1 ms Cyclic started
	ecmxf::ProcessImage &img = *b.image;
	ecmxf::Cyclic &cyc = *b.cyc;
	ecmxf::Recorder rec(300);
	for (const char *s : { "0:Target position", "0:Position actual value", "0:Following error actual value",
			       "0:Statusword", "1:0x6064:0", "wkc", "rx_fifo", "tx_fifo" })
		rec.add(img, s);
	// a trigger that fires late: the ring wraps over the pre-trigger part
	// many times first
	auto target = img.output<std::int32_t>(0, 0x607A, 0);
	ecmxf::RecorderTrigger t;
	t.edge = ecmxf::TriggerEdge::Rising;
	t.signal = "0:Target position";
	t.level = 100;
	t.preSamples = 100;
	rec.arm(t);
	int errors = 0;
	unsigned cycles = 0;
	const auto before = ecmxf_test::allocations();
	while (!rec.done() && cycles < 5000) {
		target.set(cycles >= 1000 ? 1000 : 0);
		const auto &r = cyc.cycle();
		errors += r.error != 0;
		(void)rec.sample(b.now(), r);
		(void)cyc.waitNextCycle();
		cycles++;
	}
	const auto after = ecmxf_test::allocations();
	cyc.stop();
	CHECK(after - before == 0u);
	CHECK(errors == 0);
	CHECK(rec.done());
	CHECK(cycles == 1000 + 200); // 100 before the trigger and 200 from it fill 300
	CHECK(rec.size() == 300);
	CHECK(rec.triggerIndex() == 100);
	CHECK(rec.value(99, 0) == 0);
	CHECK(rec.value(100, 0) == 1000);
}

TEST_CASE("scope alloc: Recorder sample of the ECM-SK's feedback allocates nothing")
{
	auto b = ecmxf::sk::Board::open("sk-sim:");
	b->states().set(ecmxf::State::PreOp);
	const unsigned slaves = b->setup().slaveCount();
	ecmxf::sk::bringUpToOp(*b);
	ecmxf::Recorder rec(500);
	std::int64_t target = 0;
	rec.addValue("target", "inc", &target);
	for (const char *s : { "0:position", "0:statusword", "0:torque", "fifo_remaining", "dropped" })
		rec.add(*b, slaves, s);
	ecmxf::RecorderStop stop;
	stop.cycles = 400;
	rec.arm({}, stop);
	// the windows hold sample() alone: the simulated board behind the
	// channel is not the code under test (tests/sk_lib/test_sk_alloc.cpp
	// counts the ECM-SK's cyclic path over a canned channel)
	int bad = 0;
	std::uint64_t counted = 0;
	for (int i = 0; !rec.done(); i++) {
		target = i;
		(void)b->cyclic().stage(1, ecmxf::sk::Mode::Csp, i);
		const auto r = b->cyclic().cycle();
		bad += r.status == ecmxf::sk::CycleStatus::Link;
		const auto now = b->channel().now();
		const auto before = ecmxf_test::allocations();
		(void)rec.sample(now, r);
		counted += ecmxf_test::allocations() - before;
	}
	CHECK(counted == 0u);
	CHECK(bad == 0);
	CHECK(rec.size() == 400);
	CHECK(rec.value(399, 0) == 399);
}

TEST_CASE("scope alloc: the live view's frame copy between cycles allocates nothing")
{
	// what ecmxf-util scope --live's cycling thread does (LiveView::tick):
	// every 100 cycles the latest 2000 samples of 8 signals copied into the
	// exchange's back buffer and published, unless the last one is still
	// pending; the drawer's take() in between (here in the same thread)
	motiontest::Bench b;
	ecmxf::ProcessImage &img = *b.image;
	ecmxf::Cyclic &cyc = *b.cyc;
	ecmxf::Recorder rec(3000);
	for (const char *s : { "0:Target position", "0:Position actual value", "0:Following error actual value",
			       "0:Statusword", "1:0x6064:0", "wkc", "rx_fifo", "tx_fifo" })
		rec.add(img, s);
	rec.arm();
	ecmxf::SnapshotExchange frames(rec.signals().size(), 2000); // allocated before, as LiveView does
	int errors = 0, published = 0, skipped = 0, taken = 0;
	std::size_t lastSize = 0;
	const auto before = ecmxf_test::allocations();
	for (unsigned i = 0; !rec.done(); i++) {
		const auto &r = cyc.cycle();
		errors += r.error != 0;
		(void)rec.sample(b.now(), r);
		if (i % 100 == 0) {
			if (frames.pending()) {
				skipped++;
			} else {
				frames.back().take(rec, 2000);
				frames.publish();
				published++;
			}
		}
		if (i % 300 == 150) // the drawer free every third frame: the others skipped
			if (const ecmxf::RecorderSnapshot *s = frames.take()) {
				taken++;
				lastSize = s->size();
			}
		(void)cyc.waitNextCycle();
	}
	frames.back().take(rec, 2000); // the last frame, always published
	frames.publish();
	const ecmxf::RecorderSnapshot *last = frames.take();
	const auto after = ecmxf_test::allocations();
	cyc.stop();
	CHECK(after - before == 0u);
	CHECK(errors == 0);
	CHECK(published == 11); // cycles 0, 200, 500, ..., 2900
	CHECK(skipped == 19);
	CHECK(taken == 10);
	CHECK(lastSize == 2601); // the one of cycle 2600
	REQUIRE(last != nullptr);
	CHECK(last->done());
	CHECK(last->size() == 3000);
	CHECK(last->signals() == 8);
	CHECK(last->values(5).size() == 2000);
	CHECK(last->values(5)[1999] == rec.value(2999, 5));
}
