// SPDX-License-Identifier: MIT
/*
 * ecmxf-util gpio - the chip's own GPIO lines 0..19.
 */
#include "ecmxf-util.hpp"

#include <cstdio>
#include <memory>
#include <string>

#include <ecmxf/device.hpp>
#include <ecmxf/chip/peripherals.hpp>

namespace ecmxf_util {

const char *const kGpioHelp =
	"Usage: ecmxf-util [global options] gpio get [LINE] [--json]\n"
	"       ecmxf-util [global options] gpio set LINE 0|1\n"
	"       ecmxf-util [global options] gpio config LINE in|out|open-drain|quasi\n"
	"                  [--pull none|up|down] [--debounce on|off]\n"
	"                  [--irq none|both|falling|rising]\n"
	"\n"
	"The ECM-XF's GPIO 0..19 (GPIO_CONFIG_SET 31, GPIO_FUNC_OP 32).\n"
	"get: the levels of all lines (GpioExtGetValue) as a table, or of LINE as\n"
	"0/1. set: the output latch of LINE (read the lines, change LINE, write\n"
	"all 20 latches with GpioExtSetValue; the line must be an output to drive\n"
	"the pin: gpio config LINE out). config: mode and pull (GpioSetMode), and\n"
	"optionally debounce and the interrupt type. The simulator starts from\n"
	"power-on at every call (all lines inputs).\n"
	"\n"
	"Options:\n"
	"  --pull P       none (default), up or down\n"
	"  --debounce D   on or off\n"
	"  --irq T        interrupt: none, both, falling or rising\n"
	"  --json         get: {\"value\": ..., \"lines\": [20 x 0/1]} or {line, value}\n"
	"  -h, --help     show this help\n";

namespace {

unsigned parseLine(const std::string &t)
{
	return static_cast<unsigned>(parseUnsigned("gpio", "LINE", t, ecmxf::kGpioLines - 1));
}

} // namespace

int cmdGpio(Globals &g, const Args &args)
{
	std::optional<std::string> pull, debounce, irq;
	const auto pos = parseArgs("gpio", args, g, kGpioHelp,
				   { { "", "--pull", nullptr, &pull },
				     { "", "--debounce", nullptr, &debounce },
				     { "", "--irq", nullptr, &irq } });
	if (!pos)
		return 0;
	if (pos->empty())
		throw UsageError("gpio: get, set or config? (try 'ecmxf-util gpio --help')");
	const std::string &op = (*pos)[0];
	if (op == "get") {
		if (pos->size() > 2)
			throw UsageError("gpio: get takes [LINE] (try 'ecmxf-util gpio --help')");
		const std::optional<unsigned> line =
			pos->size() == 2 ? std::optional<unsigned>(parseLine((*pos)[1])) : std::nullopt;
		const DevicePtr dev = openDevice(g);
		const std::uint32_t v = dev->peripherals().gpioReadAll();
		if (line) {
			const unsigned bit = (v >> *line) & 1u;
			if (g.json)
				std::printf("{\"line\": %u, \"value\": %u}\n", *line, bit);
			else
				std::printf("%u\n", bit);
			return 0;
		}
		if (g.json) {
			std::printf("{\"value\": %u, \"lines\": [", v);
			for (unsigned i = 0; i < ecmxf::kGpioLines; i++)
				std::printf("%s%u", i ? ", " : "", (v >> i) & 1u);
			std::printf("]}\n");
			return 0;
		}
		std::printf("GPIO 0..19: 0x%05x\n", v);
		std::printf("LINE ");
		for (unsigned i = 0; i < ecmxf::kGpioLines; i++)
			std::printf("%3u", i);
		std::printf("\nLEVEL");
		for (unsigned i = 0; i < ecmxf::kGpioLines; i++)
			std::printf("%3u", (v >> i) & 1u);
		std::printf("\n");
		return 0;
	}
	if (op == "set") {
		if (pos->size() != 3)
			throw UsageError("gpio: set needs LINE 0|1 (try 'ecmxf-util gpio --help')");
		const unsigned line = parseLine((*pos)[1]);
		const auto value = parseUnsigned("gpio", "VALUE", (*pos)[2], 1);
		const DevicePtr dev = openDevice(g);
		std::uint32_t v = dev->peripherals().gpioReadAll();
		v = value ? (v | (1u << line)) : (v & ~(1u << line));
		dev->peripherals().gpioWriteAll(v);
		return 0;
	}
	if (op == "config") {
		if (pos->size() != 3)
			throw UsageError("gpio: config needs LINE in|out|open-drain|quasi (try 'ecmxf-util gpio --help')");
		const unsigned line = parseLine((*pos)[1]);
		const std::string &m = (*pos)[2];
		ecmxf::GpioMode mode;
		if (m == "in")
			mode = ecmxf::GpioMode::Input;
		else if (m == "out")
			mode = ecmxf::GpioMode::Output;
		else if (m == "open-drain")
			mode = ecmxf::GpioMode::OpenDrain;
		else if (m == "quasi")
			mode = ecmxf::GpioMode::QuasiBidirectional;
		else
			throw UsageError("gpio: config: unknown mode '" + m + "' (in, out, open-drain, quasi)");
		ecmxf::GpioPull p = ecmxf::GpioPull::None;
		if (pull) {
			if (*pull == "up")
				p = ecmxf::GpioPull::Up;
			else if (*pull == "down")
				p = ecmxf::GpioPull::Down;
			else if (*pull != "none")
				throw UsageError("gpio: --pull: unknown '" + *pull + "' (none, up, down)");
		}
		std::optional<bool> deb;
		if (debounce) {
			if (*debounce != "on" && *debounce != "off")
				throw UsageError("gpio: --debounce: '" + *debounce + "' (on or off)");
			deb = *debounce == "on";
		}
		std::optional<ecmxf::GpioEdge> edge;
		if (irq) {
			if (*irq == "none")
				edge = ecmxf::GpioEdge::Disabled;
			else if (*irq == "both")
				edge = ecmxf::GpioEdge::Both;
			else if (*irq == "falling")
				edge = ecmxf::GpioEdge::Falling;
			else if (*irq == "rising")
				edge = ecmxf::GpioEdge::Rising;
			else
				throw UsageError("gpio: --irq: unknown '" + *irq + "' (none, both, falling, rising)");
		}
		const DevicePtr dev = openDevice(g);
		dev->peripherals().gpioSetMode(1u << line, mode, p);
		if (deb)
			dev->peripherals().gpioSetDebounce(1u << line, *deb);
		if (edge)
			dev->peripherals().gpioSetInterrupt(line, *edge);
		return 0;
	}
	throw UsageError("gpio: unknown operation '" + op + "' (get, set or config)");
}

} // namespace ecmxf_util
