// SPDX-License-Identifier: MIT
// Cia402Axis, CspTrajectory, runUntil() (include/ecmxf/cia402/cia402_axis.hpp,
// Documentation/motion.rst).

#include <ecmxf/cia402/cia402_axis.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/bus/bus.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/link.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <numbers>
#include <span>
#include <vector>
#include <string>

#include "base/text.hpp"

namespace ecmxf {

using std::chrono::nanoseconds;

namespace {

std::string objectText(std::uint16_t index, std::uint8_t sub, const char *name)
{
	static const char d[] = "0123456789ABCDEF";
	return detail::hex(index, 4).append(":").append(1, d[sub >> 4]).append(1, d[sub & 0xF]).append(" (").append(name).append(")");
}

constexpr detail::CodeText<std::int8_t> kModeNames[] = {
	{ cia402::kModePp, "profile position" },
	{ cia402::kModePv, "profile velocity" },
	{ cia402::kModeHm, "homing" },
	{ cia402::kModeCsp, "cyclic synchronous position" },
};

/// "8 (cyclic synchronous position)", or the bare number of a mode without
/// a name here.
std::string modeName(std::int8_t m)
{
	std::string s = std::to_string(m);
	const std::string_view name = detail::textOf(kModeNames, m, {});
	if (!name.empty())
		s.append(" (").append(name).append(")");
	return s;
}

std::string slaveText(unsigned slave)
{
	return std::string("slave ").append(std::to_string(slave)).append(": ");
}

/// Throws unless Cia402Axis drives @p mode; the message starts with
/// @p what and the mode's number.
void checkMode(std::int8_t mode, const std::string &what)
{
	if (mode != cia402::kModePp && mode != cia402::kModePv && mode != cia402::kModeHm && mode != cia402::kModeCsp)
		throw Error(what + std::to_string(mode) + " is not one of 1 (PP), 3 (PV), 6 (HM), 8 (CSP)", EINVAL);
}

/// @p parts joined by ", ".
std::string commaList(const std::vector<std::string> &parts)
{
	std::string s;
	for (const std::string &p : parts)
		s.append(s.empty() ? "" : ", ").append(p);
	return s;
}

std::string mappedList(const std::vector<PdoEntryInfo> &v)
{
	std::string s;
	for (const PdoEntryInfo &e : v) {
		if (e.index == 0)
			continue;
		if (!s.empty())
			s += ", ";
		s += detail::hex(e.index, 4);
		if (e.sub)
			s.append(":").append(std::to_string(e.sub));
	}
	return s.empty() ? std::string("nothing") : s;
}

bool isMapped(const std::vector<PdoEntryInfo> &v, std::uint16_t index, std::uint8_t sub)
{
	return std::any_of(v.begin(), v.end(), [&](const PdoEntryInfo &e) { return e.index == index && e.sub == sub; });
}

template <class T>
OutputVar<T> optOutput(ProcessImage &im, std::uint8_t slave, std::uint16_t index)
{
	if (!isMapped(im.slave(slave).outputs, index, 0))
		return {};
	return im.output<T>(slave, index, 0);
}

template <class T>
InputVar<T> optInput(const ProcessImage &im, std::uint8_t slave, std::uint16_t index)
{
	if (!isMapped(im.slave(slave).inputs, index, 0))
		return {};
	return im.input<T>(slave, index, 0);
}

std::string durationText(nanoseconds d)
{
	const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(d).count();
	return std::to_string(ms).append(" ms");
}

} // namespace

// ------------------------------------------------------------ Cia402Axis

Cia402Axis::Cia402Axis(Device &device, ProcessImage &image, std::uint8_t slave, Cia402AxisConfig config)
	: dev_(device), image_(image), slave_(slave), cfg_(std::move(config)), state_(slave, cfg_.state), pp_(slave),
	  hm_(slave)
{
	const SlavePdos &p = image.slave(slave); // EINVAL for a slave that is not there
	std::vector<std::string> missing;
	if (!isMapped(p.outputs, 0x6040, 0))
		missing.push_back("0x6040:00 (controlword) as an output");
	if (!isMapped(p.inputs, 0x6041, 0))
		missing.push_back("0x6041:00 (statusword) as an input");
	if (!isMapped(p.inputs, 0x6064, 0))
		missing.push_back("0x6064:00 (position actual value) as an input");
	std::string text = commaList(missing);
	if (!text.empty())
		text.append(" (every mode)");
	for (std::int8_t mode : cfg_.modes) {
		checkMode(mode, slaveText(slave) + "Cia402Axis: mode ");
		const std::string forMode = commaList(missingFor(mode));
		if (!forMode.empty())
			text.append(text.empty() ? "" : "; ").append(forMode).append(" for mode ").append(modeName(mode));
	}
	if (!text.empty())
		throw Error(slaveText(slave) + "Cia402Axis: not mapped: " + text + ". Mapped outputs: " +
				    mappedList(p.outputs) + "; inputs: " + mappedList(p.inputs),
			    EINVAL);

	cwOut_ = image.output<std::uint16_t>(slave, 0x6040, 0);
	swIn_ = image.input<std::uint16_t>(slave, 0x6041, 0);
	posActual_ = image.input<std::int32_t>(slave, 0x6064, 0);
	mode_ = optOutput<std::int8_t>(image, slave, 0x6060);
	modeDisp_ = optInput<std::int8_t>(image, slave, 0x6061);
	targetPos_ = optOutput<std::int32_t>(image, slave, 0x607A);
	targetVel_ = optOutput<std::int32_t>(image, slave, 0x60FF);
	velActual_ = optInput<std::int32_t>(image, slave, 0x606C);
	followErr_ = optInput<std::int32_t>(image, slave, 0x60F4);
	errorCode_ = optInput<std::uint16_t>(image, slave, 0x603F);
	cwOut_.set(0);
}

Cia402Axis::~Cia402Axis()
{
	if (Cyclic *c = stopVia_) {
		c->removeExitHook(this);
		stopVia_ = nullptr;
		Cia402Axis *self = this;
		(void)stopAxes(*c, std::span<Cia402Axis *const>(&self, 1), stopTimeout_);
	}
}

void Cia402Axis::stopOnExit(Cyclic &cyclic, nanoseconds timeout)
{
	if (stopVia_ && stopVia_ != &cyclic)
		stopVia_->removeExitHook(this);
	// the Cyclic goes first: it halts the drive and the axis forgets it
	cyclic.addExitHook(this, [](void *owner, Cyclic &c) noexcept {
		auto *self = static_cast<Cia402Axis *>(owner);
		self->stopVia_ = nullptr;
		(void)stopAxes(c, std::span<Cia402Axis *const>(&self, 1), self->stopTimeout_);
	});
	stopVia_ = &cyclic;
	stopTimeout_ = timeout;
}

void Cia402Axis::stopOnExit(std::nullptr_t) noexcept
{
	if (stopVia_)
		stopVia_->removeExitHook(this);
	stopVia_ = nullptr;
}

std::vector<std::string> Cia402Axis::missingFor(std::int8_t mode) const
{
	const SlavePdos &p = image_.slave(slave_);
	std::vector<std::string> v;
	if ((mode == cia402::kModePp || mode == cia402::kModeCsp) && !isMapped(p.outputs, 0x607A, 0))
		v.push_back(objectText(0x607A, 0, "target position") + " as an output");
	if (mode == cia402::kModePv && !isMapped(p.outputs, 0x60FF, 0))
		v.push_back(objectText(0x60FF, 0, "target velocity") + " as an output");
	return v;
}

std::int8_t Cia402Axis::modeDisplay() const noexcept
{
	return modeDisp_.bound() ? modeDisp_.get() : modeSet_;
}

std::optional<std::int32_t> Cia402Axis::velocity() const noexcept
{
	if (!velActual_.bound())
		return std::nullopt;
	return velActual_.get();
}

std::optional<std::int32_t> Cia402Axis::followingError() const noexcept
{
	if (!followErr_.bound())
		return std::nullopt;
	return followErr_.get();
}

void Cia402Axis::begin(Cia402Request r, nanoseconds now)
{
	req_ = r;
	progress_ = Cia402Progress::Busy;
	why_ = Why::None;
	steps_ = 0;
	since_ = now;
}

void Cia402Axis::enable(nanoseconds now)
{
	requestState(Cia402State::OperationEnabled, now);
}

void Cia402Axis::disable(nanoseconds now)
{
	requestState(Cia402State::SwitchOnDisabled, now);
}

void Cia402Axis::requestState(Cia402State s, nanoseconds now)
{
	state_.request(s, now); // EINVAL for a state that cannot be requested
	begin(Cia402Request::State, now);
}

void Cia402Axis::setMode(std::int8_t mode, nanoseconds now)
{
	checkMode(mode, slaveText(slave_) + "mode ");
	const std::string miss = commaList(missingFor(mode));
	if (!miss.empty())
		throw Error(slaveText(slave_) + "mode " + modeName(mode) + " needs " + miss +
				    " mapped; mapped outputs: " + mappedList(image_.slave(slave_).outputs),
			    EINVAL);
	// the target of the new mode starts where the drive stands
	cspTarget_ = position();
	targetPos_.set(position());
	if (mode_.bound())
		mode_.set(mode);
	else
		dev_.sdo().write<std::int8_t>(slave_, 0x6060, 0, mode); // SdoError on an abort
	modeSet_ = mode;
	modeKnown_ = true;
	begin(Cia402Request::Mode, now);
}

void Cia402Axis::needEnabledIn(std::int8_t mode, std::string_view what) const
{
	std::int8_t m = modeDisplay();
	if (!modeDisp_.bound() && !modeKnown_)
		m = dev_.sdo().read<std::int8_t>(slave_, 0x6061, 0);
	if (m != mode)
		throw Error(slaveText(slave_) + std::string(what) + " needs mode " + modeName(mode) +
				    "; the drive is in mode " + modeName(m) + " (setMode() first)",
			    EINVAL);
	if (!enabled())
		throw Error(slaveText(slave_) + std::string(what) + " needs OPERATION ENABLED; the drive is in " +
				    std::string(state() ? cia402StateName(*state()) : "no CiA-402 state") + " (statusword " +
				    cia402Hex16(sw_) + ")",
			    EINVAL);
}

void Cia402Axis::writeParam(std::uint16_t index, std::uint8_t sub, std::uint32_t value)
{
	if (isMapped(image_.slave(slave_).outputs, index, sub)) {
		image_.output<std::uint32_t>(slave_, index, sub).set(value);
		return;
	}
	dev_.sdo().write<std::uint32_t>(slave_, index, sub, value);
}

void Cia402Axis::moveTo(std::int32_t target, const PpMove &move, nanoseconds now)
{
	needEnabledIn(cia402::kModePp, "PP move");
	if (move.velocity)
		writeParam(0x6081, 0, *move.velocity);
	if (move.acceleration)
		writeParam(0x6083, 0, *move.acceleration);
	if (move.deceleration)
		writeParam(0x6084, 0, *move.deceleration);
	targetPos_.set(target);
	PpSetPointStepper::Options o;
	o.changeImmediately = move.changeImmediately;
	o.relative = move.relative;
	o.waitTargetReached = move.waitTargetReached;
	o.ackTimeout = cfg_.ackTimeout;
	o.moveTimeout = cfg_.moveTimeout;
	pp_.start(now, o);
	begin(Cia402Request::PpMove, now);
}

void Cia402Axis::setVelocity(std::int32_t velocity, nanoseconds now, std::optional<std::uint32_t> acceleration,
			     std::optional<std::uint32_t> deceleration)
{
	if (!targetVel_.bound())
		throw Error(slaveText(slave_) + "PV needs " + objectText(0x60FF, 0, "target velocity") +
				    " mapped as an output; mapped outputs: " + mappedList(image_.slave(slave_).outputs),
			    EINVAL);
	needEnabledIn(cia402::kModePv, "PV velocity");
	if (acceleration)
		writeParam(0x6083, 0, *acceleration);
	if (deceleration)
		writeParam(0x6084, 0, *deceleration);
	pvTarget_ = velocity;
	targetVel_.set(velocity);
	begin(Cia402Request::PvVelocity, now);
}

void Cia402Axis::home(const HomingParams &params, nanoseconds now)
{
	needEnabledIn(cia402::kModeHm, "homing");
	if (params.method) {
		if (isMapped(image_.slave(slave_).outputs, 0x6098, 0))
			image_.output<std::int8_t>(slave_, 0x6098, 0).set(*params.method);
		else
			dev_.sdo().write<std::int8_t>(slave_, 0x6098, 0, *params.method);
	}
	if (params.speedSearch)
		writeParam(0x6099, 1, *params.speedSearch);
	if (params.speedZero)
		writeParam(0x6099, 2, *params.speedZero);
	if (params.acceleration)
		writeParam(0x609A, 0, *params.acceleration);
	HomingStepper::Options o;
	o.timeout = cfg_.homingTimeout;
	o.settleSteps = cfg_.latencyCycles;
	hm_.start(now, o);
	begin(Cia402Request::Homing, now);
}

void Cia402Axis::startCsp(nanoseconds now)
{
	needEnabledIn(cia402::kModeCsp, "CSP");
	begin(Cia402Request::Csp, now);
	progress_ = Cia402Progress::Done;
}

void Cia402Axis::update() noexcept
{
	nanoseconds now{ 0 };
	try {
		now = dev_.link().now();
	} catch (...) {
		now = since_;
	}
	update(now);
}

// the requests on the transport's clock (a failing clock throws, as the
// request itself may)
void Cia402Axis::enable()
{
	enable(dev_.link().now());
}

void Cia402Axis::disable()
{
	disable(dev_.link().now());
}

void Cia402Axis::requestState(Cia402State s)
{
	requestState(s, dev_.link().now());
}

void Cia402Axis::setMode(std::int8_t mode)
{
	setMode(mode, dev_.link().now());
}

void Cia402Axis::moveTo(std::int32_t target, const PpMove &move)
{
	moveTo(target, move, dev_.link().now());
}

void Cia402Axis::setVelocity(std::int32_t velocity, std::optional<std::uint32_t> acceleration,
			     std::optional<std::uint32_t> deceleration)
{
	setVelocity(velocity, dev_.link().now(), acceleration, deceleration);
}

void Cia402Axis::home(const HomingParams &params)
{
	home(params, dev_.link().now());
}

void Cia402Axis::startCsp()
{
	startCsp(dev_.link().now());
}

Cia402Progress Cia402Axis::stepMotion(nanoseconds now, std::uint16_t &cw) noexcept
{
	// the PP set-point and homing steppers: their controlword, and their
	// failure as @p failed
	auto handshake = [&](auto &stepper, Why failed) {
		const Cia402Step s = stepper.step(sw_, now, cw);
		cw = s.controlword;
		if (s.progress == Cia402Progress::Failed)
			why_ = failed;
		return s.progress;
	};
	switch (req_) {
	case Cia402Request::None:
		return Cia402Progress::Idle;
	case Cia402Request::State:
		return state_.progress();
	case Cia402Request::Mode: {
		if (progress_ == Cia402Progress::Done)
			return progress_; // taken; stays done
		if (modeDisp_.bound()) {
			if (steps_ > cfg_.latencyCycles || modeDisp_.get() == modeSet_) {
				if (modeDisp_.get() == modeSet_)
					return Cia402Progress::Done;
				if (now - since_ >= cfg_.modeTimeout) {
					why_ = Why::ModeTimeout;
					return Cia402Progress::Failed;
				}
			}
			return Cia402Progress::Busy;
		}
		return steps_ > cfg_.latencyCycles ? Cia402Progress::Done : Cia402Progress::Busy;
	}
	case Cia402Request::PpMove:
		return handshake(pp_, Why::Pp);
	case Cia402Request::PvVelocity:
		if (progress_ == Cia402Progress::Done)
			return progress_; // reached once; stays done
		if (steps_ > cfg_.latencyCycles && (sw_ & cia402::kSwTargetReached))
			return Cia402Progress::Done;
		if (cfg_.velocityTimeout.count() > 0 && now - since_ >= cfg_.velocityTimeout) {
			why_ = Why::VelocityTimeout;
			return Cia402Progress::Failed;
		}
		return Cia402Progress::Busy;
	case Cia402Request::Homing:
		return handshake(hm_, Why::Homing);
	case Cia402Request::Csp:
		if (sw_ & cia402::kSwFollowingError) {
			why_ = Why::FollowingError;
			return Cia402Progress::Failed;
		}
		return Cia402Progress::Done;
	}
	return Cia402Progress::Idle;
}

void Cia402Axis::update(nanoseconds now) noexcept
{
	sw_ = swIn_.get();
	const std::int8_t mode = modeDisplay();
	// CSP: until the drive is enabled, its target follows the position
	// actual, so enabling does not make it jump
	if (mode == cia402::kModeCsp && !enabled())
		cspTarget_ = position();

	auto base = static_cast<std::uint16_t>(cw_ & ~(cia402::kCwStateBits | cia402::kCwNewSetPoint |
						       cia402::kCwChangeImmediately | cia402::kCwRelative |
						       cia402::kCwHalt));
	if (halt_)
		base |= cia402::kCwHalt;
	const Cia402Step st = state_.step(sw_, now, base);
	std::uint16_t cw = st.controlword;

	if (progress_ == Cia402Progress::Busy || (progress_ == Cia402Progress::Done && req_ != Cia402Request::State)) {
		// a motion request fails when the drive leaves its state
		if (req_ != Cia402Request::State && req_ != Cia402Request::Mode &&
		    st.progress == Cia402Progress::Failed) {
			progress_ = Cia402Progress::Failed;
			why_ = Why::Left;
			failSw_ = sw_;
			failError_ = errorCode_.bound() ? errorCode_.get() : 0;
		} else {
			const Cia402Progress p = stepMotion(now, cw);
			steps_++;
			if (p == Cia402Progress::Failed) {
				if (req_ == Cia402Request::State)
					why_ = Why::State;
				failSw_ = sw_;
				failError_ = errorCode_.bound() ? errorCode_.get() : 0;
			}
			if (p != Cia402Progress::Idle)
				progress_ = p;
		}
	} else if (req_ == Cia402Request::PpMove || req_ == Cia402Request::Homing) {
		// done or failed: the steppers keep bit 4 as they left it
		Cia402Step s = req_ == Cia402Request::PpMove ? pp_.step(sw_, now, cw) : hm_.step(sw_, now, cw);
		cw = s.controlword;
	}
	if (req_ == Cia402Request::State && progress_ == Cia402Progress::Done &&
	    st.progress == Cia402Progress::Failed) {
		progress_ = Cia402Progress::Failed;
		why_ = Why::State;
		failSw_ = sw_;
		failError_ = errorCode_.bound() ? errorCode_.get() : 0;
	}

	if (mode == cia402::kModeCsp)
		targetPos_.set(cspTarget_);
	cw_ = cw;
	cwOut_.set(cw);
}

std::string Cia402Axis::errorCodeText() const
{
	// the drive's own word for the fault (0x603F), where it maps it
	return failError_ ? ", error code " + cia402Hex16(failError_) + " (0x603F)" : std::string();
}

std::string Cia402Axis::failureMessage() const
{
	if (progress_ != Cia402Progress::Failed)
		return {};
	switch (why_) {
	case Why::State:
	case Why::Left:
		return state_.failureMessage() + errorCodeText();
	case Why::Pp:
		return pp_.failureMessage();
	case Why::Homing:
		return hm_.failureMessage();
	case Why::ModeTimeout:
		return slaveText(slave_) + "mode " + modeName(modeSet_) + " not taken within " +
		       durationText(cfg_.modeTimeout) + ": 0x6061 (modes of operation display) stays " +
		       modeName(modeDisp_.get()) + " (statusword " + cia402Hex16(failSw_) + ")";
	case Why::VelocityTimeout:
		return slaveText(slave_) + "PV velocity " + std::to_string(pvTarget_) + " not reached within " +
		       durationText(cfg_.velocityTimeout) + " (statusword " + cia402Hex16(failSw_) + ", bit 10 = 0" +
		       (velActual_.bound() ? ", velocity actual " + std::to_string(velActual_.get()) : std::string()) +
		       ")";
	case Why::FollowingError:
		return slaveText(slave_) + "CSP following error (statusword " + cia402Hex16(failSw_) +
		       ", bit 13)" +
		       (followErr_.bound() ? ": 0x60F4 = " + std::to_string(followErr_.get()) : std::string()) +
		       errorCodeText();
	case Why::None:
		break;
	}
	return slaveText(slave_) + "failed";
}

void Cia402Axis::throwIfFailed() const
{
	if (progress_ != Cia402Progress::Failed)
		return;
	bool timeout = why_ == Why::ModeTimeout || why_ == Why::VelocityTimeout;
	if (why_ == Why::State || why_ == Why::Left) {
		try {
			state_.throwIfFailed();
		} catch (const Error &e) {
			timeout = e.errnoValue() == ETIMEDOUT;
		}
	} else if (why_ == Why::Pp || why_ == Why::Homing) {
		timeout = failureMessage().find("within") != std::string::npos ||
			  failureMessage().find("timed out") != std::string::npos;
	}
	throw Error(failureMessage(), timeout ? ETIMEDOUT : EIO);
}

// ---------------------------------------------------------- CspTrajectory

CspTrajectory::CspTrajectory(std::span<const std::int32_t> from, std::span<const std::int32_t> to,
			     nanoseconds duration, TrajectoryShape shape)
	: from_(from.begin(), from.end()), to_(to.begin(), to.end()), duration_(duration), shape_(shape)
{
	if (from.empty() || from.size() != to.size())
		throw Error("CspTrajectory: " + std::to_string(from.size()) + " start and " + std::to_string(to.size()) +
				    " end positions (one of each per axis, at least one axis)",
			    EINVAL);
	if (duration.count() <= 0)
		throw Error("CspTrajectory: duration " + std::to_string(duration.count()) + " ns is not positive",
			    EINVAL);
}

double CspTrajectory::fraction(nanoseconds t) const noexcept
{
	if (t.count() <= 0)
		return 0.0;
	if (t >= duration_)
		return 1.0;
	const double u = static_cast<double>(t.count()) / static_cast<double>(duration_.count());
	if (shape_ == TrajectoryShape::Cosine)
		return (1.0 - std::cos(std::numbers::pi * u)) / 2.0;
	// trapezoid, ramps of 1/4 each: peak velocity v = 4/3 (in units of
	// distance / T); s(u) = v u^2 / (2 a) with a = v / (1/4)
	constexpr double ta = 0.25;
	constexpr double v = 1.0 / (1.0 - ta);
	if (u < ta)
		return v * u * u / (2.0 * ta);
	if (u <= 1.0 - ta)
		return v * ta / 2.0 + v * (u - ta);
	const double r = 1.0 - u;
	return 1.0 - v * r * r / (2.0 * ta);
}

std::int32_t CspTrajectory::position(std::size_t axis, nanoseconds t) const noexcept
{
	if (axis >= from_.size())
		return 0;
	if (t >= duration_)
		return to_[axis];
	const double a = from_[axis];
	const double d = static_cast<double>(to_[axis]) - a;
	return static_cast<std::int32_t>(std::llround(a + d * fraction(t)));
}

namespace {
double peakFactor(TrajectoryShape s)
{
	return s == TrajectoryShape::Cosine ? std::numbers::pi / 2.0 : 4.0 / 3.0;
}
} // namespace

double CspTrajectory::peakVelocity(std::size_t axis) const noexcept
{
	if (axis >= from_.size())
		return 0.0;
	const double d = std::fabs(static_cast<double>(to_[axis]) - static_cast<double>(from_[axis]));
	return peakFactor(shape_) * d / std::chrono::duration<double>(duration_).count();
}

void CspTrajectory::apply(std::span<Cia402Axis *const> axes, nanoseconds t) const noexcept
{
	const std::size_t n = std::min(axes.size(), from_.size());
	for (std::size_t i = 0; i < n; i++)
		if (axes[i])
			axes[i]->setCspTarget(position(i, t));
}

nanoseconds CspTrajectory::minimumDuration(std::span<const std::int32_t> from, std::span<const std::int32_t> to,
					   double maxVelocity, nanoseconds cycle, TrajectoryShape shape)
{
	if (from.size() != to.size() || from.empty())
		throw Error("CspTrajectory::minimumDuration: " + std::to_string(from.size()) + " start and " +
				    std::to_string(to.size()) + " end positions",
			    EINVAL);
	if (!(maxVelocity > 0.0) || cycle.count() <= 0)
		throw Error("CspTrajectory::minimumDuration: the velocity limit and the cycle must be positive", EINVAL);
	double dmax = 0;
	for (std::size_t i = 0; i < from.size(); i++)
		dmax = std::max(dmax, std::fabs(static_cast<double>(to[i]) - static_cast<double>(from[i])));
	const double seconds = peakFactor(shape) * dmax / maxVelocity;
	const auto cycles = static_cast<std::int64_t>(std::ceil(seconds * 1e9 / static_cast<double>(cycle.count())));
	return cycle * std::max<std::int64_t>(cycles, 1);
}

// ---------------------------------------------------------------- runner

std::uint64_t runUntil(Cyclic &cyclic, std::span<Cia402Axis *const> axes, const std::function<bool()> &until,
		       nanoseconds timeout, std::string_view what)
{
	if (axes.empty() && !until)
		throw Error("runUntil: nothing to wait for", EINVAL);
	Device *dev = nullptr;
	for (Cia402Axis *a : axes)
		if (a)
			dev = &a->device();
	// stop on scope exit: an exception out of here, or the caller's scope
	// ending, halts the drives rather than leaving them on the last outputs
	for (Cia402Axis *a : axes)
		if (a && !a->stopsVia())
			a->stopOnExit(cyclic);
	std::uint64_t cycles = 0;
	nanoseconds start{ -1 };
	for (;;) {
		const CycleResult &r = cyclic.cycle();
		cycles++;
		if (r.error)
			throw Error(std::string("runUntil: the cyclic exchange failed: ").append(r.message), r.error);
		if (r.wkcRead && !r.wkcOk) {
			std::string m = "runUntil: working counter " + std::to_string(r.wkc) + ", expected " +
					std::to_string(r.expectedWkc) + " (bus state 0x";
			static const char d[] = "0123456789ABCDEF";
			m.append(1, d[(r.ecatState >> 4) & 0xF]).append(1, d[r.ecatState & 0xF]).append(")");
			if (dev) {
				// name the slaves that left OP, with their AL status codes
				try {
					const std::uint8_t n = dev->bus().slaveCount();
					for (std::uint8_t s = 0; s < n; s++) {
						const SlaveInfo i = dev->bus().slaveInfo(s);
						if (i.state != State::Op)
							m.append("; slave ")
								.append(std::to_string(s))
								.append(" in ")
								.append(stateName(i.state))
								.append(", AL status code ")
								.append(detail::hex(i.alStatusCode, 4))
								.append(" ")
								.append(alStatusText(i.alStatusCode));
					}
				} catch (const Error &) {
				}
			}
			throw Error(m, EIO);
		}
		// the transport's clock; without an axis, the cycles' schedule
		const nanoseconds now =
			dev ? dev->link().now() : cyclic.config().period * static_cast<std::int64_t>(cycles);
		for (Cia402Axis *a : axes)
			if (a)
				a->update(now);
		if (start.count() < 0)
			start = now;
		for (Cia402Axis *a : axes)
			if (a && a->failed())
				a->throwIfFailed();
		if (until && until())
			return cycles;
		if (!until) {
			bool all = true;
			for (Cia402Axis *a : axes)
				if (a && !a->done())
					all = false;
			if (all)
				return cycles;
		}
		if (timeout.count() > 0 && now - start >= timeout)
			throw Error(std::string("runUntil: timed out after ").append(durationText(timeout))
					    .append(" waiting for ")
					    .append(what),
				    ETIMEDOUT);
		if (const int e = cyclic.waitNextCycle())
			throw Error("runUntil: waiting for the next cycle failed (the transport failed)", e);
	}
}

// ------------------------------------------------------------ stopAxes

namespace {

/// The power stage is on (the drive can move).
bool powered(std::optional<Cia402State> s)
{
	return s == Cia402State::OperationEnabled || s == Cia402State::QuickStopActive ||
	       s == Cia402State::SwitchedOn || s == Cia402State::FaultReactionActive;
}

} // namespace

std::vector<Cia402StopOutcome> stopAxes(Cyclic &cyclic, std::span<Cia402Axis *const> axes,
					nanoseconds timeout) noexcept
{
	std::vector<Cia402StopOutcome> out;
	try {
		Device *dev = nullptr;
		for (Cia402Axis *a : axes)
			if (a)
				dev = &a->device();
		if (!dev)
			return out;
		out.resize(axes.size());
		const bool restart = !cyclic.running();
		if (restart)
			cyclic.start();
		const nanoseconds period = cyclic.config().period;
		// bounded by the transport's clock and by a count of cycles (a
		// clock that stands still does not hold the stop up forever)
		const std::int64_t maxCycles = timeout / period + 2;
		int lost = 0;
		auto cycleOnce = [&]() -> bool {
			const CycleResult &r = cyclic.cycle();
			lost = r.error ? lost + 1 : 0;
			const nanoseconds t = dev->link().now();
			for (Cia402Axis *a : axes)
				if (a)
					a->update(t);
			return lost <= 3 && cyclic.waitNextCycle() == 0;
		};
		auto phase = [&](const auto &finished) {
			const nanoseconds t0 = dev->link().now();
			for (std::int64_t n = 0; n < maxCycles; n++) {
				if (!cycleOnce())
					return;
				if (finished() || dev->link().now() - t0 >= timeout)
					return;
			}
		};
		// fresh inputs, then Quick Stop for every enabled drive
		(void)cycleOnce();
		std::vector<std::int32_t> lastPos(axes.size());
		std::vector<unsigned> still(axes.size());
		for (std::size_t i = 0; i < axes.size(); i++) {
			Cia402Axis *a = axes[i];
			if (!a)
				continue;
			out[i].slave = a->slave();
			const auto st = a->state();
			out[i].wasEnabled = st == Cia402State::OperationEnabled || st == Cia402State::QuickStopActive;
			a->setHalt(false);
			if (st == Cia402State::OperationEnabled)
				a->requestState(Cia402State::QuickStopActive, dev->link().now());
			lastPos[i] = a->position();
		}
		phase([&] {
			bool all = true;
			for (std::size_t i = 0; i < axes.size(); i++) {
				Cia402Axis *a = axes[i];
				if (!a || !out[i].wasEnabled)
					continue;
				const auto st = a->state();
				still[i] = a->position() == lastPos[i] ? still[i] + 1 : 0;
				lastPos[i] = a->position();
				const bool standstill =
					a->velocity() ? *a->velocity() == 0 : still[i] >= a->config().latencyCycles;
				if (st == Cia402State::OperationEnabled || (st == Cia402State::QuickStopActive && !standstill))
					all = false;
			}
			return all;
		});
		// Disable Voltage for every drive whose power stage is on
		for (Cia402Axis *a : axes)
			if (a && powered(a->state()) && a->state() != Cia402State::FaultReactionActive)
				a->disable(dev->link().now());
		phase([&] {
			for (Cia402Axis *a : axes)
				if (a && powered(a->state()))
					return false;
			return true;
		});
		for (std::size_t i = 0; i < axes.size(); i++) {
			Cia402Axis *a = axes[i];
			if (!a)
				continue;
			Cia402StopOutcome &o = out[i];
			const auto st = a->state();
			o.halted = !powered(st);
			o.statusword = a->statusword();
			o.position = a->position();
			o.velocity = a->velocity();
			o.text = slaveText(a->slave());
			if (!o.halted)
				o.text.append("NOT halted within ").append(durationText(timeout)).append(": ");
			else
				o.text.append(o.wasEnabled ? "quick stop, then disabled: " : "not enabled: ");
			o.text.append(st ? std::string(cia402StateName(*st)) : std::string("no CiA-402 state"))
				.append(" (statusword ")
				.append(cia402Hex16(o.statusword))
				.append("), position ")
				.append(std::to_string(o.position));
			if (o.velocity)
				o.text.append(", velocity ").append(std::to_string(*o.velocity));
		}
		if (restart)
			cyclic.stop();
	} catch (...) {
		// noexcept: what was reached is in the outcomes (halted false)
	}
	return out;
}

std::uint64_t runUntilDone(Cyclic &cyclic, std::span<Cia402Axis *const> axes, nanoseconds timeout,
			   std::string_view what)
{
	return runUntil(cyclic, axes, {}, timeout, what);
}

SlavePdoAssignment est584MotionPdos(std::uint8_t slave)
{
	SlavePdoAssignment a;
	a.slave = slave;
	a.rxPdos = std::vector<PdoDef>{ PdoDef{ 0x1600,
						{ { 0x6040, 0, 16 }, { 0x607A, 0, 32 }, { 0x60FF, 0, 32 }, { 0x6060, 0, 8 } } } };
	a.txPdos = std::vector<PdoDef>{ PdoDef{
		0x1A00,
		{ { 0x6041, 0, 16 }, { 0x6061, 0, 8 }, { 0x6064, 0, 32 }, { 0x606C, 0, 32 }, { 0x60F4, 0, 32 } } } };
	return a;
}

} // namespace ecmxf
