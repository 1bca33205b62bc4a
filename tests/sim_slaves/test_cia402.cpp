// SPDX-License-Identifier: MIT
// The CiA-402 state machine of the drive models against the ECM-XF
// manual's appendix 1: every state x every controlword command, the
// statusword bits 0..3, 5, 6 of each state, and fault reset on the rising
// edge of controlword bit 7.

#include "helpers.hpp"

#include <array>

using namespace th;
using ecmxf::sim::Cia402Model;

namespace {

enum St { NRTSO, SOD, RTSO, SO, OE, QSA, FRA, FLT, kStates };
const char *const kNames[] = { "Not ready to switch on", "Switch on disabled",
			       "Ready to switch on",     "Switched on",
			       "Operation enabled",      "Quick stop active",
			       "Fault reaction active",  "Fault" };

// Appendix 1: status word bits 6, 5, 3, 2, 1, 0 of each state.
constexpr std::uint16_t kStateBits[kStates] = { 0x00, 0x40, 0x21, 0x23, 0x27, 0x07, 0x0F, 0x08 };

St stateOf(std::uint16_t sw)
{
	for (int s = 0; s < kStates; s++)
		if ((sw & 0x6F) == kStateBits[s])
			return static_cast<St>(s);
	FAIL("statusword 0x" << std::hex << sw << " is no CiA-402 state");
	return kStates;
}

// Controlword commands (CiA 402; bit 7 = fault reset).
struct Cmd {
	const char *name;
	std::uint16_t cw;
};
constexpr Cmd kCmds[] = {
	{ "Shutdown", 0x06 },       { "Switch on / disable operation", 0x07 },
	{ "Enable operation", 0x0F }, { "Disable voltage", 0x00 },
	{ "Quick stop", 0x02 },     { "Fault reset (rising edge)", 0x80 },
};
constexpr int kNumCmds = 6;

// The transitions of the appendix, per state and command (kCmds order).
constexpr St kNext[kStates][kNumCmds] = {
	/* NRTSO: 1 (automatic)   */ { SOD, SOD, SOD, SOD, SOD, SOD },
	/* SOD:   2               */ { RTSO, SOD, SOD, SOD, SOD, SOD },
	/* RTSO:  3, 3+4, 7, 7    */ { RTSO, SO, OE, SOD, SOD, RTSO },
	/* SO:    6, 4, 10, 10    */ { RTSO, SO, OE, SOD, SOD, SO },
	/* OE:    8, 5, 9, 11     */ { RTSO, SO, OE, SOD, QSA, OE },
	/* QSA:   16, 12          */ { QSA, QSA, OE, SOD, QSA, QSA },
	/* FRA:   (14 when done)  */ { FRA, FRA, FRA, FRA, FRA, FRA },
	/* Fault: 15              */ { FLT, FLT, FLT, FLT, FLT, SOD },
};

struct DriveType {
	const char *type;
	std::int8_t movingMode; // a mode in which the motor moves by a target velocity
};
constexpr DriveType kDrives[] = { { "EST-584", 3 /* PV */ }, { "servo", 9 /* CSV */ } };

class Bench
{
public:
	explicit Bench(const DriveType &t) : s(make(t.type)), type(t)
	{
		d = dynamic_cast<Cia402Model *>(s.get());
		REQUIRE(d);
	}

	void cw(std::uint16_t v) { REQUIRE(write<std::uint16_t>(*s, 0x6040, 0, v) == 0); }
	void step() { s->idle(1ms); }
	[[nodiscard]] St state() const { return stateOf(d->statusword()); }

	// Power-on, PRE-OP, then walk the drive into @p target.
	void reachState(St target)
	{
		reach(*s, ecmxf::sim::AlState::PreOp);
		REQUIRE(state() == NRTSO);
		if (target == NRTSO)
			return;
		step();
		REQUIRE(state() == SOD);
		if (target == SOD)
			return;
		if (target == FRA) {
			// moving, with a slow fault reaction ramp
			REQUIRE(write<std::int8_t>(*s, 0x6060, 0, type.movingMode) == 0);
			REQUIRE(write<std::int32_t>(*s, 0x60FF, 0, 100000) == 0);
			REQUIRE(write<std::uint32_t>(*s, 0x6085, 0, 1000) == 0);
		}
		cw(0x06);
		step();
		REQUIRE(state() == RTSO);
		if (target == RTSO)
			return;
		cw(0x07);
		step();
		REQUIRE(state() == SO);
		if (target == SO)
			return;
		cw(0x0F);
		step();
		REQUIRE(state() == OE);
		if (target == OE)
			return;
		if (target == QSA) {
			cw(0x02);
			step();
			REQUIRE(state() == QSA);
			return;
		}
		if (target == FRA) {
			for (int i = 0; i < 50; i++)
				step();
			REQUIRE(d->velocityActual() != 0);
			d->injectFault(0x5530);
			REQUIRE(state() == FRA);
			return;
		}
		d->injectFault(0x5530); // standing still: the reaction is immediate
		step();
		REQUIRE(state() == FLT);
	}

	std::unique_ptr<Slave> s;
	Cia402Model *d = nullptr;
	DriveType type;
};

} // namespace

TEST_CASE("CiA-402: statusword bits of every state are the appendix's")
{
	for (const DriveType &t : kDrives) {
		Bench b(t);
		for (int st = 0; st < kStates; st++) {
			INFO(t.type << ": " << kNames[st]);
			b.reachState(static_cast<St>(st));
			CHECK((b.d->statusword() & 0x6F) == kStateBits[st]);
			CHECK((read<std::uint16_t>(*b.s, 0x6041, 0) & 0x6F) == kStateBits[st]);
		}
	}
}

TEST_CASE("CiA-402: every state x every controlword command follows the appendix transitions")
{
	for (const DriveType &t : kDrives) {
		Bench b(t);
		for (int st = 0; st < kStates; st++) {
			for (int c = 0; c < kNumCmds; c++) {
				INFO(t.type << ": " << kNames[st] << " + " << kCmds[c].name);
				b.reachState(static_cast<St>(st));
				b.cw(kCmds[c].cw);
				b.step();
				CHECK(kNames[b.state()] == std::string(kNames[kNext[st][c]]));
			}
		}
	}
}

TEST_CASE("CiA-402: fault reset acts on the rising edge of controlword bit 7 only")
{
	for (const DriveType &t : kDrives) {
		INFO(t.type);
		Bench b(t);
		b.reachState(OE);
		while (b.s->popEmergency()) {
		}
		b.cw(0x80); // bit 7 already high when the fault comes
		b.step();
		b.d->injectFault(0x7300);
		b.step();
		REQUIRE(b.state() == FLT);
		CHECK(b.d->errorCode() == 0x7300);
		CHECK(read<std::uint16_t>(*b.s, 0x603F, 0) == 0x7300);
		CHECK((read<std::uint8_t>(*b.s, 0x1001, 0) & 0x01) == 0x01);
		auto e = b.s->popEmergency();
		REQUIRE(e);
		CHECK(e->errorCode == 0x7300);
		CHECK((e->errorRegister & 0x01) == 0x01);
		b.step(); // held high: no edge
		CHECK(b.state() == FLT);
		b.cw(0x00);
		b.step();
		CHECK(b.state() == FLT);
		b.cw(0x80); // rising edge: transition 15
		b.step();
		CHECK(b.state() == SOD);
		CHECK(b.d->errorCode() == 0);
		CHECK(read<std::uint8_t>(*b.s, 0x1001, 0) == 0);
		e = b.s->popEmergency();
		REQUIRE(e);
		CHECK(e->errorCode == 0x0000); // "error reset"
		// and on through 2, 3, 4 again
		b.cw(0x06);
		b.step();
		b.cw(0x0F);
		b.step();
		CHECK(b.state() == OE);
	}
}

TEST_CASE("CiA-402: fault reaction ramps down with 0x6085, then Fault (transition 14)")
{
	for (const DriveType &t : kDrives) {
		INFO(t.type);
		Bench b(t);
		b.reachState(FRA);
		const auto v0 = b.d->velocityActual();
		b.step();
		CHECK(std::abs(b.d->velocityActual()) < std::abs(v0));
		REQUIRE(write<std::uint32_t>(*b.s, 0x6085, 0, 100'000'000) == 0);
		b.step();
		CHECK(b.d->velocityActual() == 0);
		CHECK(b.state() == FLT);
	}
}

TEST_CASE("CiA-402: quick stop with option 5 ramps down and stays, other options stop and disable")
{
	Bench b(kDrives[0]);
	b.reachState(OE);
	REQUIRE(write<std::int8_t>(*b.s, 0x6060, 0, 3) == 0);
	REQUIRE(write<std::int32_t>(*b.s, 0x60FF, 0, 50000) == 0);
	for (int i = 0; i < 200; i++)
		b.step();
	REQUIRE(b.d->velocityActual() == 50000);
	REQUIRE(write<std::uint32_t>(*b.s, 0x6085, 0, 1'000'000) == 0);
	b.cw(0x02);
	b.step();
	CHECK(b.state() == QSA);
	CHECK(b.d->velocityActual() == 49000); // 1e6/s^2 for 1 ms
	CHECK((b.d->statusword() & 0x0100) != 0); // EST-584 bit 8: abnormal stop
	for (int i = 0; i < 100; i++)
		b.step();
	CHECK(b.d->velocityActual() == 0);
	CHECK(b.state() == QSA);

	b.cw(0x0F); // transition 16
	b.step();
	REQUIRE(b.state() == OE);
	REQUIRE(write<std::int16_t>(*b.s, 0x605A, 0, 0) == 0);
	b.cw(0x02);
	b.step();
	CHECK(b.state() == SOD); // stop at once, transition 12
}
