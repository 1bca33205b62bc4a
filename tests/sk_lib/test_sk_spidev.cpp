// SPDX-License-Identifier: MIT
// The ECM-SK over spidev: SpidevChannel with the Busy line as its ready
// line (low = ready), against a SpidevBackend played by the simulated
// board, as tests/transport does for the ECM-XF.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cerrno>
#include <memory>

#include <ecmxf/error.hpp>
#include <ecmxf/link/spidev_channel.hpp>
#include <ecmxf/sim/network.hpp>
#include <ecmxf/sk/board.hpp>
#include <ecmxf/sim/sk_board.hpp>
#include <ecmxf/sk/sim_channel.hpp>
#include <ecmxf/device_uri.hpp>

using namespace ecmxf;
using namespace std::chrono_literals;

namespace {

struct FakeFaults {
	bool busyStuck = false; ///< the Busy line reads high for ever
	int transferErrno = 0;
};

// SpidevBackend played by a SimBoard: bytes from exchange(), the INT0
// (here: Busy) level from busy(), the board's virtual clock.
class FakeSkSpidev final : public SpidevBackend
{
public:
	FakeSkSpidev(sk::SimBoard &b, FakeFaults &f) : b_(b), f_(f) {}
	int transfer(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) noexcept override
	{
		transfers++;
		if (f_.transferErrno)
			return -f_.transferErrno;
		b_.exchange(mosi, miso);
		return static_cast<int>(mosi.size());
	}
	bool hasLine(IntLine l) const noexcept override { return l == IntLine::Int0; }
	int lineValue(IntLine) noexcept override { return level() ? 1 : 0; }
	int waitEdge(IntLine, std::chrono::nanoseconds timeout) noexcept override
	{
		const bool start = level();
		const auto end = b_.now() + timeout;
		while (b_.now() < end) {
			b_.advance(std::min<std::chrono::nanoseconds>(1us, end - b_.now()));
			if (level() != start)
				return 1;
		}
		return 0;
	}
	std::chrono::nanoseconds now() const noexcept override { return b_.now(); }
	void sleepFor(std::chrono::nanoseconds d) noexcept override { b_.advance(d); }
	unsigned transfers = 0;

private:
	bool level() const { return f_.busyStuck || b_.busy(); }
	sk::SimBoard &b_;
	FakeFaults &f_;
};

struct Rig {
	sk::SimBoard board{ sim::Network::fromText(sk::defaultSkNetwork(), "t") };
	FakeFaults faults;
	FakeSkSpidev *fake = nullptr;
	std::unique_ptr<sk::Board> b;

	explicit Rig(std::chrono::milliseconds busyTimeout = 100ms)
	{
		const auto u = ecmxf::parseDeviceUri("sk-spidev:/dev/spidev0.0?busy=gpiochip0:17");
		auto be = std::make_unique<FakeSkSpidev>(board, faults);
		fake = be.get();
		auto ch = std::make_unique<SpidevChannel>(std::move(be), u.spidev);
		sk::LinkOptions o;
		o.busyTimeout = busyTimeout;
		b = std::make_unique<sk::Board>(std::move(ch), o);
	}
};

} // namespace

TEST_CASE("sk spidev: bring-up to OP and a CSP move over spidev with Busy as the ready line")
{
	Rig r;
	CHECK(r.b->channel().name() == "spidev:/dev/spidev0.0");
	r.b->states().set(ecmxf::State::PreOp);
	const std::vector<sk::SlaveType> types = { sk::SlaveType::Drive, sk::SlaveType::Step, sk::SlaveType::Io };
	CHECK(r.b->setup().setAxes(types) == 3u);
	r.b->states().set(ecmxf::State::Op);
	r.b->drives().servoOn(2);
	r.b->drives().waitEnabled(2);
	r.b->states().status();
	const auto p = r.b->drives().axis(2).position;
	for (int i = 1; i <= 100; i++) {
		REQUIRE(r.b->cyclic().stage(2, sk::Mode::Csp, p + 10 * i));
		REQUIRE(r.b->cyclic().cycle().status == sk::CycleStatus::Ok);
		r.b->channel().sleepFor(800us);
	}
	for (int i = 0; i < 10; i++) {
		r.b->cyclic().cycle();
		r.b->channel().sleepFor(1ms);
	}
	CHECK(std::abs(r.b->drives().axis(2).position - (p + 1000)) <= 5);
	// never a transfer while Busy was high
	CHECK(r.board.stats().whileBusy == 0u);
	CHECK(r.board.stats().frames == r.fake->transfers);
}

TEST_CASE("sk spidev: a Busy line stuck high is a timeout, not a transfer")
{
	Rig r(5ms);
	r.faults.busyStuck = true;
	try {
		r.b->states().status();
		FAIL("no timeout");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == ETIMEDOUT);
		CHECK(std::string(e.what()).find("Busy") != std::string::npos);
	}
	CHECK(r.fake->transfers == 0u);
	r.b->cyclic().stage(1, sk::Mode::Csp, 0);
	CHECK(r.b->cyclic().cycle().status == sk::CycleStatus::Busy);
}

TEST_CASE("sk spidev: a failing transfer is an error naming the node, cycle() reports it as Link")
{
	Rig r;
	r.faults.transferErrno = EIO;
	try {
		r.b->states().status();
		FAIL("no error");
	} catch (const Error &e) {
		CHECK(e.errnoValue() == EIO);
		CHECK(std::string(e.what()).find("/dev/spidev0.0") != std::string::npos);
	}
	CHECK(r.b->cyclic().cycle().status == sk::CycleStatus::Link);
	CHECK(r.b->cyclic().lastError().find("/dev/spidev0.0") != std::string::npos);
}
