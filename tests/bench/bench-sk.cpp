// SPDX-License-Identifier: MIT
//
// bench-sk: the ECM-SK's two performance targets (issue 16).
//
//  1. Host CPU per 504-byte frame: 40 CSP slots encoded, the CRC-8 sealed,
//     ecmsk_link_prepare(), then a 504-byte response CRC-checked,
//     ecmsk_link_complete() and all 40 slave slots decoded; against the
//     frame's wire time at 24 MHz (168 us). Target: <= 1 %.
//  2. The simulated board at its minimum cycle (250 us) with 40 slaves in
//     OP (20 EST-584, 10 servo, 10 digital I/O), a CSP target for every
//     drive in every frame: simulated time / CPU time of this thread.
//     Target: >= 10x. Cycles and FIFO drops are printed so that a broken
//     run cannot look fast.

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <time.h>

#include <ecmxf/sk/board.hpp>
#include <ecmxf/sim/sk_board.hpp>
#include <ecmxf/sk/sim_channel.hpp>

#include "ecmsk-proto.h"

namespace {

using namespace std::chrono_literals;

double cpu()
{
	timespec ts{};
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
	return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

[[noreturn]] void die(const char *what)
{
	std::fprintf(stderr, "bench-sk: %s\n", what);
	std::exit(1);
}

void frameCost()
{
	ecmsk_link l{};
	if (ecmsk_link_init(&l, 12, ECMSK_LINK_TX_CRC | ECMSK_LINK_RX_CRC))
		die("init");
	std::vector<std::uint8_t> mosi(504), miso(504, 0);
	// a response in OP, every slave answering CSP
	miso[0] = ECMSK_RSP_OP;
	miso[2] = ECMSK_STATE_OP;
	miso[8] = 200;
	for (unsigned s = 1; s <= 40; s++) {
		miso[s * 12] = ECMSK_CMD_CSP;
		miso[s * 12 + 2] = 0x37;
		miso[s * 12 + 4] = static_cast<std::uint8_t>(s);
	}
	ecmsk_frame_seal(miso.data(), miso.size());
	const unsigned n = 200000;
	std::uint64_t sink = 0;
	const double t0 = cpu();
	for (unsigned i = 0; i < n; i++) {
		std::fill(mosi.begin(), mosi.end(), 0);
		for (unsigned s = 1; s <= 40; s++) {
			ecmsk_slave_cmd c{ ECMSK_CMD_CSP, static_cast<std::uint8_t>(i), i * 10 + s, 0, 0 };
			ecmsk_put_slave(&l.g, mosi.data(), s, &c);
		}
		if (ecmsk_link_prepare(&l, mosi.data(), i, 0))
			die("prepare");
		ecmsk_result r{};
		if (ecmsk_link_complete(&l, miso.data(), i, &r))
			die("complete");
		for (unsigned s = 1; s <= 40; s++) {
			ecmsk_slave_rsp a{};
			ecmsk_get_slave(&l.g, miso.data(), s, &a);
			sink += a.position + a.statusword;
		}
		sink += mosi[3];
	}
	const double per = (cpu() - t0) / n;
	const double wire = 504.0 * 8 / 24e6;
	std::printf("bench-sk frame: %.2f us CPU per 504-byte frame (encode 40 + CRC + decode 40), "
		    "%.3f %% of its 168 us wire time at 24 MHz (target <= 1 %%)%s\n",
		    per * 1e6, per / wire * 100, sink == 42 ? " " : "");
}

void simSpeed()
{
	std::string net;
	for (int i = 0; i < 20; i++)
		net += "slave EST-584\n";
	for (int i = 0; i < 10; i++)
		net += "slave servo\n";
	for (int i = 0; i < 10; i++)
		net += "slave dio\n";
	const std::string path = "/tmp/bench-sk-40.net";
	if (std::FILE *f = std::fopen(path.c_str(), "w")) {
		std::fputs(net.c_str(), f);
		std::fclose(f);
	} else {
		die("cannot write the network file");
	}
	ecmxf::sk::BoardConfig cfg;
	cfg.fifoAbandon = false;
	auto ch = std::make_unique<ecmxf::sk::SimBoardChannel>(path, cfg);
	auto *sim = &ch->board();
	ecmxf::sk::Board b(std::move(ch));
	b.states().set(ecmxf::State::PreOp);
	std::vector<ecmxf::sk::SlaveType> types;
	for (int i = 0; i < 20; i++)
		types.push_back(ecmxf::sk::SlaveType::Step);
	for (int i = 0; i < 10; i++)
		types.push_back(ecmxf::sk::SlaveType::Drive);
	for (int i = 0; i < 10; i++)
		types.push_back(ecmxf::sk::SlaveType::Io);
	if (b.setup().setAxes(types) != 40)
		die("not 40 slaves");
	b.setup().setCycleTime(250);
	b.states().set(ecmxf::State::Op);
	for (unsigned s = 1; s <= 30; s++)
		b.drives().servoOn(s);
	b.states().status();
	std::vector<std::int32_t> start(31);
	for (unsigned s = 1; s <= 30; s++)
		start[s] = b.drives().axis(s).position;
	const auto cycles0 = sim->stats().cycles;
	const auto t0 = b.channel().now();
	const double c0 = cpu();
	unsigned dropped = 0;
	for (int i = 0; i < 4000; i++) { // 1 s of 250 us cycles
		for (unsigned s = 1; s <= 30; s++)
			b.cyclic().stage(s, ecmxf::sk::Mode::Csp, start[s] + i);
		dropped += b.cyclic().cycle().dropped;
		b.channel().sleepFor(250us - sim->wireTime() - sim->config().busyTime);
	}
	const double c = cpu() - c0;
	const double simulated = std::chrono::duration<double>(b.channel().now() - t0).count();
	b.states().status();
	const auto moved1 = b.drives().axis(1).position - start[1], moved30 = b.drives().axis(30).position - start[30];
	std::printf("bench-sk sim: 40 slaves at 250 us: %.3f s simulated in %.3f s CPU = %.1fx real time "
		    "(target >= 10x); %llu bus cycles, %llu targets applied, %u dropped; "
		    "slave 1 moved %d, slave 30 moved %d (of 3999)\n",
		    simulated, c, simulated / c,
		    static_cast<unsigned long long>(sim->stats().cycles - cycles0),
		    static_cast<unsigned long long>(sim->stats().fifoApplied), dropped, moved1, moved30);
	if (moved1 < 3900 || moved30 < 3900)
		die("the axes did not follow: the run does not count");
	std::remove(path.c_str());
}

} // namespace

int main()
{
	frameCost();
	simSpeed();
	return 0;
}
