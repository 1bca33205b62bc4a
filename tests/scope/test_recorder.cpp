// SPDX-License-Identifier: MIT
// The Recorder (include/ecmxf/scope/recorder.hpp): signals by name and by
// index:sub, cycle figures, the trigger (now, rising, falling, pre-trigger
// samples), the stop (cycles, time, buffer full), bad input; over a
// hand-made image, the simulated ECM-XF bus in OP and the simulated ECM-SK.

#include <catch2/catch.hpp>

#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/bus/master.hpp>
#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/scope/recorder.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/sk/board_views.hpp>

#include "../common/thrown.hpp"
#include "../lib_motion/bench.hpp"

using namespace std::chrono_literals;
using ecmxf::Recorder;
using ecmxf::RecorderState;
using ecmxf::TriggerEdge;
using ecmxftest::thrown;

namespace {

/// Slave 0: out 0x607A (target position, 32), 0x6040 (16); in 0x6041 (16),
/// 0x6064 (32), 0x2000:01 (12 bits, no name). Slave 1: in 0x60FD.
ecmxf::ProcessImage image()
{
	ecmxf::SlavePdos a;
	a.outputs = { { 0x1600, 0x6040, 0, 16, 0, "Controlword" }, { 0x1600, 0x607A, 0, 32, 16, "Target position" } };
	a.inputs = { { 0x1A00, 0x6041, 0, 16, 0, "Statusword" },
		     { 0x1A00, 0x6064, 0, 32, 16, "Position actual value" },
		     { 0x1A00, 0x2000, 1, 12, 48, "" } };
	a.outputBytes = 6;
	a.inputBytes = 8;
	ecmxf::SlavePdos b;
	b.inputs = { { 0x1A00, 0x60FD, 0, 32, 0, "Digital inputs" } };
	b.inputBytes = 4;
	return ecmxf::ProcessImage({ a, b });
}

bool has(const std::string &text, const std::string &part)
{
	return text.find(part) != std::string::npos;
}

} // namespace

TEST_CASE("scope recorder: signals by name and by index:sub, units and kinds")
{
	auto img = image();
	Recorder r(16);
	CHECK(r.add(img, "0:position_actual_value") == 0);
	CHECK(r.add(img, "0:0x607A:0") == 1);
	CHECK(r.add(img, "0:STATUSWORD") == 2);
	CHECK(r.add(img, "0:2000:1") == 3);
	CHECK(r.add(img, "wkc") == 4);
	const auto &s = r.signals();
	CHECK(s[0].label == "slave 0 Position actual value");
	CHECK(s[0].unit == "inc");
	CHECK(s[0].numeric);
	CHECK(s[1].label == "slave 0 Target position");
	CHECK(s[2].unit.empty());
	CHECK_FALSE(s[2].numeric); // a word of bits
	CHECK(s[3].numeric);       // not a standard object: a raw number
	CHECK(s[3].label == "slave 0 0x2000:0x01");

	ecmxf::OutputVar<std::int32_t> target = img.output<std::int32_t>(0, 0x607A, 0);
	img.inputs()[2] = 0x18; // position -1000 = 0xFFFFFC18, little-endian
	img.inputs()[3] = 0xFC;
	img.inputs()[4] = 0xFF;
	img.inputs()[5] = 0xFF;
	img.inputs()[0] = 0x37; // statusword 0x0237
	img.inputs()[1] = 0x02;
	img.inputs()[6] = 0xFF; // 0x2000:01 = 0xFFF (12 bits, unsigned)
	img.inputs()[7] = 0x0F;
	target.set(-123456);
	r.arm();
	ecmxf::CycleResult c;
	c.wkc = 3;
	CHECK(r.sample(1000ns, c) == RecorderState::Recording);
	REQUIRE(r.size() == 1);
	CHECK(r.value(0, 0) == -1000);
	CHECK(r.value(0, 1) == -123456);
	CHECK(r.value(0, 2) == 0x0237);
	CHECK(r.value(0, 3) == 0xFFF);
	CHECK(r.value(0, 4) == 3);
	CHECK(r.time(0) == 0ns);
	// a figure without a cycle's result: not sampled (NaN)
	CHECK(r.sample(2000ns) == RecorderState::Recording);
	CHECK(std::isnan(r.value(1, 4)));
	CHECK(r.time(1) == 1000ns);
}

TEST_CASE("scope recorder: bad signals are refused naming what is wrong")
{
	auto img = image();
	Recorder r(8);
	auto e = thrown([&] { r.add(img, "0:no_such_thing"); });
	CHECK(e.errnoValue() == EINVAL);
	CHECK(has(e.what(), "\"0:no_such_thing\""));
	CHECK(has(e.what(), "slave 0 has no mapped entry \"no_such_thing\""));
	CHECK(has(e.what(), "0x6064:0x00 Position actual value")); // what there is
	e = thrown([&] { r.add(img, "7:position_actual_value"); });
	CHECK(has(e.what(), "slave 7 does not exist: the bus has 2 slaves (0..1)"));
	e = thrown([&] { r.add(img, "1:0x6064:0"); });
	CHECK(has(e.what(), "slave 1 has no mapped entry \"0x6064:0\""));
	e = thrown([&] { r.add(img, "0:0x6064:zz"); });
	CHECK(has(e.what(), "is not INDEX:SUB"));
	e = thrown([&] { r.add(img, "x:Statusword"); });
	CHECK(has(e.what(), "\"x\" is not a slave position"));
	e = thrown([&] { r.add(img, "0:"); });
	CHECK(has(e.what(), "no entry after"));
	e = thrown([&] { r.add(img, "wkk"); });
	CHECK(has(e.what(), "no such cycle figure (wkc, wkc_expected"));
	r.add(img, "0:Statusword");
	e = thrown([&] { r.add(img, "0:Statusword"); });
	CHECK(has(e.what(), "added twice"));
	CHECK(thrown([] { Recorder x(0); }).errnoValue() == EINVAL);
	CHECK(thrown([] { Recorder x(10'000'001); }).errnoValue() == EINVAL);

	// the trigger: a signal recorded, numeric, a finite level
	ecmxf::RecorderTrigger t;
	t.edge = TriggerEdge::Rising;
	t.signal = "0:Statusword";
	e = thrown([&] { r.arm(t); });
	CHECK(has(e.what(), "\"0:Statusword\" (slave 0 Statusword) is a word of bits or a code, not a number"));
	t.signal = "0:position_actual_value";
	e = thrown([&] { r.arm(t); });
	CHECK(has(e.what(), "\"0:position_actual_value\" is not one of the recorded signals"));
	t.signal = "0:Statusword";
	t.edge = TriggerEdge::Now;
	t.preSamples = 8;
	e = thrown([&] { r.arm(t); });
	CHECK(has(e.what(), "8 pre-trigger samples do not fit a buffer of 8"));
	Recorder empty(4);
	CHECK(has(thrown([&] { empty.arm(); }).what(), "no signal"));
	r.arm();
	CHECK(thrown([&] { r.add(img, "wkc"); }).errnoValue() == EBUSY);
}

TEST_CASE("scope recorder: rising trigger with pre-trigger samples, stop after cycles")
{
	std::int64_t v = 0;
	Recorder r(100);
	r.addValue("ramp", "inc", &v);
	ecmxf::RecorderTrigger t;
	t.edge = TriggerEdge::Rising;
	t.signal = "ramp";
	t.level = 50;
	t.preSamples = 5;
	ecmxf::RecorderStop stop;
	stop.cycles = 10;
	r.arm(t, stop);
	// a value at the level from the start is no crossing: 60, then down, then up through 50
	std::vector<std::int64_t> seq = { 60, 60, 10, 20, 30, 40, 45, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60 };
	std::size_t fed = 0;
	for (const auto x : seq) {
		v = x;
		fed++;
		if (r.sample(std::chrono::microseconds(fed * 1000)) == RecorderState::Done)
			break;
	}
	CHECK(r.done());
	CHECK(fed == 8 + 10); // the trigger at 50 (the 9th sample), then 10 samples with it
	REQUIRE(r.size() == 15);
	CHECK(r.triggerIndex() == 5);
	CHECK(r.value(0, 0) == 20); // the 5 before 50: 20 30 40 45 49 (the older ones dropped)
	CHECK(r.value(4, 0) == 49);
	CHECK(r.value(5, 0) == 50);
	CHECK(r.value(14, 0) == 59);
	CHECK(r.time(5) == 0ns);
	CHECK(r.time(0) == -5ms);
	CHECK(r.time(14) == 9ms);
	// after the stop nothing more is taken
	CHECK(r.sample(1s) == RecorderState::Done);
	CHECK(r.size() == 15);
}

TEST_CASE("scope recorder: falling trigger, stop after a time, and a full buffer")
{
	std::int64_t v = 100;
	Recorder r(1000);
	r.addValue("x", "", &v);
	ecmxf::RecorderTrigger t;
	t.edge = TriggerEdge::Falling;
	t.signal = "x";
	t.level = 0;
	ecmxf::RecorderStop stop;
	stop.time = 5ms;
	r.arm(t, stop);
	for (int i = 0; i < 50 && !r.done(); i++) {
		v = 100 - 10 * i; // 0 at i = 10
		r.sample(std::chrono::milliseconds(i));
	}
	CHECK(r.done());
	REQUIRE(r.size() == 6); // 10 ms .. 15 ms
	CHECK(r.value(0, 0) == 0);
	CHECK(r.time(5) == 5ms);

	// no stop: the buffer full; the trigger now
	Recorder f(7);
	f.addValue("x", "", &v);
	f.arm();
	int n = 0;
	while (f.sample(std::chrono::milliseconds(n)) != RecorderState::Done)
		n++;
	CHECK(n == 6);
	CHECK(f.size() == 7);
	// finish(): a user's quit keeps what there is
	Recorder q(7);
	q.addValue("x", "", &v);
	q.arm();
	q.sample(0ns);
	q.finish();
	CHECK(q.done());
	CHECK(q.size() == 1);
	// never triggered: the times count from the first sample held
	Recorder w(4);
	w.addValue("x", "", &v);
	t.preSamples = 2;
	t.level = 1e9;
	t.edge = TriggerEdge::Rising;
	w.arm(t);
	for (int i = 0; i < 10; i++)
		w.sample(std::chrono::milliseconds(i));
	CHECK_FALSE(w.triggered());
	CHECK(w.size() == 2);
	CHECK(w.triggerIndex() == 2);
	CHECK(w.time(0) == 0ns);
	CHECK(w.time(1) == 1ms);
}

TEST_CASE("scope recorder: the ECM-XF's cyclic exchange in OP on the simulator")
{
	motiontest::Bench b; // the default network in OP, the motion PDOs, a 1 ms Cyclic started
	ecmxf::ProcessImage &img = *b.image;
	ecmxf::Cyclic &cyc = *b.cyc;
	Recorder r(200);
	r.add(img, "1:Following_error_actual_value");
	r.add(img, "1:0x6064:0");
	r.add(img, "wkc");
	r.add(img, "wkc_expected");
	CHECK(r.signals()[0].unit == "inc");
	CHECK(has(thrown([&] { r.add(img, "3:Statusword"); }).what(), "slave 3 does not exist: the bus has 3 slaves"));
	ecmxf::RecorderStop stop;
	stop.cycles = 50;
	r.arm({}, stop);
	std::vector<double> wkc;
	while (!r.done()) {
		const auto &res = cyc.cycle();
		REQUIRE(res.error == 0);
		r.sample(b.now(), res);
		wkc.push_back(res.wkc);
		cyc.waitNextCycle();
	}
	cyc.stop();
	REQUIRE(r.size() == 50);
	for (std::size_t i = 0; i < r.size(); i++) {
		CHECK(r.value(i, 2) == wkc[i]);
		CHECK(r.value(i, 3) == cyc.expectedWkc());
	}
	CHECK(r.value(49, 2) == cyc.expectedWkc()); // the bus answered
	for (std::size_t i = 1; i < r.size(); i++)
		CHECK(r.time(i) > r.time(i - 1));
}

TEST_CASE("scope recorder: the ECM-SK's feedback slots and cycle figures")
{
	auto b = ecmxf::sk::Board::open("sk-sim:");
	b->states().set(ecmxf::State::PreOp);
	const unsigned slaves = b->setup().slaveCount();
	ecmxf::sk::bringUpToOp(*b);
	REQUIRE(slaves >= 1);
	Recorder r(100);
	r.add(*b, slaves, "0:position");
	r.add(*b, slaves, "0:statusword");
	r.add(*b, slaves, "fifo_remaining");
	std::int64_t target = 0;
	r.addValue("target", "inc", &target);
	auto e = thrown([&] { r.add(*b, slaves, std::to_string(slaves) + ":position"); });
	CHECK(has(e.what(), "slave " + std::to_string(slaves) + " does not exist: the bus has " + std::to_string(slaves)));
	e = thrown([&] { r.add(*b, slaves, "0:velocity"); });
	CHECK(has(e.what(), "the ECM-SK's feedback slot has no \"velocity\" (position, statusword, torque, error_code)"));
	e = thrown([&] { r.add(*b, slaves, "wkc"); });
	CHECK(has(e.what(), "no such ECM-SK cycle figure"));
	b->drives().servoOn(1);
	b->drives().waitEnabled(1);
	ecmxf::RecorderStop stop;
	stop.cycles = 40;
	r.arm({}, stop);
	std::vector<std::int32_t> pos;
	for (int i = 1; !r.done(); i++) {
		target = 100 * i;
		(void)b->cyclic().stage(1, ecmxf::sk::Mode::Csp, static_cast<std::int32_t>(target));
		const auto res = b->cyclic().cycle();
		r.sample(b->channel().now(), res);
		pos.push_back(b->drives().axis(1).position);
		CHECK(r.value(r.size() - 1, 2) == res.fifoRemaining);
	}
	REQUIRE(r.size() == 40);
	for (std::size_t i = 0; i < r.size(); i++) {
		CHECK(r.value(i, 0) == pos[i]);
		CHECK(r.value(i, 3) == 100.0 * static_cast<double>(i + 1));
	}
	CHECK(r.value(39, 0) > 0); // the drive followed
	CHECK(static_cast<unsigned>(r.value(39, 1)) == b->drives().axis(1).statusword);
}
