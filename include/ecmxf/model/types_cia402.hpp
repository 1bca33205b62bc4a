// SPDX-License-Identifier: MIT
/**
 * @file types_cia402.hpp
 * @brief Value types of the typed commands for the chip's CiA-402 engine and the CiA-402 state codes.
 *
 * The CiA-402 states and their codes are those of the ECM-XF manuals
 * (402_STATE_SET, appendix "CiA 402 State Machine"): the code of a state
 * is the statusword's bits 6, 5, 3, 2, 1, 0 in their places, e.g.
 * OPERATION ENABLED = 0x27. The host-side state machine over controlword
 * and statusword is in <ecmxf/model/cia402.hpp>; Documentation/cia402.rst
 * describes both.
 */
#pragma once

#include <ecmxf/export.hpp>

#include <cstdint>
#include <optional>
#include <string_view>

namespace ecmxf {

/// The states of the CiA-402 drive state machine.
enum class Cia402State : std::uint8_t {
	NotReadyToSwitchOn,
	SwitchOnDisabled,
	ReadyToSwitchOn,
	SwitchedOn,
	OperationEnabled,
	QuickStopActive,
	FaultReactionActive,
	Fault,
};

/// The state codes of 402_STATE_SET / 402_STATE_GET (both manuals): the
/// statusword bits 6, 5, 3, 2, 1, 0 of the state.
namespace cia402code {
inline constexpr std::uint8_t NotReadyToSwitchOn = 0x00;
inline constexpr std::uint8_t SwitchOnDisabled = 0x40;
inline constexpr std::uint8_t ReadyToSwitchOn = 0x21;
inline constexpr std::uint8_t SwitchedOn = 0x23;
inline constexpr std::uint8_t OperationEnabled = 0x27;
inline constexpr std::uint8_t QuickStopActive = 0x07;
inline constexpr std::uint8_t FaultReactionActive = 0x0F;
inline constexpr std::uint8_t Fault = 0x08;
} // namespace cia402code

/// The chip's code of @p s (cia402code).
[[nodiscard]] constexpr std::uint8_t cia402StateCode(Cia402State s) noexcept
{
	switch (s) {
	case Cia402State::NotReadyToSwitchOn:
		return cia402code::NotReadyToSwitchOn;
	case Cia402State::SwitchOnDisabled:
		return cia402code::SwitchOnDisabled;
	case Cia402State::ReadyToSwitchOn:
		return cia402code::ReadyToSwitchOn;
	case Cia402State::SwitchedOn:
		return cia402code::SwitchedOn;
	case Cia402State::OperationEnabled:
		return cia402code::OperationEnabled;
	case Cia402State::QuickStopActive:
		return cia402code::QuickStopActive;
	case Cia402State::FaultReactionActive:
		return cia402code::FaultReactionActive;
	case Cia402State::Fault:
		return cia402code::Fault;
	}
	return 0xFF;
}

/// The state of a chip state code; std::nullopt for a code that is none
/// of the eight.
[[nodiscard]] constexpr std::optional<Cia402State> cia402StateFromCode(std::uint8_t code) noexcept
{
	switch (code) {
	case cia402code::NotReadyToSwitchOn:
		return Cia402State::NotReadyToSwitchOn;
	case cia402code::SwitchOnDisabled:
		return Cia402State::SwitchOnDisabled;
	case cia402code::ReadyToSwitchOn:
		return Cia402State::ReadyToSwitchOn;
	case cia402code::SwitchedOn:
		return Cia402State::SwitchedOn;
	case cia402code::OperationEnabled:
		return Cia402State::OperationEnabled;
	case cia402code::QuickStopActive:
		return Cia402State::QuickStopActive;
	case cia402code::FaultReactionActive:
		return Cia402State::FaultReactionActive;
	case cia402code::Fault:
		return Cia402State::Fault;
	default:
		return std::nullopt;
	}
}

/// The state's name as the manuals write it, e.g. "OPERATION ENABLED".
[[nodiscard]] constexpr std::string_view cia402StateName(Cia402State s) noexcept
{
	switch (s) {
	case Cia402State::NotReadyToSwitchOn:
		return "NOT READY TO SWITCH ON";
	case Cia402State::SwitchOnDisabled:
		return "SWITCH ON DISABLED";
	case Cia402State::ReadyToSwitchOn:
		return "READY TO SWITCH ON";
	case Cia402State::SwitchedOn:
		return "SWITCHED ON";
	case Cia402State::OperationEnabled:
		return "OPERATION ENABLED";
	case Cia402State::QuickStopActive:
		return "QUICK STOP ACTIVE";
	case Cia402State::FaultReactionActive:
		return "FAULT REACTION ACTIVE";
	case Cia402State::Fault:
		return "FAULT";
	}
	return "?";
}

/// The control byte of the chip's CiA-402 engine (402_CONFIG_SET data 2,
/// 402_CTL_SET data 0, 402_CTL_GET return value).
struct Chip402Flags {
	/// Bit 4: the engine drives the motor's controlword (it owns bits
	/// 0-3 and 7; the host's bits 0-3 and 7 are ignored).
	bool engine = false;
	/// Bit 3: one fault reset; the chip clears the bit once the drive
	/// has left FAULT.
	bool singleFaultReset = false;
	/// Bit 7: reset every fault automatically.
	bool autoFaultReset = false;

	static constexpr std::uint8_t kSingleFaultReset = 0x08;
	static constexpr std::uint8_t kEngine = 0x10;
	static constexpr std::uint8_t kAutoFaultReset = 0x80;

	/// The control byte.
	[[nodiscard]] constexpr std::uint8_t toByte() const noexcept
	{
		return static_cast<std::uint8_t>((engine ? kEngine : 0) |
						 (singleFaultReset ? kSingleFaultReset : 0) |
						 (autoFaultReset ? kAutoFaultReset : 0));
	}
	/// The flags of a control byte (bits the manuals do not name are
	/// dropped).
	[[nodiscard]] static constexpr Chip402Flags fromByte(std::uint8_t b) noexcept
	{
		Chip402Flags f;
		f.engine = (b & kEngine) != 0;
		f.singleFaultReset = (b & kSingleFaultReset) != 0;
		f.autoFaultReset = (b & kAutoFaultReset) != 0;
		return f;
	}
	friend constexpr bool operator==(const Chip402Flags &, const Chip402Flags &) = default;
};

/// 402_CONFIG_SET: which slave a motor is and where its controlword and
/// statusword are in that slave's process data.
struct Chip402Config {
	/// Slave position (0 = first slave on the bus), 0..255.
	unsigned slave = 0;
	/// Byte offset of the controlword (0x6040) within the slave's outputs.
	unsigned controlwordOffset = 0;
	/// Byte offset of the statusword (0x6041) within the slave's inputs.
	unsigned statuswordOffset = 0;
	/// The engine's control byte.
	Chip402Flags flags;
};

/// 402_CTL_SET: the control byte again, with the total motor count and the
/// motor's slave.
struct Chip402Control {
	Chip402Flags flags;
	/// Total number of motors the engine handles (data 2), 1..128.
	unsigned motorCount = 1;
	/// Slave position of the motor (data 3), 0..255.
	unsigned slave = 0;
};

/// 402_STATE_GET: the chip's state code of the motor and the state it
/// stands for.
struct Chip402State {
	std::uint8_t code = 0;            ///< the return value as the chip sent it
	std::optional<Cia402State> state; ///< std::nullopt: not a CiA-402 state code
};

} // namespace ecmxf
