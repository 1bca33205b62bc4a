// SPDX-License-Identifier: MIT
/*
 * ecmxf-demo --board ecm-sk: the same tour on the simulated ECM-SK
 * starter kit (servo = Drive, EST-584 = STEP, digital I/O = IO): the slot
 * frame, bring-up by SET_AXIS (types found by the board), SET_DC, DRIVE_MODE,
 * SDO through the SDO slot with a real abort, SV_ON, a CSP move of both
 * axes through the cyclic FIFO with live positions, IO and the ECM IC's
 * own I/O, homing, and a summary. With --plot DIR the move of each axis
 * (staged target, position, their difference, statusword) is recorded
 * and written as DIR/axisN.csv and DIR/axisN.svg (ecmxf-demo-plot.cpp).
 */
#include "ecmxf-demo-sk.hpp"

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <ecmxf/model/types_bus.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/slaves.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/sim/sk_board.hpp>
#include <ecmxf/scope/recorder.hpp>

#include "ecmxf-demo-plot.hpp"

namespace {

using namespace std::chrono_literals;
using namespace ecmxf::sk;

void heading(int n, const char *title)
{
	std::printf("\n== ECM-SK %d. %s ==\n", n, title);
	std::fflush(stdout);
}

} // namespace

int ecmxfDemoSk(bool fast, const std::string &plotDir)
{
	std::vector<std::string> failures;
	auto fail = [&](const std::string &what) {
		std::printf("   FAILED: %s\n", what.c_str());
		failures.push_back(what);
	};
	auto b = Board::open("sk-sim:");
	SimBoard &sim = *b->simulator();

	heading(1, "the board and its frame");
	std::printf("   %zu-byte frames: slot 0 the ECM, slots 1..%u the slaves, slot %u the SDO slot\n",
		    b->frameSize(), b->maxSlaves(), b->maxSlaves() + 1);
	std::printf("   state %s; every answer comes with the next exchange; Busy low = ready\n",
		    std::string(stateName(b->states().status().state)).c_str());

	heading(2, "bring-up: PRE-OP, slave types by SET_AXIS, SET_DC, DRIVE_MODE, OP");
	b->states().set(ecmxf::State::PreOp);
	const auto types = b->setup().detectAxes();
	for (std::size_t i = 0; i < types.size(); i++)
		std::printf("   slave %zu: %s\n", i, std::string(slaveTypeName(types[i])).c_str());
	b->setup().setCycleTime(1000);
	b->drives().setMode(1, Mode::Csp);
	b->drives().setMode(2, Mode::Csp);
	b->states().set(ecmxf::State::Op);
	const auto st = b->states().status();
	std::printf("   %s, FIFO %u free\n", std::string(stateName(st.state)).c_str(), st.fifoRemaining);
	if (st.state != ecmxf::State::Op)
		fail("not in OP");

	heading(3, "SDO through the SDO slot");
	const auto vendor = b->sdo().read<std::uint32_t>(2, 0x1018, 1);
	std::printf("   slave 1 vendor id 0x%08X\n", vendor);
	try {
		(void)b->sdo().read(2, 0x5FFF, 0);
		fail("0x5FFF did not abort");
	} catch (const ecmxf::SdoError &e) {
		std::printf("   slave 1 0x5FFF: abort 0x%08X %s\n", e.abortCode(),
			    std::string(ecmxf::sdoAbortText(e.abortCode())).c_str());
	}

	heading(4, "SV_ON and a CSP move of the Drive and the STEP slave");
	b->drives().servoOn(1);
	b->drives().servoOn(2);
	b->drives().waitEnabled(1);
	b->drives().waitEnabled(2);
	b->states().status();
	const auto p1 = b->drives().axis(1).position, p2 = b->drives().axis(2).position;
	unsigned dropped = 0, held = 0;
	// --plot: per axis (slot 1 and 2: bus positions 0 and 1) the target
	// staged last, the feedback position, their difference, the statusword
	std::array<std::int64_t, 2> staged{ p1, p2 }, lag{ 0, 0 };
	std::array<std::unique_ptr<ecmxf::Recorder>, 2> recs;
	if (!plotDir.empty())
		for (std::size_t i = 0; i < 2; i++) {
			const std::string n = std::to_string(i) + ":";
			recs[i] = std::make_unique<ecmxf::Recorder>(2000);
			(void)recs[i]->addValue(n + "target", "inc", &staged[i]);
			(void)recs[i]->add(*b, b->maxSlaves(), n + "position");
			(void)recs[i]->addValue(n + "following_error", "inc", &lag[i]);
			(void)recs[i]->add(*b, b->maxSlaves(), n + "statusword");
			recs[i]->arm();
		}
	const auto sample = [&](const CycleResult &r) {
		for (std::size_t i = 0; i < 2; i++)
			if (recs[i]) {
				lag[i] = staged[i] - b->drives().axis(static_cast<unsigned>(i + 1)).position;
				(void)recs[i]->sample(b->channel().now(), r);
			}
	};
	for (int i = 1; i <= 1000; i++) {
		const double x = static_cast<double>(i) / 1000.0;
		const double s = x * x * (3 - 2 * x); // smooth start and stop
		const std::int32_t t1 = p1 + static_cast<std::int32_t>(20000 * s), t2 = p2 + static_cast<std::int32_t>(50000 * s);
		if (b->cyclic().stage(1, Mode::Csp, t1))
			staged[0] = t1;
		else
			held++;
		if (b->cyclic().stage(2, Mode::Csp, t2))
			staged[1] = t2;
		else
			held++;
		const auto r = b->cyclic().cycle();
		dropped += r.dropped;
		sample(r);
		b->channel().sleepFor(1ms - sim.wireTime()); // one frame per 1 ms cycle
		if (!fast)
			std::this_thread::sleep_for(1ms);
		if (i % 250 == 0)
			std::printf("   t=%4d ms  drive %8d  step %8d  FIFO %u free\n", i, b->drives().axis(1).position,
				    b->drives().axis(2).position, r.fifoRemaining);
	}
	for (int i = 0; i < 20; i++) {
		sample(b->cyclic().cycle());
		b->channel().sleepFor(1ms);
	}
	for (auto &r : recs)
		if (r)
			r->finish();
	std::printf("   end: drive %d (target %d), step %d (target %d); %u dropped, %u held back\n",
		    b->drives().axis(1).position, p1 + 20000, b->drives().axis(2).position, p2 + 50000, dropped, held);
	if (b->drives().axis(1).position != p1 + 20000 || b->drives().axis(2).position != p2 + 50000)
		fail("the axes did not reach their targets");

	heading(5, "IO and the ECM IC's own I/O");
	b->io().write(3, 0xA5);
	b->channel().sleepFor(3ms);
	auto *io = dynamic_cast<ecmxf::sim::DioModel *>(&sim.network().at(2));
	std::printf("   IO_WR 0xA5 -> terminal outputs 0x%02X\n", io ? io->outputs()[0] : 0);
	sim.setLioInputs(0x2D);
	std::printf("   LIO_RD 0x%02X\n", b->io().readLocal());

	heading(6, "homing the STEP slave (method 37: here is home)");
	b->sdo().write<std::int32_t>(2, 0x607C, 0, 0);
	b->drives().home(2, 37); // returns once statusword bits 10 and 12 said "homed"
	b->states().status();
	std::printf("   homed; back in CSP: statusword 0x%04X, position %d\n", b->drives().axis(2).statusword,
		    b->drives().axis(2).position);
	if (b->drives().axis(2).position != 0)
		fail("not at the home offset");

	if (!plotDir.empty()) {
		const std::vector<DemoAxisPlot> plots{
			{ recs[0].get(), "ecmxf-demo --board ecm-sk: CSP move of slave 0 (Drive), " + std::to_string(p1) +
						 " to " + std::to_string(p1 + 20000) },
			{ recs[1].get(), "ecmxf-demo --board ecm-sk: CSP move of slave 1 (STEP), " + std::to_string(p2) +
						 " to " + std::to_string(p2 + 50000) },
		};
		std::printf("   plots:");
		for (const std::string &f : writeDemoPlots(plotDir, plots))
			std::printf(" %s", f.c_str());
		std::printf("\n");
	}

	heading(7, "summary");
	std::printf("   %s\n", failures.empty() ? "all steps worked" : "some steps FAILED");
	return failures.empty() ? 0 : 1;
}
