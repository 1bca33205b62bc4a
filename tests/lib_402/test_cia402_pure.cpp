// SPDX-License-Identifier: MIT
// The host-side CiA-402 state machine without I/O: statusword decoding by
// the appendix table, the controlword commands, the transitions 0..16 as
// data, the shortest path, and the steppers (state machine, fault reset on
// a rising edge, timeouts, PP set-point handshake, homing) against
// hand-written statusword/controlword tables.
//
// Statuswords below are built by hand from the appendix table (bits 6, 5,
// 3, 2, 1, 0) plus bit 4 (voltage enabled) and bit 9 (remote), e.g.
// SWITCHED ON = 0x23 | 0x10 | 0x200 = 0x0233.

#include <catch2/catch.hpp>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <ecmxf/model/cia402.hpp>
#include <ecmxf/error.hpp>

using namespace std::chrono_literals;
using Catch::Matchers::Equals;
using ecmxf::Cia402Command;
using ecmxf::Cia402Progress;
using ecmxf::Cia402State;
using ecmxf::Cia402Stepper;

namespace {

// statuswords with bit 4 (voltage enabled) and bit 9 (remote)
constexpr std::uint16_t kNotReady = 0x0000;
constexpr std::uint16_t kSod = 0x0250;
constexpr std::uint16_t kRtso = 0x0231;
constexpr std::uint16_t kSo = 0x0233;
constexpr std::uint16_t kOe = 0x0237;
constexpr std::uint16_t kQsa = 0x0217;
constexpr std::uint16_t kFra = 0x021F;
constexpr std::uint16_t kFault = 0x0218;

/// One row of a walk: the statusword read, the controlword expected back
/// and the progress expected.
struct Row {
	std::uint16_t sw;
	std::uint16_t cw;
	Cia402Progress progress;
};

void walk(Cia402Stepper &s, const std::vector<Row> &rows, std::chrono::milliseconds t0 = 0ms,
	  std::uint16_t callerBits = 0)
{
	auto t = t0;
	for (std::size_t i = 0; i < rows.size(); i++) {
		INFO("row " << i << " statusword 0x" << std::hex << rows[i].sw);
		const ecmxf::Cia402Step r = s.step(rows[i].sw, t, callerBits);
		CHECK(r.controlword == rows[i].cw);
		CHECK(r.progress == rows[i].progress);
		t += 1ms;
	}
}

constexpr auto Busy = Cia402Progress::Busy;
constexpr auto Done = Cia402Progress::Done;
constexpr auto Failed = Cia402Progress::Failed;

} // namespace

TEST_CASE("cia402: statusword decoding by the appendix masks 0x4F and 0x6F", "[402][pure]")
{
	const std::vector<std::pair<std::uint16_t, std::optional<Cia402State>>> table{
		{ 0x0000, Cia402State::NotReadyToSwitchOn },
		{ 0x0020, Cia402State::NotReadyToSwitchOn }, // bit 5 is x
		{ 0x0040, Cia402State::SwitchOnDisabled },
		{ 0x0060, Cia402State::SwitchOnDisabled },
		{ 0x0250, Cia402State::SwitchOnDisabled },
		{ 0x0021, Cia402State::ReadyToSwitchOn },
		{ 0x0023, Cia402State::SwitchedOn },
		{ 0x0027, Cia402State::OperationEnabled },
		{ 0x1237, Cia402State::OperationEnabled },
		{ 0x0007, Cia402State::QuickStopActive },
		{ 0x000F, Cia402State::FaultReactionActive },
		{ 0x002F, Cia402State::FaultReactionActive },
		{ 0x0008, Cia402State::Fault },
		{ 0x0028, Cia402State::Fault },
		{ 0x2218, Cia402State::Fault },
		{ 0x0001, std::nullopt },
		{ 0x0061, std::nullopt },
		{ 0x0048, std::nullopt },
		{ 0xFFFF, std::nullopt },
	};
	for (const auto &[sw, st] : table) {
		INFO("statusword 0x" << std::hex << sw);
		CHECK(ecmxf::cia402StateFrom(sw) == st);
	}
}

TEST_CASE("cia402: the chip's state codes and the state names", "[402][pure]")
{
	using C = std::pair<Cia402State, std::uint8_t>;
	for (const auto &[st, code] : { C{ Cia402State::NotReadyToSwitchOn, 0x00 }, C{ Cia402State::SwitchOnDisabled, 0x40 },
					C{ Cia402State::ReadyToSwitchOn, 0x21 }, C{ Cia402State::SwitchedOn, 0x23 },
					C{ Cia402State::OperationEnabled, 0x27 }, C{ Cia402State::QuickStopActive, 0x07 },
					C{ Cia402State::FaultReactionActive, 0x0F }, C{ Cia402State::Fault, 0x08 } }) {
		CHECK(ecmxf::cia402StateCode(st) == code);
		CHECK(ecmxf::cia402StateFromCode(code) == st);
		// the code is the statusword pattern itself
		CHECK(ecmxf::cia402StateFrom(code) == st);
	}
	CHECK_FALSE(ecmxf::cia402StateFromCode(0x55).has_value());
	CHECK(ecmxf::cia402StateName(Cia402State::SwitchOnDisabled) == "SWITCH ON DISABLED");
	CHECK(ecmxf::cia402StateName(Cia402State::FaultReactionActive) == "FAULT REACTION ACTIVE");
	CHECK(ecmxf::cia402StateName(Cia402State::NotReadyToSwitchOn) == "NOT READY TO SWITCH ON");
}

TEST_CASE("cia402: controlword command patterns", "[402][pure]")
{
	using ecmxf::cia402Pattern;
	// CiA 402: shutdown 0xxx x110, switch on 0xxx 0111, enable operation
	// 0xxx 1111, disable voltage 0xxx xx0x, quick stop 0xxx x01x, disable
	// operation 0xxx 0111, fault reset 0 -> 1 of bit 7
	CHECK(cia402Pattern(Cia402Command::Shutdown).mask == 0x87);
	CHECK(cia402Pattern(Cia402Command::Shutdown).bits == 0x06);
	CHECK(cia402Pattern(Cia402Command::SwitchOn).mask == 0x8F);
	CHECK(cia402Pattern(Cia402Command::SwitchOn).bits == 0x07);
	CHECK(cia402Pattern(Cia402Command::EnableOperation).mask == 0x8F);
	CHECK(cia402Pattern(Cia402Command::EnableOperation).bits == 0x0F);
	CHECK(cia402Pattern(Cia402Command::DisableVoltage).mask == 0x82);
	CHECK(cia402Pattern(Cia402Command::DisableVoltage).bits == 0x00);
	CHECK(cia402Pattern(Cia402Command::QuickStop).mask == 0x86);
	CHECK(cia402Pattern(Cia402Command::QuickStop).bits == 0x02);
	CHECK(cia402Pattern(Cia402Command::DisableOperation).mask == 0x8F);
	CHECK(cia402Pattern(Cia402Command::DisableOperation).bits == 0x07);
	CHECK(cia402Pattern(Cia402Command::FaultReset).mask == 0x80);
	CHECK(cia402Pattern(Cia402Command::FaultReset).bits == 0x80);
	CHECK(ecmxf::cia402CommandName(Cia402Command::EnableOperation) == "Enable Operation");
	CHECK(ecmxf::cia402CommandName(Cia402Command::FaultReset) == "Fault Reset");
}

TEST_CASE("cia402: the transitions 0..16 of the appendix as data", "[402][pure]")
{
	using S = Cia402State;
	using C = Cia402Command;
	struct T {
		unsigned n;
		std::optional<S> from;
		S to;
		std::optional<C> cmd;
	};
	const std::vector<T> want{
		{ 0, std::nullopt, S::NotReadyToSwitchOn, std::nullopt },
		{ 1, S::NotReadyToSwitchOn, S::SwitchOnDisabled, std::nullopt },
		{ 2, S::SwitchOnDisabled, S::ReadyToSwitchOn, C::Shutdown },
		{ 3, S::ReadyToSwitchOn, S::SwitchedOn, C::SwitchOn },
		{ 4, S::SwitchedOn, S::OperationEnabled, C::EnableOperation },
		{ 5, S::OperationEnabled, S::SwitchedOn, C::DisableOperation },
		{ 6, S::SwitchedOn, S::ReadyToSwitchOn, C::Shutdown },
		{ 7, S::ReadyToSwitchOn, S::SwitchOnDisabled, C::DisableVoltage },
		{ 7, S::ReadyToSwitchOn, S::SwitchOnDisabled, C::QuickStop },
		{ 8, S::OperationEnabled, S::ReadyToSwitchOn, C::Shutdown },
		{ 9, S::OperationEnabled, S::SwitchOnDisabled, C::DisableVoltage },
		{ 10, S::SwitchedOn, S::SwitchOnDisabled, C::DisableVoltage },
		{ 10, S::SwitchedOn, S::SwitchOnDisabled, C::QuickStop },
		{ 11, S::OperationEnabled, S::QuickStopActive, C::QuickStop },
		{ 12, S::QuickStopActive, S::SwitchOnDisabled, std::nullopt },
		{ 12, S::QuickStopActive, S::SwitchOnDisabled, C::DisableVoltage },
		{ 13, std::nullopt, S::FaultReactionActive, std::nullopt },
		{ 14, S::FaultReactionActive, S::Fault, std::nullopt },
		{ 15, S::Fault, S::SwitchOnDisabled, C::FaultReset },
		{ 16, S::QuickStopActive, S::OperationEnabled, C::EnableOperation },
	};
	REQUIRE(ecmxf::kCia402Transitions.size() == want.size());
	for (std::size_t i = 0; i < want.size(); i++) {
		INFO("row " << i << " transition " << want[i].n);
		const ecmxf::Cia402Transition &t = ecmxf::kCia402Transitions[i];
		CHECK(t.number == want[i].n);
		CHECK(t.from == want[i].from);
		CHECK(t.to == want[i].to);
		CHECK(t.command == want[i].cmd);
	}
}

TEST_CASE("cia402: the next command on the shortest legal path, for every state and target", "[402][pure]")
{
	using S = Cia402State;
	using C = Cia402Command;
	const S targets[] = { S::SwitchOnDisabled, S::ReadyToSwitchOn, S::SwitchedOn, S::OperationEnabled,
			      S::QuickStopActive };
	using O = std::optional<C>;
	const O none;
	// rows: from; columns: the targets above
	const std::vector<std::pair<S, std::vector<O>>> table{
		{ S::NotReadyToSwitchOn, { none, none, none, none, none } },
		{ S::SwitchOnDisabled,
		  { C::DisableVoltage, C::Shutdown, C::Shutdown, C::Shutdown, C::Shutdown } },
		{ S::ReadyToSwitchOn,
		  { C::DisableVoltage, C::Shutdown, C::SwitchOn, C::SwitchOn, C::SwitchOn } },
		{ S::SwitchedOn,
		  { C::DisableVoltage, C::Shutdown, C::SwitchOn, C::EnableOperation, C::EnableOperation } },
		{ S::OperationEnabled,
		  { C::DisableVoltage, C::Shutdown, C::DisableOperation, C::EnableOperation, C::QuickStop } },
		// not through OPERATION ENABLED unless it is the target
		{ S::QuickStopActive,
		  { C::DisableVoltage, C::DisableVoltage, C::DisableVoltage, C::EnableOperation, C::QuickStop } },
		{ S::FaultReactionActive, { none, none, none, none, none } },
		{ S::Fault, { C::FaultReset, C::FaultReset, C::FaultReset, C::FaultReset, C::FaultReset } },
	};
	for (const auto &[from, cmds] : table) {
		for (std::size_t i = 0; i < 5; i++) {
			INFO(ecmxf::cia402StateName(from) << " -> " << ecmxf::cia402StateName(targets[i]));
			const O got = ecmxf::cia402NextCommand(from, targets[i]);
			// Disable Operation and Switch On are one pattern
			if (cmds[i] && got)
				CHECK(ecmxf::cia402Controlword(*got) == ecmxf::cia402Controlword(*cmds[i]));
			else
				CHECK(got == cmds[i]);
		}
	}
	CHECK_FALSE(ecmxf::cia402NextCommand(S::SwitchOnDisabled, S::Fault).has_value());
}

TEST_CASE("cia402 stepper: SWITCH ON DISABLED to OPERATION ENABLED by transitions 2, 3, 4", "[402][pure]")
{
	Cia402Stepper s(1);
	CHECK(s.progress() == Cia402Progress::Idle);
	CHECK(s.step(kSod, 0ms).controlword == 0x0000); // idle: Disable Voltage
	s.request(Cia402State::OperationEnabled, 0ms);
	walk(s, {
			{ kSod, 0x0006, Busy },  // 2 Shutdown
			{ kSod, 0x0006, Busy },  // not yet
			{ kRtso, 0x0007, Busy }, // 3 Switch On
			{ kSo, 0x000F, Busy },   // 4 Enable Operation
			{ kOe, 0x000F, Done },   // held
			{ kOe, 0x000F, Done },
		});
	CHECK(s.state() == Cia402State::OperationEnabled);
	CHECK(s.failureMessage().empty());
}

TEST_CASE("cia402 stepper: transitions 1 and 14 are waited for with Disable Voltage", "[402][pure]")
{
	Cia402Stepper s(0);
	s.request(Cia402State::SwitchOnDisabled, 0ms);
	walk(s, {
			{ kNotReady, 0x0000, Busy }, // 1 is automatic
			{ kSod, 0x0000, Done },
		});
	Cia402Stepper f(0);
	f.request(Cia402State::OperationEnabled, 0ms);
	walk(f, {
			{ kFra, 0x0000, Busy }, // 14 is automatic; bit 7 = 0
			{ kFault, 0x0000, Busy }, // 15: bit 7 = 0 first
			{ kFault, 0x0080, Busy }, // then the rising edge
			{ kSod, 0x0006, Busy },
		});
}

TEST_CASE("cia402 stepper: every commanded transition, one step each", "[402][pure]")
{
	using S = Cia402State;
	struct Case {
		unsigned transition;
		std::uint16_t before;
		S target;
		std::uint16_t cw;
		std::uint16_t after;
	};
	// transition, statusword before, target, controlword written,
	// statusword after
	const std::vector<Case> cases{
		{ 2, kSod, S::ReadyToSwitchOn, 0x0006, kRtso },
		{ 3, kRtso, S::SwitchedOn, 0x0007, kSo },
		{ 4, kSo, S::OperationEnabled, 0x000F, kOe },
		{ 5, kOe, S::SwitchedOn, 0x0007, kSo },
		{ 6, kSo, S::ReadyToSwitchOn, 0x0006, kRtso },
		{ 7, kRtso, S::SwitchOnDisabled, 0x0000, kSod },
		{ 8, kOe, S::ReadyToSwitchOn, 0x0006, kRtso },
		{ 9, kOe, S::SwitchOnDisabled, 0x0000, kSod },
		{ 10, kSo, S::SwitchOnDisabled, 0x0000, kSod },
		{ 11, kOe, S::QuickStopActive, 0x0002, kQsa },
		{ 12, kQsa, S::SwitchOnDisabled, 0x0000, kSod },
		{ 16, kQsa, S::OperationEnabled, 0x000F, kOe },
	};
	for (const Case &c : cases) {
		INFO("transition " << c.transition);
		Cia402Stepper s(3);
		s.request(c.target, 0ms);
		walk(s, { { c.before, c.cw, Busy }, { c.after, c.cw, Done } });
		// the row of the table this is
		bool found = false;
		for (const ecmxf::Cia402Transition &t : ecmxf::kCia402Transitions)
			if (t.number == c.transition && t.command &&
			    ecmxf::cia402Controlword(*t.command) == c.cw &&
			    t.from == ecmxf::cia402StateFrom(c.before) && t.to == ecmxf::cia402StateFrom(c.after))
				found = true;
		CHECK(found);
	}
	// 7 and 10 by Quick Stop: the pattern 0xxx x01x leads there too
	for (const ecmxf::Cia402Transition &t : ecmxf::kCia402Transitions)
		if ((t.number == 7 || t.number == 10) && t.command == Cia402Command::QuickStop)
			CHECK((0x0002 & ecmxf::cia402Pattern(*t.command).mask) == ecmxf::cia402Pattern(*t.command).bits);
}

TEST_CASE("cia402 stepper: a walk down from OPERATION ENABLED and the path from QUICK STOP ACTIVE", "[402][pure]")
{
	Cia402Stepper s(1);
	s.request(Cia402State::SwitchedOn, 0ms);
	walk(s, { { kOe, 0x0007, Busy }, { kSo, 0x0007, Done } });
	Cia402Stepper q(1);
	q.request(Cia402State::SwitchedOn, 0ms);
	// not back through OPERATION ENABLED: 12, 2, 3
	walk(q, {
			{ kQsa, 0x0000, Busy },
			{ kSod, 0x0006, Busy },
			{ kRtso, 0x0007, Busy },
			{ kSo, 0x0007, Done },
		});
}

TEST_CASE("cia402 stepper: the caller's bits 4-6 and 8-15 are kept, 0-3 and 7 are the stepper's", "[402][pure]")
{
	Cia402Stepper s(1);
	s.request(Cia402State::OperationEnabled, 0ms);
	walk(s, { { kSod, 0xFF76, Busy }, { kRtso, 0xFF77, Busy }, { kSo, 0xFF7F, Busy }, { kOe, 0xFF7F, Done } }, 0ms,
	     0xFFFF);
	Cia402Stepper f(1);
	f.request(Cia402State::SwitchOnDisabled, 0ms);
	walk(f, { { kFault, 0x0170, Busy }, { kFault, 0x01F0, Busy }, { kSod, 0x0170, Done } }, 0ms, 0x0170);
}

TEST_CASE("cia402 stepper: fault reset is a rising edge of bit 7, held until FAULT is left", "[402][pure]")
{
	Cia402Stepper s(2);
	s.request(Cia402State::OperationEnabled, 0ms);
	walk(s, {
			{ kOe, 0x000F, Done },
		});
	s.request(Cia402State::OperationEnabled, 1ms); // there, but the next statusword decides
	CHECK(s.progress() == Busy);
	walk(s, { { kOe, 0x000F, Done } }, 1ms);

	// a fault during a walk (13, 14) is reset on the way
	Cia402Stepper w(2);
	w.request(Cia402State::OperationEnabled, 0ms);
	walk(w, {
			{ kSod, 0x0006, Busy },
			{ kFra, 0x0000, Busy },   // 13: reaction, bit 7 = 0
			{ kFault, 0x0000, Busy }, // bit 7 = 0 first even so
			{ kFault, 0x0080, Busy }, // 0 -> 1
			{ kFault, 0x0080, Busy }, // held: the drive decides
			{ kFault, 0x0080, Busy },
			{ kSod, 0x0006, Busy },   // 15 done: bit 7 back to 0
			{ kRtso, 0x0007, Busy },
			{ kSo, 0x000F, Busy },
			{ kOe, 0x000F, Done },
		});
}

TEST_CASE("cia402 stepper: with fault reset off, FAULT fails the walk", "[402][pure]")
{
	Cia402Stepper s(4, Cia402Stepper::Options{ 1000ms, false });
	s.request(Cia402State::OperationEnabled, 0ms);
	walk(s, { { kFault, 0x0000, Failed } });
	CHECK(s.failureMessage() ==
	      "slave 4: CiA-402 drive in FAULT (statusword 0x0218) on the way to OPERATION ENABLED, and fault "
	      "reset is off");
	try {
		s.throwIfFailed();
		FAIL("no error");
	} catch (const ecmxf::Error &e) {
		CHECK(e.errnoValue() == EIO);
		CHECK_THAT(e.what(), Equals(s.failureMessage()));
	}
}

TEST_CASE("cia402 stepper: timeout names the awaited state, the state it stays in and the statusword",
	  "[402][pure]")
{
	Cia402Stepper s(1, Cia402Stepper::Options{ 500ms, true });
	s.request(Cia402State::OperationEnabled, 0ms);
	CHECK(s.step(kSo, 0ms).progress == Busy);
	CHECK(s.step(kSo, 499ms).progress == Busy);
	const ecmxf::Cia402Step r = s.step(kSo, 500ms);
	CHECK(r.progress == Failed);
	CHECK(r.controlword == 0x000F);
	CHECK(s.failureMessage() ==
	      "slave 1: CiA-402 timed out after 500 ms waiting for OPERATION ENABLED: stays in SWITCHED ON "
	      "(statusword 0x0233)");
	try {
		s.throwIfFailed();
		FAIL("no error");
	} catch (const ecmxf::Error &e) {
		CHECK(e.errnoValue() == ETIMEDOUT);
		CHECK_THAT(e.what(), Equals("slave 1: CiA-402 timed out after 500 ms waiting for OPERATION ENABLED: "
					    "stays in SWITCHED ON (statusword 0x0233)"));
	}

	// a state change restarts the time; the awaited state is the next one
	Cia402Stepper t(7, Cia402Stepper::Options{ 500ms, true });
	t.request(Cia402State::OperationEnabled, 0ms);
	CHECK(t.step(kSod, 0ms).progress == Busy);
	CHECK(t.step(kRtso, 400ms).progress == Busy);
	CHECK(t.step(kRtso, 899ms).progress == Busy);
	CHECK(t.step(kRtso, 900ms).progress == Failed);
	CHECK(t.failureMessage() ==
	      "slave 7: CiA-402 timed out after 500 ms waiting for SWITCHED ON on the way to OPERATION ENABLED: "
	      "stays in READY TO SWITCH ON (statusword 0x0231)");

	// a fault that does not go away
	Cia402Stepper f(2, Cia402Stepper::Options{ 250ms, true });
	f.request(Cia402State::OperationEnabled, 0ms);
	f.step(kFault, 0ms);
	CHECK(f.step(kFault, 1ms).controlword == 0x0080);
	CHECK(f.step(kFault, 250ms).progress == Failed);
	CHECK(f.failureMessage() ==
	      "slave 2: CiA-402 timed out after 250 ms waiting for SWITCH ON DISABLED on the way to OPERATION "
	      "ENABLED: stays in FAULT (statusword 0x0218)");
	// failed: bit 7 released
	CHECK(f.step(kFault, 251ms).controlword == 0x0000);

	// a statusword that is no state
	Cia402Stepper u(0, Cia402Stepper::Options{ 10ms, true });
	u.request(Cia402State::SwitchOnDisabled, 0ms);
	u.step(0x0001, 0ms);
	u.step(0x0001, 10ms);
	CHECK(u.failureMessage() ==
	      "slave 0: CiA-402 timed out after 10 ms waiting for SWITCH ON DISABLED: stays in no CiA-402 state "
	      "(statusword 0x0001)");
}

TEST_CASE("cia402 stepper: leaving the reached state fails the walk", "[402][pure]")
{
	Cia402Stepper s(1);
	s.request(Cia402State::OperationEnabled, 0ms);
	walk(s, { { kOe, 0x000F, Done }, { kFra, 0x000F, Failed }, { kFault, 0x000F, Failed } });
	CHECK(s.failureMessage() ==
	      "slave 1: CiA-402 drive left OPERATION ENABLED: now FAULT REACTION ACTIVE (statusword 0x021F)");
	// a new request walks again (with the fault reset)
	s.request(Cia402State::OperationEnabled, 10ms);
	walk(s, { { kFault, 0x0000, Busy }, { kFault, 0x0080, Busy }, { kSod, 0x0006, Busy } }, 10ms);
}

TEST_CASE("cia402 stepper: a drive that does not settle fails the walk", "[402][pure]")
{
	// QUICK STOP ACTIVE requested from a drive whose quick stop ends at
	// once in SWITCH ON DISABLED (0x605A not 5..8): it would go round
	Cia402Stepper s(1);
	s.request(Cia402State::QuickStopActive, 0ms);
	auto t = 0ms;
	Cia402Progress p = Busy;
	unsigned steps = 0;
	const std::uint16_t loop[] = { kSod, kRtso, kSo, kOe };
	while (p == Busy && steps < 100) {
		p = s.step(loop[steps % 4], t).progress;
		t += 1ms;
		steps++;
	}
	CHECK(p == Failed);
	CHECK(steps == 14); // the 13th state change: the first statusword is none
	CHECK(s.failureMessage() ==
	      "slave 1: CiA-402 drive does not settle on the way to QUICK STOP ACTIVE: 13 state changes, now "
	      "READY TO SWITCH ON (statusword 0x0231)");
}

TEST_CASE("cia402 stepper: only requestable states can be requested", "[402][pure]")
{
	Cia402Stepper s(5);
	for (Cia402State bad : { Cia402State::NotReadyToSwitchOn, Cia402State::FaultReactionActive, Cia402State::Fault }) {
		try {
			s.request(bad, 0ms);
			FAIL("no error");
		} catch (const ecmxf::Error &e) {
			CHECK(e.errnoValue() == EINVAL);
			CHECK_THAT(e.what(), Equals(std::string("slave 5: CiA-402: ")
							    .append(ecmxf::cia402StateName(bad))
							    .append(" cannot be requested (SWITCH ON DISABLED, READY TO "
								    "SWITCH ON, SWITCHED ON, OPERATION ENABLED or QUICK "
								    "STOP ACTIVE)")));
		}
	}
	CHECK(s.progress() == Cia402Progress::Idle);
}

// ---------------------------------------------------------------- PP

TEST_CASE("cia402 PP: the set-point handshake (bit 4 edge, bit 12 acknowledge, bit 10 target reached)",
	  "[402][pure][pp]")
{
	ecmxf::PpSetPointStepper pp(1);
	// idle: the caller's word passes
	CHECK(pp.step(0x0637, 0ms, 0x001F).controlword == 0x001F);
	pp.start(0ms);
	struct R {
		std::uint16_t sw, cw;
		Cia402Progress p;
	};
	const std::vector<R> rows{
		{ 0x0637, 0x000F, Busy }, // bit 4 = 0 first; bit 12 = 0: free
		{ 0x0637, 0x001F, Busy }, // new set-point
		{ 0x0637, 0x001F, Busy }, // not acknowledged yet
		{ 0x1237, 0x000F, Busy }, // acknowledged, moving: bit 4 back to 0
		{ 0x0237, 0x000F, Busy }, // moving
		{ 0x0637, 0x000F, Done }, // target reached
	};
	auto t = 0ms;
	for (const R &r : rows) {
		INFO("statusword 0x" << std::hex << r.sw);
		const ecmxf::Cia402Step s = pp.step(r.sw, t, 0x000F);
		CHECK(s.controlword == r.cw);
		CHECK(s.progress == r.p);
		t += 1ms;
	}
	CHECK(pp.acknowledged());
}

TEST_CASE("cia402 PP: change immediately and relative, done at the acknowledge", "[402][pure][pp]")
{
	ecmxf::PpSetPointStepper pp(1);
	ecmxf::PpSetPointStepper::Options o;
	o.changeImmediately = true;
	o.relative = true;
	o.waitTargetReached = false;
	pp.start(0ms, o);
	// with change immediately bit 12 = 1 (a buffered set-point) does not hold it
	CHECK(pp.step(0x1237, 0ms, 0x000F).controlword == 0x006F);
	CHECK(pp.step(0x1237, 1ms, 0x000F).controlword == 0x007F);
	const ecmxf::Cia402Step s = pp.step(0x1237, 2ms, 0x000F);
	CHECK(s.controlword == 0x006F);
	CHECK(s.progress == Done);
}

TEST_CASE("cia402 PP: failures name what was awaited", "[402][pure][pp]")
{
	ecmxf::PpSetPointStepper::Options o;
	o.ackTimeout = 100ms;
	{
		// EST-584: bit 14 = a movement parameter is 0, bit 15 = NOT bit 12
		ecmxf::PpSetPointStepper pp(2);
		pp.start(0ms, o);
		pp.step(0xC637, 0ms, 0x000F);
		CHECK(pp.step(0xC637, 1ms, 0x000F).controlword == 0x001F);
		CHECK(pp.step(0xC637, 99ms, 0x000F).progress == Busy);
		const ecmxf::Cia402Step s = pp.step(0xC637, 100ms, 0x000F);
		CHECK(s.progress == Failed);
		CHECK(s.controlword == 0x000F);
		CHECK(pp.failureMessage() ==
		      "slave 2: PP set-point not acknowledged within 100 ms: statusword bit 12 stays 0 (statusword "
		      "0xC637); bit 14 is set: on the EST-584 a movement parameter (0x6081, 0x6083, 0x6084) is 0");
		CHECK_THROWS_AS(pp.throwIfFailed(), ecmxf::Error);
	}
	{
		ecmxf::PpSetPointStepper pp(2);
		pp.start(0ms, o);
		pp.step(0x1237, 0ms, 0x000F);
		CHECK(pp.step(0x1237, 100ms, 0x000F).progress == Failed);
		CHECK(pp.failureMessage() == "slave 2: PP set-point: the drive takes no new set-point within 100 ms: "
					     "statusword bit 12 stays 1 (statusword 0x1237)");
	}
	{
		ecmxf::PpSetPointStepper pp(3);
		pp.start(0ms, o);
		CHECK(pp.step(0x0233, 0ms, 0x000F).progress == Failed);
		CHECK(pp.failureMessage() ==
		      "slave 3: PP set-point: the drive is in SWITCHED ON, not OPERATION ENABLED (statusword 0x0233)");
		try {
			pp.throwIfFailed();
			FAIL("no error");
		} catch (const ecmxf::Error &e) {
			CHECK(e.errnoValue() == EIO);
		}
	}
	{
		ecmxf::PpSetPointStepper pp(3);
		o.moveTimeout = 2000ms;
		pp.start(0ms, o);
		pp.step(0x0637, 0ms, 0x000F);
		pp.step(0x0637, 1ms, 0x000F);
		pp.step(0x1237, 2ms, 0x000F); // acknowledged
		CHECK(pp.step(0x0237, 2001ms, 0x000F).progress == Busy);
		CHECK(pp.step(0x0237, 2002ms, 0x000F).progress == Failed);
		CHECK(pp.failureMessage() == "slave 3: PP target not reached within 2000 ms after the set-point "
					     "acknowledge (statusword 0x0237)");
	}
}

// ---------------------------------------------------------------- HM

TEST_CASE("cia402 HM: homing status of bits 13, 12, 10", "[402][pure][hm]")
{
	using H = ecmxf::HomingStatus;
	CHECK(ecmxf::homingStatus(0x0237) == H::InProgress);
	CHECK(ecmxf::homingStatus(0x0637) == H::InterruptedOrIdle);
	CHECK(ecmxf::homingStatus(0x1237) == H::AttainedNotReached);
	CHECK(ecmxf::homingStatus(0x1637) == H::Completed);
	CHECK(ecmxf::homingStatus(0x2237) == H::ErrorMoving);
	CHECK(ecmxf::homingStatus(0x2637) == H::ErrorStopped);
	CHECK(ecmxf::homingStatusName(H::InterruptedOrIdle) == "homing interrupted or not started");
}

TEST_CASE("cia402 HM: start edge, attained and target reached, an earlier result is not taken", "[402][pure][hm]")
{
	ecmxf::HomingStepper hm(1);
	hm.start(0ms);
	struct R {
		std::uint16_t sw, cw;
		Cia402Progress p;
	};
	const std::vector<R> rows{
		{ 0x1637, 0x000F, Busy }, // an earlier homing completed; bit 4 = 0 first
		{ 0x1637, 0x001F, Busy }, // start; this statusword is older than the edge
		{ 0x0237, 0x001F, Busy }, // in progress
		{ 0x1237, 0x001F, Busy }, // attained, still moving
		{ 0x1637, 0x000F, Done }, // completed: bit 4 released
	};
	auto t = 0ms;
	for (const R &r : rows) {
		INFO("statusword 0x" << std::hex << r.sw);
		const ecmxf::Cia402Step s = hm.step(r.sw, t, 0x000F);
		CHECK(s.controlword == r.cw);
		CHECK(s.progress == r.p);
		t += 1ms;
	}
}

TEST_CASE("cia402 HM: homing error and timeout", "[402][pure][hm]")
{
	ecmxf::HomingStepper hm(1);
	hm.start(0ms);
	hm.step(0x0637, 0ms, 0x000F);
	hm.step(0x0637, 1ms, 0x000F);
	CHECK(hm.step(0x2637, 2ms, 0x000F).progress == Failed);
	CHECK(hm.failureMessage() == "slave 1: homing failed: homing error, velocity 0 (statusword 0x2637)");

	ecmxf::HomingStepper t(4);
	t.start(0ms, ecmxf::HomingStepper::Options{ 5000ms, 1 });
	t.step(0x0637, 0ms, 0x000F);
	t.step(0x0637, 1ms, 0x000F);
	CHECK(t.step(0x0637, 4999ms, 0x000F).progress == Busy);
	CHECK(t.step(0x0637, 5000ms, 0x000F).progress == Failed);
	CHECK(t.failureMessage() ==
	      "slave 4: homing timed out after 5000 ms: homing interrupted or not started (statusword 0x0637)");
	try {
		t.throwIfFailed();
		FAIL("no error");
	} catch (const ecmxf::Error &e) {
		CHECK(e.errnoValue() == ETIMEDOUT);
	}

	ecmxf::HomingStepper n(0);
	n.start(0ms);
	CHECK(n.step(0x0250, 0ms, 0x0000).progress == Failed);
	CHECK(n.failureMessage() ==
	      "slave 0: homing: the drive is in SWITCH ON DISABLED, not OPERATION ENABLED (statusword 0x0250)");
}
