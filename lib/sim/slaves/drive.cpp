// SPDX-License-Identifier: MIT
//
// drive.cpp - CiA-402 state machine and modes of operation of the drive
// models (EST-584, servo).

#include "slaves/drive.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace ecmxf::sim::slaves {

Cia402Command decodeControlword(std::uint16_t cw)
{
	if (cw & 0x80)
		return Cia402Command::None; // fault reset pending: no command
	if ((cw & 0x02) == 0)
		return Cia402Command::DisableVoltage;
	if ((cw & 0x06) == 0x02)
		return Cia402Command::QuickStop;
	if ((cw & 0x07) == 0x06)
		return Cia402Command::Shutdown;
	if ((cw & 0x0F) == 0x07)
		return Cia402Command::SwitchOn;
	return Cia402Command::EnableOperation; // 0x0F
}

std::uint16_t cia402StateBits(Cia402State s)
{
	// in the enum's order: NOT READY, SWITCH ON DISABLED, READY, SWITCHED
	// ON, OPERATION ENABLED, QUICK STOP, FAULT REACTION, FAULT
	static constexpr std::uint16_t kBits[] = { 0x00, 0x40, 0x21, 0x23, 0x27, 0x07, 0x0F, 0x08 };
	static_assert(std::size(kBits) == static_cast<std::size_t>(Cia402State::Fault) + 1);
	const auto i = static_cast<std::size_t>(s);
	return i < std::size(kBits) ? kBits[i] : 0;
}

bool profileStep(double &pos, double &vel, double target, double vmax, double acc, double dec,
		 double dt)
{
	const double d = target - pos;
	const double dist = std::abs(d);
	if (dist < 1e-9 && std::abs(vel) < 1e-9) {
		pos = target;
		vel = 0;
		return true;
	}
	const double dir = d >= 0 ? 1.0 : -1.0;
	const double v = vel * dir; // speed toward the target
	// The highest end-of-step speed from which the target can still be
	// reached braking with dec: vNew^2 <= 2 dec (dist - (v + vNew) / 2 dt).
	const double a = dec * dt;
	const double disc = a * a + 4 * (2 * dec * dist - a * v);
	const double vStop = disc > 0 ? std::max(0.0, (std::sqrt(disc) - a) / 2) : 0.0;
	const double vWant = std::min(vmax, vStop);
	double vNew;
	if (v < 0)
		vNew = std::min(v + dec * dt, vWant); // moving away: brake first
	else if (v < vWant)
		vNew = std::min(v + acc * dt, vWant);
	else
		vNew = std::max(v - dec * dt, vWant);
	const double stepLen = (v + vNew) / 2 * dt;
	if (vNew >= 0 && v >= 0 && (stepLen >= dist - 1e-9 || (vNew == 0 && v == 0))) {
		pos = target;
		vel = 0;
		return true;
	}
	pos += stepLen * dir;
	vel = vNew * dir;
	return false;
}

double ramp(double vel, double target, double acc, double dec, double dt)
{
	if (vel == target)
		return vel;
	const bool faster = std::abs(target) > std::abs(vel) && (vel == 0 || (vel > 0) == (target > 0));
	const double step = (faster ? acc : dec) * dt;
	if (vel < target)
		return std::min(vel + step, target);
	return std::max(vel - step, target);
}

// ---- DriveBase ----

DriveBase::DriveBase(BaseConfig base, DriveConfig drive)
	: SlaveBase(std::move(base)), drv_(std::move(drive))
{
}

bool DriveBase::modeSupported(std::int8_t m) const
{
	return m >= 1 && m <= 32 && (drv_.supportedModes & mode::bit(m));
}

std::uint32_t DriveBase::checkMode(std::uint64_t raw) const
{
	return modeSupported(static_cast<std::int8_t>(raw)) ? 0 : abort::ValueRange;
}

bool DriveBase::quickStopStays() const
{
	return quickStopOption_ >= 5 && quickStopOption_ <= 8;
}

bool DriveBase::homeSwitchAt(double userPos) const
{
	return homeSwitch_ && userPos - homeShift_ >= *homeSwitch_;
}

void DriveBase::addDeviceObjects(std::uint32_t &deviceType, std::string &name,
				 std::string *hwVersion, std::string *swVersion)
{
	od_.var(0x1000, "Device type", DataType::U32, Access::RO, &deviceType).def(deviceType);
	od_.var(0x1001, "Error register", DataType::U8, Access::RO, &errorRegister_).map(TxPdo);
	od_.string(0x1008, "Device name", &name);
	if (hwVersion)
		od_.string(0x1009, "Hardware version", hwVersion);
	if (swVersion)
		od_.string(0x100A, "Software version", swVersion);
}

void DriveBase::addCia402Objects()
{
	od_.var(0x603F, "Error code", DataType::U16, Access::RO, &errorCode_).map(TxPdo);
	od_.var(0x6040, "Controlword", DataType::U16, Access::RW, &controlword_).map(RxPdo);
	od_.var(0x6041, "Statusword", DataType::U16, Access::RO, &statusword_).map(TxPdo);
	od_.var(0x6060, "Modes of operation", DataType::I8, Access::RW, &modeOfOperation_)
		.def(mode::CSP)
		.map(RxPdo)
		.onCheck([this](std::uint64_t v) { return checkMode(v); });
	od_.var(0x6061, "Modes of operation display", DataType::I8, Access::RO, &modeDisplay_).map(TxPdo);
	od_.var(0x6064, "Position actual value", DataType::I32, Access::RO, &positionActual_).map(TxPdo);
	od_.var(0x606C, "Velocity actual value", DataType::I32, Access::RO, &velocityActual_).map(TxPdo);
	od_.var(0x607A, "Target position", DataType::I32, Access::RW, &targetPosition_).map(RxPdo);
	od_.var(0x60FF, "Target velocity", DataType::I32, Access::RW, &targetVelocity_).map(RxPdo);
	od_.var(0x6502, "Supported drive modes", DataType::U32, Access::RO, &supportedModes_)
		.def(drv_.supportedModes);
}

void DriveBase::onPowerOn()
{
	st_ = Cia402State::NotReadyToSwitchOn;
	prevCw_ = 0;
	pos_ = 0;
	vel_ = 0;
	homeShift_ = 0;
	limited_ = false;
	ppMoving_ = ppBuffered_ = ppRequest_ = ppAck_ = false;
	ppTarget_ = ppBufferedTarget_ = ppLastTarget_ = 0;
	hm_ = Homing::Idle;
	hmAttained_ = false;
	supportedModes_ = drv_.supportedModes;
	modeDisplay_ = modeSupported(modeOfOperation_) ? modeOfOperation_ : 0;
	composeOutputs();
}

void DriveBase::setPositionActual(std::int32_t position)
{
	pos_ = position;
	composeOutputs();
}

void DriveBase::fault(std::uint16_t code)
{
	errorCode_ = code;
	std::uint8_t reg = 0x01;
	switch (code & 0xF000) {
	case 0x2000:
		reg |= 0x02; // current
		break;
	case 0x3000:
		reg |= 0x04; // voltage
		break;
	case 0x4000:
		reg |= 0x08; // temperature
		break;
	default:
		break;
	}
	if ((code & 0xFF00) == 0x8100)
		reg |= 0x10; // communication
	if ((code & 0xFF00) == 0x8600)
		reg |= 0x20; // device profile specific
	errorRegister_ = reg;
	pushEmergency(Emergency{ code, reg, {} });
	if (st_ != Cia402State::Fault && st_ != Cia402State::FaultReactionActive)
		st_ = Cia402State::FaultReactionActive; // transition 13
}

void DriveBase::injectFault(std::uint16_t code)
{
	fault(code);
	composeOutputs();
}

// Transition 4/16: the drive function is enabled, set-points cleared.
void DriveBase::enableOperation()
{
	ppMoving_ = ppBuffered_ = ppRequest_ = ppAck_ = false;
	ppTarget_ = ppLastTarget_ = pos_;
	hm_ = Homing::Idle;
	hmAttained_ = false;
	limited_ = false;
}

void DriveBase::decelerate(double dec, double dt)
{
	const double v0 = vel_;
	vel_ = dec > 0 ? ramp(vel_, 0, dec, dec, dt) : 0;
	pos_ += (v0 + vel_) / 2 * dt;
}

void DriveBase::step(std::chrono::nanoseconds dtNs, bool)
{
	const double dt = dtNs.count() > 0 ? static_cast<double>(dtNs.count()) * 1e-9 : 0.0;
	const std::uint16_t cw = controlword_;
	const std::uint16_t prev = prevCw_;
	prevCw_ = cw;
	const Cia402Command cmd = decodeControlword(cw);
	const bool resetEdge = (cw & 0x80) && !(prev & 0x80);

	bool modeChanged = false;
	if (modeOfOperation_ != modeDisplay_ && modeSupported(modeOfOperation_)) {
		modeDisplay_ = modeOfOperation_;
		modeChanged = true;
	}

	using S = Cia402State;
	using C = Cia402Command;
	const S before = st_;
	// the transitions a controlword command makes alone (the appendix's numbers)
	static constexpr struct {
		S from;
		C cmd;
		S to;
	} kTransitions[] = {
		{ S::SwitchOnDisabled, C::Shutdown, S::ReadyToSwitchOn },	 // 2
		{ S::ReadyToSwitchOn, C::SwitchOn, S::SwitchedOn },		 // 3
		{ S::ReadyToSwitchOn, C::EnableOperation, S::OperationEnabled }, // 3 + 4
		{ S::ReadyToSwitchOn, C::DisableVoltage, S::SwitchOnDisabled },	 // 7
		{ S::ReadyToSwitchOn, C::QuickStop, S::SwitchOnDisabled },	 // 7
		{ S::SwitchedOn, C::EnableOperation, S::OperationEnabled },	 // 4
		{ S::SwitchedOn, C::Shutdown, S::ReadyToSwitchOn },		 // 6
		{ S::SwitchedOn, C::DisableVoltage, S::SwitchOnDisabled },	 // 10
		{ S::SwitchedOn, C::QuickStop, S::SwitchOnDisabled },		 // 10
		{ S::OperationEnabled, C::SwitchOn, S::SwitchedOn },		 // 5
		{ S::OperationEnabled, C::Shutdown, S::ReadyToSwitchOn },	 // 8
		{ S::OperationEnabled, C::DisableVoltage, S::SwitchOnDisabled }, // 9
		{ S::OperationEnabled, C::QuickStop, S::QuickStopActive },	 // 11
		{ S::QuickStopActive, C::DisableVoltage, S::SwitchOnDisabled },	 // 12
	};
	const auto *t = std::find_if(std::begin(kTransitions), std::end(kTransitions),
				     [&](const auto &e) { return e.from == st_ && e.cmd == cmd; });
	if (t != std::end(kTransitions)) {
		st_ = t->to;
	} else if (st_ == S::NotReadyToSwitchOn) {
		st_ = S::SwitchOnDisabled; // 1: self-test done
	} else if (st_ == S::QuickStopActive && cmd == C::EnableOperation && quickStopStays()) {
		st_ = S::OperationEnabled; // 16
	} else if (st_ == S::Fault && resetEdge) {
		st_ = S::SwitchOnDisabled; // 15
		errorCode_ = 0;
		errorRegister_ = 0;
		pushEmergency(Emergency{ 0x0000, 0x00, {} });
	}
	// FAULT REACTION ACTIVE: 14 when the reaction is complete (below)

	if (st_ == S::OperationEnabled && (before != S::OperationEnabled || modeChanged))
		enableOperation();

	switch (st_) {
	case S::OperationEnabled:
		runMode(dt, cw, prev);
		break;
	case S::QuickStopActive:
		if (quickStopStays()) {
			decelerate(static_cast<double>(quickStopDeceleration_), dt);
		} else {
			vel_ = 0;
			st_ = S::SwitchOnDisabled; // 12: quick stop complete
		}
		torqueActual_ = 0;
		break;
	case S::FaultReactionActive:
		decelerate(static_cast<double>(quickStopDeceleration_), dt);
		torqueActual_ = 0;
		if (vel_ == 0)
			st_ = S::Fault; // 14
		break;
	default:
		vel_ = 0;
		torqueActual_ = 0;
		break;
	}
	if (st_ != S::OperationEnabled) {
		ppMoving_ = ppBuffered_ = ppRequest_ = ppAck_ = false;
		if (hm_ != Homing::Idle && hm_ != Homing::Done)
			hm_ = Homing::Idle;
		limited_ = false;
	}
	composeOutputs();
}

void DriveBase::runMode(double dt, std::uint16_t cw, std::uint16_t prev)
{
	switch (modeDisplay_) {
	case mode::PP:
		runPp(dt, cw, prev);
		break;
	case mode::PV:
		runPv(dt, cw);
		break;
	case mode::HM:
		runHm(dt, cw, prev);
		break;
	case mode::CSP:
		runCsp(dt);
		break;
	case mode::CSV:
		runCsv(dt);
		break;
	case mode::CST:
		runCst(dt);
		break;
	default: // no mode: hold still
		decelerate(static_cast<double>(quickStopDeceleration_), dt);
		break;
	}
}

void DriveBase::startPpMove(double target)
{
	ppTarget_ = target;
	ppMoving_ = true;
}

void DriveBase::runPp(double dt, std::uint16_t cw, std::uint16_t prev)
{
	const bool paramsZero =
		profileVelocity_ == 0 || profileAcceleration_ == 0 || profileDeceleration_ == 0;
	if ((cw & 0x10) && !(prev & 0x10) && !paramsZero)
		ppRequest_ = true; // new set-point (rising edge of bit 4)
	if (!(cw & 0x10)) {
		ppRequest_ = false;
		ppAck_ = false;
	}
	if (ppRequest_) {
		const double target = (cw & 0x40) ? ppLastTarget_ + targetPosition_
						  : static_cast<double>(targetPosition_);
		bool accepted = false;
		if (!ppMoving_ || (cw & 0x20)) { // idle, or "change set immediately"
			startPpMove(target);
			ppBuffered_ = false;
			accepted = true;
		} else if (!ppBuffered_) { // a single set-point buffer
			ppBuffered_ = true;
			ppBufferedTarget_ = target;
			accepted = true;
		}
		if (accepted) {
			ppLastTarget_ = target;
			ppRequest_ = false;
			ppAck_ = true;
		}
	}
	const double vmax =
		static_cast<double>(std::min(profileVelocity_, maxProfileVelocity_));
	const auto acc = static_cast<double>(profileAcceleration_);
	const auto dec = static_cast<double>(profileDeceleration_);
	const bool halt = cw & 0x100;
	if (halt) {
		decelerate(dec, dt);
	} else if (ppMoving_) {
		if (profileStep(pos_, vel_, ppTarget_, vmax, acc, dec, dt)) {
			if (ppBuffered_) {
				ppBuffered_ = false;
				startPpMove(ppBufferedTarget_);
			} else {
				ppMoving_ = false;
			}
		}
	} else {
		vel_ = 0;
	}
	bit10_ = (!ppMoving_ && !ppBuffered_) || (halt && vel_ == 0);
	bit12_ = ppAck_ || ppBuffered_;
	bit13_ = false;
}

void DriveBase::runPv(double dt, std::uint16_t cw)
{
	const auto vmax = static_cast<double>(maxProfileVelocity_);
	double vt = std::clamp(static_cast<double>(targetVelocity_), -vmax, vmax);
	limited_ = std::abs(static_cast<double>(targetVelocity_)) > vmax;
	if (cw & 0x100)
		vt = 0; // halt
	const double v0 = vel_;
	vel_ = ramp(vel_, vt, static_cast<double>(profileAcceleration_),
		    static_cast<double>(profileDeceleration_), dt);
	pos_ += (v0 + vel_) / 2 * dt;
	bit10_ = vel_ == vt;              // velocity reached
	bit12_ = vel_ == 0 || vt == 0;    // speed is 0 (or ramping to 0)
	bit13_ = false;
}

void DriveBase::runHm(double dt, std::uint16_t cw, std::uint16_t prev)
{
	const bool halt = cw & 0x100;
	const bool start = (cw & 0x10) && !(prev & 0x10) && !halt;
	const bool running = hm_ == Homing::Fast || hm_ == Homing::Back || hm_ == Homing::Slow;
	if (start) {
		hmAttained_ = false;
		hmStart_ = pos_;
		switch (homingMethod_) {
		case 19: // positive home switch, final approach in positive direction
		case 20: // positive home switch, final approach in negative direction
			hmFinalDir_ = homingMethod_ == 19 ? 1.0 : -1.0;
			hmPreEdge_ = hmFinalDir_ < 0; // switch state just before the edge
			hmDir_ = homeSwitchAt(pos_) ? -1.0 : 1.0;
			hm_ = Homing::Fast;
			break;
		case 35:
		case 37: // current position is home
			homeShift_ += homeOffset_ - pos_;
			pos_ = homeOffset_;
			hmAttained_ = true;
			hm_ = vel_ == 0 ? Homing::Done : Homing::Stop;
			break;
		default:
			hm_ = Homing::Error;
			break;
		}
	} else if (running && (!(cw & 0x10) || halt)) {
		hm_ = Homing::Interrupted;
	}

	const auto acc = static_cast<double>(homingAcceleration_);
	auto move = [&](double v) {
		const double v0 = vel_;
		vel_ = ramp(vel_, v, acc, acc, dt);
		pos_ += (v0 + vel_) / 2 * dt;
	};
	const auto fast = static_cast<double>(homingSpeedFast_);
	const auto slow = static_cast<double>(homingSpeedSlow_);
	switch (hm_) {
	case Homing::Fast: {
		const bool wasActive = homeSwitchAt(pos_);
		move(hmDir_ * fast);
		if (homeSwitchAt(pos_) != wasActive)
			hm_ = hmDir_ == hmFinalDir_ ? Homing::Back : Homing::Slow;
		break;
	}
	case Homing::Back:
		move(-hmFinalDir_ * fast);
		if (homeSwitchAt(pos_) == hmPreEdge_)
			hm_ = Homing::Slow;
		break;
	case Homing::Slow:
		move(hmFinalDir_ * slow);
		if (homeSwitchAt(pos_) != hmPreEdge_) {
			// The edge is at shaft position *homeSwitch_: make it homeOffset_.
			const double shaft = pos_ - homeShift_;
			homeShift_ = homeOffset_ - *homeSwitch_;
			pos_ = shaft + homeShift_;
			hmAttained_ = true;
			hm_ = Homing::Stop;
		}
		break;
	case Homing::Stop:
	case Homing::Error:
	case Homing::Interrupted:
		decelerate(acc, dt);
		if (hm_ == Homing::Stop && vel_ == 0)
			hm_ = Homing::Done;
		break;
	case Homing::Idle:
	case Homing::Done:
		vel_ = 0;
		break;
	}
	if ((hm_ == Homing::Fast || hm_ == Homing::Back || hm_ == Homing::Slow) &&
	    std::abs(pos_ - hmStart_) > drv_.homingTravelLimit) {
		hm_ = Homing::Error;
		hmAttained_ = false;
	}
	const bool settled = hm_ == Homing::Idle || hm_ == Homing::Done ||
			     hm_ == Homing::Error || hm_ == Homing::Interrupted;
	bit10_ = settled && vel_ == 0;
	bit12_ = hmAttained_;
	bit13_ = hm_ == Homing::Error;
}

namespace {

// Target minus actual, with the int32 position wrap-around of the bus.
double wrappedDiff(double target, double actual)
{
	double d = target - actual;
	if (std::abs(d) > 2147483648.0)
		d = std::remainder(d, 4294967296.0);
	return d;
}

} // namespace

void DriveBase::runCsp(double dt)
{
	const double target = static_cast<double>(targetPosition_) + positionOffset_;
	const double maxStep = static_cast<double>(maxProfileVelocity_) * dt;
	double d = wrappedDiff(target, pos_);
	limited_ = std::abs(d) > maxStep;
	if (limited_)
		d = std::copysign(maxStep, d);
	pos_ += d;
	vel_ = dt > 0 ? d / dt : 0;
	torqueActual_ = static_cast<std::int16_t>(loadTorque_);
	const double fe = wrappedDiff(target, pos_);
	followingError_ = static_cast<std::int32_t>(std::clamp(fe, -2147483648.0, 2147483647.0));
	bit10_ = false;
	bit12_ = true;
	bit13_ = std::abs(fe) > followingWindow();
	if (bit13_)
		fault(errc::FollowingError);
}

void DriveBase::runCsv(double dt)
{
	const auto vmax = static_cast<double>(maxProfileVelocity_);
	const double vt = static_cast<double>(targetVelocity_);
	limited_ = std::abs(vt) > vmax;
	vel_ = std::clamp(vt, -vmax, vmax);
	pos_ += vel_ * dt;
	torqueActual_ = static_cast<std::int16_t>(loadTorque_);
	bit10_ = false;
	bit12_ = true;
	bit13_ = false;
}

void DriveBase::runCst(double dt)
{
	const auto tmax = static_cast<double>(maxTorque_);
	const double t = std::clamp(static_cast<double>(targetTorque_), -tmax, tmax);
	const double a = (t - loadTorque_) * drv_.accelPerPermille - drv_.viscous * vel_;
	const auto vmax = static_cast<double>(maxProfileVelocity_);
	const double v0 = vel_;
	vel_ = std::clamp(vel_ + a * dt, -vmax, vmax);
	limited_ = std::abs(vel_) >= vmax;
	pos_ += (v0 + vel_) / 2 * dt;
	torqueActual_ = static_cast<std::int16_t>(t);
	bit10_ = false;
	bit12_ = true;
	bit13_ = false;
}

void DriveBase::composeOutputs()
{
	using S = Cia402State;
	std::uint16_t sw = cia402StateBits(st_);
	if (st_ != S::NotReadyToSwitchOn)
		sw |= 0x0010; // voltage enabled
	sw |= 0x0200;         // remote
	const bool oe = st_ == S::OperationEnabled;
	const bool halt = controlword_ & 0x100;
	if (!oe) {
		// Not enabled: nothing running; report the idle state of the mode.
		bit10_ = modeDisplay_ == mode::PP || modeDisplay_ == mode::HM ||
			 (modeDisplay_ == mode::PV && vel_ == 0 && targetVelocity_ == 0);
		bit12_ = modeDisplay_ == mode::PV ? vel_ == 0 : (modeDisplay_ == mode::HM && hmAttained_);
		// CSP: a following error fault keeps bit 13 until reset
		bit13_ = modeDisplay_ == mode::CSP && errorCode_ == errc::FollowingError;
	}
	if (bit10_)
		sw |= 0x0400;
	if (limited_)
		sw |= 0x0800;
	if (bit12_)
		sw |= 0x1000;
	if (bit13_)
		sw |= 0x2000;
	if (drv_.est584) {
		if (st_ == S::QuickStopActive || (oe && halt))
			sw |= 0x0100; // abnormal stop
		if (modeDisplay_ == mode::PP) {
			if (profileVelocity_ == 0 || profileAcceleration_ == 0 ||
			    profileDeceleration_ == 0)
				sw |= 0x4000; // a movement parameter is 0
			if (!(sw & 0x1000))
				sw |= 0x8000; // can take a new set-point
		}
	}
	statusword_ = sw;

	// round half away from zero, like llround, without the libm call
	const auto round64 = [](double x) {
		return static_cast<std::int64_t>(x >= 0 ? x + 0.5 : x - 0.5);
	};
	const auto asPos = [&](double p) {
		if (!(std::abs(p) < 9.0e18))
			p = 0;
		return static_cast<std::int32_t>(static_cast<std::uint32_t>(round64(p)));
	};
	const auto asVel = [&](double v) {
		return static_cast<std::int32_t>(round64(std::clamp(v, -2147483648.0, 2147483647.0)));
	};
	positionActual_ = asPos(pos_);
	positionDemand_ = positionActual_;
	velocityActual_ = asVel(vel_);
	velocityDemand_ = velocityActual_;
	if (modeDisplay_ != mode::CSP || !oe)
		followingError_ = 0;
	digitalInputs_ = homeSwitchAt(pos_) ? 0x04u : 0u;
	probeStatus_ = static_cast<std::uint16_t>(probeFunction_ & 0x0001);
}

// ---- AL interplay ----

std::uint16_t DriveBase::checkTransition(AlState, AlState to)
{
	const bool active = sync0Active();
	const std::uint32_t cycle = sync0CycleNs();
	const bool allowed = std::find(drv_.dcCyclesNs.begin(), drv_.dcCyclesNs.end(), cycle) !=
			     drv_.dcCyclesNs.end();
	if (to == AlState::SafeOp && active && !allowed)
		return alcode::InvalidDcSync;
	if (to == AlState::Op && ((drv_.dcRequired && !active) || (active && !allowed)))
		return alcode::InvalidDcSync;
	return 0;
}

void DriveBase::onAlChange(AlState from, AlState to, bool error)
{
	if (from != AlState::Op || to == AlState::Op)
		return;
	// Outputs are no longer applied: the power stage goes off.
	using S = Cia402State;
	if (st_ == S::SwitchedOn || st_ == S::OperationEnabled || st_ == S::QuickStopActive) {
		if (error) {
			fault(errc::CommunicationLost);
		} else {
			st_ = S::SwitchOnDisabled;
			vel_ = 0;
		}
	}
	composeOutputs();
}

} // namespace ecmxf::sim::slaves
