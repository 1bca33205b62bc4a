// SPDX-License-Identifier: MIT
/*
 * ecmxf-util cia402 - a CiA-402 drive over SDO: status, and walks of the
 * state machine with the library's Cia402Stepper.
 */
#include "ecmxf-util.hpp"

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include <ecmxf/model/cia402.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/bus/sdo.hpp>
#include <ecmxf/error.hpp>
#include <ecmxf/link/link.hpp>
#include <ecmxf/verbs.hpp>

namespace ecmxf_util {

const char *const kCia402Help =
	"Usage: ecmxf-util [global options] cia402 -p N status [--json]\n"
	"       ecmxf-util [global options] cia402 -p N enable|disable|fault-reset|quick-stop\n"
	"       ecmxf-util [global options] cia402 -p N move (--pp|--pv|--csp) TARGET\n"
	"                  [--velocity V] [--accel A] [--relative] [--time MS]\n"
	"       ecmxf-util [global options] cia402 -p N home [--method M]\n"
	"\n"
	"A CiA-402 drive at position N, over SDO (0x6040 controlword, 0x6041\n"
	"statusword, 0x6061 mode display, 0x6064 position actual, 0x606C velocity\n"
	"actual).\n"
	"  status       statusword, state, mode of operation, position, velocity\n"
	"  enable       walk to OPERATION ENABLED (resetting a fault on the way)\n"
	"  disable      walk to SWITCH ON DISABLED (Disable Voltage: power stage off)\n"
	"  fault-reset  leave FAULT (rising edge of controlword bit 7) to SWITCH ON\n"
	"               DISABLED; a drive not in FAULT is left as it is\n"
	"  quick-stop   Quick Stop from OPERATION ENABLED to QUICK STOP ACTIVE\n"
	"  move, home   motion (profile position / velocity, cyclic synchronous\n"
	"               position; homing)\n"
	"The walks poll the statusword and write the controlword by SDO, one step\n"
	"of the library's Cia402Stepper per millisecond, and print the state\n"
	"reached; a drive that does not follow within 1 s fails naming the state\n"
	"awaited, the state it stays in and its statusword.\n"
	"\n"
	"A fresh bus is brought up to PRE-OP first (SDO needs a mailbox); a bus\n"
	"that is already up is used as it is. In OP the controlword of the\n"
	"process data overrides the SDO writes (cia402 move stops a drive through\n"
	"the process data). A signal (SIGINT, SIGTERM, SIGHUP) during enable\n"
	"walks the drive back to SWITCH ON DISABLED; exit 128 + the signal.\n"
	"\n"
	"Options:\n"
	"  -p, --position N  the drive (bus position, from 0); required\n"
	"  --json            status: {position, statusword, state, mode, mode_name,\n"
	"                    position_actual, velocity_actual}; walks: {position,\n"
	"                    state, statusword}\n"
	"  -h, --help        show this help\n";

namespace {

const char *modeName(std::int8_t m)
{
	switch (m) {
	case 0: return "none";
	case 1: return "profile position";
	case 3: return "profile velocity";
	case 4: return "profile torque";
	case 6: return "homing";
	case 7: return "interpolated position";
	case 8: return "cyclic synchronous position";
	case 9: return "cyclic synchronous velocity";
	case 10: return "cyclic synchronous torque";
	default: return "manufacturer specific";
	}
}

std::string stateText(std::uint16_t sw)
{
	const auto s = ecmxf::cia402StateFrom(sw);
	return s ? std::string(ecmxf::cia402StateName(*s)) : "no CiA-402 state";
}

} // namespace

int cmdCia402(Globals &g, const Args &args)
{
	// move / home have their own options: hand them over whole
	for (const std::string_view a : args)
		if (a == "move" || a == "home")
			return cia402Motion(g, args);

	std::optional<std::string> posText;
	const auto pos = parseArgs("cia402", args, g, kCia402Help, { { "-p", "--position", nullptr, &posText } });
	if (!pos)
		return 0;
	if (pos->size() != 1)
		throw UsageError(pos->empty() ? "cia402: what? (status, enable, disable, fault-reset, quick-stop, "
						"move, home)"
					      : "cia402: one operation only (try 'ecmxf-util cia402 --help')");
	const std::string &op = pos->front();
	std::optional<ecmxf::Cia402State> target;
	bool faultResetOnly = false;
	if (op == "status") {
	} else if (op == "enable") {
		target = ecmxf::Cia402State::OperationEnabled;
	} else if (op == "disable") {
		target = ecmxf::Cia402State::SwitchOnDisabled;
	} else if (op == "fault-reset") {
		target = ecmxf::Cia402State::SwitchOnDisabled;
		faultResetOnly = true;
	} else if (op == "quick-stop") {
		target = ecmxf::Cia402State::QuickStopActive;
	} else {
		throw UsageError("cia402: unknown operation '" + op +
				 "' (status, enable, disable, fault-reset, quick-stop, move, home)");
	}
	std::uint8_t position = parsePosition("cia402", posText);

	const DevicePtr dev = openDevice(g);
	position = selectSlave(*dev, position, ensureBus(*dev, BusNeed::PreOp));
	ecmxf::Device &d = *dev;
	// an I/O terminal has no statusword: say what it is not, not only the abort
	try {
		(void)d.sdo().read<std::uint16_t>(position, 0x6041, 0);
	} catch (const ecmxf::SdoError &e) {
		// 0x06020000 object does not exist, 0x08000023 no object dictionary
		if (e.abortCode() != 0x06020000 && e.abortCode() != 0x08000023)
			throw;
		throw ecmxf::Error("slave " + std::to_string(position) +
					   " is not a CiA-402 drive: it has no statusword 0x6041 (" + e.what() + ")",
				   ENODEV);
	}

	if (!target) {
		const auto sw = d.sdo().read<std::uint16_t>(position, 0x6041, 0);
		const auto mode = d.sdo().read<std::int8_t>(position, 0x6061, 0);
		const auto actPos = d.sdo().read<std::int32_t>(position, 0x6064, 0);
		const auto actVel = d.sdo().read<std::int32_t>(position, 0x606C, 0);
		if (g.json) {
			std::printf("{\"position\": %u, \"statusword\": %u, \"state\": %s, \"mode\": %d, "
				    "\"mode_name\": %s, \"position_actual\": %d, \"velocity_actual\": %d}\n",
				    position, sw, jsonString(stateText(sw)).c_str(), mode,
				    jsonString(modeName(mode)).c_str(), actPos, actVel);
			return 0;
		}
		std::printf("statusword:  0x%04x\n", sw);
		std::printf("state:       %s\n", stateText(sw).c_str());
		std::printf("mode:        %d (%s)\n", mode, modeName(mode));
		std::printf("position:    %d\n", actPos);
		std::printf("velocity:    %d\n", actVel);
		return 0;
	}

	// the verbs of both masters (include/ecmxf/verbs.hpp): the state machine over SDO.
	// enable: a stop signal during the walk walks the drive back to
	// SWITCH ON DISABLED (said on stderr, exit 128 + the signal)
	std::optional<StopSignals> signals;
	if (*target == ecmxf::Cia402State::OperationEnabled)
		signals.emplace();
	const std::uint16_t sw = ecmxf::cia402WalkBySdo(d, position, *target, faultResetOnly);
	if (const int sig = StopSignals::pending()) {
		const std::uint16_t off = ecmxf::cia402WalkBySdo(d, position, ecmxf::Cia402State::SwitchOnDisabled);
		std::fprintf(stderr, "ecmxf-util: cia402 enable: interrupted by %s: slave %u: disabled: %s (statusword 0x%04x)\n",
			     std::string(signalName(sig)).c_str(), position, stateText(off).c_str(), off);
		return StopSignals::exitCode(sig);
	}
	if (g.json) {
		std::printf("{\"position\": %u, \"state\": %s, \"statusword\": %u}\n", position,
			    jsonString(stateText(sw)).c_str(), sw);
		return 0;
	}
	std::printf("%s (statusword 0x%04x)\n", stateText(sw).c_str(), sw);
	return 0;
}

} // namespace ecmxf_util
