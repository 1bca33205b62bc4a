// SPDX-License-Identifier: MIT
/**
 * @file cia402_axis.hpp
 * @brief One CiA-402 drive driven from the application's cyclic loop
 *        (PP, PV, HM, CSP), a synchronized CSP trajectory for several
 *        axes, and a small blocking runner for tools.
 *
 * A Cia402Axis binds to the drive's objects in a ProcessImage (controlword,
 * statusword, modes, target/actual position, target velocity... as
 * mapped). The application calls update() once per cycle, after
 * Cyclic::cycle() exchanged the frames; update() reads the statusword,
 * advances the current request (state walk, PP set-point handshake, PV,
 * homing, CSP) with the steppers of cia402.hpp and writes the controlword
 * and targets into the image's outputs. update() neither allocates nor
 * throws. Requests do not block, except for the SDO writes some of them
 * make before they start (objects that are not mapped, e.g. 0x6060 or the
 * profile velocity); their progress is progress() / done() / failed().
 *
 * @code
 *   ecmxf::Cyclic cyc(dev, image, ecmxf::CyclicConfig::motion(1ms));
 *   cyc.start();                                   // the exchange runs from here
 *   ecmxf::Cia402Axis axis(dev, image, 0);
 *   axis.stopOnExit(cyc);                          // halted on scope exit
 *   axis.setMode(ecmxf::cia402::kModePp, now);    // SDO or PDO
 *   ... cycles until axis.done()
 *   axis.enable(now);                              // -> OPERATION ENABLED
 *   ... cycles until axis.done()
 *   axis.moveTo(100000, {}, now);                  // PP handshake
 *   for (;;) { cyc.cycle(); axis.update(now); if (axis.done()) break; cyc.waitNextCycle(); }
 * @endcode
 *
 * runUntil() does that loop for tools and tests. Documentation/motion.rst
 * describes the choices.
 *
 * Stopping: stopAxes() brings drives to a halt (quick stop, then disable)
 * through the process data in one call; an axis run by runUntil(), or
 * given stopOnExit(), does that by itself when it or its Cyclic goes out
 * of scope (an exception included).
 */
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <ecmxf/model/cia402.hpp>
#include <ecmxf/export.hpp>
#include <ecmxf/bus/master.hpp>
#include <ecmxf/pdo/process_image.hpp>

namespace ecmxf {

class Cyclic;
class Device;

/// How a Cia402Axis runs.
struct Cia402AxisConfig {
	/// The modes the application will use (cia402::kModePp...): the
	/// constructor checks that their objects are mapped. Empty: only the
	/// basics are checked at construction; each request checks its mode.
	std::vector<std::int8_t> modes;
	/// The state walk: timeout without a state change, fault reset.
	Cia402Stepper::Options state{};
	/// PP: longest wait for the set-point acknowledge, and for target
	/// reached after it (zero: no limit).
	std::chrono::nanoseconds ackTimeout = std::chrono::milliseconds(500);
	std::chrono::nanoseconds moveTimeout{ 0 };
	/// PV: longest wait for "velocity reached" (zero: no limit).
	std::chrono::nanoseconds velocityTimeout = std::chrono::seconds(10);
	/// HM: longest homing.
	std::chrono::nanoseconds homingTimeout = std::chrono::seconds(30);
	/// setMode() by PDO: longest wait for 0x6061 to show the mode.
	std::chrono::nanoseconds modeTimeout = std::chrono::milliseconds(500);
	/// Cycles between writing a controlword and the first statusword that
	/// can answer it (the RxFIFO fill + the TxFIFO's frame + one): the
	/// statuswords of the first this many cycles after an edge are not
	/// taken as a result (homing, PV, mode display).
	unsigned latencyCycles = 6;
};

/// Profile-position move options (moveTo()).
struct PpMove {
	bool relative = false;           ///< controlword bit 6: relative to the previous target
	bool changeImmediately = false;  ///< controlword bit 5
	bool waitTargetReached = true;   ///< done at target reached (else at the acknowledge)
	/// 0x6081 / 0x6083 / 0x6084, written before the set-point (PDO when
	/// mapped, else SDO); unset: the drive's values.
	std::optional<std::uint32_t> velocity, acceleration, deceleration;
};

/// Homing options (home()); unset values keep the drive's.
struct HomingParams {
	std::optional<std::int8_t> method;           ///< 0x6098
	std::optional<std::uint32_t> speedSearch;    ///< 0x6099:01 (switch search)
	std::optional<std::uint32_t> speedZero;      ///< 0x6099:02 (zero search)
	std::optional<std::uint32_t> acceleration;   ///< 0x609A
};

/// What an axis is doing (the last request).
enum class Cia402Request : std::uint8_t {
	None,
	State,     ///< enable(), disable(), requestState()
	Mode,      ///< setMode()
	PpMove,    ///< moveTo()
	PvVelocity,///< setVelocity()
	Homing,    ///< home()
	Csp,       ///< startCsp(): following setCspTarget()
};

/// One CiA-402 drive on the bus (file comment).
class ECMXF_EXPORT Cia402Axis
{
public:
	/// Binds to slave @p slave's objects in @p image (both @p device and
	/// @p image must outlive the axis). Needs 0x6040 (controlword) mapped
	/// as an output and 0x6041 (statusword) and 0x6064 (position actual)
	/// as inputs, plus each mode's objects of config.modes (PP and CSP:
	/// 0x607A; PV: 0x60FF); else ecmxf::Error (EINVAL) naming what is
	/// missing, for which mode, and what is mapped.
	Cia402Axis(Device &device, ProcessImage &image, std::uint8_t slave, Cia402AxisConfig config = {});
	/// With stopOnExit() in force (runUntil() sets it): brings the drive
	/// to a halt through that Cyclic first (stopAxes()), so that leaving
	/// the axis's scope, by an exception too, never leaves the drive
	/// running on the last outputs the chip keeps sending.
	~Cia402Axis();
	Cia402Axis(const Cia402Axis &) = delete;
	Cia402Axis &operator=(const Cia402Axis &) = delete;

	/// Stop on scope exit: when the axis or @p cyclic goes away, whichever
	/// goes first, the drive is brought to a halt through @p cyclic
	/// (stopAxes() with @p timeout). runUntil() and runUntilDone() set it
	/// for their axes. stopOnExit(nullptr) turns it off.
	void stopOnExit(Cyclic &cyclic, std::chrono::nanoseconds timeout = std::chrono::seconds(1));
	void stopOnExit(std::nullptr_t) noexcept;
	/// The Cyclic of stopOnExit(), or null.
	[[nodiscard]] Cyclic *stopsVia() const noexcept { return stopVia_; }

	[[nodiscard]] std::uint8_t slave() const noexcept { return slave_; }
	[[nodiscard]] Device &device() const noexcept { return dev_; }
	[[nodiscard]] const Cia402AxisConfig &config() const noexcept { return cfg_; }
	/// 0x6060 is mapped (modes go by PDO), else by SDO.
	[[nodiscard]] bool modeByPdo() const noexcept { return mode_.bound(); }
	/// The objects @p mode needs that are not mapped ("0x60FF:00 (target
	/// velocity)"); empty when the mode can run.
	[[nodiscard]] std::vector<std::string> missingFor(std::int8_t mode) const;

	// ---- requests: each replaces the previous one; progress() follows
	// it. They need not be called on the cyclic path (some write SDOs).

	/// Walks the drive to OPERATION ENABLED / SWITCH ON DISABLED / @p s.
	void enable(std::chrono::nanoseconds now);
	void disable(std::chrono::nanoseconds now);
	void requestState(Cia402State s, std::chrono::nanoseconds now);
	/// Modes of operation (0x6060): by PDO when mapped (done when 0x6061
	/// shows it, if mapped), else an SDO write now (SdoError on an abort)
	/// and done when 0x6061 shows it (at once when 0x6061 is not mapped).
	void setMode(std::int8_t mode, std::chrono::nanoseconds now);
	/// PP: target position @p target (0x607A) with the set-point
	/// handshake; done at target reached. Needs mode PP and OPERATION
	/// ENABLED (EINVAL otherwise, naming what is missing).
	void moveTo(std::int32_t target, const PpMove &move, std::chrono::nanoseconds now);
	/// PV: target velocity (0x60FF); done when the drive reports the
	/// velocity reached (bit 10). Optional 0x6083/0x6084 first.
	void setVelocity(std::int32_t velocity, std::chrono::nanoseconds now,
			 std::optional<std::uint32_t> acceleration = {},
			 std::optional<std::uint32_t> deceleration = {});
	/// HM: writes the parameters, then starts homing; done at homing
	/// attained + target reached, failed on a homing error.
	void home(const HomingParams &params, std::chrono::nanoseconds now);
	/// CSP: from now on the target position written every cycle is the
	/// one of setCspTarget() (initially where the drive stands). Done at
	/// once; failed when the drive leaves OPERATION ENABLED or reports a
	/// following error (bit 13).
	void startCsp(std::chrono::nanoseconds now);
	/// The requests above on the transport's clock (Link::now(): virtual
	/// time on the simulator), for callers that keep no time of their own.
	void enable();
	void disable();
	void requestState(Cia402State s);
	void setMode(std::int8_t mode);
	void moveTo(std::int32_t target, const PpMove &move = {});
	void setVelocity(std::int32_t velocity, std::optional<std::uint32_t> acceleration = {},
			 std::optional<std::uint32_t> deceleration = {});
	void home(const HomingParams &params);
	void startCsp();
	/// CSP target for the next cycles (any time; allocation-free).
	void setCspTarget(std::int32_t position) noexcept { cspTarget_ = position; }
	[[nodiscard]] std::int32_t cspTarget() const noexcept { return cspTarget_; }
	/// Controlword bit 8 (halt) on or off.
	void setHalt(bool on) noexcept { halt_ = on; }

	/// Once per cycle after Cyclic::cycle(): reads the inputs, advances
	/// the request, writes the outputs. Never throws, never allocates.
	void update(std::chrono::nanoseconds now) noexcept;
	/// The same on the transport's clock.
	void update() noexcept;

	// ---- progress
	[[nodiscard]] Cia402Request request() const noexcept { return req_; }
	[[nodiscard]] Cia402Progress progress() const noexcept { return progress_; }
	[[nodiscard]] bool done() const noexcept { return progress_ == Cia402Progress::Done; }
	[[nodiscard]] bool failed() const noexcept { return progress_ == Cia402Progress::Failed; }
	/// Why the request failed, in the steppers' words ("slave 0: CiA-402
	/// drive left OPERATION ENABLED: now FAULT (statusword 0x0218)"), with
	/// the drive's error code where it maps 0x603F (", error code 0x8611
	/// (0x603F)"); empty unless failed().
	[[nodiscard]] std::string failureMessage() const;
	/// Throws ecmxf::Error with failureMessage() if failed() (ETIMEDOUT
	/// for timeouts, EIO otherwise).
	void throwIfFailed() const;
	/// PP: the drive acknowledged the last set-point (statusword bit 12).
	[[nodiscard]] bool setPointAcknowledged() const noexcept { return pp_.acknowledged(); }

	// ---- the drive as last read
	[[nodiscard]] std::uint16_t statusword() const noexcept { return sw_; }
	[[nodiscard]] std::uint16_t controlword() const noexcept { return cw_; }
	[[nodiscard]] std::optional<Cia402State> state() const noexcept { return cia402StateFrom(sw_); }
	[[nodiscard]] bool enabled() const noexcept { return state() == Cia402State::OperationEnabled; }
	[[nodiscard]] bool targetReached() const noexcept { return sw_ & cia402::kSwTargetReached; }
	/// 0x6061 if mapped, else the mode last set.
	[[nodiscard]] std::int8_t modeDisplay() const noexcept;
	/// 0x6064.
	[[nodiscard]] std::int32_t position() const noexcept { return posActual_.get(); }
	/// 0x606C if mapped.
	[[nodiscard]] std::optional<std::int32_t> velocity() const noexcept;
	/// 0x60F4 if mapped.
	[[nodiscard]] std::optional<std::int32_t> followingError() const noexcept;

private:
	void begin(Cia402Request r, std::chrono::nanoseconds now);
	void needEnabledIn(std::int8_t mode, std::string_view what) const;
	/// PDO when mapped, else SDO.
	void writeParam(std::uint16_t index, std::uint8_t sub, std::uint32_t value);
	[[nodiscard]] Cia402Progress stepMotion(std::chrono::nanoseconds now, std::uint16_t &cw) noexcept;
	/// ", error code 0x8611 (0x603F)" when the drive failed with one.
	[[nodiscard]] std::string errorCodeText() const;

	enum class Why : std::uint8_t { None, State, Pp, Homing, ModeTimeout, VelocityTimeout, FollowingError, Left };

	Device &dev_;
	ProcessImage &image_;
	std::uint8_t slave_;
	Cia402AxisConfig cfg_;

	OutputVar<std::uint16_t> cwOut_;
	InputVar<std::uint16_t> swIn_;
	OutputVar<std::int8_t> mode_;
	InputVar<std::int8_t> modeDisp_;
	OutputVar<std::int32_t> targetPos_;
	OutputVar<std::int32_t> targetVel_;
	InputVar<std::int32_t> posActual_;
	InputVar<std::int32_t> velActual_;
	InputVar<std::int32_t> followErr_;
	InputVar<std::uint16_t> errorCode_; ///< 0x603F, where mapped

	Cia402Stepper state_;
	PpSetPointStepper pp_;
	HomingStepper hm_;

	Cia402Request req_ = Cia402Request::None;
	Cia402Progress progress_ = Cia402Progress::Idle;
	Why why_ = Why::None;
	std::int8_t modeSet_ = 0;
	bool modeKnown_ = false;
	std::int32_t cspTarget_ = 0;
	std::int32_t pvTarget_ = 0;
	bool halt_ = false;
	std::uint16_t sw_ = 0;
	std::uint16_t cw_ = 0;
	std::uint16_t failSw_ = 0;
	std::uint16_t failError_ = 0; ///< 0x603F when it failed (0: none, or not mapped)
	unsigned steps_ = 0; ///< update() calls since the request
	std::chrono::nanoseconds since_{ 0 };
	Cyclic *stopVia_ = nullptr;
	std::chrono::nanoseconds stopTimeout_{ 0 };
};

/// What stopAxes() did to one axis.
struct Cia402StopOutcome {
	std::uint8_t slave = 0;
	/// The drive was in OPERATION ENABLED or QUICK STOP ACTIVE: it was
	/// quick-stopped and disabled; false: it was only disabled (or left
	/// as it was, in FAULT).
	bool wasEnabled = false;
	/// It reached a state with the power stage off (SWITCH ON DISABLED,
	/// READY TO SWITCH ON, FAULT...) within the time given.
	bool halted = false;
	std::uint16_t statusword = 0;
	std::int32_t position = 0;
	std::optional<std::int32_t> velocity; ///< 0x606C if mapped
	/// "slave 0: quick stop, then disabled: SWITCH ON DISABLED (statusword
	/// 0x0250), position 41210, velocity 0"
	std::string text;
};

/**
 * Brings @p axes to a halt through @p cyclic's process data (in OP the
 * process data's controlword overrides SDO writes, so this is the path
 * that controls the drive): each axis in OPERATION ENABLED gets Quick
 * Stop (controlword 0x0002) until it stands still in QUICK STOP ACTIVE
 * (velocity actual 0 when 0x606C is mapped, else the position unchanged
 * over latencyCycles cycles) or leaves it by itself (quick stop option
 * codes 1..4), then Disable Voltage until SWITCH ON DISABLED. Each phase
 * takes at most @p timeout on the transport's clock. A Cyclic that was
 * stopped is started again for it (and stopped after). Never throws: an
 * axis that could not be halted says so in its outcome (halted false).
 * Not for the cyclic path (it allocates).
 */
[[nodiscard]] ECMXF_EXPORT std::vector<Cia402StopOutcome>
stopAxes(Cyclic &cyclic, std::span<Cia402Axis *const> axes,
	 std::chrono::nanoseconds timeout = std::chrono::seconds(1)) noexcept;

/// The shape of a CspTrajectory.
enum class TrajectoryShape : std::uint8_t {
	/// (1 - cos(pi t / T)) / 2: smooth start and stop, peak velocity
	/// pi/2 x distance / T.
	Cosine,
	/// Constant acceleration for T/4, constant velocity, constant
	/// deceleration for T/4: peak velocity 4/3 x distance / T.
	Trapezoid,
};

/**
 * Positions over time for several axes that start and finish together:
 * each axis goes from its start to its end position along the same
 * normalized profile over one common duration ("synchronized"). Pure and
 * allocation-free after construction.
 */
class ECMXF_EXPORT CspTrajectory
{
public:
	/// @p from and @p to: one position per axis (same size, at least 1);
	/// @p duration > 0. Throws ecmxf::Error (EINVAL) otherwise.
	CspTrajectory(std::span<const std::int32_t> from, std::span<const std::int32_t> to,
		      std::chrono::nanoseconds duration, TrajectoryShape shape = TrajectoryShape::Cosine);

	[[nodiscard]] std::size_t axes() const noexcept { return from_.size(); }
	[[nodiscard]] std::chrono::nanoseconds duration() const noexcept { return duration_; }
	[[nodiscard]] TrajectoryShape shape() const noexcept { return shape_; }
	/// Axis @p axis's position at @p t after the start: from before 0,
	/// exactly to from duration() on.
	[[nodiscard]] std::int32_t position(std::size_t axis, std::chrono::nanoseconds t) const noexcept;
	/// The profile's fraction of the way (0..1) at @p t.
	[[nodiscard]] double fraction(std::chrono::nanoseconds t) const noexcept;
	/// Peak velocity (units/s) of axis @p axis.
	[[nodiscard]] double peakVelocity(std::size_t axis) const noexcept;
	/// setCspTarget(position(i, t)) on axes[i] (as many as both have).
	void apply(std::span<Cia402Axis *const> axes, std::chrono::nanoseconds t) const noexcept;
	[[nodiscard]] bool finished(std::chrono::nanoseconds t) const noexcept { return t >= duration_; }

	/// The shortest duration in which no axis exceeds @p maxVelocity
	/// (units/s, > 0) with this shape, rounded up to @p cycle.
	[[nodiscard]] static std::chrono::nanoseconds minimumDuration(std::span<const std::int32_t> from,
								      std::span<const std::int32_t> to,
								      double maxVelocity, std::chrono::nanoseconds cycle,
								      TrajectoryShape shape = TrajectoryShape::Cosine);

private:
	std::vector<std::int32_t> from_, to_;
	std::chrono::nanoseconds duration_;
	TrajectoryShape shape_;
};

/**
 * A blocking loop for tools and tests: each cycle runs Cyclic::cycle(),
 * update() of every axis (on the transport's clock), then @p until; it
 * returns the number of cycles run once @p until returns true, pacing the
 * cycles with Cyclic::waitNextCycle() (virtual time on the simulator).
 * Throws ecmxf::Error: a failed cycle (its message), a WKC mismatch
 * (naming the bus state), a failed axis request (failureMessage()), or
 * ETIMEDOUT after @p timeout, naming @p what was awaited.
 */
ECMXF_EXPORT std::uint64_t runUntil(Cyclic &cyclic, std::span<Cia402Axis *const> axes,
				    const std::function<bool()> &until, std::chrono::nanoseconds timeout,
				    std::string_view what = "the axes");

/// runUntil() until every axis is done().
ECMXF_EXPORT std::uint64_t runUntilDone(Cyclic &cyclic, std::span<Cia402Axis *const> axes,
					std::chrono::nanoseconds timeout, std::string_view what = "the axes");

/// The PDO assignment the motion tools use for an EST-584 at bus position
/// @p slave: RxPDO 0x1600 = controlword, target position, target
/// velocity, modes of operation (11 bytes); TxPDO 0x1A00 = statusword,
/// modes display, position actual, velocity actual, following error
/// actual (15 bytes). Every mode (PP, PV, HM, CSP) runs by PDO with it.
[[nodiscard]] ECMXF_EXPORT SlavePdoAssignment est584MotionPdos(std::uint8_t slave);

} // namespace ecmxf
