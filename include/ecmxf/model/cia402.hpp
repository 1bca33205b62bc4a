// SPDX-License-Identifier: MIT
/**
 * @file cia402.hpp
 * @brief The CiA-402 drive state machine on the host side: statusword
 *        decoding, controlword commands, the transitions of the ECM-XF
 *        manuals' appendix as data, and pure, I/O-free steppers for the
 *        state machine, the profile-position set-point handshake and
 *        homing.
 *
 * Nothing here talks to a device: a stepper takes the statusword the
 * caller read and the time on the caller's clock, and returns the
 * controlword to write. step() neither allocates nor throws, so it can run
 * on a cyclic path; only the failure message is built on demand.
 * Documentation/cia402.rst describes the state machine and the choices made
 * where the manuals are silent.
 */
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <ecmxf/export.hpp>
#include <ecmxf/model/types_cia402.hpp>

namespace ecmxf {

// ---------------------------------------------------------------- words

/// Statusword (0x6041) and controlword (0x6040) bits.
namespace cia402 {

// modes of operation (0x6060) of the EST-584 manual
inline constexpr std::int8_t kModePp = 1;  ///< profile position
inline constexpr std::int8_t kModePv = 3;  ///< profile velocity
inline constexpr std::int8_t kModeHm = 6;  ///< homing
inline constexpr std::int8_t kModeCsp = 8; ///< cyclic synchronous position

// statusword masks of the appendix table (bits 6, 5, 3, 2, 1, 0)
inline constexpr std::uint16_t kStateMaskShort = 0x004F; ///< states without bit 5 in their pattern
inline constexpr std::uint16_t kStateMaskLong = 0x006F;  ///< states with bit 5 (quick stop) in their pattern

// statusword bits
inline constexpr std::uint16_t kSwVoltageEnabled = 1u << 4;
inline constexpr std::uint16_t kSwQuickStop = 1u << 5;
inline constexpr std::uint16_t kSwWarning = 1u << 7;
inline constexpr std::uint16_t kSwAbnormalStop = 1u << 8;   ///< EST-584: hardware limit, halt, E-stop
inline constexpr std::uint16_t kSwRemote = 1u << 9;
inline constexpr std::uint16_t kSwTargetReached = 1u << 10; ///< PP/HM target reached, PV speed reached
inline constexpr std::uint16_t kSwInternalLimit = 1u << 11;
inline constexpr std::uint16_t kSwSetPointAck = 1u << 12;   ///< PP set-point acknowledge
inline constexpr std::uint16_t kSwSpeedZero = 1u << 12;     ///< PV speed is 0
inline constexpr std::uint16_t kSwHomingAttained = 1u << 12;///< HM homing attained
inline constexpr std::uint16_t kSwFollowsTarget = 1u << 12; ///< CSP drive follows the target
inline constexpr std::uint16_t kSwHomingError = 1u << 13;   ///< HM homing error
inline constexpr std::uint16_t kSwFollowingError = 1u << 13;///< CSP following error
inline constexpr std::uint16_t kSwParamZero = 1u << 14;     ///< EST-584 PP: 0x6081/0x6083/0x6084 is 0
inline constexpr std::uint16_t kSwTriggerResponse = 1u << 15;///< EST-584 PP: a new set-point is taken

// controlword bits
inline constexpr std::uint16_t kCwSwitchOn = 1u << 0;
inline constexpr std::uint16_t kCwEnableVoltage = 1u << 1;
inline constexpr std::uint16_t kCwQuickStop = 1u << 2; ///< active low: 0 = quick stop
inline constexpr std::uint16_t kCwEnableOperation = 1u << 3;
inline constexpr std::uint16_t kCwNewSetPoint = 1u << 4;      ///< PP: 0 -> 1 takes 0x607A
inline constexpr std::uint16_t kCwHomingStart = 1u << 4;      ///< HM: 0 -> 1 starts homing
inline constexpr std::uint16_t kCwChangeImmediately = 1u << 5;///< PP: interrupt the current move
inline constexpr std::uint16_t kCwRelative = 1u << 6;         ///< PP: 0x607A is relative
inline constexpr std::uint16_t kCwFaultReset = 1u << 7;       ///< 0 -> 1 resets a fault
inline constexpr std::uint16_t kCwHalt = 1u << 8;
/// The bits the state machine owns (0-3 and 7, as the chip's engine).
inline constexpr std::uint16_t kCwStateBits = 0x008F;

} // namespace cia402

/// The state of a statusword by the masks of the appendix table
/// (0x4F / 0x6F); std::nullopt for a pattern that is no state.
[[nodiscard]] constexpr std::optional<Cia402State> cia402StateFrom(std::uint16_t statusword) noexcept
{
	const unsigned s = statusword & cia402::kStateMaskShort;
	const unsigned l = statusword & cia402::kStateMaskLong;
	if (s == 0x00)
		return Cia402State::NotReadyToSwitchOn;
	if (s == 0x40)
		return Cia402State::SwitchOnDisabled;
	if (l == 0x21)
		return Cia402State::ReadyToSwitchOn;
	if (l == 0x23)
		return Cia402State::SwitchedOn;
	if (l == 0x27)
		return Cia402State::OperationEnabled;
	if (l == 0x07)
		return Cia402State::QuickStopActive;
	if (s == 0x0F)
		return Cia402State::FaultReactionActive;
	if (s == 0x08)
		return Cia402State::Fault;
	return std::nullopt;
}

/// The device control commands of the controlword.
enum class Cia402Command : std::uint8_t {
	Shutdown,         ///< 0xxx x110
	SwitchOn,         ///< 0xxx 0111
	EnableOperation,  ///< 0xxx 1111
	DisableVoltage,   ///< 0xxx xx0x
	QuickStop,        ///< 0xxx x01x
	DisableOperation, ///< 0xxx 0111
	FaultReset,       ///< bit 7: 0 -> 1
};

/// A command's bit pattern: the bits that matter (@c mask) and their
/// values (@c bits). The fault reset is the rising edge of bit 7; its
/// pattern is the level after the edge.
struct Cia402CommandPattern {
	std::uint16_t mask;
	std::uint16_t bits;
};

/// The pattern of @p c (CiA 402 device control commands).
[[nodiscard]] constexpr Cia402CommandPattern cia402Pattern(Cia402Command c) noexcept
{
	switch (c) {
	case Cia402Command::Shutdown:
		return { 0x0087, 0x0006 };
	case Cia402Command::SwitchOn:
	case Cia402Command::DisableOperation:
		return { 0x008F, 0x0007 };
	case Cia402Command::EnableOperation:
		return { 0x008F, 0x000F };
	case Cia402Command::DisableVoltage:
		return { 0x0082, 0x0000 };
	case Cia402Command::QuickStop:
		return { 0x0086, 0x0002 };
	case Cia402Command::FaultReset:
		return { 0x0080, 0x0080 };
	}
	return { 0, 0 };
}

/// The controlword bits 0-3 and 7 the steppers write for @p c (the pattern
/// with every "x" among bits 0-3 as 0).
[[nodiscard]] constexpr std::uint16_t cia402Controlword(Cia402Command c) noexcept
{
	return cia402Pattern(c).bits;
}

/// The command's name, e.g. "Enable Operation".
[[nodiscard]] constexpr std::string_view cia402CommandName(Cia402Command c) noexcept
{
	switch (c) {
	case Cia402Command::Shutdown:
		return "Shutdown";
	case Cia402Command::SwitchOn:
		return "Switch On";
	case Cia402Command::EnableOperation:
		return "Enable Operation";
	case Cia402Command::DisableVoltage:
		return "Disable Voltage";
	case Cia402Command::QuickStop:
		return "Quick Stop";
	case Cia402Command::DisableOperation:
		return "Disable Operation";
	case Cia402Command::FaultReset:
		return "Fault Reset";
	}
	return "?";
}

/// One transition of the state diagram (ECM-XF manual appendix, transitions
/// 0..16). A transition that two commands cause (7, 10) or that is also
/// automatic (12) has a row for each.
struct Cia402Transition {
	std::uint8_t number;
	/// std::nullopt: transition 0 (from power-on) and 13 (from any state).
	std::optional<Cia402State> from;
	Cia402State to;
	/// std::nullopt: automatic or caused by the drive (0, 1, 12, 13, 14).
	std::optional<Cia402Command> command;
};

/// The transitions of the state diagram, in the order of the appendix.
inline constexpr std::array<Cia402Transition, 20> kCia402Transitions{ {
	{ 0, std::nullopt, Cia402State::NotReadyToSwitchOn, std::nullopt },
	{ 1, Cia402State::NotReadyToSwitchOn, Cia402State::SwitchOnDisabled, std::nullopt },
	{ 2, Cia402State::SwitchOnDisabled, Cia402State::ReadyToSwitchOn, Cia402Command::Shutdown },
	{ 3, Cia402State::ReadyToSwitchOn, Cia402State::SwitchedOn, Cia402Command::SwitchOn },
	{ 4, Cia402State::SwitchedOn, Cia402State::OperationEnabled, Cia402Command::EnableOperation },
	{ 5, Cia402State::OperationEnabled, Cia402State::SwitchedOn, Cia402Command::DisableOperation },
	{ 6, Cia402State::SwitchedOn, Cia402State::ReadyToSwitchOn, Cia402Command::Shutdown },
	{ 7, Cia402State::ReadyToSwitchOn, Cia402State::SwitchOnDisabled, Cia402Command::DisableVoltage },
	{ 7, Cia402State::ReadyToSwitchOn, Cia402State::SwitchOnDisabled, Cia402Command::QuickStop },
	{ 8, Cia402State::OperationEnabled, Cia402State::ReadyToSwitchOn, Cia402Command::Shutdown },
	{ 9, Cia402State::OperationEnabled, Cia402State::SwitchOnDisabled, Cia402Command::DisableVoltage },
	{ 10, Cia402State::SwitchedOn, Cia402State::SwitchOnDisabled, Cia402Command::DisableVoltage },
	{ 10, Cia402State::SwitchedOn, Cia402State::SwitchOnDisabled, Cia402Command::QuickStop },
	{ 11, Cia402State::OperationEnabled, Cia402State::QuickStopActive, Cia402Command::QuickStop },
	{ 12, Cia402State::QuickStopActive, Cia402State::SwitchOnDisabled, std::nullopt },
	{ 12, Cia402State::QuickStopActive, Cia402State::SwitchOnDisabled, Cia402Command::DisableVoltage },
	{ 13, std::nullopt, Cia402State::FaultReactionActive, std::nullopt },
	{ 14, Cia402State::FaultReactionActive, Cia402State::Fault, std::nullopt },
	{ 15, Cia402State::Fault, Cia402State::SwitchOnDisabled, Cia402Command::FaultReset },
	{ 16, Cia402State::QuickStopActive, Cia402State::OperationEnabled, Cia402Command::EnableOperation },
} };

/// The command the host sends in @p from on the way to @p target, as the
/// Cia402Stepper does: the first step of the shortest legal path, or, when
/// @p from is @p target, the command that keeps the drive there (SWITCH ON
/// DISABLED: Disable Voltage, READY TO SWITCH ON: Shutdown, SWITCHED ON:
/// Switch On, OPERATION ENABLED: Enable Operation, QUICK STOP ACTIVE:
/// Quick Stop). FAULT is left by Fault Reset. std::nullopt for the states
/// the drive leaves by itself (NOT READY TO SWITCH ON, FAULT REACTION
/// ACTIVE) and for a target that cannot be requested. The path never
/// passes OPERATION ENABLED unless that is the target (so from QUICK STOP
/// ACTIVE to SWITCHED ON it goes by Disable Voltage, not Enable
/// Operation); Disable Voltage is preferred to Quick Stop (transitions 7,
/// 10).
[[nodiscard]] ECMXF_EXPORT std::optional<Cia402Command> cia402NextCommand(Cia402State from,
									  Cia402State target) noexcept;

/// Whether @p s can be requested (as for 402_STATE_SET): SWITCH ON
/// DISABLED, READY TO SWITCH ON, SWITCHED ON, OPERATION ENABLED, QUICK
/// STOP ACTIVE.
[[nodiscard]] constexpr bool cia402Requestable(Cia402State s) noexcept
{
	return s == Cia402State::SwitchOnDisabled || s == Cia402State::ReadyToSwitchOn ||
	       s == Cia402State::SwitchedOn || s == Cia402State::OperationEnabled ||
	       s == Cia402State::QuickStopActive;
}

/// "0x0233"
[[nodiscard]] ECMXF_EXPORT std::string cia402Hex16(std::uint16_t v);

// -------------------------------------------------------------- steppers

/// Where a stepper is.
enum class Cia402Progress : std::uint8_t {
	Idle,    ///< nothing requested
	Busy,    ///< on the way
	Done,    ///< reached; the stepper holds it
	Failed,  ///< see failureMessage()
};

/// What one step returns.
struct Cia402Step {
	/// The controlword to write: the caller's bits with the stepper's
	/// bits in place.
	std::uint16_t controlword = 0;
	Cia402Progress progress = Cia402Progress::Idle;
};

/**
 * Walks a drive to a requested state over controlword and statusword.
 *
 * Each step() takes the statusword the caller has just read and the time
 * on the caller's clock, and returns the controlword to write: the
 * caller's bits (modes: 4-6, 8, 9, 10-15) with bits 0-3 and 7 set to the
 * command of the next transition on the shortest legal path. A fault is
 * reset by a rising edge of bit 7 (one step with bit 7 = 0, then bit 7 = 1
 * held until the drive leaves FAULT; then 0 again). If the state does not
 * change for the timeout, the walk fails with a message naming the awaited
 * state, the state the drive stays in and the statusword. Once the target is
 * reached the stepper keeps sending its command; if the drive leaves it
 * (e.g. a fault), the walk fails until request() is called again. A drive
 * that changes state more than kMaxChanges times in one walk without
 * reaching the target (e.g. QUICK STOP ACTIVE requested from a drive whose
 * quick stop ends in SWITCH ON DISABLED) fails the walk too.
 */
class ECMXF_EXPORT Cia402Stepper
{
public:
	/// State changes one walk may see before it fails.
	static constexpr unsigned kMaxChanges = 12;

	struct Options {
		/// Longest time without a state change before the walk fails.
		std::chrono::nanoseconds timeout = std::chrono::milliseconds(1000);
		/// Reset a fault on the way (else FAULT fails the walk at once).
		bool faultReset = true;
	};

	/// A stepper for the drive at bus position @p slave (for messages).
	explicit Cia402Stepper(unsigned slave);
	Cia402Stepper(unsigned slave, Options options);

	/// Starts a walk to @p target at time @p now. Throws ecmxf::Error
	/// (EINVAL) for a state that cannot be requested (cia402Requestable).
	void request(Cia402State target, std::chrono::nanoseconds now);

	/// One cycle: @p statusword just read, @p now on the caller's clock,
	/// @p controlword the caller's bits (its bits 0-3 and 7 are replaced).
	/// Never throws, never allocates.
	Cia402Step step(std::uint16_t statusword, std::chrono::nanoseconds now,
			std::uint16_t controlword = 0) noexcept;

	[[nodiscard]] Cia402Progress progress() const noexcept { return progress_; }
	[[nodiscard]] Cia402State target() const noexcept { return target_; }
	/// The state of the last statusword (std::nullopt: none yet, or no
	/// CiA-402 state).
	[[nodiscard]] std::optional<Cia402State> state() const noexcept { return state_; }
	[[nodiscard]] std::uint16_t lastStatusword() const noexcept { return statusword_; }
	/// Why the walk failed, e.g. "slave 1: CiA-402 timed out after 500 ms
	/// waiting for OPERATION ENABLED: stays in SWITCHED ON (statusword
	/// 0x0233)"; empty unless progress() is Failed.
	[[nodiscard]] std::string failureMessage() const;
	/// Throws ecmxf::Error with failureMessage() (ETIMEDOUT for a timeout,
	/// EIO for a fault or a lost state) if the walk failed.
	void throwIfFailed() const;

	[[nodiscard]] const Options &options() const noexcept { return opt_; }

private:
	enum class Why : std::uint8_t { None, Timeout, FaultNoReset, Left, Unstable };
	enum class ResetPhase : std::uint8_t { None, Low, High };

	unsigned slave_;
	Options opt_;
	Cia402State target_ = Cia402State::SwitchOnDisabled;
	Cia402Progress progress_ = Cia402Progress::Idle;
	std::optional<Cia402State> state_;
	bool seen_ = false;
	std::uint16_t statusword_ = 0;
	std::uint16_t lastBits_ = 0; // bits 0-3, 7 last written
	std::chrono::nanoseconds since_{ 0 };
	ResetPhase reset_ = ResetPhase::None;
	unsigned changes_ = 0; // state changes in this walk
	std::uint16_t failSw_ = 0;
	std::optional<Cia402State> failState_;
	Why why_ = Why::None;
	std::optional<Cia402State> awaited_;
};

/**
 * The profile-position set-point handshake (EST-584 manual 2.1.2/2.1.4):
 * the caller has written the target position (0x607A); the stepper makes a
 * rising edge of controlword bit 4 (new set-point) with bit 5 (change
 * immediately) and bit 6 (relative) as asked, waits for statusword bit 12
 * (set-point acknowledge), clears bit 4, and then, if asked, waits for
 * bit 10 (target reached). The drive must be in OPERATION ENABLED.
 */
class ECMXF_EXPORT PpSetPointStepper
{
public:
	struct Options {
		bool changeImmediately = false; ///< controlword bit 5
		bool relative = false;          ///< controlword bit 6
		/// Done only when the target is reached (bit 10), else when the
		/// set-point is acknowledged and bit 4 is back to 0.
		bool waitTargetReached = true;
		/// Longest wait for the acknowledge.
		std::chrono::nanoseconds ackTimeout = std::chrono::milliseconds(500);
		/// Longest wait for target reached after the acknowledge (zero:
		/// no limit).
		std::chrono::nanoseconds moveTimeout{ 0 };
	};

	explicit PpSetPointStepper(unsigned slave) : slave_(slave) {}

	/// Starts a new set-point at @p now.
	void start(std::chrono::nanoseconds now, Options options);
	void start(std::chrono::nanoseconds now) { start(now, Options{}); }

	/// One cycle: @p controlword is the caller's controlword (state bits
	/// included); bits 4-6 are replaced. Never throws, never allocates.
	Cia402Step step(std::uint16_t statusword, std::chrono::nanoseconds now,
			std::uint16_t controlword) noexcept;

	[[nodiscard]] Cia402Progress progress() const noexcept { return progress_; }
	/// The acknowledge was seen (the drive took the set-point).
	[[nodiscard]] bool acknowledged() const noexcept { return acked_; }
	[[nodiscard]] std::string failureMessage() const;
	void throwIfFailed() const;

private:
	enum class Phase : std::uint8_t { Low, Request, Move };
	enum class Why : std::uint8_t { None, NotEnabled, NoFreeBuffer, AckTimeout, MoveTimeout };

	unsigned slave_;
	Options opt_;
	Phase phase_ = Phase::Low;
	Cia402Progress progress_ = Cia402Progress::Idle;
	bool acked_ = false;
	unsigned requestSteps_ = 0;
	std::uint16_t statusword_ = 0;
	std::chrono::nanoseconds since_{ 0 };
	Why why_ = Why::None;
};

/// Homing status from statusword bits 13, 12, 10 (CiA 402 homing mode).
enum class HomingStatus : std::uint8_t {
	InProgress,          ///< 0 0 0
	InterruptedOrIdle,   ///< 0 0 1: interrupted or not started
	AttainedNotReached,  ///< 0 1 0: attained, target not reached yet
	Completed,           ///< 0 1 1
	ErrorMoving,         ///< 1 x 0: homing error, velocity not 0
	ErrorStopped,        ///< 1 x 1: homing error, velocity 0
};

[[nodiscard]] constexpr HomingStatus homingStatus(std::uint16_t statusword) noexcept
{
	const bool reached = statusword & cia402::kSwTargetReached;
	if (statusword & cia402::kSwHomingError)
		return reached ? HomingStatus::ErrorStopped : HomingStatus::ErrorMoving;
	if (statusword & cia402::kSwHomingAttained)
		return reached ? HomingStatus::Completed : HomingStatus::AttainedNotReached;
	return reached ? HomingStatus::InterruptedOrIdle : HomingStatus::InProgress;
}

[[nodiscard]] ECMXF_EXPORT std::string_view homingStatusName(HomingStatus s) noexcept;

/**
 * Homing (mode 6): a rising edge of controlword bit 4 starts the method in
 * 0x6098; bit 4 stays 1 while homing runs (0 interrupts it). Done when
 * statusword bits 12 (homing attained) and 10 (target reached) are 1;
 * failed on bit 13 (homing error) or the timeout. Statuswords of the first
 * @c settleSteps steps after the edge are not taken as a result (they may
 * still show an earlier homing).
 */
class ECMXF_EXPORT HomingStepper
{
public:
	struct Options {
		std::chrono::nanoseconds timeout = std::chrono::seconds(30);
		unsigned settleSteps = 1;
	};

	explicit HomingStepper(unsigned slave) : slave_(slave) {}

	void start(std::chrono::nanoseconds now, Options options);
	void start(std::chrono::nanoseconds now) { start(now, Options{}); }

	/// One cycle; bit 4 of @p controlword is replaced. Never throws,
	/// never allocates.
	Cia402Step step(std::uint16_t statusword, std::chrono::nanoseconds now,
			std::uint16_t controlword) noexcept;

	[[nodiscard]] Cia402Progress progress() const noexcept { return progress_; }
	[[nodiscard]] std::string failureMessage() const;
	void throwIfFailed() const;

private:
	enum class Phase : std::uint8_t { Low, Running };
	enum class Why : std::uint8_t { None, NotEnabled, Error, Timeout };

	unsigned slave_;
	Options opt_;
	Phase phase_ = Phase::Low;
	Cia402Progress progress_ = Cia402Progress::Idle;
	unsigned settle_ = 0;
	std::uint16_t statusword_ = 0;
	std::chrono::nanoseconds since_{ 0 };
	Why why_ = Why::None;
};

} // namespace ecmxf
