// SPDX-License-Identifier: MIT
// The cyclic path allocates nothing: this binary replaces the global
// operator new/delete with counting versions and runs Cyclic on the
// simulator transport. The count covers everything in the process during
// the measured cycles: the library's cyclic path (Cyclic::cycle(),
// Cyclic::waitNextCycle(), Device::transact(), the protocol engine) and the
// simulated chip and slave models behind SimChannel.

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <new>

#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>

#include "../common/alloc_counter.hpp"
#include "bus.hpp"

using namespace std::chrono_literals;

TEST_CASE("Cyclic: 1000 cycles on the simulator allocate nothing", "[lib][pdo][cyclic][alloc]")
{
	// the synchronous cycle, and the one that leaves its FIFO command's
	// answer to the next cycle (with a working counter read every 10th)
	const bool ahead = GENERATE(false, true);
	INFO("fifoAnswerNextCycle " << ahead);
	// the counter counts. A call of operator new itself: clang may elide
	// the allocation of a new-expression (a vector's) whose memory is
	// not used
	const auto before = ecmxf_test::allocations();
	void *p = ::operator new(12);
	::operator delete(p);
	REQUIRE(ecmxf_test::allocations() == before + 1);

	pdotest::Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	auto cw = image.output<std::uint16_t>(0, 0x6040, 0);
	auto dio = image.output<std::uint8_t>(2, 0x7000, 1);
	auto pos = image.input<std::int32_t>(1, 0x6064, 0);
	ecmxf::CyclicConfig cfg;
	cfg.period = 1ms;
	cfg.busCycle = 1ms;
	cfg.fifoAnswerNextCycle = ahead;
	if (ahead)
		cfg.wkcEvery = 10;
	ecmxf::Cyclic cyc(*bus.dev, image, cfg);
	cyc.start();
	// warm-up: the first fill, the first reads
	for (int i = 0; i < 100; i++) {
		(void)cyc.cycle();
		(void)cyc.waitNextCycle();
	}

	int errors = 0;
	std::int64_t sum = 0;
	const auto start = ecmxf_test::allocations();
	for (int i = 0; i < 1000; i++) {
		cw.set(static_cast<std::uint16_t>(i));
		dio.set(static_cast<std::uint8_t>(i));
		const ecmxf::CycleResult &r = cyc.cycle();
		errors += r.error != 0 || !r.wkcOk;
		sum += pos.get();
		(void)cyc.waitNextCycle();
	}
	const auto allocs = ecmxf_test::allocations() - start;

	CHECK(allocs == 0);
	CHECK(errors == 0);
	CHECK(sum == 0);
	CHECK(cyc.stats().cycles == 1100);
	CHECK(cyc.stats().failedCycles == 0);
	CHECK(cyc.stats().wkcMismatches == 0);
}
