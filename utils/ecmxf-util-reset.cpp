// SPDX-License-Identifier: MIT
/*
 * ecmxf-util reset - ASYNCCMD_RESET, or WARM_RESET with --warm --force.
 */
#include "ecmxf-util.hpp"

#include <cstdio>
#include <memory>

#include <ecmxf/device.hpp>
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/verbs.hpp>

namespace ecmxf_util {

const char *const kResetHelp =
	"Usage: ecmxf-util [global options] reset [--async | --warm --force]\n"
	"\n"
	"--async (the default): ASYNCCMD_RESET with parameter 0x05 (clear the\n"
	"async busy flag and abandon the last async command), which frees a chip\n"
	"stuck in an async command; the network is left as it is.\n"
	"--warm: WARM_RESET, the chip restarts with its power-on settings\n"
	"(112-byte data section, fixed check word, no network): destructive, it\n"
	"stops the bus; needs --force.\n"
	"Prints what was sent (nothing with -q).\n"
	"\n"
	"Options:\n"
	"  --async      ASYNCCMD_RESET (default)\n"
	"  --warm       WARM_RESET\n"
	"  --force      allow --warm\n"
	"  -h, --help   show this help\n";

int cmdReset(Globals &g, const Args &args)
{
	bool async = false, warm = false, force = false;
	const auto pos = parseArgs("reset", args, g, kResetHelp,
				   { { "", "--async", &async, nullptr },
				     { "", "--warm", &warm, nullptr },
				     { "", "--force", &force, nullptr } });
	if (!pos)
		return 0;
	if (!pos->empty())
		throw UsageError("reset: unexpected argument '" + pos->front() + "' (try 'ecmxf-util reset --help')");
	if (async && warm)
		throw UsageError("reset: --async or --warm, not both");
	if (warm && !force)
		throw UsageError("reset: --warm restarts the chip and stops the EtherCAT bus: add --force to do it");

	const DevicePtr dev = openDevice(g);
	if (warm) {
		ecmxf::verbsOf(*dev)->reset(); // WARM_RESET (include/ecmxf/verbs.hpp)
		if (!g.quiet)
			std::printf("WARM_RESET: the chip restarted with its power-on settings\n");
		return 0;
	}
	const std::uint8_t actions = ecmxf::async_reset::kClearBusy | ecmxf::async_reset::kAbandon;
	dev->chip().resetAsyncCommand(actions);
	if (!g.quiet)
		std::printf("ASYNCCMD_RESET 0x%02x: async busy flag cleared, last async command abandoned\n",
			    actions);
	return 0;
}

} // namespace ecmxf_util
