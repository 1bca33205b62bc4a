// SPDX-License-Identifier: MIT
// Cyclic on the simulator: outputs reach the slave models and inputs come
// back, the working counter, no frame lost, duplicated or reordered over
// 2000 cycles, RxFIFO refusals and TxFIFO overflows counted, pacing on
// virtual time, and the errors.

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <vector>

#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/sim/slaves.hpp>

#include "bus.hpp"
#include "../common/thrown.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Equals;
using pdotest::Bus;

namespace {

using ecmxftest::thrown;

ecmxf::CyclicConfig config(unsigned rxFill = 0)
{
	ecmxf::CyclicConfig c;
	c.period = 1ms;
	c.busCycle = 1ms; // ECAT_INIT_OP's SYNC0 in Bus::init()
	c.rxFill = rxFill;
	return c;
}

/// Runs @p n cycles paced at the period; every one must succeed.
void runCycles(ecmxf::Cyclic &cyc, int n)
{
	for (int i = 0; i < n; i++) {
		const ecmxf::CycleResult &r = cyc.cycle();
		INFO("cycle " << i << ": " << r.message);
		REQUIRE(r.error == 0);
		REQUIRE(cyc.waitNextCycle() == 0);
	}
}

} // namespace

TEST_CASE("Cyclic: what it reads from the chip for the default network", "[lib][pdo][cyclic]")
{
	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	ecmxf::Cyclic cyc(*bus.dev, image, config());
	CHECK(cyc.packSizes().rxPdoBytes == 25);
	CHECK(cyc.packSizes().txPdoBytes == 35);
	CHECK(cyc.slaveCounts().inputSlaves == 3);
	CHECK(cyc.slaveCounts().outputSlaves == 3);
	// 3 slaves with inputs x 1 + 3 slaves with outputs x 2
	CHECK(cyc.expectedWkc() == 9);
	CHECK(cyc.rxDepth() == 64);
	CHECK(cyc.txDepth() == 64);
	CHECK(cyc.rxFill() == 62);
	// 112 data bytes: 4 frames of 25 out, 3 frames of 35 in
	CHECK(cyc.framesPerWrite() == 4);
	CHECK(cyc.framesPerRead() == 3);
}

TEST_CASE("Cyclic: outputs reach the slave models and inputs come back", "[lib][pdo][cyclic]")
{
	Bus bus;
	bus.toOp();
	auto &drive0 = bus.model<ecmxf::sim::Cia402Model>(0);
	auto &drive1 = bus.model<ecmxf::sim::Cia402Model>(1);
	auto &dio = bus.model<ecmxf::sim::DioModel>(2);

	ecmxf::ProcessImage image(pdotest::defaultPdos());
	auto cw0 = image.output<std::uint16_t>(0, 0x6040, 0);
	auto target1 = image.output<std::int32_t>(1, "Target position");
	auto out2 = image.output<bool>(2, 0x7000, 2);
	auto out8 = image.output<bool>(2, 0x7000, 8);
	auto sw0 = image.input<std::uint16_t>(0, 0x6041, 0);
	auto pos1 = image.input<std::int32_t>(1, 0x6064, 0);
	auto in6 = image.input<bool>(2, 0x6000, 6);

	ecmxf::Cyclic cyc(*bus.dev, image, config(4));
	CHECK(cyc.rxFill() == 4);
	cw0.set(0x0006); // shutdown: SWITCH ON DISABLED -> READY TO SWITCH ON
	target1.set(-1000);
	out2.set(true);
	out8.set(true);
	cyc.start();
	runCycles(cyc, 20);

	CHECK(drive0.controlword() == 0x0006);
	CHECK(drive1.controlword() == 0x0000);
	CHECK(dio.outputs()[0] == 0x82);
	// statusword x01x 0001: ready to switch on (CiA 402)
	CHECK((sw0.get() & 0x6F) == 0x21);

	drive1.setPositionActual(-123456);
	dio.setInput(5, true);
	runCycles(cyc, 10);
	CHECK(pos1.get() == -123456);
	CHECK(in6.get());
	CHECK(image.inputs()[34] == 0x20);

	const ecmxf::CycleResult &r = cyc.lastResult();
	CHECK(r.error == 0);
	CHECK(r.message == std::string());
	CHECK(r.ecatState == 8);
	CHECK(r.wkcRead);
	CHECK(r.wkc == 9);
	CHECK(r.expectedWkc == 9);
	CHECK(r.wkcOk);
	CHECK(r.inputsUpdated);
	CHECK((r.ecmStatus & 0x40) != 0); // FIFO enabled
	CHECK(cyc.stats().cycles == 30);
	CHECK(cyc.stats().failedCycles == 0);
	CHECK(cyc.stats().wkcReads == 30);
	CHECK(cyc.stats().wkcMismatches == 0);
	CHECK(cyc.stats().txOverflows == 0);
	CHECK(cyc.stats().rxRefusals == 0);

	cyc.stop();
	CHECK((bus.info().ecmStatus & 0x40) == 0);
}

TEST_CASE("Cyclic: no frame lost, duplicated or reordered over 2000 cycles", "[lib][pdo][cyclic]")
{
	Bus bus(pdotest::network("loopback.net"));
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::loopbackPdos());
	auto counter = image.output<std::uint32_t>(2, 0x7000, 1);
	auto echo = image.input<std::uint32_t>(2, 0x6000, 1);

	// every TxPDO frame: the value the I/O terminal got in that bus cycle
	// (its inputs mirror its outputs), at byte 17 + 17 of the frame
	std::vector<std::uint32_t> seen;
	seen.reserve(4000);
	ecmxf::CyclicConfig cfg = config();
	cfg.context = &seen;
	cfg.onInputFrame = [](void *ctx, std::span<const std::uint8_t> f) noexcept {
		const std::uint32_t v = static_cast<std::uint32_t>(f[34]) | static_cast<std::uint32_t>(f[35]) << 8 |
					static_cast<std::uint32_t>(f[36]) << 16 |
					static_cast<std::uint32_t>(f[37]) << 24;
		static_cast<std::vector<std::uint32_t> *>(ctx)->push_back(v);
	};
	ecmxf::Cyclic cyc(*bus.dev, image, cfg);
	REQUIRE(cyc.rxFill() == 62);
	cyc.start();

	const auto cycles0 = bus.chip().stats().busCycles;
	std::uint64_t underruns1 = 0;
	for (std::uint32_t i = 1; i <= 2000; i++) {
		counter.set(i);
		const ecmxf::CycleResult &r = cyc.cycle();
		INFO("cycle " << i << ": " << r.message);
		REQUIRE(r.error == 0);
		REQUIRE(r.wkc == 9);
		if (i == 1)
			underruns1 = bus.chip().stats().rxUnderruns;
		REQUIRE(cyc.waitNextCycle() == 0);
	}
	const auto busCycles = bus.chip().stats().busCycles - cycles0;

	// every bus cycle's frame came back once, in order
	CHECK(cyc.stats().framesPopped == seen.size());
	CHECK(seen.size() + 2 >= busCycles);
	CHECK(seen.size() <= busCycles);
	CHECK(bus.chip().stats().txDropped == 0);
	CHECK(cyc.stats().txOverflows == 0);
	CHECK(cyc.stats().rxRefusals == 0);
	CHECK(bus.chip().stats().rxRefused == 0);
	// the RxFIFO never ran dry once filled: no output frame was repeated
	CHECK(bus.chip().stats().rxUnderruns == underruns1);

	// zeros (the pre-loaded outputs), then 1, 2, 3... in order without a
	// gap. Values repeat only while the RxFIFO is first topped up (the
	// first fill takes 17 commands, during which bus cycles take frames);
	// from the 5th cycle on every value arrives exactly once.
	const pdotest::Sequence q = pdotest::sequenceOf(seen, 4);
	REQUIRE(q.found);
	CHECK(q.first == 1);
	if (q.badFrame < seen.size())
		FAIL_CHECK("frame " << q.badFrame << " carries " << seen[q.badFrame] << " after "
				    << seen[q.badFrame - 1]);
	CHECK(q.badFrame == seen.size());
	const std::uint32_t expect = seen.back() + 1;
	CHECK(q.repeated == 0);
	CHECK(q.distinct == seen.back());
	// what is still queued: about rxFill frames
	CHECK(expect - 1 >= 2000 - 62 - 2);
	CHECK(echo.get() == seen.back());
}

TEST_CASE("Cyclic: a TxFIFO overflow while the application sleeps is counted", "[lib][pdo][cyclic]")
{
	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	ecmxf::Cyclic cyc(*bus.dev, image, config(8));
	cyc.start();
	runCycles(cyc, 50);
	REQUIRE(cyc.stats().txOverflows == 0);
	REQUIRE(bus.chip().stats().txDropped == 0);

	// 200 bus cycles without the application: 64 frames fit, the chip
	// drops the oldest of the rest. The I/O inputs change 30 cycles before
	// the end: the older queued frames carry 0x00, the newest 0x22.
	auto &dio = bus.model<ecmxf::sim::DioModel>(2);
	bus.run(170ms);
	dio.setInputs(std::vector<std::uint8_t>{ 0x22 });
	bus.run(30ms);
	const ecmxf::CycleResult &r = cyc.cycle();
	REQUIRE(r.error == 0);
	CHECK(image.slaveInputs(2)[0] == 0x22); // the newest frame went into the image
	CHECK(r.txOverflow);
	const auto dropped = bus.chip().stats().txDropped;
	CHECK(dropped >= 130);
	CHECK(r.txDroppedEstimate + 1 >= dropped);
	CHECK(r.txDroppedEstimate <= dropped + 1);
	// the whole queue was read in this one cycle: 64 frames
	CHECK(r.framesPopped >= 64);
	CHECK(r.txFifoCount <= 1);
	(void)cyc.waitNextCycle();
	const std::uint32_t estimate = r.txDroppedEstimate;
	runCycles(cyc, 20);
	CHECK(cyc.stats().txOverflows == 1);
	CHECK(cyc.stats().txDroppedEstimate == estimate);
	CHECK(cyc.stats().lateCycles == 1);
}

TEST_CASE("Cyclic: of several queued frames the newest goes into the image", "[lib][pdo][cyclic]")
{
	Bus bus;
	bus.toOp();
	auto &dio = bus.model<ecmxf::sim::DioModel>(2);
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	std::vector<std::uint8_t> seen;
	seen.reserve(64);
	ecmxf::CyclicConfig cfg = config(8);
	cfg.context = &seen;
	cfg.onInputFrame = [](void *ctx, std::span<const std::uint8_t> f) noexcept {
		static_cast<std::vector<std::uint8_t> *>(ctx)->push_back(f[34]);
	};
	ecmxf::Cyclic cyc(*bus.dev, image, cfg);
	cyc.start();
	runCycles(cyc, 10);
	// queue a known set of frames: the FIFO off and drained, then on for
	// the bus cycles up to the one after the inputs changed, then off
	auto &chip = bus.chip();
	bus.dev->pdo().fifoEnable(false);
	REQUIRE(cyc.cycle().error == 0);
	REQUIRE(bus.info().txFifoCnt == 0);
	const auto b0 = chip.stats().busCycles;
	auto waitFor = [&](std::uint64_t n) {
		while (chip.stats().busCycles < b0 + n)
			bus.run(10us);
	};
	bus.dev->pdo().fifoEnable(true);
	waitFor(2);
	dio.setInputs(std::vector<std::uint8_t>{ 0x5A });
	waitFor(3);
	bus.dev->pdo().fifoEnable(false);
	const unsigned queued = bus.info().txFifoCnt;
	REQUIRE(queued >= 2);
	REQUIRE(queued <= 3); // one answer holds 3
	seen.clear();
	const ecmxf::CycleResult &r = cyc.cycle();
	REQUIRE(r.error == 0);
	CHECK(r.framesPopped == queued);
	REQUIRE(seen.size() == queued);
	CHECK(seen.back() == 0x5A);
	CHECK(seen.front() == 0x00);
	CHECK(image.slaveInputs(2)[0] == 0x5A);
}

TEST_CASE("Cyclic: frames refused by a full RxFIFO are counted", "[lib][pdo][cyclic]")
{
	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	ecmxf::Cyclic cyc(*bus.dev, image, config());
	cyc.start();
	// an application that does not wait for its cycle pushes faster than
	// the bus takes frames: the FIFO fills to 64 and refuses the rest
	bool refused = false;
	std::uint8_t errStatus = 0;
	for (int i = 0; i < 30; i++) {
		const ecmxf::CycleResult &r = cyc.cycle();
		REQUIRE(r.error == 0);
		if (r.rxRefused) {
			refused = true;
			errStatus = r.errStatus;
		}
	}
	CHECK(refused);
	CHECK((errStatus & 0x20) != 0); // FIFO error
	CHECK(cyc.stats().rxRefusals > 0);
	// one frame per refused cycle
	CHECK(cyc.stats().rxRefusals == bus.chip().stats().rxRefused);
}

TEST_CASE("Cyclic: a slave that stops answering shows in the working counter", "[lib][pdo][cyclic]")
{
	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	{
		ecmxf::Cyclic cyc(*bus.dev, image, config(4));
		cyc.start();
		runCycles(cyc, 5);
		CHECK(cyc.lastResult().wkcOk);
		bus.chip().faults().slaveDropped = 2;
		runCycles(cyc, 3);
		const ecmxf::CycleResult &r = cyc.lastResult();
		// the two drives: 2 x (1 + 2)
		CHECK(r.wkc == 6);
		CHECK(r.expectedWkc == 9);
		CHECK_FALSE(r.wkcOk);
		CHECK(r.ecatState == 0x10);
		CHECK(r.wkcErrorCount >= 2);
		CHECK(cyc.stats().wkcMismatches >= 2);
		CHECK(r.error == 0); // the exchange itself works
	}

	// one Cyclic per Device: the next one after the first is gone; the
	// bus in ERROR (0x10, a slave dropped out of OP) still takes it
	SECTION("reading the WKC every 4th cycle")
	{
		ecmxf::CyclicConfig c = config(4);
		c.wkcEvery = 4;
		ecmxf::Cyclic sparse(*bus.dev, image, c);
		sparse.start();
		runCycles(sparse, 8);
		CHECK(sparse.stats().wkcReads == 2);
		CHECK(sparse.stats().commands == 8 + 2);
		CHECK(sparse.lastResult().wkc == 6); // as last read
		CHECK_FALSE(sparse.lastResult().wkcRead);
	}
}

TEST_CASE("Cyclic: waitNextCycle paces on the transport's virtual clock", "[lib][pdo][cyclic]")
{
	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	ecmxf::CyclicConfig c = config(4);
	c.period = 2ms;
	ecmxf::Cyclic cyc(*bus.dev, image, c);
	CHECK(cyc.boundary() == 0ns); // never started
	cyc.start();
	const auto t0 = bus.dev->link().now();
	CHECK(cyc.boundary() == t0); // the first cycle's
	runCycles(cyc, 500);
	CHECK(bus.dev->link().now() - t0 == 1000ms);
	CHECK(cyc.boundary() == t0 + 1000ms);
	CHECK(cyc.stats().lateCycles == 0);
	// late by more than a period: skip to the next boundary ahead
	bus.run(5ms + 300us);
	REQUIRE(cyc.waitNextCycle() == 0);
	CHECK(cyc.stats().lateCycles == 1);
	CHECK(bus.dev->link().now() - t0 == 1006ms);
	CHECK(cyc.boundary() == t0 + 1006ms);
	// start() again: the boundaries count from the new start
	cyc.stop();
	bus.run(700us);
	cyc.start();
	const auto t1 = bus.dev->link().now();
	CHECK(cyc.boundary() == t1);
	REQUIRE(cyc.waitNextCycle() == 0);
	CHECK(cyc.boundary() == t1 + 2ms);
	CHECK(bus.dev->link().now() == t1 + 2ms);
}

TEST_CASE("Cyclic: errors come back in the result with a static text", "[lib][pdo][cyclic]")
{
	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	ecmxf::Cyclic cyc(*bus.dev, image, config(4));

	const ecmxf::CycleResult &early = cyc.cycle();
	CHECK(early.error == EINVAL);
	CHECK_THAT(early.message, Equals("Cyclic: cycle() before start()"));

	cyc.start();
	runCycles(cyc, 3);
	// every answer arrives with a bad check word: the engine gives up
	bus.chip().faults().misoBitErrors = 1000;
	const ecmxf::CycleResult &r = cyc.cycle();
	CHECK(r.error == EBADMSG);
	CHECK_THAT(r.message, Equals("ECAT_PDO_DATA_FIFO_OP: bad packets in a row (check word mismatch): the SPI "
				     "link is failing"));
	CHECK(cyc.stats().failedCycles == 1);
	bus.chip().faults().misoBitErrors = 0;
	(void)cyc.waitNextCycle();
	const ecmxf::CycleResult &ok = cyc.cycle();
	CHECK(ok.error == 0);
	CHECK(ok.message == std::string());
}

TEST_CASE("Cyclic: a setup that cannot work is refused when constructed", "[lib][pdo][cyclic]")
{
	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage twoDrives({ pdotest::est584(), pdotest::est584() });
	ecmxf::Error e = thrown([&] { ecmxf::Cyclic c(*bus.dev, twoDrives); });
	CHECK_THAT(e.what(), Equals("Cyclic: the process image has 24 output bytes but the chip's RxPDO frame is 25 "
				    "bytes (FIFO_PACK_SIZE_GET 0): the mapping does not match the bus"));
	CHECK(e.errnoValue() == EINVAL);

	ecmxf::ProcessImage image(pdotest::defaultPdos());
	e = thrown([&] { ecmxf::Cyclic c(*bus.dev, image, config(63)); });
	CHECK_THAT(e.what(),
		   Equals("Cyclic: rxFill 63 out of range (1..62: the RxFIFO depth 64 minus a margin of 2)"));
	ecmxf::CyclicConfig zero = config();
	zero.period = 0ms;
	e = thrown([&] { ecmxf::Cyclic c(*bus.dev, image, zero); });
	CHECK_THAT(e.what(), Equals("Cyclic: the cycle period must be positive (got 0 ns)"));
}

TEST_CASE("Cyclic: 128 slaves need a larger SPI data section", "[lib][pdo][cyclic]")
{
	Bus bus(pdotest::bundled("slaves128.net"));
	bus.toOp();
	std::vector<ecmxf::SlavePdos> pdos;
	for (int i = 0; i < 64; i++)
		pdos.push_back(pdotest::est584());
	for (int i = 0; i < 64; i++)
		pdos.push_back(pdotest::dioBits());
	ecmxf::ProcessImage image(std::move(pdos));
	REQUIRE(image.outputs().size() == 832);
	REQUIRE(image.inputs().size() == 1152);
	const ecmxf::Error e = thrown([&] { ecmxf::Cyclic c(*bus.dev, image); });
	CHECK_THAT(e.what(), Equals("Cyclic: the RxPDO frame (832 bytes) does not fit the SPI data section (112 "
				    "bytes); enlarge it with SPI_RECONFIG_OP"));
	CHECK(e.errnoValue() == EMSGSIZE);

	bus.dataSize(1408);
	ecmxf::Cyclic cyc(*bus.dev, image, config(4));
	CHECK(cyc.framesPerWrite() == 1);
	CHECK(cyc.framesPerRead() == 1);
	// 128 slaves with inputs x 1 + 128 with outputs x 2
	CHECK(cyc.expectedWkc() == 384);
	cyc.start();
	auto last = image.output<bool>(127, 0x7000, 1);
	last.set(true);
	runCycles(cyc, 20);
	CHECK(cyc.lastResult().wkc == 384);
	CHECK(bus.model<ecmxf::sim::DioModel>(127).outputs()[0] == 0x01);
}
