// SPDX-License-Identifier: MIT
// ecmxf::sk::Board on the in-process simulated board: bring-up, SDO with
// typed values and clear errors, servo on/off, alarm clear, IO, homing,
// reset, and the cyclic path with FIFO back-pressure.

#include <catch2/catch.hpp>

#include <algorithm>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <ecmxf/model/types_bus.hpp>
#include <ecmxf/model/cia402.hpp>
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
	b.states().set(ecmxf::State::PreOp);
	CHECK(b.setup().setAxes(kTypes) == 3u);
	b.setup().setCycleTime(cycleUs);
	b.drives().setMode(1, Mode::Csp);
	b.drives().setMode(2, Mode::Csp);
	b.states().set(ecmxf::State::Op);
	REQUIRE(b.state() == ecmxf::State::Op);
}

// SV_ON for the Drive (1) and the STEP slave (2), and their positions
std::pair<std::int32_t, std::int32_t> enableDrives(Board &b)
{
	b.drives().servoOn(1);
	b.drives().servoOn(2);
	b.drives().waitEnabled(1);
	b.drives().waitEnabled(2);
	b.states().status();
	return { b.drives().axis(1).position, b.drives().axis(2).position };
}

} // namespace

TEST_CASE("sk lib: status, bring-up to OP, slave count")
{
	auto b = Board::open("sk-sim:");
	REQUIRE(b->simulator() != nullptr);
	CHECK(b->frameSize() == 504u);
	CHECK(b->states().status().state == ecmxf::State::Init);
	CHECK(b->setup().slaveCount() == 0u); // INIT: SET_AXIS answers 0
	b->states().set(ecmxf::State::PreOp);
	CHECK(b->setup().slaveCount() == 3u);
	bringUp(*b);
	const auto s = b->states().status();
	CHECK(s.state == ecmxf::State::Op);
	CHECK(s.fifoRemaining == 160); // the simulated FIFO's depth
}

TEST_CASE("sk lib: wrong types, bad cycle times and commands in the wrong state are clear errors")
{
	auto b = Board::open("sk-sim:");
	b->states().set(ecmxf::State::PreOp);
	const std::vector<SlaveType> wrong = { SlaveType::Step, SlaveType::Step, SlaveType::Io };
	const auto msg = messageOf([&] { b->setup().setAxes(wrong); });
	CHECK(msg.find("slave 0 (STEP)") != std::string::npos); // bus position, not the slot
	CHECK(errnoOf([&] { b->setup().setAxes(wrong); }) == EPERM);
	CHECK(errnoOf([&] { b->setup().setCycleTime(750); }) == EINVAL);
	CHECK(errnoOf([&] { b->setup().setCycleTime(0); }) == EINVAL);
	CHECK(errnoOf([&] { b->setup().setExtensions(4); }) == EINVAL);
	CHECK(errnoOf([&] { b->drives().setMode(0, Mode::Csp); }) == EINVAL);
	CHECK(errnoOf([&] { b->drives().setMode(41, Mode::Csp); }) == EINVAL);
	CHECK(errnoOf([&] { b->drives().setMode(3, Mode::Csp); }) == EPERM); // IO slave
	CHECK(errnoOf([&] { b->drives().servoOn(1); }) == EPERM);	     // not OP
	CHECK(messageOf([&] { b->drives().servoOn(1); }).find("SV_ON is allowed in OP; the ECM-SK is in PRE-OP") !=
	      std::string::npos);
	// SAFE-OP refused: the types were never set
	const auto st = messageOf([&] { b->states().set(ecmxf::State::SafeOp, 100ms); });
	CHECK(st.find("stayed in PRE-OP") != std::string::npos);
	CHECK(st.find("SET_AXIS") != std::string::npos);
	CHECK(errnoOf([&] { b->io().writeLocal(64); }) == EINVAL);
	CHECK(errnoOf([&] { b->sdo().write(1, 0x6060, 0, 6, 3); }) == EINVAL);
	CHECK(errnoOf([&] { b->sdo().write(1, 0x6060, 0, 0x100, 1); }) == EINVAL);
	b->setup().setAxes(kTypes);
	b->states().set(ecmxf::State::Op);
	CHECK(errnoOf([&] { b->setup().setCycleTime(500); }) == EPERM);
	CHECK(errnoOf([&] { b->setup().setAxes(kTypes); }) == EPERM);
	CHECK(errnoOf([&] { b->io().write(1, 1); }) == EPERM); // a drive
}

TEST_CASE("sk lib: SDO typed read and write, aborts carry the code and its text")
{
	auto b = Board::open("sk-sim:");
	CHECK(errnoOf([&] { (void)b->sdo().read(1, 0x1000, 0); }) == EPERM); // INIT
	b->states().set(ecmxf::State::PreOp);
	CHECK(b->sdo().read<std::uint32_t>(1, 0x1018, 1) == ecmxf::sim::model::kVendorId);
	b->sdo().write<std::int8_t>(2, 0x6098, 0, 37);
	CHECK(b->sdo().read<std::int8_t>(2, 0x6098, 0) == 37);
	CHECK(errnoOf([&] { (void)b->sdo().read<std::uint32_t>(2, 0x6098, 0); }) == EMSGSIZE);
	try {
		(void)b->sdo().read(1, 0x5FFF, 0);
		FAIL("no abort");
	} catch (const ecmxf::SdoError &e) {
		CHECK(e.abortCode() == 0x06020000u);
		CHECK(e.errnoValue() == EREMOTEIO);
		CHECK(std::string(e.what()).find(std::string(ecmxf::sdoAbortText(0x06020000u))) !=
		      std::string::npos);
	}
	CHECK(errnoOf([&] { b->sdo().write<std::uint16_t>(1, 0x6041, 0, 1); }) == EREMOTEIO); // read-only
}

TEST_CASE("sk lib: servo on, a CSP move of the Drive and the STEP slave through the cyclic path")
{
	auto b = Board::open("sk-sim:");
	bringUp(*b);
	const auto [p1, p2] = enableDrives(*b);
	int drops = 0;
	for (int i = 1; i <= 500; i++) {
		REQUIRE(b->cyclic().stage(1, Mode::Csp, p1 + 40 * i));
		REQUIRE(b->cyclic().stage(2, Mode::Csp, p2 + 20 * i));
		CHECK_FALSE(b->cyclic().stage(1, Mode::Csp, 0)); // one per slave per exchange
		const auto r = b->cyclic().cycle();
		REQUIRE(r.status != CycleStatus::Link);
		drops += r.dropped;
		b->channel().sleepFor(1ms - b->simulator()->wireTime() - 20us);
	}
	for (int i = 0; i < 30; i++) {
		b->cyclic().cycle();
		b->channel().sleepFor(1ms);
	}
	CHECK(drops == 0);
	CHECK(std::abs(b->drives().axis(1).position - (p1 + 20000)) <= 10);
	CHECK(std::abs(b->drives().axis(2).position - (p2 + 10000)) <= 10);
	CHECK(b->cyclic().stage(5, Mode::Csp, 0) == true); // slave 5: no slave, the board refuses
	CHECK_FALSE(b->cyclic().stage(0, Mode::Csp, 0));
	CHECK_FALSE(b->cyclic().stage(41, Mode::Csp, 0));
}

TEST_CASE("sk lib: stage() refuses what the FIFO has no room for, nothing is dropped")
{
	auto b = Board::open("sk-sim:?abandon=0");
	bringUp(*b, 4000); // slow cycle: the FIFO fills faster than it drains
	const auto [p1, p2] = enableDrives(*b);
	unsigned refusedStage = 0, dropped = 0;
	for (int i = 0; i < 300; i++) {
		if (!b->cyclic().stage(1, Mode::Csp, p1))
			refusedStage++;
		if (!b->cyclic().stage(2, Mode::Csp, p2))
			refusedStage++;
		const auto r = b->cyclic().cycle();
		REQUIRE(r.status != CycleStatus::Link);
		dropped += r.dropped;
	}
	CHECK(refusedStage > 100u);
	CHECK(dropped == 0u);
	CHECK(b->states().status().fifoFull == 0);
	// outside OP nothing is staged
	b->states().set(ecmxf::State::SafeOp);
	CHECK_FALSE(b->cyclic().stage(1, Mode::Csp, p1));
}

TEST_CASE("sk lib: stage() keeps at most 100 queued: a long one-axis ramp loses nothing to CONFIG3")
{
	auto b = Board::open("sk-sim:"); // abandon=1, the default
	bringUp(*b);
	const auto [p1, p2] = enableDrives(*b);
	(void)p2;
	auto *sim = b->simulator();
	REQUIRE(sim != nullptr);
	// as fast as stage() takes them: 1000 targets, one axis
	unsigned most = 0;
	for (int i = 1; i <= 1000;) {
		if (b->cyclic().stage(1, Mode::Csp, p1 + i))
			i++;
		const auto r = b->cyclic().cycle();
		REQUIRE(r.status == CycleStatus::Ok);
		most = std::max(most, sim->fifoUsed());
	}
	b->channel().sleepFor(200ms);
	b->cyclic().cycle();
	CHECK(most <= 100u);
	CHECK(most >= 90u); // it did fill up to the bound
	CHECK(sim->stats().fifoAbandoned == 0u);
	CHECK(sim->stats().fifoDropped == 0u);
	CHECK(b->drives().axis(1).position == p1 + 1000);
}

TEST_CASE("sk lib: a full FIFO is a FifoOverflow the application sees")
{
	auto b = Board::open("sk-sim:?abandon=0");
	bringUp(*b, 4000);
	auto *sim = b->simulator();
	REQUIRE(sim != nullptr);
	b->states().status(); // the library saw an empty FIFO
	// a second host on the same board fills the FIFO behind the
	// library's back: 280 CSPs, more than its 160 entries take
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
	const auto r = b->cyclic().cycle();
	CHECK(r.status == CycleStatus::FifoOverflow);
	CHECK(r.dropped == r.fifoFull);
	CHECK(r.dropped > 0);
	// now the library knows: it holds back instead of sending into it
	CHECK_FALSE(b->cyclic().stage(1, Mode::Csp, 0));
}

TEST_CASE("sk lib: servo off, alarm clear, IO, LIO, homing, reset")
{
	auto b = Board::open("sk-sim:");
	bringUp(*b);
	b->drives().servoOn(1);
	b->drives().waitEnabled(1);
	auto *drive = dynamic_cast<ecmxf::sim::Cia402Model *>(&b->simulator()->network().at(0));
	REQUIRE(drive != nullptr);
	drive->injectFault(0x7500);
	b->channel().sleepFor(20ms);
	b->states().status();
	CHECK(b->drives().axis(1).errorCode == 0x7500);
	CHECK(errnoOf([&] { b->drives().waitEnabled(1, 10ms); }) == ETIMEDOUT);
	b->drives().alarmClear(1);
	b->drives().waitEnabled(1);
	b->drives().servoOff(1);
	b->channel().sleepFor(20ms);
	b->states().status();
	CHECK(ecmxf::cia402StateFrom(b->drives().axis(1).statusword) != ecmxf::Cia402State::OperationEnabled);

	b->io().write(3, 0x5A);
	b->channel().sleepFor(5ms);
	auto *io = dynamic_cast<ecmxf::sim::DioModel *>(&b->simulator()->network().at(2));
	REQUIRE(io != nullptr);
	CHECK(io->outputs()[0] == 0x5A);
	io->setInput(2, true);
	b->channel().sleepFor(5ms);
	CHECK((b->io().read(3) & 0x4u) != 0);

	b->simulator()->setLioInputs(0x21);
	CHECK(b->io().readLocal() == 0x21u);
	b->io().writeLocal(0x12);
	CHECK(b->simulator()->lioOutputs() == 0x12u);

	b->drives().servoOn(2);
	b->drives().waitEnabled(2);
	b->sdo().write<std::int32_t>(2, 0x607C, 0, 500);
	b->drives().home(2, 37);
	b->states().status();
	CHECK(b->drives().axis(2).position == 500);
	CHECK((b->drives().axis(2).statusword & (ecmxf::cia402::kSwTargetReached | ecmxf::cia402::kSwHomingAttained)) ==
	      (ecmxf::cia402::kSwTargetReached | ecmxf::cia402::kSwHomingAttained));
	CHECK(errnoOf([&] { b->drives().home(3, 37); }) != 0); // an IO slave has no homing

	b->states().reset();
	CHECK(b->state() == ecmxf::State::Init);
	CHECK(b->simulator()->lioOutputs() == 0u);
}

TEST_CASE("sk lib: 16-byte slots and CRCs both ways after SET_EX and a power cycle")
{
	auto b = Board::open("sk-sim:?slot=16");
	CHECK(b->frameSize() == 512u);
	CHECK(b->maxSlaves() == 30u);
	b->setup().setExtensions(3);
	b->simulator()->powerCycle();
	// the host was not told: its frames have no CRC and are refused
	CHECK(errnoOf([&] { b->io().writeLocal(1); }) == EBADMSG);
	// the same board with the right link options
	auto ch = std::make_unique<ecmxf::sk::SimBoardChannel>(std::string{}, BoardConfig::parse("slot=16&ex=3"));
	Board crc(std::move(ch), LinkOptions{ 16, 3 });
	crc.states().set(ecmxf::State::PreOp);
	crc.io().writeLocal(5);
	CHECK(crc.simulator()->lioOutputs() == 5u);
	CHECK(crc.states().status().crcErrors == 0);
}

TEST_CASE("sk lib: detectAxes finds each slave's type through SET_AXIS")
{
	auto b = Board::open("sk-sim:");
	CHECK(errnoOf([&] { (void)b->setup().detectAxes(); }) == EPERM); // INIT
	b->states().set(ecmxf::State::PreOp);
	const auto t = b->setup().detectAxes();
	CHECK(t == kTypes);
	CHECK(b->simulator()->slaveType(2) == static_cast<std::uint8_t>(SlaveType::Step));
}

TEST_CASE("sk lib: stage2() drives both channels of a 2-channel HSP, 12-byte slots refuse it")
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
	b->states().set(ecmxf::State::PreOp);
	CHECK(b->setup().detectAxes() == std::vector<SlaveType>{ SlaveType::Hsp, SlaveType::Io });
	b->states().set(ecmxf::State::Op);
	b->drives().servoOn(1);
	b->drives().waitEnabled(1);
	for (int i = 1; i <= 50; i++) {
		REQUIRE(b->cyclic().stage2(1, Mode::Csp, 20 * i, -30 * i));
		CHECK_FALSE(b->cyclic().stage2(1, Mode::Csp, 0, 0)); // once per exchange
		REQUIRE(b->cyclic().cycle().status == CycleStatus::Ok);
		b->channel().sleepFor(1ms);
	}
	b->channel().sleepFor(20ms);
	b->states().status();
	const auto h = b->drives().hsp2(1);
	CHECK(h.position1 == 1000);
	CHECK(h.position2 == -1500);
	CHECK_FALSE(b->cyclic().stage2(1, Mode::Cst, 0, 0));
	CHECK(errnoOf([&] { (void)b12->drives().hsp2(1); }) == EINVAL);
	CHECK_FALSE(b12->cyclic().stage2(1, Mode::Csp, 0, 0));
}

TEST_CASE("sk board: the EtherCAT state is ecmxf::State, sk::State stays one release as its alias")
{
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
	STATIC_REQUIRE(std::is_same_v<ecmxf::sk::State, ecmxf::State>);
#pragma GCC diagnostic pop
	STATIC_REQUIRE(static_cast<int>(ecmxf::State::Init) == 0x01);
	STATIC_REQUIRE(static_cast<int>(ecmxf::State::PreOp) == 0x02);
	STATIC_REQUIRE(static_cast<int>(ecmxf::State::SafeOp) == 0x04);
	STATIC_REQUIRE(static_cast<int>(ecmxf::State::Op) == 0x08);
	CHECK(ecmxf::sk::stateName(ecmxf::State::PreOp) == "PRE-OP");
	CHECK(ecmxf::sk::stateName(ecmxf::State::SafeOp) == "SAFE-OP");
}

TEST_CASE("sk board: the flat members of before still forward to the views (deprecated, one release)")
{
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
	auto b = Board::open("sk-sim:");
	CHECK(b->status().state == ecmxf::State::Init);
	b->setState(ecmxf::State::PreOp);
	CHECK(b->state() == ecmxf::State::PreOp);
	CHECK(b->slaveCount() == 3u);
	CHECK(b->sdoRead<std::uint32_t>(1, 0x1000, 0) == b->sdo().read<std::uint32_t>(1, 0x1000, 0));
	CHECK(b->lioRead() == b->io().readLocal());
	CHECK(errnoOf([&] { b->servoOn(1); }) == EPERM); // PRE-OP
	CHECK(b->cycle().status == ecmxf::sk::CycleStatus::Ok);
	CHECK(b->lastError().empty());
#pragma GCC diagnostic pop
}
