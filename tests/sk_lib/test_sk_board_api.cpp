// SPDX-License-Identifier: MIT
// ecmxf::sk::Board on the in-process simulated board: bring-up, SDO with
// typed values and clear errors, servo on/off, alarm clear, IO, homing,
// reset, and the cyclic path with FIFO back-pressure.

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>
#include <string>
#include <vector>

#include <ecmxf/model/types_bus.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/sim/slaves.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/sim/sk_board.hpp>
#include <ecmxf/sk/sim_channel.hpp>

using namespace ecmxf::sk;
using namespace std::chrono_literals;

namespace {

int errnoOf(auto &&fn)
{
	try {
		fn();
	} catch (const ecmxf::Error &e) {
		return e.errnoValue();
	}
	return 0;
}

std::string messageOf(auto &&fn)
{
	try {
		fn();
	} catch (const ecmxf::Error &e) {
		return e.what();
	}
	return {};
}

const std::vector<SlaveType> kTypes = { SlaveType::Drive, SlaveType::Step, SlaveType::Io };

void bringUp(Board &b, std::uint32_t cycleUs = 1000)
{
	b.setState(State::PreOp);
	CHECK(b.setAxes(kTypes) == 3u);
	b.setCycleTime(cycleUs);
	b.driveMode(1, Mode::Csp);
	b.driveMode(2, Mode::Csp);
	b.setState(State::Op);
	REQUIRE(b.state() == State::Op);
}

} // namespace

TEST_CASE("sk lib: status, bring-up to OP, slave count")
{
	auto b = Board::open("sk-sim:");
	REQUIRE(b->simulator() != nullptr);
	CHECK(b->frameSize() == 504u);
	CHECK(b->status().state == State::Init);
	CHECK(b->slaveCount() == 0u); // INIT: SET_AXIS answers 0
	b->setState(State::PreOp);
	CHECK(b->slaveCount() == 3u);
	bringUp(*b);
	const auto s = b->status();
	CHECK(s.state == State::Op);
	CHECK(s.fifoRemaining == 256);
}

TEST_CASE("sk lib: wrong types, bad cycle times and commands in the wrong state are clear errors")
{
	auto b = Board::open("sk-sim:");
	b->setState(State::PreOp);
	const std::vector<SlaveType> wrong = { SlaveType::Step, SlaveType::Step, SlaveType::Io };
	const auto msg = messageOf([&] { b->setAxes(wrong); });
	CHECK(msg.find("slave 1 (STEP)") != std::string::npos);
	CHECK(errnoOf([&] { b->setAxes(wrong); }) == EPERM);
	CHECK(errnoOf([&] { b->setCycleTime(750); }) == EINVAL);
	CHECK(errnoOf([&] { b->setCycleTime(0); }) == EINVAL);
	CHECK(errnoOf([&] { b->setExtensions(4); }) == EINVAL);
	CHECK(errnoOf([&] { b->driveMode(0, Mode::Csp); }) == EINVAL);
	CHECK(errnoOf([&] { b->driveMode(41, Mode::Csp); }) == EINVAL);
	CHECK(errnoOf([&] { b->driveMode(3, Mode::Csp); }) == EPERM); // IO slave
	CHECK(errnoOf([&] { b->servoOn(1); }) == EPERM);	     // not OP
	CHECK(messageOf([&] { b->servoOn(1); }).find("SV_ON is allowed in OP; the ECM-SK is in PRE-OP") !=
	      std::string::npos);
	// SAFE-OP refused: the types were never set
	const auto st = messageOf([&] { b->setState(State::SafeOp, 100ms); });
	CHECK(st.find("stayed in PRE-OP") != std::string::npos);
	CHECK(st.find("SET_AXIS") != std::string::npos);
	CHECK(errnoOf([&] { b->lioWrite(64); }) == EINVAL);
	CHECK(errnoOf([&] { b->sdoWrite(1, 0x6060, 0, 6, 3); }) == EINVAL);
	CHECK(errnoOf([&] { b->sdoWrite(1, 0x6060, 0, 0x100, 1); }) == EINVAL);
	b->setAxes(kTypes);
	b->setState(State::Op);
	CHECK(errnoOf([&] { b->setCycleTime(500); }) == EPERM);
	CHECK(errnoOf([&] { b->setAxes(kTypes); }) == EPERM);
	CHECK(errnoOf([&] { b->ioWrite(1, 1); }) == EPERM); // a drive
}

TEST_CASE("sk lib: SDO typed read and write; aborts carry the code and its text")
{
	auto b = Board::open("sk-sim:");
	CHECK(errnoOf([&] { (void)b->sdoRead(1, 0x1000, 0); }) == EPERM); // INIT
	b->setState(State::PreOp);
	CHECK(b->sdoRead<std::uint32_t>(1, 0x1018, 1) == ecmxf::sim::model::kVendorId);
	b->sdoWrite<std::int8_t>(2, 0x6098, 0, 37);
	CHECK(b->sdoRead<std::int8_t>(2, 0x6098, 0) == 37);
	CHECK(errnoOf([&] { (void)b->sdoRead<std::uint32_t>(2, 0x6098, 0); }) == EMSGSIZE);
	try {
		(void)b->sdoRead(1, 0x5FFF, 0);
		FAIL("no abort");
	} catch (const ecmxf::SdoError &e) {
		CHECK(e.abortCode() == 0x06020000u);
		CHECK(e.errnoValue() == EREMOTEIO);
		CHECK(std::string(e.what()).find(std::string(ecmxf::sdoAbortText(0x06020000u))) !=
		      std::string::npos);
	}
	CHECK(errnoOf([&] { b->sdoWrite<std::uint16_t>(1, 0x6041, 0, 1); }) == EREMOTEIO); // read-only
}

TEST_CASE("sk lib: servo on, a CSP move of the Drive and the STEP slave through the cyclic path")
{
	auto b = Board::open("sk-sim:");
	bringUp(*b);
	b->servoOn(1);
	b->servoOn(2);
	b->waitEnabled(1);
	b->waitEnabled(2);
	b->status();
	const auto p1 = b->axis(1).position, p2 = b->axis(2).position;
	int drops = 0;
	for (int i = 1; i <= 500; i++) {
		REQUIRE(b->stage(1, Mode::Csp, p1 + 40 * i));
		REQUIRE(b->stage(2, Mode::Csp, p2 + 20 * i));
		CHECK_FALSE(b->stage(1, Mode::Csp, 0)); // one per slave per exchange
		const auto r = b->cycle();
		REQUIRE(r.status != CycleStatus::Link);
		drops += r.dropped;
		b->channel().sleepFor(1ms - b->simulator()->wireTime() - 20us);
	}
	for (int i = 0; i < 30; i++) {
		b->cycle();
		b->channel().sleepFor(1ms);
	}
	CHECK(drops == 0);
	CHECK(std::abs(b->axis(1).position - (p1 + 20000)) <= 10);
	CHECK(std::abs(b->axis(2).position - (p2 + 10000)) <= 10);
	CHECK(b->stage(5, Mode::Csp, 0) == true); // slave 5: no slave, the board refuses
	CHECK_FALSE(b->stage(0, Mode::Csp, 0));
	CHECK_FALSE(b->stage(41, Mode::Csp, 0));
}

TEST_CASE("sk lib: stage() refuses what the FIFO has no room for; nothing is dropped")
{
	auto b = Board::open("sk-sim:?abandon=0");
	bringUp(*b, 4000); // slow cycle: the FIFO fills faster than it drains
	b->servoOn(1);
	b->servoOn(2);
	b->waitEnabled(1);
	b->waitEnabled(2);
	b->status();
	const auto p1 = b->axis(1).position, p2 = b->axis(2).position;
	unsigned refusedStage = 0, dropped = 0;
	for (int i = 0; i < 300; i++) {
		if (!b->stage(1, Mode::Csp, p1))
			refusedStage++;
		if (!b->stage(2, Mode::Csp, p2))
			refusedStage++;
		const auto r = b->cycle();
		REQUIRE(r.status != CycleStatus::Link);
		dropped += r.dropped;
	}
	CHECK(refusedStage > 100u);
	CHECK(dropped == 0u);
	CHECK(b->status().fifoFull == 0);
	// outside OP nothing is staged
	b->setState(State::SafeOp);
	CHECK_FALSE(b->stage(1, Mode::Csp, p1));
}

TEST_CASE("sk lib: a full FIFO is a FifoOverflow the application sees")
{
	auto b = Board::open("sk-sim:?abandon=0");
	bringUp(*b, 4000);
	auto *sim = b->simulator();
	REQUIRE(sim != nullptr);
	b->status(); // the library saw an empty FIFO
	// a second host on the same board fills the FIFO behind the
	// library's back: 280 CSPs, 24 of them dropped by the board
	std::vector<std::uint8_t> mosi(504, 0), miso(504, 0);
	for (int i = 0; i < 140; i++) {
		while (sim->busy())
			sim->advance(1us);
		mosi.assign(504, 0);
		mosi[12] = 0x15;
		mosi[24] = 0x15;
		sim->exchange(mosi, miso);
	}
	REQUIRE(sim->fifoFullCount() > 0u);
	const auto r = b->cycle();
	CHECK(r.status == CycleStatus::FifoOverflow);
	CHECK(r.dropped == r.fifoFull);
	CHECK(r.dropped > 0);
	// now the library knows: it holds back instead of sending into it
	CHECK_FALSE(b->stage(1, Mode::Csp, 0));
}

TEST_CASE("sk lib: servo off, alarm clear, IO, LIO, homing, reset")
{
	auto b = Board::open("sk-sim:");
	bringUp(*b);
	b->servoOn(1);
	b->waitEnabled(1);
	auto *drive = dynamic_cast<ecmxf::sim::Cia402Model *>(&b->simulator()->network().at(0));
	REQUIRE(drive != nullptr);
	drive->injectFault(0x7500);
	b->channel().sleepFor(20ms);
	b->status();
	CHECK(b->axis(1).errorCode == 0x7500);
	CHECK(errnoOf([&] { b->waitEnabled(1, 10ms); }) == ETIMEDOUT);
	b->alarmClear(1);
	b->waitEnabled(1);
	b->servoOff(1);
	b->channel().sleepFor(20ms);
	b->status();
	CHECK((b->axis(1).statusword & 0x6F) != 0x27);

	b->ioWrite(3, 0x5A);
	b->channel().sleepFor(5ms);
	auto *io = dynamic_cast<ecmxf::sim::DioModel *>(&b->simulator()->network().at(2));
	REQUIRE(io != nullptr);
	CHECK(io->outputs()[0] == 0x5A);
	io->setInput(2, true);
	b->channel().sleepFor(5ms);
	CHECK((b->ioRead(3) & 0x4u) != 0);

	b->simulator()->setLioInputs(0x21);
	CHECK(b->lioRead() == 0x21u);
	b->lioWrite(0x12);
	CHECK(b->simulator()->lioOutputs() == 0x12u);

	b->servoOn(2);
	b->waitEnabled(2);
	b->sdoWrite<std::int32_t>(2, 0x607C, 0, 500);
	b->home(2, 37);
	b->status();
	CHECK(b->axis(2).position == 500);
	CHECK((b->axis(2).statusword & 0x1400) == 0x1400);
	CHECK(errnoOf([&] { b->home(3, 37); }) != 0); // an IO slave has no homing

	b->reset();
	CHECK(b->state() == State::Init);
	CHECK(b->simulator()->lioOutputs() == 0u);
}

TEST_CASE("sk lib: 16-byte slots and CRCs both ways after SET_EX and a power cycle")
{
	auto b = Board::open("sk-sim:?slot=16");
	CHECK(b->frameSize() == 512u);
	CHECK(b->maxSlaves() == 30u);
	b->setExtensions(3);
	b->simulator()->powerCycle();
	// the host was not told: its frames have no CRC and are refused
	CHECK(errnoOf([&] { b->lioWrite(1); }) == EBADMSG);
	// the same board with the right link options
	auto ch = std::make_unique<ecmxf::sk::SimBoardChannel>(std::string{}, BoardConfig::parse("slot=16&ex=3"));
	Board crc(std::move(ch), LinkOptions{ 16, 3 });
	crc.setState(State::PreOp);
	crc.lioWrite(5);
	CHECK(crc.simulator()->lioOutputs() == 5u);
	CHECK(crc.status().crcErrors == 0);
}

TEST_CASE("sk lib: detectAxes finds each slave's type through SET_AXIS")
{
	auto b = Board::open("sk-sim:");
	CHECK(errnoOf([&] { (void)b->detectAxes(); }) == EPERM); // INIT
	b->setState(State::PreOp);
	const auto t = b->detectAxes();
	CHECK(t == kTypes);
	CHECK(b->simulator()->slaveType(2) == static_cast<std::uint8_t>(SlaveType::Step));
}

TEST_CASE("sk lib: stage2() drives both channels of a 2-channel HSP; 12-byte slots refuse it")
{
	const std::string path = "/tmp/ecmxf-test-sk-hsp2-" + std::to_string(::getpid()) + ".net";
	{
		std::FILE *f = std::fopen(path.c_str(), "w");
		REQUIRE(f != nullptr);
		std::fputs("slave hsp channels=2\nslave dio\n", f);
		std::fclose(f);
	}
	auto b = Board::open("sk-sim:" + path + "?slot=16");
	auto b12 = Board::open("sk-sim:" + path);
	std::remove(path.c_str());
	b->setState(State::PreOp);
	CHECK(b->detectAxes() == std::vector<SlaveType>{ SlaveType::Hsp, SlaveType::Io });
	b->setState(State::Op);
	b->servoOn(1);
	b->waitEnabled(1);
	for (int i = 1; i <= 50; i++) {
		REQUIRE(b->stage2(1, Mode::Csp, 20 * i, -30 * i));
		CHECK_FALSE(b->stage2(1, Mode::Csp, 0, 0)); // once per exchange
		REQUIRE(b->cycle().status == CycleStatus::Ok);
		b->channel().sleepFor(1ms);
	}
	b->channel().sleepFor(20ms);
	b->status();
	const auto h = b->hsp2(1);
	CHECK(h.position1 == 1000);
	CHECK(h.position2 == -1500);
	CHECK_FALSE(b->stage2(1, Mode::Cst, 0, 0));
	CHECK(errnoOf([&] { (void)b12->hsp2(1); }) == EINVAL);
	CHECK_FALSE(b12->stage2(1, Mode::Csp, 0, 0));
}
