// SPDX-License-Identifier: MIT
//
// drive.hpp - the CiA-402 drive shared by the EST-584 and servo models: the
// state machine of the ECM-XF manual's appendix (transitions 0..16, fault
// reset on a rising edge of controlword bit 7), the statusword, and the
// modes PP (1), PV (3), HM (6), CSP (8), CSV (9), CST (10) on a simple
// shaft model. Each model binds the process variables below to its own
// object dictionary and says which modes it supports.

#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <ecmxf/model/types_cia402.hpp>
#include <ecmxf/sim/slaves.hpp>

#include "slaves/slave_base.hpp"

namespace ecmxf::sim::slaves {

/// CiA-402 states (ECM-XF manual, appendix 1): the one state type of the
/// model (<ecmxf/model/types_cia402.hpp>), which the library decodes too.
using Cia402State = ecmxf::Cia402State;

/// Controlword commands (CiA 402; bit 7 = fault reset).
enum class Cia402Command : std::uint8_t {
	None,           ///< bit 7 set, or no pattern
	Shutdown,       ///< xxxx x110 (bit 7 = 0)
	SwitchOn,       ///< xxxx 0111: switch on / disable operation
	EnableOperation,///< xxxx 1111
	DisableVoltage, ///< xxxx xx0x
	QuickStop,      ///< xxxx x01x
};

[[nodiscard]] Cia402Command decodeControlword(std::uint16_t cw);
/// Statusword bits 0..3, 5, 6 of a state (the appendix table).
[[nodiscard]] std::uint16_t cia402StateBits(Cia402State s);

/// Modes of operation (0x6060) and their 0x6502 bits.
namespace mode {
inline constexpr std::int8_t PP = 1;
inline constexpr std::int8_t PV = 3;
inline constexpr std::int8_t HM = 6;
inline constexpr std::int8_t CSP = 8;
inline constexpr std::int8_t CSV = 9;
inline constexpr std::int8_t CST = 10;
[[nodiscard]] inline std::uint32_t bit(std::int8_t m)
{
	return m >= 1 ? std::uint32_t{ 1 } << (m - 1) : 0;
}
} // namespace mode

/// CiA-402 emergency error codes the drives raise.
namespace errc {
inline constexpr std::uint16_t FollowingError = 0x8611;
inline constexpr std::uint16_t CommunicationLost = 0x8130; // left OP by an error
} // namespace errc

struct DriveConfig {
	std::uint32_t supportedModes = 0;   ///< 0x6502
	bool est584 = false;                ///< EST-584 statusword bits 8, 14, 15
	double homingTravelLimit = 1e6;     ///< units searched before a homing error
	double accelPerPermille = 0;        ///< CST: units/s^2 per 1 permille torque
	double viscous = 0;                 ///< CST: viscous friction, 1/s
	std::vector<std::uint32_t> dcCyclesNs; ///< allowed SYNC0 cycles
	bool dcRequired = false;            ///< S->O needs SYNC0 (servo)
};

class DriveBase : public SlaveBase, public virtual Cia402Model
{
public:
	// ---- Cia402Model ----
	[[nodiscard]] std::uint16_t controlword() const override { return controlword_; }
	[[nodiscard]] std::uint16_t statusword() const override { return statusword_; }
	[[nodiscard]] std::int8_t modeDisplay() const override { return modeDisplay_; }
	[[nodiscard]] std::int32_t positionActual() const override { return positionActual_; }
	[[nodiscard]] std::int32_t velocityActual() const override { return velocityActual_; }
	[[nodiscard]] std::uint16_t errorCode() const override { return errorCode_; }
	void setPositionActual(std::int32_t position) override;
	void injectFault(std::uint16_t errorCode) override;

	[[nodiscard]] Cia402State cia402State() const { return st_; }

protected:
	DriveBase(BaseConfig base, DriveConfig drive);

	void step(std::chrono::nanoseconds dt, bool outputsApplied) override;
	std::uint16_t checkTransition(AlState from, AlState to) override;
	void onAlChange(AlState from, AlState to, bool error) override;
	void onPowerOn() override;

	/// The CiA-301 objects every drive model has: 0x1000 device type (bound to
	/// @p deviceType, its value the default), 0x1001 error register, 0x1008
	/// device name and, where given, 0x1009/0x100A hardware and software
	/// versions.
	void addDeviceObjects(std::uint32_t &deviceType, std::string &name,
			      std::string *hwVersion = nullptr, std::string *swVersion = nullptr);
	/// The CiA-402 objects every drive model has alike: 0x603F, 0x6040,
	/// 0x6041, 0x6060 (default CSP, checked by checkMode()), 0x6061, 0x6064,
	/// 0x606C, 0x607A, 0x60FF and 0x6502 (drv_.supportedModes).
	void addCia402Objects();
	/// Check hook for 0x6060: supported mode or abort 0x06090030.
	[[nodiscard]] std::uint32_t checkMode(std::uint64_t raw) const;
	/// The following error window in force (0x6065).
	[[nodiscard]] virtual double followingWindow() const { return followingWindow_; }
	/// Home switch state at the current position.
	[[nodiscard]] bool homeSwitchAt(double userPos) const;
	void fault(std::uint16_t code);
	/// Statusword, actual values and inputs from the current state.
	void composeOutputs();

	DriveConfig drv_;

	// ---- process variables, bound to the object dictionary by the model ----
	std::uint16_t controlword_ = 0;      // 0x6040
	std::uint16_t statusword_ = 0;       // 0x6041
	std::uint16_t errorCode_ = 0;        // 0x603F
	std::uint8_t errorRegister_ = 0;     // 0x1001
	std::int8_t modeOfOperation_ = 0;    // 0x6060
	std::int8_t modeDisplay_ = 0;        // 0x6061
	std::int32_t positionDemand_ = 0;    // 0x6062
	std::int32_t positionActual_ = 0;    // 0x6064
	std::int32_t velocityDemand_ = 0;    // 0x606B
	std::int32_t velocityActual_ = 0;    // 0x606C
	std::int32_t targetPosition_ = 0;    // 0x607A
	std::int32_t homeOffset_ = 0;        // 0x607C
	std::uint32_t followingWindow_ = 0;  // 0x6065
	std::uint32_t maxProfileVelocity_ = 0; // 0x607F
	std::uint32_t profileVelocity_ = 0;  // 0x6081
	std::uint32_t startStopVelocity_ = 0;// 0x6082
	std::uint32_t profileAcceleration_ = 0; // 0x6083
	std::uint32_t profileDeceleration_ = 0; // 0x6084
	std::uint32_t quickStopDeceleration_ = 0; // 0x6085
	std::int16_t quickStopOption_ = 0;   // 0x605A
	std::int8_t homingMethod_ = 0;       // 0x6098
	std::uint32_t homingSpeedFast_ = 0;  // 0x6099:01
	std::uint32_t homingSpeedSlow_ = 0;  // 0x6099:02
	std::uint32_t homingAcceleration_ = 0; // 0x609A
	std::int32_t positionOffset_ = 0;    // 0x60B0
	std::uint16_t probeFunction_ = 0;    // 0x60B8
	std::uint16_t probeStatus_ = 0;      // 0x60B9
	std::int32_t probePosition_ = 0;     // 0x60BA
	std::int32_t followingError_ = 0;    // 0x60F4
	std::uint32_t digitalInputs_ = 0;    // 0x60FD
	std::int32_t targetVelocity_ = 0;    // 0x60FF
	std::int16_t targetTorque_ = 0;      // 0x6071
	std::uint16_t maxTorque_ = 0;        // 0x6072
	std::int16_t torqueActual_ = 0;      // 0x6077
	std::uint32_t supportedModes_ = 0;   // 0x6502

	// ---- shaft ----
	double pos_ = 0;       // position actual, user units
	double vel_ = 0;       // units/s
	double homeShift_ = 0; // user = shaft + homeShift_
	std::optional<double> homeSwitch_; // shaft position of the switch edge
	double loadTorque_ = 0;

private:
	enum class Homing : std::uint8_t { Idle, Fast, Back, Slow, Stop, Done, Error, Interrupted };

	void enableOperation();
	void runMode(double dt, std::uint16_t cw, std::uint16_t prev);
	void runPp(double dt, std::uint16_t cw, std::uint16_t prev);
	void runPv(double dt, std::uint16_t cw);
	void runHm(double dt, std::uint16_t cw, std::uint16_t prev);
	void runCsp(double dt);
	void runCsv(double dt);
	void runCst(double dt);
	void decelerate(double dec, double dt);
	void startPpMove(double target);
	[[nodiscard]] bool quickStopStays() const;
	[[nodiscard]] bool modeSupported(std::int8_t m) const;

	Cia402State st_ = Cia402State::NotReadyToSwitchOn;
	std::uint16_t prevCw_ = 0;
	bool limited_ = false; // CSP/CSV speed limit active (statusword bit 11)

	// PP
	bool ppMoving_ = false;
	double ppTarget_ = 0;
	bool ppBuffered_ = false;
	double ppBufferedTarget_ = 0;
	double ppLastTarget_ = 0;
	bool ppRequest_ = false;
	bool ppAck_ = false;
	// HM
	Homing hm_ = Homing::Idle;
	bool hmPreEdge_ = false;   // switch state before the final edge
	double hmDir_ = 1;         // direction of the fast search
	double hmFinalDir_ = 1;    // direction of the final, slow approach
	double hmStart_ = 0;
	bool hmAttained_ = false;
	// mode-dependent statusword bits of the last step
	bool bit10_ = true, bit12_ = false, bit13_ = false;
};

/// Trapezoidal move of @p pos toward @p target (velocity @p vel updated),
/// limited by @p vmax, @p acc, @p dec. Returns true on arrival (pos ==
/// target, vel == 0).
bool profileStep(double &pos, double &vel, double target, double vmax, double acc, double dec,
		 double dt);
/// Velocity ramp of @p vel toward @p target; returns the new velocity.
double ramp(double vel, double target, double acc, double dec, double dt);

} // namespace ecmxf::sim::slaves
