// SPDX-License-Identifier: MIT
// Cyclic with CyclicConfig::fifoAnswerNextCycle on the simulator: one SPI
// exchange per cycle (two with a working counter read), the inputs and the
// FIFO command's outcome one cycle late and exactly those of the previous
// cycle's command, a refused or failed command reported by the next cycle
// with nothing lost, a steady RxFIFO (no refusal, no underrun, no
// overflow), and nothing left in flight by stop() or the destructor.
// Virtual time: every count is exact.

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/link/byte_channel.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/link/sim_channel.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/sim/slaves.hpp>

#include "bus.hpp"

using namespace std::chrono_literals;
using Catch::Matchers::Equals;
using pdotest::Bus;

namespace {

ecmxf::CyclicConfig ahead(unsigned rxFill = 4)
{
	ecmxf::CyclicConfig c;
	c.period = 1ms;
	c.busCycle = 1ms; // ECAT_INIT_OP's SYNC0 in Bus::init()
	c.rxFill = rxFill;
	c.fifoAnswerNextCycle = true;
	return c;
}

std::uint64_t exchanges(Bus &bus)
{
	return bus.dev->link().counters().exchanges;
}

/// The simulator's channel, with one fault of its own: the next
/// ECAT_PDO_DATA_FIFO_OP it carries gets the frame count 255, which the
/// chip refuses (command error: nothing pushed, nothing popped). The fixed
/// check word does not cover the header: the packet stays valid.
class RefusingChannel final : public ecmxf::ByteChannel
{
public:
	explicit RefusingChannel(const std::string &network) : sim_(network) {}

	bool refuseNextFifoOp = false;
	unsigned refused = 0;

	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override
	{
		if (refuseNextFifoOp && mosi.size() > 0x0E && mosi[0x0C] == 5) {
			refuseNextFifoOp = false;
			refused++;
			std::vector<std::uint8_t> bad(mosi.begin(), mosi.end());
			bad[0x04] |= 0x01; // push
			bad[0x0D] = 0xFF;  // 255 frames: more than the data holds
			sim_.exchange(bad, miso);
			return;
		}
		sim_.exchange(mosi, miso);
	}
	bool waitReady(std::chrono::nanoseconds timeout) override { return sim_.waitReady(timeout); }
	std::chrono::nanoseconds now() const override { return sim_.now(); }
	void sleepFor(std::chrono::nanoseconds d) override { sim_.sleepFor(d); }
	void sleepUntil(std::chrono::nanoseconds t) override { sim_.sleepUntil(t); }
	std::string name() const override { return "refusing " + sim_.name(); }
	ecmxf::sim::Chip &chip() noexcept { return sim_.chip(); }

private:
	ecmxf::SimChannel sim_;
};

/// The I/O terminal's echo (inputs mirror outputs) in a loopback TxPDO
/// frame: the value its outputs had in that bus cycle.
std::uint32_t echoOf(std::span<const std::uint8_t> f)
{
	return static_cast<std::uint32_t>(f[34]) | static_cast<std::uint32_t>(f[35]) << 8 |
	       static_cast<std::uint32_t>(f[36]) << 16 | static_cast<std::uint32_t>(f[37]) << 24;
}

} // namespace

TEST_CASE("Cyclic fifoAnswerNextCycle: one SPI exchange per cycle, two in a cycle with a working counter read",
	  "[lib][pdo][cyclic][ahead]")
{
	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	constexpr unsigned kCycles = 300;

	SECTION("no working counter read: 1 exchange, 1 command")
	{
		ecmxf::CyclicConfig c = ahead();
		c.wkcEvery = 0;
		ecmxf::Cyclic cyc(*bus.dev, image, c);
		cyc.start();
		const std::uint64_t x0 = exchanges(bus);
		for (unsigned i = 0; i < kCycles; i++) {
			const std::uint64_t before = exchanges(bus);
			const ecmxf::CycleResult &r = cyc.cycle();
			INFO("cycle " << i << ": " << r.message);
			REQUIRE(r.error == 0);
			CHECK(r.commands == 1);
			CHECK(exchanges(bus) - before == 1);
			REQUIRE(cyc.waitNextCycle() == 0);
		}
		CHECK(exchanges(bus) - x0 == kCycles);
		CHECK(cyc.stats().commands == kCycles);
		CHECK(cyc.stats().wkcReads == 0);
	}

	// the read goes first, its answer comes back in the exchange that
	// sends the FIFO command: wkcAnswerNextCycle changes nothing
	for (const bool wkcNext : { false, true }) {
		DYNAMIC_SECTION("a read every 10th cycle, wkcAnswerNextCycle " << wkcNext)
		{
			ecmxf::CyclicConfig c = ahead();
			c.wkcEvery = 10;
			c.wkcAnswerNextCycle = wkcNext;
			ecmxf::Cyclic cyc(*bus.dev, image, c);
			cyc.start();
			const std::uint64_t x0 = exchanges(bus);
			for (unsigned i = 0; i < kCycles; i++) {
				const std::uint64_t before = exchanges(bus);
				const ecmxf::CycleResult &r = cyc.cycle();
				INFO("cycle " << i << ": " << r.message);
				REQUIRE(r.error == 0);
				const bool read = i % 10 == 0;
				CHECK(r.wkcRead == read);
				CHECK(r.commands == (read ? 2u : 1u));
				CHECK(exchanges(bus) - before == (read ? 2u : 1u));
				if (read) {
					// this cycle's read, not the one before
					CHECK(r.wkc == 9);
					CHECK(r.wkcOk);
				}
				REQUIRE(cyc.waitNextCycle() == 0);
			}
			// 300 FIFO commands + 30 reads
			CHECK(exchanges(bus) - x0 == kCycles + kCycles / 10);
			CHECK(cyc.stats().wkcReads == kCycles / 10);
			CHECK(cyc.stats().wkcMismatches == 0);
		}
	}

	SECTION("the synchronous cycle, for comparison: 2 exchanges, 3 with a read")
	{
		ecmxf::CyclicConfig c = ahead();
		c.fifoAnswerNextCycle = false;
		c.wkcEvery = 10;
		ecmxf::Cyclic cyc(*bus.dev, image, c);
		cyc.start();
		for (unsigned i = 0; i < 20; i++) {
			REQUIRE(cyc.cycle().error == 0);
			REQUIRE(cyc.waitNextCycle() == 0);
		}
		const std::uint64_t x0 = exchanges(bus);
		for (unsigned i = 0; i < 100; i++) {
			REQUIRE(cyc.cycle().error == 0);
			REQUIRE(cyc.waitNextCycle() == 0);
		}
		CHECK(exchanges(bus) - x0 == 2 * 100 + 10);
	}
}

TEST_CASE("Cyclic fifoAnswerNextCycle: cycle N reports exactly what the FIFO command of cycle N - 1 did",
	  "[lib][pdo][cyclic][ahead]")
{
	Bus bus;
	bus.toOp();
	auto &chip = bus.chip();
	auto &dio = bus.model<ecmxf::sim::DioModel>(2);
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	auto &drive0 = bus.model<ecmxf::sim::Cia402Model>(0);
	auto cw = image.output<std::uint16_t>(0, 0x6040, 0);
	ecmxf::Cyclic cyc(*bus.dev, image, ahead());
	cyc.start();

	// the first cycle: no answer yet
	const auto read0 = chip.stats().txRead;
	const auto accepted0 = chip.stats().rxAccepted;
	const ecmxf::CycleResult &first = cyc.cycle();
	REQUIRE(first.error == 0);
	CHECK_FALSE(first.inputsUpdated);
	CHECK(first.framesPopped == 0);
	CHECK(first.framesPushed == 0);
	CHECK(first.commands == 2); // with the read of cycle 0
	CHECK(first.wkcRead);
	CHECK(first.ecatState == 8);
	// but the command went out: the chip took its frames
	CHECK(chip.stats().rxAccepted > accepted0);
	REQUIRE(cyc.waitNextCycle() == 0);

	// from then on, cycle N's frames are the chip's count while it ran
	// cycle N - 1's command, to the frame
	std::uint64_t read = chip.stats().txRead, accepted = chip.stats().rxAccepted;
	std::uint64_t prevRead = read - read0, prevAccepted = accepted - accepted0;
	for (int i = 1; i < 100; i++) {
		cw.set(static_cast<std::uint16_t>(0x100 + i));
		const ecmxf::CycleResult &r = cyc.cycle();
		INFO("cycle " << i << ": " << r.message);
		REQUIRE(r.error == 0);
		CHECK(r.framesPopped == prevRead);
		CHECK(r.framesPushed == prevAccepted);
		CHECK(r.inputsUpdated == (prevRead > 0));
		prevRead = chip.stats().txRead - read;
		prevAccepted = chip.stats().rxAccepted - accepted;
		read = chip.stats().txRead;
		accepted = chip.stats().rxAccepted;
		REQUIRE(cyc.waitNextCycle() == 0);
	}
	// the outputs reach the slave about rxFill bus cycles later
	CHECK(drive0.controlword() >= 0x100 + 99 - 4 - 2);
	CHECK(drive0.controlword() < 0x100 + 99);

	// an input change after cycle k's command ran shows in cycle k + 2's
	// result: cycle k + 1 reports the command of cycle k (frames made
	// before the change)
	REQUIRE(image.slaveInputs(2)[0] == 0x00);
	dio.setInputs(std::vector<std::uint8_t>{ 0x5A });
	bus.run(3ms); // frames with 0x5A queue up
	const ecmxf::CycleResult &k1 = cyc.cycle();
	REQUIRE(k1.error == 0);
	CHECK(k1.inputsUpdated);
	CHECK(image.slaveInputs(2)[0] == 0x00);
	(void)cyc.waitNextCycle();
	const ecmxf::CycleResult &k2 = cyc.cycle();
	REQUIRE(k2.error == 0);
	CHECK(k2.inputsUpdated);
	CHECK(image.slaveInputs(2)[0] == 0x5A);
	CHECK(cyc.stats().failedCycles == 0);
}

TEST_CASE("Cyclic fifoAnswerNextCycle: a steady RxFIFO over 500 cycles, and no frame lost, repeated or reordered",
	  "[lib][pdo][cyclic][ahead]")
{
	// rxFill: motion (2), 4, the deep default (62)
	const unsigned fill = GENERATE(2u, 4u, 0u);
	const unsigned wkcEvery = GENERATE(0u, 1u, 10u);
	INFO("rxFill " << fill << ", wkcEvery " << wkcEvery);
	Bus bus(pdotest::network("loopback.net"));
	bus.toOp();
	auto &chip = bus.chip();
	ecmxf::ProcessImage image(pdotest::loopbackPdos());
	auto counter = image.output<std::uint32_t>(2, 0x7000, 1);
	auto echo = image.input<std::uint32_t>(2, 0x6000, 1);
	std::vector<std::uint32_t> seen;
	seen.reserve(2000);
	ecmxf::CyclicConfig cfg = ahead(fill);
	cfg.wkcEvery = wkcEvery;
	cfg.context = &seen;
	cfg.onInputFrame = [](void *ctx, std::span<const std::uint8_t> f) noexcept {
		static_cast<std::vector<std::uint32_t> *>(ctx)->push_back(echoOf(f));
	};
	ecmxf::Cyclic cyc(*bus.dev, image, cfg);
	cyc.start();

	constexpr std::uint32_t kCycles = 500;
	// the fill: one command per cycle, framesPerWrite() frames each; the
	// RxFIFO may run dry until the fill level is reached
	const std::uint32_t settled = cyc.rxFill() / (cyc.framesPerWrite() - 1) + 4;
	std::uint64_t underruns = 0, read0 = chip.stats().txRead, readBefore = 0;
	for (std::uint32_t i = 1; i <= kCycles; i++) {
		counter.set(i);
		readBefore = chip.stats().txRead;
		const ecmxf::CycleResult &r = cyc.cycle();
		INFO("cycle " << i << ": " << r.message);
		REQUIRE(r.error == 0);
		CHECK_FALSE(r.rxRefused);
		CHECK_FALSE(r.txOverflow);
		if (i == settled)
			underruns = chip.stats().rxUnderruns;
		REQUIRE(cyc.waitNextCycle() == 0);
	}
	const ecmxf::CyclicStats &s = cyc.stats();
	CHECK(s.failedCycles == 0);
	CHECK(s.rxRefusals == 0);
	CHECK(s.txOverflows == 0);
	CHECK(chip.stats().rxRefused == 0);
	CHECK(chip.stats().txDropped == 0);
	CHECK(chip.stats().rxUnderruns == underruns);
	// every frame the chip gave out up to the last cycle's command was
	// reported, once, in order; the last command's are in flight
	CHECK(s.framesPopped == readBefore - read0);
	CHECK(seen.size() == s.framesPopped);
	CHECK(s.framesPushed + chip.stats().rxRefused <= chip.stats().rxAccepted);
	const pdotest::Sequence q = pdotest::sequenceOf(seen, settled);
	REQUIRE(q.found);
	CHECK(q.first == 1);
	if (q.badFrame < seen.size())
		FAIL("frame " << q.badFrame << " carries " << seen[q.badFrame] << " after " << seen[q.badFrame - 1]);
	// after the fill every output frame reached the bus exactly once
	CHECK(q.repeated == 0);
	CHECK(echo.get() == seen.back());
	// the outputs of the last cycle are about rxFill + 2 bus cycles away
	CHECK(seen.back() + cyc.rxFill() + 4 >= kCycles);
}

TEST_CASE("Cyclic fifoAnswerNextCycle: a command the chip refuses is reported by the next cycle, nothing lost",
	  "[lib][pdo][cyclic][ahead]")
{
	auto ch = std::make_unique<RefusingChannel>(pdotest::network("loopback.net"));
	RefusingChannel &refusing = *ch;
	ecmxf::sim::Chip &chip = ch->chip();
	Bus bus(std::make_unique<ecmxf::Device>(std::move(ch)), chip);
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::loopbackPdos());
	auto counter = image.output<std::uint32_t>(2, 0x7000, 1);
	std::vector<std::uint32_t> seen;
	seen.reserve(200);
	ecmxf::CyclicConfig cfg = ahead(4);
	cfg.context = &seen;
	cfg.onInputFrame = [](void *ctx, std::span<const std::uint8_t> f) noexcept {
		static_cast<std::vector<std::uint32_t> *>(ctx)->push_back(echoOf(f));
	};
	ecmxf::Cyclic cyc(*bus.dev, image, cfg);
	cyc.start();
	const auto read0 = chip.stats().txRead;
	std::uint32_t i = 0;
	auto step = [&] {
		counter.set(++i);
		const ecmxf::CycleResult &r = cyc.cycle();
		(void)cyc.waitNextCycle();
		return r;
	};
	for (int j = 0; j < 30; j++)
		REQUIRE(step().error == 0);

	refusing.refuseNextFifoOp = true;
	const std::uint32_t refusedValue = i + 1; // its output frame never reaches the bus
	const std::uint64_t txBefore = chip.stats().txRead;
	ecmxf::CycleResult own = step(); // its command is refused; it reports the one before
	REQUIRE(refusing.refused == 1);
	CHECK(own.error == 0);
	CHECK(own.inputsUpdated);
	CHECK(chip.stats().txRead == txBefore); // the refused command popped nothing
	const ecmxf::CycleResult next = step();
	CHECK(next.error == EREMOTEIO);
	CHECK_THAT(next.message,
		   Equals("ECAT_PDO_DATA_FIFO_OP: the chip refused the command (error status bit 7, command error)"));
	CHECK(next.framesPopped == 0);
	CHECK_FALSE(next.inputsUpdated);
	CHECK(cyc.stats().failedCycles == 1);
	// the frames the refused command would have read come with the next
	// command: two bus cycles' worth
	const ecmxf::CycleResult after = step();
	CHECK(after.error == 0);
	CHECK(after.framesPopped == 2);
	for (int j = 0; j < 30; j++)
		REQUIRE(step().error == 0);
	CHECK(cyc.stats().failedCycles == 1);
	CHECK(chip.stats().txDropped == 0);
	// every frame read out reached the application (but those of the
	// last command, in flight), in order; the outputs skip only the
	// refused command's
	const std::uint64_t inFlight = chip.stats().txRead - read0 - cyc.stats().framesPopped;
	CHECK(inFlight <= cyc.framesPerRead());
	CHECK(seen.size() == cyc.stats().framesPopped);
	bool skipped = false;
	for (std::size_t j = 1; j < seen.size(); j++) {
		// copies of one output frame (the fill) come back as repeats
		if (seen[j - 1] == 0 || seen[j] == seen[j - 1] || seen[j] == seen[j - 1] + 1)
			continue;
		if (seen[j - 1] == refusedValue - 1 && seen[j] == refusedValue + 1) {
			skipped = true;
			continue;
		}
		FAIL("frame " << j << " carries " << seen[j] << " after " << seen[j - 1]);
	}
	CHECK(skipped);
}

TEST_CASE("Cyclic fifoAnswerNextCycle: a failing link is reported, and the next cycles recover",
	  "[lib][pdo][cyclic][ahead]")
{
	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	ecmxf::Cyclic cyc(*bus.dev, image, ahead());
	cyc.start();
	for (int j = 0; j < 5; j++) {
		REQUIRE(cyc.cycle().error == 0);
		REQUIRE(cyc.waitNextCycle() == 0);
	}
	// every answer arrives with a bad check word: the engine gives up on
	// the answer it fetches (the previous cycle's command)
	bus.chip().faults().misoBitErrors = 1000;
	const ecmxf::CycleResult &r = cyc.cycle();
	CHECK(r.error == EBADMSG);
	CHECK_THAT(r.message, Equals("ECAT_PDO_DATA_FIFO_OP: bad packets in a row (check word mismatch): the SPI "
				     "link is failing"));
	bus.chip().faults().misoBitErrors = 0;
	(void)cyc.waitNextCycle();
	// whatever was left of the failed exchange, the cycles after it work
	// and bring inputs again
	bool inputs = false;
	for (int j = 0; j < 3; j++) {
		const ecmxf::CycleResult &ok = cyc.cycle();
		INFO("cycle " << j << ": " << ok.message);
		if (j > 0)
			CHECK(ok.error == 0);
		inputs |= ok.inputsUpdated;
		(void)cyc.waitNextCycle();
	}
	CHECK(inputs);
	CHECK(cyc.stats().failedCycles <= 2);
}

TEST_CASE("Cyclic fifoAnswerNextCycle: stop() and the destructor leave no answer in flight",
	  "[lib][pdo][cyclic][ahead]")
{
	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	{
		ecmxf::Cyclic cyc(*bus.dev, image, ahead());
		cyc.start();
		for (int j = 0; j < 10; j++) {
			REQUIRE(cyc.cycle().error == 0);
			REQUIRE(cyc.waitNextCycle() == 0);
		}
		cyc.stop();
		// the next command on the device gets its own answer
		CHECK((bus.info().ecmStatus & 0x40) == 0); // FIFO off
		CHECK(bus.cmd(16).ret == 3);               // ECAT_SLV_CNT_GET
		// and the Cyclic starts again: the first cycle reports nothing
		cyc.start();
		const ecmxf::CycleResult &r = cyc.cycle();
		CHECK(r.error == 0);
		CHECK_FALSE(r.inputsUpdated);
		CHECK(r.framesPopped == 0);
		REQUIRE(cyc.waitNextCycle() == 0);
		REQUIRE(cyc.cycle().error == 0);
		CHECK(cyc.lastResult().framesPushed > 0);
		// destroyed with a command in flight
	}
	CHECK(bus.cmd(16).ret == 3);
	// a new Cyclic on the same device works from its first cycle
	ecmxf::Cyclic again(*bus.dev, image, ahead());
	again.start();
	for (int j = 0; j < 10; j++) {
		INFO("cycle " << j);
		REQUIRE(again.cycle().error == 0);
		REQUIRE(again.waitNextCycle() == 0);
	}
	CHECK(again.lastResult().inputsUpdated);
}

TEST_CASE("Cyclic fifoAnswerNextCycle: waitInputs takes the answer in flight first",
	  "[lib][pdo][cyclic][ahead]")
{
	Bus bus;
	bus.toOp();
	ecmxf::ProcessImage image(pdotest::defaultPdos());
	ecmxf::Cyclic cyc(*bus.dev, image, ahead());
	cyc.start();
	for (int j = 0; j < 10; j++) {
		REQUIRE(cyc.cycle().error == 0);
		REQUIRE(cyc.waitNextCycle() == 0);
	}
	// the command in flight popped the frame of the last bus cycle
	const auto t0 = bus.dev->link().now();
	CHECK(cyc.waitInputs(5ms) == 0);
	CHECK(bus.dev->link().now() - t0 < 1ms);
	const ecmxf::CycleResult &r = cyc.cycle();
	CHECK(r.error == 0);
	CHECK(r.inputsUpdated);
}
