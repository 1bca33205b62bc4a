// SPDX-License-Identifier: MIT
/**
 * @file ecmxf/chip/chip402.hpp
 * @brief The chip's own CiA-402 engine (402_* commands).
 *
 * The engine's calls: dev.chip402().configure(), requestState(), state(),
 * setControl(), control(), statusword(), awaitState(); the names before
 * 0.4 (configure()...) are deprecated aliases, kept for one release.
 *
 * Motors are numbered 0..127. With the engine on, the chip owns
 * controlword bits 0-3 and 7 of the motor in every frame. A command the
 * chip refuses (command error) throws ecmxf::Error (EREMOTEIO) saying why it
 * can be refused; bad arguments throw EINVAL (Documentation/cia402.rst).
 *
 * A Chip402 is a view: it holds a reference to a Device (not owning it,
 * cheap to copy) and runs its commands through the device's command
 * runner. Get one with Device::chip402() or construct it from a Device&;
 * it must not outlive the device. Not thread-safe, like Device.
 */
#pragma once

#include <chrono>
#include <cstdint>

#include <ecmxf/export.hpp>
#include <ecmxf/model/types_cia402.hpp>

namespace ecmxf {

class Device;

/// The chip's own CiA-402 engine (402_* commands).
class ECMXF_EXPORT Chip402
{
public:
	/// The view of @p device's chip's CiA-402 engine.
	explicit Chip402(Device &device) noexcept : dev_(&device) {}
	/// The device this view runs its commands on.
	[[nodiscard]] Device &device() const noexcept { return *dev_; }

	/// 402_CONFIG_SET: @p motor is the drive at @p config.slave, with its
	/// controlword and statusword at the given byte offsets of that
	/// slave's process data, and the engine's control byte. Needs the bus
	/// initialized (ECAT_INIT_OP).
	void configure(unsigned motor, const Chip402Config &config) const;
	/// 402_STATE_SET: the state the engine walks @p motor to: SWITCH ON
	/// DISABLED, READY TO SWITCH ON, SWITCHED ON, OPERATION ENABLED or
	/// QUICK STOP ACTIVE (else EINVAL).
	void requestState(unsigned motor, Cia402State target) const;
	/// 402_STATE_GET: the motor's state as the chip reads its statusword.
	[[nodiscard]] Chip402State state(unsigned motor) const;
	/// 402_CTL_SET: the control byte, total motor count and slave.
	void setControl(unsigned motor, const Chip402Control &control) const;
	/// 402_CTL_GET: the control byte (bit 3 reads 0 again once a single
	/// fault reset is done).
	[[nodiscard]] Chip402Flags control(unsigned motor) const;
	/// 402_GET_STATUSWORD: the motor's statusword as the chip last read it.
	[[nodiscard]] std::uint16_t statusword(unsigned motor) const;
	/// Polls 402_STATE_GET (every @p poll on the link's clock) until
	/// @p motor is in @p target; throws ecmxf::Error (ETIMEDOUT) naming
	/// the awaited state, the state the motor stays in and its statusword
	/// after @p timeout.
	Cia402State awaitState(unsigned motor, Cia402State target, std::chrono::nanoseconds timeout,
				      std::chrono::nanoseconds poll = std::chrono::milliseconds(1)) const;

	// ---- the names before 0.4, kept for one release: each forwards to
	// the call above (Documentation/library.rst, "API changes before 0.1.0: one model for two masters")
	[[deprecated("use Chip402::configure")]] void chip402Configure(unsigned motor,
								       const Chip402Config &config) const
	{
		configure(motor, config);
	}
	[[deprecated("use Chip402::requestState")]] void chip402RequestState(unsigned motor, Cia402State target) const
	{
		requestState(motor, target);
	}
	[[deprecated("use Chip402::state")]] [[nodiscard]] Chip402State chip402State(unsigned motor) const
	{
		return state(motor);
	}
	[[deprecated("use Chip402::setControl")]] void chip402SetControl(unsigned motor,
									 const Chip402Control &control) const
	{
		setControl(motor, control);
	}
	[[deprecated("use Chip402::control")]] [[nodiscard]] Chip402Flags chip402Control(unsigned motor) const
	{
		return control(motor);
	}
	[[deprecated("use Chip402::statusword")]] [[nodiscard]] std::uint16_t chip402Statusword(unsigned motor) const
	{
		return statusword(motor);
	}
	[[deprecated("use Chip402::awaitState")]] Cia402State
	chip402AwaitState(unsigned motor, Cia402State target, std::chrono::nanoseconds timeout,
			  std::chrono::nanoseconds poll = std::chrono::milliseconds(1)) const
	{
		return awaitState(motor, target, timeout, poll);
	}

private:
	Device *dev_;
};

} // namespace ecmxf
