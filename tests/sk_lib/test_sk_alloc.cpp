// SPDX-License-Identifier: MIT
// Board::stage() and Board::cycle() allocate nothing and throw nothing:
// 1000 cycles over a channel that answers every frame with a canned OP
// response (the channel itself allocates nothing), counted by the
// process-wide operator new of tests/common/alloc_counter.cpp; the same
// with a packet trace recording (text and pcapng).

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>

#include <ecmxf/link/byte_channel.hpp>
#include <ecmxf/sk/board.hpp>

#include "../common/alloc_counter.hpp"
#include "ecmsk-proto.h"

namespace {

class CannedChannel final : public ecmxf::ByteChannel
{
public:
	CannedChannel()
	{
		rsp_.fill(0);
		rsp_[0] = ECMSK_RSP_OP;
		rsp_[2] = ECMSK_STATE_OP;
		rsp_[8] = 0x00;
		rsp_[9] = 0x01; // 256 free
	}
	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override
	{
		frames++;
		staged = 0;
		for (std::size_t s = 1; s <= 40; s++)
			staged += mosi[s * 12] == ECMSK_CMD_CSP;
		std::copy(rsp_.begin(), rsp_.end(), miso.begin());
		t_ += std::chrono::microseconds(168);
	}
	bool waitReady(std::chrono::nanoseconds) override { return true; }
	std::chrono::nanoseconds now() const override { return t_; }
	void sleepFor(std::chrono::nanoseconds d) override { t_ += d; }
	std::string name() const override { return "canned"; }
	unsigned frames = 0, staged = 0;

private:
	std::array<std::uint8_t, 504> rsp_{};
	std::chrono::nanoseconds t_{ 0 };
};

} // namespace

TEST_CASE("sk alloc: stage() and cycle() allocate nothing")
{
	auto owned = std::make_unique<CannedChannel>();
	CannedChannel *ch = owned.get();
	ecmxf::sk::Board b(std::move(owned));
	b.states().status(); // OP, 256 free
	REQUIRE(b.state() == ecmxf::State::Op);
	const auto before = ecmxf_test::allocations();
	unsigned ok = 0;
	for (int i = 0; i < 1000; i++) {
		for (unsigned s = 1; s <= 40; s++)
			ok += b.cyclic().stage(s, ecmxf::sk::Mode::Csp, i) ? 1u : 0u;
		const auto r = b.cyclic().cycle();
		ok += r.status == ecmxf::sk::CycleStatus::Ok ? 0u : 1000000u;
	}
	const auto after = ecmxf_test::allocations();
	CHECK(after - before == 0u);
	CHECK(ok == 40000u); // every target staged, every cycle Ok
	CHECK(ch->staged == 40u);
	CHECK(ch->frames == 1001u);
}

TEST_CASE("sk alloc: recording a trace (text and pcapng) allocates nothing per exchange")
{
	for (const char *path : { "/dev/null", "/tmp/ecmxf-test-sk-alloc.pcapng" }) {
		auto owned = std::make_unique<CannedChannel>();
		ecmxf::sk::Board b(std::move(owned));
		b.startTrace(path);
		b.states().status(); // the first frames: the trace's buffers exist
		REQUIRE(b.state() == ecmxf::State::Op);
		const auto before = ecmxf_test::allocations();
		unsigned ok = 0;
		for (int i = 0; i < 200; i++) {
			for (unsigned s = 1; s <= 40; s++)
				ok += b.cyclic().stage(s, ecmxf::sk::Mode::Csp, i) ? 1u : 0u;
			ok += b.cyclic().cycle().status == ecmxf::sk::CycleStatus::Ok ? 0u : 1000000u;
		}
		const auto after = ecmxf_test::allocations();
		CHECK(after - before == 0u);
		CHECK(ok == 8000u);
		b.stopTrace();
	}
	std::remove("/tmp/ecmxf-test-sk-alloc.pcapng");
}
