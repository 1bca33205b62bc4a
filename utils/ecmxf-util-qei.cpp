// SPDX-License-Identifier: MIT
/*
 * ecmxf-util qei - the chip's quadrature encoder interface.
 */
#include "ecmxf-util.hpp"

#include <cstdio>
#include <memory>
#include <string>

#include <ecmxf/device.hpp>
#include <ecmxf/chip/peripherals.hpp>

namespace ecmxf_util {

const char *const kQeiHelp =
	"Usage: ecmxf-util [global options] qei open [CH] [--mode x4|x2|x4-compare|x2-compare]\n"
	"       ecmxf-util [global options] qei start|stop [CH]\n"
	"       ecmxf-util [global options] qei count [CH] [--json]\n"
	"\n"
	"The ECM-XF's quadrature encoder (QEI_FUNC_OP 33). It has one, channel 0;\n"
	"CH may be left out. open: EncOpen with the counting mode (default x4,\n"
	"free counting), which stops and clears the counter; start / stop:\n"
	"EncStart / EncStop; count: EncGetCount, printed as the unsigned 32-bit\n"
	"counter in decimal and hex and as a signed position. The simulator\n"
	"starts from power-on at every call.\n"
	"\n"
	"Options:\n"
	"  --mode M    x4 (default), x2, x4-compare, x2-compare\n"
	"  --json      count: {channel, count, position}\n"
	"  -h, --help  show this help\n";

int cmdQei(Globals &g, const Args &args)
{
	std::optional<std::string> modeText;
	const auto pos = parseArgs("qei", args, g, kQeiHelp, { { "", "--mode", nullptr, &modeText } });
	if (!pos)
		return 0;
	if (pos->empty())
		throw UsageError("qei: open, start, stop or count? (try 'ecmxf-util qei --help')");
	const std::string &op = (*pos)[0];
	if (op != "open" && op != "start" && op != "stop" && op != "count")
		throw UsageError("qei: unknown operation '" + op + "' (open, start, stop or count)");
	if (pos->size() > 2)
		throw UsageError("qei: " + op + " takes [CH] (try 'ecmxf-util qei --help')");
	if (pos->size() == 2)
		parseUnsigned("qei", "CH (the ECM-XF has one encoder, channel 0)", (*pos)[1], 0);
	if (modeText && op != "open")
		throw UsageError("qei: --mode belongs to 'qei open'");
	ecmxf::QeiMode mode = ecmxf::QeiMode::X4Free;
	if (modeText) {
		if (*modeText == "x4")
			mode = ecmxf::QeiMode::X4Free;
		else if (*modeText == "x2")
			mode = ecmxf::QeiMode::X2Free;
		else if (*modeText == "x4-compare")
			mode = ecmxf::QeiMode::X4Compare;
		else if (*modeText == "x2-compare")
			mode = ecmxf::QeiMode::X2Compare;
		else
			throw UsageError("qei: --mode: unknown '" + *modeText + "' (x4, x2, x4-compare, x2-compare)");
	}

	const DevicePtr dev = openDevice(g);
	if (op == "open") {
		dev->peripherals().qeiOpen(mode);
	} else if (op == "start") {
		dev->peripherals().qeiStart();
	} else if (op == "stop") {
		dev->peripherals().qeiStop();
	} else {
		const std::uint32_t c = dev->peripherals().qeiCount();
		const auto signedPos = static_cast<std::int32_t>(c);
		if (g.json)
			std::printf("{\"channel\": 0, \"count\": %u, \"position\": %d}\n", c, signedPos);
		else
			std::printf("count: %u (0x%08x), position %d\n", c, c, signedPos);
	}
	return 0;
}

} // namespace ecmxf_util
