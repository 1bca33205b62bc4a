// SPDX-License-Identifier: MIT
//
// cia402.cpp - the host-side CiA-402 state machine: the shortest legal
// path to a requested state, the steppers for the state machine, the PP
// set-point handshake and homing (Documentation/cia402.rst).

#include <ecmxf/model/cia402.hpp>

#include <cerrno>
#include <cstdio>

#include <ecmxf/error.hpp>

#include "base/text.hpp"

namespace ecmxf {

namespace {

using std::chrono::nanoseconds;

constexpr std::size_t kStates = 8;

std::size_t idx(Cia402State s)
{
	return static_cast<std::size_t>(s);
}

/// "500 ms", "250 us", "17 ns"
std::string formatDuration(nanoseconds d)
{
	const auto ns = d.count();
	std::string s;
	if (ns % 1'000'000 == 0)
		s.append(std::to_string(ns / 1'000'000)).append(" ms");
	else if (ns % 1'000 == 0)
		s.append(std::to_string(ns / 1'000)).append(" us");
	else
		s.append(std::to_string(ns)).append(" ns");
	return s;
}

std::string stateText(std::optional<Cia402State> s)
{
	return s ? std::string(cia402StateName(*s)) : std::string("no CiA-402 state");
}

/// "<what>: the drive is in <state>, not OPERATION ENABLED (statusword
/// 0x....)": why a PP set-point or a homing run cannot start.
std::string notEnabledText(std::string_view what, std::uint16_t statusword)
{
	std::string m(what);
	m.append(": the drive is in ")
		.append(stateText(cia402StateFrom(statusword)))
		.append(", not OPERATION ENABLED (statusword ")
		.append(cia402Hex16(statusword))
		.append(")");
	return m;
}

std::string slaveText(unsigned slave)
{
	std::string s("slave ");
	s.append(std::to_string(slave)).append(": ");
	return s;
}

/// What a PP set-point and a homing step do first: false when the run is
/// idle (nothing to do); a busy run keeps @p statusword in @p kept (for the
/// failure message) and fails with Why::NotEnabled unless the drive is in
/// OPERATION ENABLED.
template <typename Why>
bool handshakeStep(Cia402Progress &progress, Why &why, std::uint16_t &kept, std::uint16_t statusword) noexcept
{
	if (progress == Cia402Progress::Idle)
		return false;
	if (progress == Cia402Progress::Busy) {
		kept = statusword; // kept from the failure on
		if (cia402StateFrom(statusword) != Cia402State::OperationEnabled) {
			progress = Cia402Progress::Failed;
			why = Why::NotEnabled;
		}
	}
	return true;
}

/// The failure message of a PP set-point or homing run ("" unless it
/// failed): "slave N: ", then notEnabledText(@p what) for Why::NotEnabled,
/// else what @p reason appends for the other reasons, given the statusword
/// in hex.
template <typename Why, typename Reason>
std::string handshakeFailure(Cia402Progress progress, unsigned slave, std::string_view what, Why why,
			     std::uint16_t statusword, Reason reason)
{
	if (progress != Cia402Progress::Failed)
		return {};
	std::string m = slaveText(slave);
	if (why == Why::NotEnabled)
		m.append(notEnabledText(what, statusword));
	else
		reason(m, cia402Hex16(statusword));
	return m;
}

/// The state a command leads to from @p from (the first row of the table).
std::optional<Cia402State> leadsTo(Cia402State from, Cia402Command c)
{
	// Switch On and Disable Operation have one pattern
	for (const Cia402Transition &t : kCia402Transitions) {
		if (!t.from || *t.from != from || !t.command)
			continue;
		const Cia402CommandPattern a = cia402Pattern(*t.command);
		const Cia402CommandPattern b = cia402Pattern(c);
		if (a.mask == b.mask && a.bits == b.bits)
			return t.to;
	}
	return std::nullopt;
}

/// The command that keeps a drive in @p s.
std::optional<Cia402Command> holdCommand(Cia402State s)
{
	switch (s) {
	case Cia402State::SwitchOnDisabled:
		return Cia402Command::DisableVoltage;
	case Cia402State::ReadyToSwitchOn:
		return Cia402Command::Shutdown;
	case Cia402State::SwitchedOn:
		return Cia402Command::SwitchOn;
	case Cia402State::OperationEnabled:
		return Cia402Command::EnableOperation;
	case Cia402State::QuickStopActive:
		return Cia402Command::QuickStop;
	default:
		return std::nullopt;
	}
}

} // namespace

std::string cia402Hex16(std::uint16_t v)
{
	char buf[8];
	std::snprintf(buf, sizeof(buf), "0x%04X", static_cast<unsigned>(v));
	return buf;
}

std::optional<Cia402Command> cia402NextCommand(Cia402State from, Cia402State target) noexcept
{
	if (!cia402Requestable(target))
		return std::nullopt;
	if (from == Cia402State::Fault)
		return Cia402Command::FaultReset;
	if (from == Cia402State::NotReadyToSwitchOn || from == Cia402State::FaultReactionActive)
		return std::nullopt;
	if (from == target)
		return holdCommand(from);

	// breadth-first search over the command rows of the table, in table
	// order (so Disable Voltage comes before Quick Stop), never through
	// OPERATION ENABLED unless it is the target
	std::array<std::optional<Cia402Command>, kStates> first{};
	std::array<bool, kStates> seen{};
	std::array<Cia402State, kStates> queue{};
	std::size_t head = 0, tail = 0;
	queue[tail++] = from;
	seen[idx(from)] = true;
	while (head < tail) {
		const Cia402State s = queue[head++];
		if (s == target)
			return first[idx(s)];
		if (s == Cia402State::OperationEnabled && s != from && target != Cia402State::QuickStopActive)
			continue; // QUICK STOP ACTIVE is reached only from there
		for (const Cia402Transition &t : kCia402Transitions) {
			if (!t.from || *t.from != s || !t.command || *t.command == Cia402Command::FaultReset)
				continue;
			if (seen[idx(t.to)])
				continue;
			seen[idx(t.to)] = true;
			first[idx(t.to)] = s == from ? t.command : first[idx(s)];
			queue[tail++] = t.to;
		}
	}
	return std::nullopt;
}

// ---------------------------------------------------------------- Cia402Stepper

Cia402Stepper::Cia402Stepper(unsigned slave) : Cia402Stepper(slave, Options{}) {}

Cia402Stepper::Cia402Stepper(unsigned slave, Options options) : slave_(slave), opt_(options) {}

void Cia402Stepper::request(Cia402State target, nanoseconds now)
{
	if (!cia402Requestable(target)) {
		std::string m = slaveText(slave_);
		m.append("CiA-402: ")
			.append(cia402StateName(target))
			.append(" cannot be requested (SWITCH ON DISABLED, READY TO SWITCH ON, SWITCHED ON, "
				"OPERATION ENABLED or QUICK STOP ACTIVE)");
		throw Error(m, EINVAL);
	}
	target_ = target;
	progress_ = Cia402Progress::Busy;
	since_ = now;
	changes_ = 0;
	why_ = Why::None;
	awaited_.reset();
	// the state seen last may be old: the next step decides
}

Cia402Step Cia402Stepper::step(std::uint16_t statusword, nanoseconds now, std::uint16_t controlword) noexcept
{
	const std::optional<Cia402State> st = cia402StateFrom(statusword);
	statusword_ = statusword;
	if (!seen_ || st != state_) {
		if (seen_ && progress_ == Cia402Progress::Busy) {
			since_ = now;
			changes_++;
		}
		state_ = st;
		seen_ = true;
	}

	auto fail = [&](Why why) {
		progress_ = Cia402Progress::Failed;
		why_ = why;
		failSw_ = statusword;
		failState_ = st;
	};

	if (progress_ == Cia402Progress::Done && st != target_)
		fail(Why::Left);
	if (progress_ == Cia402Progress::Busy && st == target_)
		progress_ = Cia402Progress::Done;
	if (progress_ == Cia402Progress::Busy && changes_ > kMaxChanges)
		fail(Why::Unstable);
	if (progress_ == Cia402Progress::Busy && st == Cia402State::Fault && !opt_.faultReset)
		fail(Why::FaultNoReset);
	if (progress_ == Cia402Progress::Busy && now - since_ >= opt_.timeout)
		fail(Why::Timeout);

	std::uint16_t bits = lastBits_;
	if (progress_ == Cia402Progress::Idle) {
		bits = 0; // Disable Voltage until something is requested
	} else if (progress_ == Cia402Progress::Failed) {
		bits = static_cast<std::uint16_t>(lastBits_ & ~cia402::kCwFaultReset);
		reset_ = ResetPhase::None;
	} else if (!st) {
		awaited_ = target_; // no state: hold what was sent
	} else if (*st == Cia402State::Fault) {
		awaited_ = Cia402State::SwitchOnDisabled; // transition 15
		switch (reset_) {
		case ResetPhase::None:
			bits = 0; // bit 7 = 0 first
			reset_ = ResetPhase::Low;
			break;
		case ResetPhase::Low:
		case ResetPhase::High:
			bits = cia402::kCwFaultReset; // the rising edge, held
			reset_ = ResetPhase::High;
			break;
		}
	} else {
		reset_ = ResetPhase::None;
		if (*st == Cia402State::NotReadyToSwitchOn) {
			bits = 0;
			awaited_ = Cia402State::SwitchOnDisabled; // transition 1
		} else if (*st == Cia402State::FaultReactionActive) {
			bits = 0;
			awaited_ = Cia402State::Fault; // transition 14
		} else if (const auto c = cia402NextCommand(*st, target_)) {
			bits = cia402Controlword(*c);
			awaited_ = *st == target_ ? target_ : leadsTo(*st, *c);
		}
	}

	lastBits_ = bits;
	return Cia402Step{ static_cast<std::uint16_t>((controlword & ~cia402::kCwStateBits) | bits), progress_ };
}

std::string Cia402Stepper::failureMessage() const
{
	if (progress_ != Cia402Progress::Failed)
		return {};
	std::string m = slaveText(slave_);
	const std::string sw = cia402Hex16(failSw_);
	const std::string target(cia402StateName(target_));
	switch (why_) {
	case Why::Timeout: {
		m.append("CiA-402 timed out after ").append(formatDuration(opt_.timeout)).append(" waiting for ");
		const Cia402State awaited = awaited_.value_or(target_);
		m.append(cia402StateName(awaited));
		if (awaited != target_)
			m.append(" on the way to ").append(target);
		m.append(": stays in ").append(stateText(failState_)).append(" (statusword ").append(sw).append(")");
		break;
	}
	case Why::FaultNoReset:
		m.append("CiA-402 drive in FAULT (statusword ")
			.append(sw)
			.append(") on the way to ")
			.append(target)
			.append(", and fault reset is off");
		break;
	case Why::Left:
		m.append("CiA-402 drive left ")
			.append(target)
			.append(": now ")
			.append(stateText(failState_))
			.append(" (statusword ")
			.append(sw)
			.append(")");
		break;
	case Why::Unstable:
		m.append("CiA-402 drive does not settle on the way to ")
			.append(target)
			.append(": ")
			.append(std::to_string(changes_))
			.append(" state changes, now ")
			.append(stateText(failState_))
			.append(" (statusword ")
			.append(sw)
			.append(")");
		break;
	case Why::None:
		break;
	}
	return m;
}

void Cia402Stepper::throwIfFailed() const
{
	if (progress_ == Cia402Progress::Failed)
		throw Error(failureMessage(), why_ == Why::Timeout ? ETIMEDOUT : EIO);
}

// ---------------------------------------------------------------- PP set-point

void PpSetPointStepper::start(nanoseconds now, Options options)
{
	opt_ = options;
	phase_ = Phase::Low;
	progress_ = Cia402Progress::Busy;
	acked_ = false;
	requestSteps_ = 0;
	since_ = now;
	why_ = Why::None;
}

Cia402Step PpSetPointStepper::step(std::uint16_t statusword, nanoseconds now, std::uint16_t controlword) noexcept
{
	auto cw = static_cast<std::uint16_t>(controlword & ~(cia402::kCwNewSetPoint | cia402::kCwChangeImmediately |
								cia402::kCwRelative));
	if (opt_.changeImmediately)
		cw |= cia402::kCwChangeImmediately;
	if (opt_.relative)
		cw |= cia402::kCwRelative;

	if (!handshakeStep(progress_, why_, statusword_, statusword))
		return Cia402Step{ controlword, progress_ };
	const bool ack = statusword & cia402::kSwSetPointAck;
	if (progress_ == Cia402Progress::Busy) {
		switch (phase_) {
		case Phase::Low:
			// bit 4 = 0 first (the edge), and the drive free for a new
			// set-point: bit 12 = 0 (EST-584 manual 2.1.4); with "change
			// immediately" the drive takes one anyway
			if (!ack || opt_.changeImmediately) {
				phase_ = Phase::Request;
				since_ = now;
			} else if (now - since_ >= opt_.ackTimeout) {
				progress_ = Cia402Progress::Failed;
				why_ = Why::NoFreeBuffer;
			}
			break;
		case Phase::Request:
			// the statusword of the step that raised bit 4 is older than
			// the edge
			if (ack && requestSteps_ >= 1) {
				acked_ = true;
				since_ = now;
				if (opt_.waitTargetReached) {
					phase_ = Phase::Move;
				} else {
					progress_ = Cia402Progress::Done;
				}
			} else if (now - since_ >= opt_.ackTimeout) {
				progress_ = Cia402Progress::Failed;
				why_ = Why::AckTimeout;
			} else {
				cw |= cia402::kCwNewSetPoint;
				requestSteps_++;
			}
			break;
		case Phase::Move:
			if (statusword & cia402::kSwTargetReached)
				progress_ = Cia402Progress::Done;
			else if (opt_.moveTimeout.count() > 0 && now - since_ >= opt_.moveTimeout) {
				progress_ = Cia402Progress::Failed;
				why_ = Why::MoveTimeout;
			}
			break;
		}
	}
	return Cia402Step{ cw, progress_ };
}

std::string PpSetPointStepper::failureMessage() const
{
	auto reason = [this](std::string &m, const std::string &sw) {
		switch (why_) {
		case Why::NoFreeBuffer:
			m.append("PP set-point: the drive takes no new set-point within ")
				.append(formatDuration(opt_.ackTimeout))
				.append(": statusword bit 12 stays 1 (statusword ")
				.append(sw)
				.append(")");
			break;
		case Why::AckTimeout:
			m.append("PP set-point not acknowledged within ")
				.append(formatDuration(opt_.ackTimeout))
				.append(": statusword bit 12 stays 0 (statusword ")
				.append(sw)
				.append(")");
			if (statusword_ & cia402::kSwParamZero)
				m.append("; bit 14 is set: on the EST-584 a movement parameter (0x6081, 0x6083, "
					 "0x6084) is 0");
			break;
		case Why::MoveTimeout:
			m.append("PP target not reached within ")
				.append(formatDuration(opt_.moveTimeout))
				.append(" after the set-point acknowledge (statusword ")
				.append(sw)
				.append(")");
			break;
		case Why::NotEnabled:
		case Why::None:
			break;
		}
	};
	return handshakeFailure(progress_, slave_, "PP set-point", why_, statusword_, reason);
}

void PpSetPointStepper::throwIfFailed() const
{
	if (progress_ == Cia402Progress::Failed)
		throw Error(failureMessage(), why_ == Why::NotEnabled ? EIO : ETIMEDOUT);
}

// ---------------------------------------------------------------- homing

namespace {

constexpr detail::CodeText<HomingStatus> kHomingStatusNames[] = {
	{ HomingStatus::InProgress, "homing in progress" },
	{ HomingStatus::InterruptedOrIdle, "homing interrupted or not started" },
	{ HomingStatus::AttainedNotReached, "homing attained, target not reached" },
	{ HomingStatus::Completed, "homing completed" },
	{ HomingStatus::ErrorMoving, "homing error, velocity not 0" },
	{ HomingStatus::ErrorStopped, "homing error, velocity 0" },
};

} // namespace

std::string_view homingStatusName(HomingStatus s) noexcept
{
	return detail::textOf(kHomingStatusNames, s, "?");
}

void HomingStepper::start(nanoseconds now, Options options)
{
	opt_ = options;
	phase_ = Phase::Low;
	progress_ = Cia402Progress::Busy;
	settle_ = 0;
	since_ = now;
	why_ = Why::None;
}

Cia402Step HomingStepper::step(std::uint16_t statusword, nanoseconds now, std::uint16_t controlword) noexcept
{
	auto cw = static_cast<std::uint16_t>(controlword & ~cia402::kCwHomingStart);
	if (!handshakeStep(progress_, why_, statusword_, statusword))
		return Cia402Step{ controlword, progress_ };
	if (progress_ == Cia402Progress::Busy) {
		switch (phase_) {
		case Phase::Low:
			phase_ = Phase::Running; // bit 4 = 0 this step, 1 from the next
			break;
		case Phase::Running: {
			const HomingStatus hs = homingStatus(statusword);
			if (settle_ >= opt_.settleSteps && hs == HomingStatus::Completed) {
				progress_ = Cia402Progress::Done;
			} else if (settle_ >= opt_.settleSteps &&
				   (hs == HomingStatus::ErrorMoving || hs == HomingStatus::ErrorStopped)) {
				progress_ = Cia402Progress::Failed;
				why_ = Why::Error;
			} else if (now - since_ >= opt_.timeout) {
				progress_ = Cia402Progress::Failed;
				why_ = Why::Timeout;
			} else {
				cw |= cia402::kCwHomingStart;
				settle_++;
			}
			break;
		}
		}
	}
	return Cia402Step{ cw, progress_ };
}

std::string HomingStepper::failureMessage() const
{
	auto reason = [this](std::string &m, const std::string &sw) {
		switch (why_) {
		case Why::Error:
			m.append("homing failed: ");
			break;
		case Why::Timeout:
			m.append("homing timed out after ").append(formatDuration(opt_.timeout)).append(": ");
			break;
		case Why::NotEnabled:
		case Why::None:
			return;
		}
		m.append(homingStatusName(homingStatus(statusword_))).append(" (statusword ").append(sw).append(")");
	};
	return handshakeFailure(progress_, slave_, "homing", why_, statusword_, reason);
}

void HomingStepper::throwIfFailed() const
{
	if (progress_ == Cia402Progress::Failed)
		throw Error(failureMessage(), why_ == Why::Timeout ? ETIMEDOUT : EIO);
}

} // namespace ecmxf
