// SPDX-License-Identifier: MIT
//
// ecmxf-soak: ecmxf::Cyclic over the in-process simulator at 8 kHz in
// virtual time for millions of cycles, with a fault schedule drawn from a
// seed, and invariants checked every cycle (Documentation/building.rst,
// "Soak").
//
//   ecmxf-soak [--cycles N] [--seed S] [--network default|128]
//              [--bit-error-rate P] [--quiet]
//
// The network is built in code: the default network (2 x EST-584 + dio) or
// the 128-slave one (64 x EST-584 + 64 x dio), with the last dio replaced
// by a tagged terminal (4 output bytes, 8 input bytes) that checks every
// output frame it applies and stamps every input frame:
//  - outputs: the application writes its cycle number (the output
//    sequence number) into the tag's 4 output bytes every cycle;
//  - inputs: bytes 0..3 the TxFIFO push number of the frame (the chip's
//    ChipStats::txPushed + 1 when the frame is built), bytes 4..7 the
//    output sequence number the slave applied in that bus cycle.
// The channel between the library and the chip (FaultChannel) injects the
// SPI faults and reads the output frames the chip takes in; the chip's
// ChipStats give the ground truth of every FIFO (accepted, popped, pushed,
// read, dropped, cleared).
//
// Exit status: 0 all invariants held, 1 an invariant failed (the first
// failures are printed with their cycle), 2 bad arguments or setup failure.

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <sys/resource.h>

#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/slave_access.hpp>
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/byte_channel.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_data.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/sim/chip.hpp>
#include <ecmxf/sim/network.hpp>

#include "ecmxf-proto.h"

#include "../common/alloc_counter.hpp"

namespace {

using namespace std::chrono_literals;
using std::chrono::nanoseconds;

constexpr std::size_t kTagOut = 4, kTagIn = 8;
constexpr std::size_t kWindow = 1u << 16; // output sequence numbers tracked at once

std::uint32_t le32(const std::uint8_t *p)
{
	return static_cast<std::uint32_t>(p[0] | p[1] << 8 | p[2] << 16 | static_cast<std::uint32_t>(p[3]) << 24);
}

void put32(std::uint8_t *p, std::uint32_t v)
{
	for (int i = 0; i < 4; i++)
		p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

/// splitmix64: the schedule is a function of the seed alone.
struct Rng {
	std::uint64_t s;
	std::uint64_t next()
	{
		std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
		z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
		z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
		return z ^ (z >> 31);
	}
	std::uint64_t range(std::uint64_t lo, std::uint64_t hi) { return lo + next() % (hi - lo + 1); }
	double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
};

// ---------------------------------------------------------------------------
// invariant failures
// ---------------------------------------------------------------------------

struct Failures {
	/// what failed and how often: a fixed table, so that a failure found
	/// inside cycle() (the checks run there) allocates nothing
	struct Entry {
		const char *what = nullptr;
		std::uint64_t n = 0;
	};
	std::array<Entry, 32> count{};
	unsigned printed = 0;
	std::uint64_t cycle = 0; ///< the application cycle being run
	/// @p a and @p b: the values involved (printed as "[a b]").
	void fail(const char *what, std::uint64_t a = 0, std::uint64_t b = 0)
	{
		for (Entry &e : count) {
			if (!e.what || e.what == what || std::strcmp(e.what, what) == 0) {
				e.what = what;
				e.n++;
				break;
			}
		}
		if (printed < 20) {
			printed++;
			std::printf("FAIL cycle %" PRIu64 ": %s [%" PRIu64 " %" PRIu64 "]\n", cycle, what, a, b);
		}
	}
	[[nodiscard]] std::uint64_t total() const
	{
		std::uint64_t n = 0;
		for (const Entry &e : count)
			n += e.n;
		return n;
	}
};

Failures g_fail;

/// --inject-bug K: a defect planted on purpose, to show that the checks
/// catch it (the ctest soak-catches-* expect the run to fail):
/// 1 an input frame handed over twice, 2 an input frame lost without an
/// error, 3 an old output frame applied again, 4 an allocation in cycle().
unsigned g_bug = 0;
constexpr std::uint64_t kBugCycle = 5000;

// ---------------------------------------------------------------------------
// the tagged slave: a dio model behind a decorator that checks and stamps
// ---------------------------------------------------------------------------

struct TagState {
	const ecmxf::sim::Chip *chip = nullptr;
	std::uint32_t written = 0;        ///< newest output sequence number the application wrote
	std::uint32_t lastApplied = 0;    ///< output sequence number of the last frame applied
	std::uint64_t lastRxPopped = 0;   ///< ChipStats::rxPopped at the previous cycle()
	std::uint64_t consumed = 0;       ///< frames applied (popped from the RxFIFO in a cycle that reached us)
	std::uint64_t poppedUnreached = 0;///< frames popped while the link was down (never applied)
	std::uint64_t notApplied = 0;     ///< frames popped while the slave was not in OP
	std::vector<std::uint32_t> accepted = std::vector<std::uint32_t>(kWindow); ///< per seq: copies the chip took in
	std::vector<std::uint32_t> applied = std::vector<std::uint32_t>(kWindow);  ///< per seq: copies applied
};

TagState g_tag;

class TaggedSlave final : public ecmxf::sim::Slave
{
public:
	explicit TaggedSlave(std::unique_ptr<ecmxf::sim::Slave> inner) : in_(std::move(inner)) {}

	const ecmxf::sim::Identity &identity() const override { return in_->identity(); }
	std::string typeName() const override { return in_->typeName(); }
	std::vector<std::uint16_t> sii() const override { return in_->sii(); }
	bool hasCoE() const override { return in_->hasCoE(); }
	bool hasFoE() const override { return in_->hasFoE(); }
	std::uint16_t dcAssignActivate() const override { return in_->dcAssignActivate(); }
	nanoseconds mailboxLatency() const override { return in_->mailboxLatency(); }
	std::uint8_t escRead8(std::uint16_t reg) const override { return in_->escRead8(reg); }
	void escWrite8(std::uint16_t reg, std::uint8_t value) override { in_->escWrite8(reg, value); }
	void alControl(std::uint8_t value) override { in_->alControl(value); }
	std::uint8_t alStatus() const override { return in_->alStatus(); }
	std::uint16_t alStatusCode() const override { return in_->alStatusCode(); }
	void configureDc(std::uint16_t aa, std::uint32_t s0, std::uint32_t s1, std::int32_t shift) override
	{
		in_->configureDc(aa, s0, s1, shift);
	}
	std::uint32_t sdoUpload(std::uint16_t i, std::uint8_t s, bool c, std::vector<std::uint8_t> &out) override
	{
		return in_->sdoUpload(i, s, c, out);
	}
	std::uint32_t sdoDownload(std::uint16_t i, std::uint8_t s, bool c, std::span<const std::uint8_t> d) override
	{
		return in_->sdoDownload(i, s, c, d);
	}
	std::optional<ecmxf::sim::Emergency> popEmergency() override { return in_->popEmergency(); }
	std::vector<ecmxf::sim::Pdo> rxPdos() const override { return in_->rxPdos(); }
	std::vector<ecmxf::sim::Pdo> txPdos() const override { return in_->txPdos(); }
	std::size_t outputBytes() const override { return in_->outputBytes(); }
	std::size_t inputBytes() const override { return in_->inputBytes(); }
	void reset() override { in_->reset(); }

	void idle(nanoseconds dt) override
	{
		// a frame popped in a cycle that did not reach us: never applied
		g_tag.poppedUnreached += account();
		in_->idle(dt);
	}

	unsigned cycle(std::span<const std::uint8_t> outputs, bool valid, std::span<std::uint8_t> inputs,
		       nanoseconds dt, bool sync0) override
	{
		TagState &t = g_tag;
		const std::uint64_t d = account();
		const bool popped = d > 0;
		if (d > 1)
			t.poppedUnreached += d - 1; // earlier cycles that did not reach us
		const unsigned wkc = in_->cycle(outputs, valid, inputs, dt, sync0);
		if (popped && wkc < 2)
			t.notApplied++; // not in OP: the outputs were not written
		if (popped && outputs.size() >= kTagOut && wkc >= 2) {
			// this bus cycle applied a frame taken from the RxFIFO
			std::uint32_t seq = le32(outputs.data());
			if (g_bug == 3 && seq > kBugCycle && seq > 1) {
				g_bug = 0;
				seq -= 2; // planted: an older frame applied again
				t.applied[seq % kWindow]++;
			}
			if (seq != 0) {
				if (seq < t.lastApplied)
					g_fail.fail("output frame out of order", seq,
						    t.lastApplied);
				if (seq > t.written)
					g_fail.fail("output frame never written applied", seq,
						    t.written);
				std::uint32_t &a = t.applied[seq % kWindow];
				a++;
				if (a > t.accepted[seq % kWindow])
					g_fail.fail("output frame applied more often than the chip took it in", seq, a);
				t.lastApplied = std::max(t.lastApplied, seq);
			}
			t.consumed++;
		}
		if (inputs.size() >= kTagIn) {
			put32(inputs.data(), static_cast<std::uint32_t>(t.chip->stats().txPushed + 1));
			put32(inputs.data() + 4, popped ? le32(outputs.data()) : 0);
		}
		return wkc;
	}

private:
	/// Frames the chip popped from the RxFIFO since the previous call (the
	/// chip calls cycle() or idle() of every slave once per bus cycle,
	/// after the pop).
	static std::uint64_t account()
	{
		TagState &t = g_tag;
		const std::uint64_t p = t.chip ? t.chip->stats().rxPopped : 0;
		const std::uint64_t d = p - t.lastRxPopped;
		t.lastRxPopped = p;
		return d;
	}

	std::unique_ptr<ecmxf::sim::Slave> in_;
};

// ---------------------------------------------------------------------------
// the channel: SPI faults between the library and the chip
// ---------------------------------------------------------------------------

class FaultChannel final : public ecmxf::ByteChannel
{
public:
	FaultChannel(ecmxf::sim::Network net, ecmxf::sim::ChipConfig cfg, std::uint64_t seed)
		: chip_(std::move(net), cfg), rng_{ seed ^ 0x5EED5EED5EEDull }
	{
		buf_.resize(ECMXF_PKT_MAX);
	}

	void exchange(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override
	{
		const std::size_t n = mosi.size();
		std::memcpy(buf_.data(), mosi.data(), n);
		const std::size_t check = n - ECMXF_TRAILER_SIZE;
		// the faults of this exchange: a burst, or the random rate
		bool badMosi = false, badMiso = false;
		if (burst > 0) {
			burst--;
			(rng_.next() & 1 ? badMosi : badMiso) = true;
		} else if (oneMosi > 0) {
			oneMosi--;
			badMosi = true;
		} else if (oneMiso > 0) {
			oneMiso--;
			badMiso = true;
		} else if (rate_ > 0 && rng_.unit() < rate_) {
			(rng_.next() & 1 ? badMosi : badMiso) = true;
		}
		if (badMosi) {
			buf_[check] ^= 0x01; // one bit of the check word: every check type sees it
			mosiErrors++;
		}
		const std::uint64_t acc0 = chip_.stats().rxAccepted;
		chip_.exchange(std::span<const std::uint8_t>(buf_.data(), n), miso);
		const std::uint64_t acc = chip_.stats().rxAccepted - acc0;
		if (acc && rxTagOffset != SIZE_MAX) {
			// the RxPDO frames the chip took in: all copies of one frame
			const std::uint32_t seq = le32(buf_.data() + ECMXF_HDR_SIZE + rxTagOffset);
			g_tag.accepted[seq % kWindow] += static_cast<std::uint32_t>(acc);
			acceptedTotal += acc;
		}
		if (badMiso) {
			miso[check] ^= 0x01;
			misoErrors++;
		}
	}

	bool waitReady(nanoseconds timeout) override
	{
		const nanoseconds end = chip_.now() + std::max(timeout, nanoseconds::zero());
		while (!chip_.ready()) {
			const nanoseconds t = chip_.now();
			if (t >= end)
				return false;
			chip_.advance(std::min(nanoseconds(10us), end - t));
		}
		return true;
	}
	nanoseconds now() const override { return chip_.now(); }
	void sleepFor(nanoseconds d) override
	{
		if (d.count() > 0)
			chip_.advance(d);
	}
	std::string name() const override { return "soak:"; }
	ecmxf::sim::Chip &chip() { return chip_; }
	/// Random bit errors: each exchange's MOSI or MISO with probability @p p.
	void setRate(double p) { rate_ = p; }

	unsigned burst = 0, oneMosi = 0, oneMiso = 0;
	std::uint64_t mosiErrors = 0, misoErrors = 0, acceptedTotal = 0;
	std::size_t rxTagOffset = SIZE_MAX;

private:
	ecmxf::sim::Chip chip_;
	Rng rng_;
	double rate_ = 0;
	std::vector<std::uint8_t> buf_;
};

// ---------------------------------------------------------------------------
// set-up
// ---------------------------------------------------------------------------

ecmxf::sim::Network makeNetwork(const std::string &which)
{
	using ecmxf::sim::Network;
	Network net;
	const std::map<std::string, std::string> tag = { { "outputs", "4" }, { "inputs", "8" } };
	if (which == "default") {
		net.setName("2x EST-584 + tagged digital I/O");
		net.add(Network::makeSlave("EST-584", 0));
		net.add(Network::makeSlave("EST-584", 1));
		net.add(std::make_unique<TaggedSlave>(Network::makeSlave("dio", 2, tag)));
	} else if (which == "128") {
		net.setName("64x EST-584 + 63x dio + tagged dio");
		unsigned pos = 0;
		for (int i = 0; i < 64; i++, pos++)
			net.add(Network::makeSlave("EST-584", pos));
		for (int i = 0; i < 63; i++, pos++)
			net.add(Network::makeSlave("dio", pos));
		net.add(std::make_unique<TaggedSlave>(Network::makeSlave("dio", pos, tag)));
	} else {
		throw std::invalid_argument("--network: default or 128");
	}
	return net;
}

void bringUp(ecmxf::Device &d, nanoseconds period)
{
	ecmxf::Command init;
	init.code = ECMXF_CMD_ECAT_INIT_OP;
	init.payload = { 0xFF, 0x81, 0x00, 0x00 };
	const auto sync0 = static_cast<std::uint32_t>(period.count());
	for (int i = 0; i < 4; i++)
		init.payload.push_back(static_cast<std::uint8_t>(sync0 >> (8 * i)));
	init.payload.resize(16, 0);
	(void)d.command(init);
	for (auto st : { ecmxf::State::PreOp, ecmxf::State::SafeOp, ecmxf::State::Op })
		d.bus().stateSet(ecmxf::kAllSlaves, st);
}

std::vector<ecmxf::SlavePdos> sizes(ecmxf::Device &d)
{
	const unsigned n = d.bus().slaveCount();
	std::vector<ecmxf::SlavePdos> v(n);
	for (unsigned i = 0; i < n; i++) {
		const ecmxf::SlaveInfo si = d.bus().slaveInfo(static_cast<std::uint8_t>(i));
		v[i].outputBytes = si.outputBytes;
		v[i].inputBytes = si.inputBytes;
	}
	return v;
}

long maxRssKb()
{
	rusage u{};
	getrusage(RUSAGE_SELF, &u);
	return u.ru_maxrss;
}

// ---------------------------------------------------------------------------
// the fault schedule
// ---------------------------------------------------------------------------

enum Kind : unsigned {
	kBitMosi,
	kBitMiso,
	kBurst,
	kSilent,
	kLinkLoss,
	kSlaveDrop,
	kWkcErrors,
	kAsyncStuck,
	kStarve,
	kKinds
};

const char *const kKindName[kKinds] = { "bit error (MOSI)", "bit error (MISO)", "bad packet burst",
					"chip silent",      "link loss",        "slave drop",
					"WKC errors",       "stuck async busy", "FIFO starvation" };

/// How soon (application cycles after the fault took effect) the
/// application must see it.
constexpr std::uint64_t kDetectBound = 3;
/// How long recovery may take (cycles after the fault ended).
constexpr std::uint64_t kRecoverBound = 2000;

struct KindStats {
	std::uint64_t injected = 0, detected = 0, undetected = 0, absorbed = 0, recovered = 0, notRecovered = 0;
	std::uint64_t detectMax = 0;
	std::uint64_t recSum = 0, recMax = 0, recMin = UINT64_MAX; ///< recovery time, ns of virtual time
	std::uint64_t appActions = 0;
};

struct Active {
	Kind kind = kKinds;
	std::uint64_t start = 0;     ///< cycle the fault took effect
	std::uint64_t endAt = 0;     ///< cycle it is removed (scheduled)
	bool ended = false;
	nanoseconds endTime{ 0 };
	std::uint64_t endCycle = 0;
	bool detected = false;
	bool lossy = false;          ///< frames were lost (a silent fault must then be detected)
};

struct Options {
	std::uint64_t cycles = 100000;
	std::uint64_t seed = 1;
	std::string network = "default";
	double bitErrorRate = 1e-5;
	bool quiet = false;
	bool verbose = false;
	/// the chip's time per packet (INT0 busy); the simulator's default is 50 us
	nanoseconds processing{ 20us };
	nanoseconds period{ 0 }; ///< 0: 125 us (default network), 500 us (128 slaves)
};

int run(const Options &o)
{
	const nanoseconds period = o.period.count() ? o.period : o.network == "128" ? nanoseconds(500us) : nanoseconds(125us);
	std::printf("ecmxf-soak: network %s, %" PRIu64 " cycles of %lld us (bus and application), seed %" PRIu64
		    " (replay: SOAK_SEED=%" PRIu64 "), bit error rate %g per exchange, chip processing %lld us\n",
		    o.network.c_str(), o.cycles, static_cast<long long>(period.count() / 1000), o.seed, o.seed,
		    o.bitErrorRate, static_cast<long long>(o.processing.count() / 1000));
	const long rss0 = maxRssKb();

	ecmxf::sim::ChipConfig cc;
	cc.spiClockHz = 96'000'000;
	cc.processingTime = o.processing;
	auto ch = std::make_unique<FaultChannel>(makeNetwork(o.network), cc, o.seed);
	FaultChannel &fc = *ch;
	ecmxf::sim::Chip &chip = fc.chip();
	g_tag.chip = &chip;
	ecmxf::Device dev(std::move(ch));
	bringUp(dev, period);

	ecmxf::ProcessImage image(sizes(dev));
	// the smallest data section that holds a frame each way (a multiple
	// of 32): the shorter the packet, the more exchanges fit a cycle
	const std::size_t frameMax = std::max(image.outputs().size(), image.inputs().size());
	const std::size_t dataSize = std::max<std::size_t>(128, (frameMax + 31) / 32 * 32);
	dev.chip().setDataSize(static_cast<std::uint16_t>(dataSize));
	const std::size_t tagPos = image.slaveCount() - 1;
	const std::size_t outOff = image.outputOffset(tagPos), inOff = image.inputOffset(tagPos);
	fc.rxTagOffset = outOff;

	// the input frames, checked as the library hands them over
	struct InState {
		std::size_t off = 0;
		std::uint64_t delivered = 0;
		std::uint32_t lastStamp = 0;
		std::uint64_t gaps = 0;      ///< frames missing between delivered stamps
		std::uint64_t cycleFrames = 0;
	} in;
	in.off = inOff;
	ecmxf::CyclicConfig cfg;
	cfg.period = period;
	cfg.busCycle = period;
	cfg.wkcEvery = 4;
	cfg.commandTimeout = 1ms;
	cfg.context = &in;
	cfg.onInputFrame = [](void *ctx, std::span<const std::uint8_t> f) noexcept {
		auto &s = *static_cast<InState *>(ctx);
		const std::uint32_t stamp = le32(f.data() + s.off);
		if (g_bug == 2 && g_fail.cycle == kBugCycle && s.cycleFrames == 0) {
			g_bug = 0;
			return; // planted: the frame vanishes, no error
		}
		if (g_bug == 1 && g_fail.cycle == kBugCycle) {
			g_bug = 0;
			s.lastStamp = stamp; // planted: the same frame once more below
			s.delivered++;
			s.cycleFrames++;
		}
		if (stamp <= s.lastStamp)
			g_fail.fail("input frame delivered twice or out of order", stamp,
				    s.lastStamp);
		else
			s.gaps += stamp - s.lastStamp - 1;
		s.lastStamp = std::max(s.lastStamp, stamp);
		s.delivered++;
		s.cycleFrames++;
	};
	ecmxf::Cyclic cyc(dev, image, cfg);
	// the stamps start at the first push after start() (the FIFO is off
	// until then; start() empties it)
	const ecmxf::sim::ChipStats base = chip.stats();
	const std::uint64_t txBase = base.txPushed;
	in.lastStamp = static_cast<std::uint32_t>(txBase);
	cyc.start();
	const std::uint64_t txDropBase = chip.stats().txDropped, txClrBase = chip.stats().txCleared;
	const std::uint64_t txReadBase = chip.stats().txRead;
	const std::uint64_t rxAccBase = chip.stats().rxAccepted, rxClrBase = chip.stats().rxCleared;
	const std::uint64_t unreachedBase = g_tag.poppedUnreached, consumedBase = g_tag.consumed;
	const std::uint64_t notAppliedBase = g_tag.notApplied;
	fc.acceptedTotal = 0;

	Rng sched{ o.seed };
	// a duration in microseconds as whole cycles (at least one)
	const auto cyclesOf = [&](std::uint64_t us) {
		return std::max<std::uint64_t>(1, us * 1000 / static_cast<std::uint64_t>(period.count()));
	};
	KindStats ks[kKinds];
	Active act;
	std::uint64_t nextFault = 2000 + sched.range(0, 2000);
	const std::size_t nSlaves = image.slaveCount();
	const std::size_t dropPos = nSlaves > 3 ? 5 : 0; // never the tagged slave
	std::uint64_t allocs = 0, allocCycles = 0;
	std::uint64_t refreshes = 0, errClears = 0, stateSets = 0;
	std::uint64_t errorCycles = 0, silentLossCycles = 0, overflowCycles = 0;
	std::uint64_t lostInAnswers = 0;
	std::uint64_t starveLeft = 0;
	bool recovering = false;
	std::uint8_t lastWkcErr = 0;

	const auto wall0 = std::chrono::steady_clock::now();
	const long rssStart = maxRssKb();
	fc.burst = 0;

	// the random bit errors from here on
	fc.setRate(o.bitErrorRate);
	for (std::uint64_t c = 0; c < o.cycles; c++) {
		g_fail.cycle = c;
		// ---- the schedule: start and end faults ----
		if (act.kind == kKinds && c >= nextFault) {
			act = Active{};
			act.kind = static_cast<Kind>(sched.range(0, kKinds - 1));
			act.start = c;
			ks[act.kind].injected++;
			if (o.verbose)
				std::printf("cycle %" PRIu64 ": %s\n", c, kKindName[act.kind]);
			switch (act.kind) {
			case kBitMosi:
				fc.oneMosi = 1;
				act.endAt = c + 1;
				break;
			case kBitMiso:
				fc.oneMiso = 1;
				act.endAt = c + 1;
				break;
			case kBurst:
				fc.burst = static_cast<unsigned>(sched.range(2, 24));
				act.endAt = c + 1;
				break;
			case kSilent:
				chip.faults().int0StuckBusy = true;
				act.endAt = c + cyclesOf(sched.range(125, 5000));
				break;
			case kLinkLoss:
				chip.faults().linkLost = true;
				act.endAt = c + cyclesOf(sched.range(125, 50000)); // < the 100 ms SM watchdog
				break;
			case kSlaveDrop:
				chip.faults().slaveDropped = static_cast<int>(dropPos);
				act.endAt = c + cyclesOf(sched.range(2500, 50000));
				break;
			case kWkcErrors:
				chip.faults().slaveDropped = static_cast<int>(dropPos);
				act.endAt = c + sched.range(1, 3);
				break;
			case kAsyncStuck:
				chip.faults().asyncStuckBusy = true;
				act.endAt = c; // the async command below
				break;
			case kStarve:
				starveLeft = cyclesOf(sched.range(125, 8000));
				act.endAt = c;
				break;
			case kKinds:
				break;
			}
		}
		if (act.kind != kKinds && !act.ended && c >= act.endAt) {
			switch (act.kind) {
			case kSilent:
				chip.faults().int0StuckBusy = false;
				break;
			case kLinkLoss:
				chip.faults().linkLost = false;
				break;
			case kSlaveDrop:
			case kWkcErrors:
				chip.faults().slaveDropped = -1;
				break;
			case kAsyncStuck: {
				// the application runs an async command: it times out
				try {
					(void)dev.slaves().eepromRead(0, 0x0008);
				} catch (const ecmxf::Error &e) {
					if (e.errnoValue() == ETIMEDOUT)
						act.detected = true;
				}
				ks[kAsyncStuck].appActions++;
				dev.chip().resetAsyncCommand(ecmxf::async_reset::kClearBusy);
				break;
			}
			case kStarve:
				// the application is late: k cycles pass without it
				chip.advance(period * static_cast<long>(starveLeft));
				starveLeft = 0;
				break;
			default:
				break;
			}
			act.ended = true;
			act.endTime = chip.now();
			act.endCycle = c;
			recovering = true;
		}

		// ---- one cycle ----
		const std::uint32_t seq = static_cast<std::uint32_t>(c + 1);
		put32(image.outputs().data() + outOff, seq);
		g_tag.written = seq;
		g_tag.accepted[(seq + kWindow / 2) % kWindow] = 0; // recycle the window
		g_tag.applied[(seq + kWindow / 2) % kWindow] = 0;
		const std::uint64_t late0 = cyc.stats().lateCycles;
		const std::uint64_t read0 = chip.stats().txRead, drop0 = chip.stats().txDropped;
		in.cycleFrames = 0;
		const std::uint64_t a0 = ecmxf_test::allocations();
		const ecmxf::CycleResult &r = cyc.cycle();
		if (g_bug == 4 && c == kBugCycle)
			delete new std::uint64_t(c); // planted: an allocation on the cyclic path
		const int w = cyc.waitNextCycle();
		const std::uint64_t da = ecmxf_test::allocations() - a0;
		if (da) {
			allocs += da;
			allocCycles++;
		}
		if (w)
			g_fail.fail("waitNextCycle failed", static_cast<std::uint64_t>(w));

		// ---- per-cycle invariants ----
		const std::uint64_t readNow = chip.stats().txRead - read0;
		if (readNow > in.cycleFrames) {
			lostInAnswers += readNow - in.cycleFrames;
			if (!r.error) {
				silentLossCycles++;
				g_fail.fail("input frames read from the chip but neither delivered nor reported", readNow - in.cycleFrames);
			}
			if (act.kind != kKinds)
				act.lossy = true;
		} else if (readNow < in.cycleFrames) {
			g_fail.fail("more input frames delivered than the chip gave", in.cycleFrames,
				    readNow);
		}
		if (chip.stats().txDropped != drop0 || r.txOverflow) {
			overflowCycles++;
		}
		if (r.error)
			errorCycles++;

		// ---- detection ----
		if (act.kind != kKinds && !act.detected && c >= act.start) {
			bool seen = false;
			const bool wkcBad = (r.wkcRead && !r.wkcOk) || r.wkcErrorCount != lastWkcErr;
			switch (act.kind) {
			case kBitMosi:
			case kBitMiso:
			case kBurst:
				seen = r.error || (r.errStatus & ECMXF_ERR_SPI_CRC);
				break;
			case kSilent:
				seen = r.error == ETIMEDOUT;
				break;
			case kLinkLoss:
				seen = r.ecatState == ECMXF_ECAT_ERROR || wkcBad;
				break;
			case kSlaveDrop:
			case kWkcErrors:
				seen = wkcBad || r.ecatState == ECMXF_ECAT_ERROR;
				break;
			case kStarve:
				seen = cyc.stats().lateCycles != late0;
				break;
			default:
				break;
			}
			if (seen) {
				act.detected = true;
				ks[act.kind].detectMax = std::max(ks[act.kind].detectMax, c - act.start);
				if (c - act.start > kDetectBound)
					g_fail.fail("fault seen too late (cycles after it took effect)", c - act.start,
						    act.kind);
			}
		}
		lastWkcErr = r.wkcErrorCount;

		// ---- the application's reaction (outside the cyclic path) ----
		const bool healthy = !r.error && r.wkcRead && r.wkcOk && r.ecatState == ECMXF_ECAT_OP &&
				     r.inputsUpdated;
		try {
			std::uint8_t clear = 0;
			if (r.errStatus & ECMXF_ERR_SPI_CRC)
				clear |= ECMXF_ERR_SPI_CRC;
			if (r.errStatus & ECMXF_ERR_FIFO)
				clear |= ECMXF_ERR_FIFO;
			const bool fault = act.kind != kKinds && !act.ended;
			const bool refresh = !fault && r.ecatState == ECMXF_ECAT_ERROR && r.wkcRead && r.wkcOk;
			if (clear || refresh) {
				ecmxf::InfoUpdateOptions io;
				io.clearErrorBits = clear;
				io.refreshEcatState = refresh;
				(void)dev.chip().infoUpdate(io);
				if (clear)
					errClears++;
				if (refresh) {
					refreshes++;
					if (act.kind != kKinds)
						ks[act.kind].appActions++;
				}
			}
			// still not back long after the fault ended (slaves left OP,
			// e.g. their SM watchdog expired): request OP again
			if (act.ended && !healthy && c - act.endCycle >= 32 && (c - act.endCycle) % 64 == 0) {
				ks[act.kind].appActions++;
				stateSets++;
				dev.bus().stateSet(ecmxf::kAllSlaves, ecmxf::State::Op);
			}
		} catch (const ecmxf::Error &) {
			// the next cycle reports what is wrong
		}

		// ---- recovery ----
		if (recovering && act.ended) {
			KindStats &k = ks[act.kind];
			if (healthy && c > act.endCycle) {
				const auto t = static_cast<std::uint64_t>((chip.now() - act.endTime).count());
				k.recovered++;
				k.recSum += t;
				k.recMax = std::max(k.recMax, t);
				k.recMin = std::min(k.recMin, t);
				if (act.detected)
					k.detected++;
				else if (act.lossy || act.kind >= kSilent) {
					k.undetected++;
					g_fail.fail("fault not seen by the application", 0);
					std::printf("     kind: %s, started at cycle %" PRIu64 "\n", kKindName[act.kind],
						    act.start);
				} else {
					k.absorbed++; // a bit error the engine's retry absorbed, nothing lost
				}
				if (o.verbose)
					std::printf("cycle %" PRIu64 ": recovered after %" PRIu64 " us%s\n", c, t / 1000,
						    act.detected ? "" : " (not seen)");
				recovering = false;
				act = Active{};
				nextFault = c + sched.range(200, 3000);
			} else if (c - act.endCycle > kRecoverBound) {
				k.notRecovered++;
				g_fail.fail("no recovery", kRecoverBound);
				std::printf("     kind: %s, started at cycle %" PRIu64 ", last result error %d \"%s\", "
					    "state 0x%02x, wkc %u/%u\n",
					    kKindName[act.kind], act.start, r.error, r.message, r.ecatState, r.wkc,
					    r.expectedWkc);
				recovering = false;
				act = Active{};
				nextFault = c + sched.range(200, 3000);
			}
		}
		if (!o.quiet && c && c % 1'000'000 == 0) {
			const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
			std::printf("  %" PRIu64 " cycles, %.0f cycles/s, %" PRIu64 " failures\n", c, static_cast<double>(c) / s,
				    g_fail.total());
			std::fflush(stdout);
		}
	}
	const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
	const long rssEnd = maxRssKb();

	// ---- the end: drain nothing, count what is left ----
	// What is left in the FIFOs, read from the chip at the instant of its
	// counters: a response header's counts are those of when the chip built
	// it, and a bus cycle may run before the exchange that brings it ends.
	(void)dev.chip().infoUpdate();
	const ecmxf::sim::ChipStats &s = chip.stats();
	const ecmxf::sim::Chip::FifoLevels left = chip.fifoLevels();
	const std::uint64_t txPushed = s.txPushed - txBase, txDropped = s.txDropped - txDropBase;
	const std::uint64_t txCleared = s.txCleared - txClrBase, txRead = s.txRead - txReadBase;
	const std::uint64_t txLeft = left.tx;
	const std::uint64_t rxAccepted = s.rxAccepted - rxAccBase, rxCleared = s.rxCleared - rxClrBase;
	const std::uint64_t rxLeft = left.rx;
	const std::uint64_t consumed = g_tag.consumed - consumedBase;
	const std::uint64_t unreached = g_tag.poppedUnreached - unreachedBase;
	const std::uint64_t notApplied = g_tag.notApplied - notAppliedBase;
	// stamps of the frames still queued are after the last delivered one
	const std::uint64_t stampLost = in.gaps + (txBase + txPushed - in.lastStamp) - txLeft;

	std::printf("\n== frames\n");
	std::printf("outputs: %" PRIu64 " taken in by the chip (seen on the wire: %" PRIu64 "), %" PRIu64
		    " applied, %" PRIu64 " sent while the link was down, %" PRIu64 " not applied (slave not in OP), %" PRIu64 " cleared, %" PRIu64
		    " left; %" PRIu64 " refused (RxFIFO full)\n",
		    rxAccepted, fc.acceptedTotal, consumed, unreached, notApplied, rxCleared, rxLeft, s.rxRefused - base.rxRefused);
	if (rxAccepted != fc.acceptedTotal)
		g_fail.fail("output frames taken in differ from the chip's count", fc.acceptedTotal,
			    rxAccepted);
	if (rxAccepted != consumed + unreached + notApplied + rxCleared + rxLeft)
		g_fail.fail("output frames not accounted for", rxAccepted,
			    consumed + unreached + notApplied + rxCleared + rxLeft);
	std::printf("inputs:  %" PRIu64 " pushed by bus cycles, %" PRIu64 " delivered, %" PRIu64
		    " dropped (TxFIFO full; application's estimate %" PRIu64 "), %" PRIu64 " cleared, %" PRIu64
		    " lost with failed answers, %" PRIu64 " left; missing stamps %" PRIu64 "\n",
		    txPushed, in.delivered, txDropped, cyc.stats().txDroppedEstimate, txCleared, lostInAnswers, txLeft,
		    stampLost);
	if (txRead != in.delivered + lostInAnswers)
		g_fail.fail("input frames read != delivered + lost in answers", txRead,
			    in.delivered + lostInAnswers);
	if (stampLost != txDropped + txCleared + lostInAnswers)
		g_fail.fail("lost input frames != counted losses", stampLost,
			    txDropped + txCleared + lostInAnswers);
	if (txPushed != txRead + txDropped + txCleared + txLeft)
		g_fail.fail("TxFIFO frames not accounted for", txPushed,
			    txRead + txDropped + txCleared + txLeft);

	std::printf("\n== faults (injected / seen / absorbed without loss / unseen; recovery in virtual time)\n");
	for (unsigned k = 0; k < kKinds; k++) {
		const KindStats &x = ks[k];
		if (!x.injected)
			continue;
		std::printf("%-18s %6" PRIu64 " injected, %6" PRIu64 " seen (within %" PRIu64
			    " cycles), %5" PRIu64 " absorbed, %" PRIu64 " unseen, %" PRIu64 " not recovered",
			    kKindName[k], x.injected, x.detected, x.detectMax, x.absorbed, x.undetected,
			    x.notRecovered);
		if (x.recovered)
			std::printf("; recovery min %.0f / mean %.0f / max %.0f us", static_cast<double>(x.recMin) / 1e3,
				    static_cast<double>(x.recSum) / static_cast<double>(x.recovered) / 1e3,
				    static_cast<double>(x.recMax) / 1e3);
		if (x.appActions)
			std::printf(" (%" PRIu64 " application actions)", x.appActions);
		// the run may end while the last fault is on or recovering
		const std::uint64_t open = act.kind == k ? 1 : 0;
		if (open)
			std::printf("; 1 still under way at the end");
		std::printf("\n");
		if (x.injected != x.detected + x.absorbed + x.undetected + x.notRecovered + open)
			g_fail.fail("faults not accounted for", x.injected,
				    x.detected + x.absorbed + x.undetected + x.notRecovered + open);
	}
	std::printf("random bit errors: %" PRIu64 " MOSI, %" PRIu64 " MISO packets corrupted in all\n", fc.mosiErrors,
		    fc.misoErrors);

	const ecmxf::CyclicStats &cs = cyc.stats();
	std::printf("\n== cycles\n");
	std::printf("%" PRIu64 " cycles in %.1f s: %.0f cycles/s (%.1f x real time); %" PRIu64
		    " failed, %" PRIu64 " late, %" PRIu64 " WKC mismatches, %" PRIu64
		    " with TxFIFO overflow, %" PRIu64 " RxFIFO refusals\n",
		    cs.cycles, wall, static_cast<double>(cs.cycles) / wall,
		    static_cast<double>(cs.cycles) * static_cast<double>(period.count()) * 1e-9 / wall, cs.failedCycles, cs.lateCycles, cs.wkcMismatches,
		    overflowCycles, cs.rxRefusals);
	std::printf("application actions: %" PRIu64 " state refreshes, %" PRIu64 " error-bit clears, %" PRIu64
		    " OP requests\n",
		    refreshes, errClears, stateSets);
	std::printf("allocations on the cyclic path: %" PRIu64 " (in %" PRIu64 " cycles)\n", allocs, allocCycles);
	std::printf("max RSS: %ld kB before set-up, %ld kB at the first cycle, %ld kB at the end\n", rss0, rssStart,
		    rssEnd);
	if (allocs)
		g_fail.fail("allocation on the cyclic path", allocs);
	// flat: the whole run may not grow the peak by more than 1 MiB
	if (rssEnd - rssStart > 1024)
		g_fail.fail("memory grew during the run", static_cast<std::uint64_t>(rssStart),
			    static_cast<std::uint64_t>(rssEnd));
	std::printf("cycles with an error: %" PRIu64 ", with input frames lost unreported: %" PRIu64 "\n", errorCycles,
		    silentLossCycles);

	std::printf("\n== invariants\n");
	if (g_fail.total() == 0) {
		std::printf("ecmxf-soak: PASS (seed %" PRIu64 ")\n", o.seed);
		return 0;
	}
	for (const auto &e : g_fail.count)
		if (e.what)
			std::printf("  %" PRIu64 " x %s\n", e.n, e.what);
	std::printf("ecmxf-soak: FAIL (seed %" PRIu64 ", replay with SOAK_SEED=%" PRIu64 ")\n", o.seed, o.seed);
	return 1;
}

} // namespace

int main(int argc, char **argv)
{
	Options o;
	for (int i = 1; i < argc; i++) {
		const std::string a = argv[i];
		const auto value = [&]() -> std::string {
			if (i + 1 >= argc) {
				std::fprintf(stderr, "ecmxf-soak: %s needs a value\n", a.c_str());
				std::exit(2);
			}
			return argv[++i];
		};
		try {
			if (a == "--cycles")
				o.cycles = std::stoull(value());
			else if (a == "--seed")
				o.seed = std::stoull(value(), nullptr, 0);
			else if (a == "--network")
				o.network = value();
			else if (a == "--bit-error-rate")
				o.bitErrorRate = std::stod(value());
			else if (a == "--period-us")
				o.period = std::chrono::microseconds(std::stoull(value()));
			else if (a == "--processing-us")
				o.processing = std::chrono::microseconds(std::stoull(value()));
			else if (a == "--inject-bug")
				g_bug = static_cast<unsigned>(std::stoul(value()));
			else if (a == "--verbose")
				o.verbose = true;
			else if (a == "--quiet")
				o.quiet = true;
			else {
				std::fprintf(stderr,
					     "usage: ecmxf-soak [--cycles N] [--seed S] [--network default|128] "
					     "[--bit-error-rate P] [--period-us US] [--processing-us US] [--verbose] [--quiet] [--inject-bug 1..4]\n");
				return 2;
			}
		} catch (const std::exception &) {
			std::fprintf(stderr, "ecmxf-soak: bad value for %s\n", a.c_str());
			return 2;
		}
	}
	try {
		return run(o);
	} catch (const std::exception &e) {
		std::fprintf(stderr, "ecmxf-soak: set-up failed: %s\n", e.what());
		return 2;
	}
}
