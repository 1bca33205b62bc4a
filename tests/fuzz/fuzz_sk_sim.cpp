// SPDX-License-Identifier: MIT
/*
 * fuzz_sk_sim.cpp - libFuzzer target: arbitrary frames into the simulated
 * ECM-SK (ecmxf::sk::SimBoard) with a servo, an EST-584, a 2-channel HSP and a
 * digital I/O terminal on its bus.
 *
 *   [0]   bit 0: 16-byte slots; bit 1: test mode; bit 2: FIFO abandon
 *         off; bits 4-5: SET_EX saved (in force from power-on)
 *   then per exchange (at most kMaxSteps): dt (time passes dt * 50 us,
 *   0xFF: a power cycle), flags (bit 0: wait for Busy to fall first;
 *   bit 1: seal the frame's CRC), then the frame (zero-padded)
 *
 * Invariants (abort() on violation): Current State is one of the four;
 * a response sealed when response CRCs are in force; FIFO remaining never
 * above the depth, used + remaining = depth; Busy falls within 20 ms of
 * an exchange; a transfer while Busy is high answers zeros.
 */
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/sk_board.hpp>

#include "ecmsk-proto.h"
#include "fuzz.h"

const char *ecmxf_fuzz_context = nullptr;

namespace {

constexpr unsigned kMaxSteps = 48;

void require(bool ok, const char *what)
{
	if (!ok) {
		std::fprintf(stderr, "fuzz_sk_sim: invariant violated: %s (input %s)\n", what,
			     ecmxf_fuzz_context ? ecmxf_fuzz_context : "?");
		std::abort();
	}
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	using namespace std::chrono_literals;
	if (size < 1)
		return 0;
	ecmxf::sk::BoardConfig cfg;
	cfg.slotSize = (data[0] & 1) ? 16 : 12;
	cfg.testMode = data[0] & 2;
	cfg.fifoAbandon = !(data[0] & 4);
	cfg.extensions = (data[0] >> 4) & 3;
	ecmxf::sk::SimBoard b(ecmxf::sim::Network::fromText("slave servo\nslave EST-584\nslave hsp channels=2\nslave dio\n",
							    "fuzz"),
			      cfg);
	const std::size_t n = b.frameSize();
	std::vector<std::uint8_t> mosi(n), miso(n);
	std::size_t pos = 1;
	for (unsigned step = 0; step < kMaxSteps && pos + 2 <= size; step++) {
		const std::uint8_t dt = data[pos++];
		const std::uint8_t flags = data[pos++];
		if (dt == 0xFF)
			b.powerCycle();
		else
			b.advance(std::chrono::microseconds(50) * dt);
		std::fill(mosi.begin(), mosi.end(), 0);
		for (std::size_t i = 0; i < n && pos < size; i++)
			mosi[i] = data[pos++];
		if (flags & 1) {
			for (int i = 0; i < 20000 && b.busy(); i++)
				b.advance(1us);
			require(!b.busy(), "Busy stayed high for 20 ms");
		}
		if (flags & 2)
			ecmsk_frame_seal(mosi.data(), n);
		const bool wasBusy = b.busy();
		b.exchange(mosi, miso);
		if (wasBusy) {
			for (auto c : miso)
				require(c == 0, "a transfer while Busy answered data");
			continue;
		}
		require(ecmsk_state_valid(miso[2]), "Current State is no state");
		if (b.extensionsInForce() & ECMSK_EX_RSP_CRC)
			require(ecmsk_frame_crc_ok(miso.data(), n), "response without its CRC");
		require(b.fifoUsed() <= cfg.fifoDepth, "FIFO above its depth");
		if (miso[2] == ECMSK_STATE_OP) {
			const unsigned remaining = miso[8] | static_cast<unsigned>(miso[9]) << 8;
			require(remaining <= cfg.fifoDepth, "FIFO remaining above the depth");
		}
	}
	return 0;
}
