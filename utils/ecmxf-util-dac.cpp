// SPDX-License-Identifier: MIT
/*
 * ecmxf-util dac - the chip's analog output.
 */
#include "ecmxf-util.hpp"

#include <cstdio>
#include <memory>
#include <string>

#include <ecmxf/device.hpp>
#include <ecmxf/chip/peripherals.hpp>

namespace ecmxf_util {

const char *const kDacHelp =
	"Usage: ecmxf-util [global options] dac write CH VALUE\n"
	"\n"
	"Set the ECM-XF's 12-bit DAC output (DAC_FUNC_OP 34). The chip has one\n"
	"output, channel 0. VALUE is 0..4095 (0..3.3 V). Sends DacOpen with\n"
	"trigger 0x0000 (every DacSetData converts), then DacSetData. Prints\n"
	"nothing on success.\n"
	"\n"
	"Options:\n"
	"  -h, --help  show this help\n";

int cmdDac(Globals &g, const Args &args)
{
	const auto pos = parseArgs("dac", args, g, kDacHelp, {});
	if (!pos)
		return 0;
	if (pos->empty() || (*pos)[0] != "write")
		throw UsageError(pos->empty() ? "dac: write? (dac write CH VALUE)"
					      : "dac: unknown operation '" + (*pos)[0] + "' (write)");
	if (pos->size() != 3)
		throw UsageError("dac: write needs CH VALUE (try 'ecmxf-util dac --help')");
	parseUnsigned("dac", "CH (the ECM-XF has one DAC output, channel 0)", (*pos)[1], 0);
	const auto value = static_cast<std::uint16_t>(parseUnsigned("dac", "VALUE", (*pos)[2], 4095));
	const DevicePtr dev = openDevice(g);
	dev->peripherals().dacOpen(ecmxf::DacTrigger::SetData);
	dev->peripherals().dacWrite(value);
	return 0;
}

} // namespace ecmxf_util
