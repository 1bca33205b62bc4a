// SPDX-License-Identifier: MIT
//
// Chip402 (include/ecmxf/chip/chip402.hpp): the ECM-XF's internal CiA-402
// engine:
// 402_CONFIG_SET (26), 402_STATE_SET (27), 402_STATE_GET (28),
// 402_CTL_SET (29), 402_CTL_GET (30), 402_GET_STATUSWORD (74), and a wait
// for a state (Documentation/cia402.rst).

#include <ecmxf/chip/chip402.hpp>

#include <ecmxf/device.hpp>

#include <cerrno>
#include <string>

#include <ecmxf/model/cia402.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/link.hpp>

#include "base/text.hpp"
#include "device/runner.hpp"
#include "ecmxf-proto.h"

namespace ecmxf {

using detail::hex8;

namespace {

constexpr unsigned kMotors = 128;   // 402_* command parameter: motor 0..127
constexpr unsigned kSlaves = 128;   // the chip's slave positions 0..127
constexpr std::uint8_t kCtlKey = 0x5A; // 402_CTL_SET data 1

/// "402_STATE_SET (motor 3): "
std::string prefix(const char *name, unsigned motor)
{
	std::string s(name);
	s.append(" (motor ").append(std::to_string(motor)).append("): ");
	return s;
}

void checkRange(const char *name, unsigned motor, const char *what, unsigned value, unsigned lo, unsigned hi)
{
	if (value >= lo && value <= hi)
		return;
	std::string m(name);
	m.append(": ")
		.append(what)
		.append(" ")
		.append(std::to_string(value))
		.append(" is out of range ")
		.append(std::to_string(lo))
		.append("..")
		.append(std::to_string(hi));
	if (std::string_view(what) != "motor")
		m.append(" (motor ").append(std::to_string(motor)).append(")");
	throw Error(m, EINVAL);
}

void checkMotor(const char *name, unsigned motor)
{
	checkRange(name, motor, "motor", motor, 0, kMotors - 1);
}

Command command402(std::uint8_t code, unsigned motor)
{
	return detail::cmd(code, static_cast<std::uint8_t>(motor));
}

/// Runs @p c through the one command runner; a refusal (command error)
/// throws EREMOTEIO naming the command, the motor and @p why.
Response run(Device &dev, const Command &c, const char *name, unsigned motor, const std::string &why)
{
	std::string context = prefix(name, motor);
	context.resize(context.size() - 2); // "402_STATE_SET (motor 3)"
	return detail::immediate(dev, c, context, why, EREMOTEIO);
}

std::string notConfigured(unsigned motor)
{
	std::string s("motor ");
	s.append(std::to_string(motor)).append(" is not configured (402_CONFIG_SET first)");
	return s;
}

} // namespace

Chip402 Device::chip402() noexcept
{
	return Chip402(*this);
}

void Chip402::configure(unsigned motor, const Chip402Config &config) const
{
	const char *name = "402_CONFIG_SET";
	checkMotor(name, motor);
	checkRange(name, motor, "slave", config.slave, 0, kSlaves - 1);
	checkRange(name, motor, "controlword offset", config.controlwordOffset, 0, 255);
	checkRange(name, motor, "statusword offset", config.statuswordOffset, 0, 255);
	Command c = command402(ECMXF_CMD_402_CONFIG_SET, motor);
	c.data = { static_cast<std::uint8_t>(config.controlwordOffset),
		   static_cast<std::uint8_t>(config.statuswordOffset), config.flags.toByte(),
		   static_cast<std::uint8_t>(config.slave) };
	std::string why("the bus is not initialized (ECAT_INIT_OP), slave ");
	why.append(std::to_string(config.slave))
		.append(" does not exist, or the controlword (offset ")
		.append(std::to_string(config.controlwordOffset))
		.append(") or statusword (offset ")
		.append(std::to_string(config.statuswordOffset))
		.append(") is not inside that slave's process data");
	run(*dev_, c, name, motor, why);
}

void Chip402::requestState(unsigned motor, Cia402State target) const
{
	const char *name = "402_STATE_SET";
	checkMotor(name, motor);
	if (!cia402Requestable(target)) {
		std::string m = prefix(name, motor);
		m.append(cia402StateName(target))
			.append(" (code ")
			.append(hex8(cia402StateCode(target)))
			.append(") cannot be requested: SWITCH ON DISABLED 0x40, READY TO SWITCH ON 0x21, "
				"SWITCHED ON 0x23, OPERATION ENABLED 0x27 or QUICK STOP ACTIVE 0x07");
		throw Error(m, EINVAL);
	}
	Command c = command402(ECMXF_CMD_402_STATE_SET, motor);
	c.data[0] = cia402StateCode(target);
	run(*dev_, c, name, motor, notConfigured(motor));
}

Chip402State Chip402::state(unsigned motor) const
{
	const char *name = "402_STATE_GET";
	checkMotor(name, motor);
	const Response r = run(*dev_, command402(ECMXF_CMD_402_STATE_GET, motor), name, motor, notConfigured(motor));
	Chip402State s;
	s.code = r.ret;
	s.state = cia402StateFromCode(r.ret);
	return s;
}

void Chip402::setControl(unsigned motor, const Chip402Control &control) const
{
	const char *name = "402_CTL_SET";
	checkMotor(name, motor);
	checkRange(name, motor, "motor count", control.motorCount, 1, kMotors);
	checkRange(name, motor, "slave", control.slave, 0, kSlaves - 1);
	Command c = command402(ECMXF_CMD_402_CTL_SET, motor);
	c.data = { control.flags.toByte(), kCtlKey, static_cast<std::uint8_t>(control.motorCount),
		   static_cast<std::uint8_t>(control.slave) };
	std::string why = notConfigured(motor);
	why.append(", or slave ").append(std::to_string(control.slave)).append(" does not exist");
	run(*dev_, c, name, motor, why);
}

Chip402Flags Chip402::control(unsigned motor) const
{
	const char *name = "402_CTL_GET";
	checkMotor(name, motor);
	const Response r = run(*dev_, command402(ECMXF_CMD_402_CTL_GET, motor), name, motor, notConfigured(motor));
	return Chip402Flags::fromByte(r.ret);
}

std::uint16_t Chip402::statusword(unsigned motor) const
{
	const char *name = "402_GET_STATUSWORD";
	checkMotor(name, motor);
	const Response r =
		run(*dev_, command402(ECMXF_CMD_402_GET_STATUSWORD, motor), name, motor, notConfigured(motor));
	if (r.data.size() != 2) {
		std::string m = prefix(name, motor);
		m.append("the answer has ").append(std::to_string(r.data.size())).append(" data bytes, expected 2");
		throw Error(m, EPROTO);
	}
	return static_cast<std::uint16_t>(r.data[0] | r.data[1] << 8);
}

Cia402State Chip402::awaitState(unsigned motor, Cia402State target, std::chrono::nanoseconds timeout,
				std::chrono::nanoseconds poll) const
{
	const char *name = "402_STATE_GET";
	checkMotor(name, motor);
	Link &t = dev_->link();
	const auto start = t.now();
	for (;;) {
		const Chip402State s = state(motor);
		if (s.state == target)
			return target;
		if (t.now() - start >= timeout) {
			const std::uint16_t sw = statusword(motor);
			std::string m("motor ");
			m.append(std::to_string(motor)).append(": the chip's CiA-402 engine timed out after ");
			const auto ns = timeout.count();
			if (ns % 1'000'000 == 0)
				m.append(std::to_string(ns / 1'000'000)).append(" ms");
			else
				m.append(std::to_string(ns / 1'000)).append(" us");
			m.append(" waiting for ")
				.append(cia402StateName(target))
				.append(": stays in ")
				.append(s.state ? std::string(cia402StateName(*s.state))
						: std::string("no CiA-402 state (code ").append(hex8(s.code)).append(")"))
				.append(" (statusword ")
				.append(cia402Hex16(sw))
				.append(")");
			throw Error(m, ETIMEDOUT);
		}
		t.sleepFor(poll);
	}
}

} // namespace ecmxf
