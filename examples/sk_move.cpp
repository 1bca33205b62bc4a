// SPDX-License-Identifier: MIT
/*
 * Enable a drive behind an ECM-SK starter kit and move it in CSP mode,
 * one staged target per 1 ms cycle; the servo goes off however the move
 * ends.
 *
 *   ecmxf-example-sk-move [URI]    (default "sk-sim:"; slave 1 is a servo)
 */
#include <chrono>
#include <cstdio>
#include <exception>
#include <stdexcept>

#include <ecmxf/ecmxf.hpp>

using namespace std::chrono_literals;
using ecmxf::sk::Board;

int main(int argc, char **argv)
{
	if (argc > 2) {
		std::fprintf(stderr, "usage: %s [URI]\n", argv[0]);
		return 2;
	}
	try {
		auto board = Board::open(argc > 1 ? argv[1] : "sk-sim:");
		auto drives = board->drives();
		auto cyclic = board->cyclic();
		// PRE-OP, the slaves' types, 1 ms cycle, CSP, OP
		board->states().set(ecmxf::State::PreOp);
		board->setup().detectAxes();
		board->setup().setCycleTime(1000);
		drives.setMode(1, ecmxf::sk::Mode::Csp);
		board->states().set(ecmxf::State::Op);

		drives.servoOn(1);
		// servo off on every way out of this scope
		struct ServoOff {
			ecmxf::sk::BoardDrives &d;
			~ServoOff() { try { d.servoOff(1); } catch (const std::exception &) {} }
		} const off{ drives };
		drives.waitEnabled(1);

		// 20000 counts in 500 cycles; a full FIFO holds the target back a cycle
		board->states().status();
		const std::int32_t from = drives.axis(1).position, to = from + 20000;
		for (int i = 1; i <= 500;) {
			if (cyclic.stage(1, ecmxf::sk::Mode::Csp, from + (to - from) * i / 500))
				i++;
			const auto st = cyclic.cycle().status;
			if (st == ecmxf::sk::CycleStatus::Link || st == ecmxf::sk::CycleStatus::Busy)
				throw std::runtime_error("the cyclic exchange failed: " + cyclic.lastError());
			board->channel().sleepFor(1ms);
		}
		for (int i = 0; i < 20; i++, board->channel().sleepFor(1ms)) // let the FIFO drain
			cyclic.cycle();
		std::printf("slave 1: moved from %d to %d (target %d)\n", from, drives.axis(1).position, to);
	} catch (const std::exception &e) {
		std::fprintf(stderr, "sk-move: %s\n", e.what());
		return 1;
	}
	return 0;
}
