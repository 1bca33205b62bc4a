// SPDX-License-Identifier: MIT
/*
 * ecmxf-util adc - the chip's analog inputs.
 */
#include "ecmxf-util.hpp"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <ecmxf/device.hpp>
#include <ecmxf/chip/peripherals.hpp>

namespace ecmxf_util {

const char *const kAdcHelp =
	"Usage: ecmxf-util [global options] adc read [CH] [--differential] [--json]\n"
	"\n"
	"Convert analog input CH (0..15), or all 16 without CH, with the chip's\n"
	"12-bit ADC (ADC_FUNC_OP 35): AdcOpen, then per channel\n"
	"AdcConfigSampleModule (sample module 12, the manuals' module, bound to\n"
	"CH; software trigger), AdcStartConv, AdcGetDataValidFlag until valid,\n"
	"AdcGetConvData. Prints the raw value 0..4095 and volts (x 3.3 V / 4095).\n"
	"\n"
	"Options:\n"
	"  --differential  differential input mode (pairs 2k, 2k+1; 0 V reads 2048)\n"
	"  --json          {channel, raw, volts} or an array of them\n"
	"  -h, --help      show this help\n";

int cmdAdc(Globals &g, const Args &args)
{
	bool diff = false;
	const auto pos = parseArgs("adc", args, g, kAdcHelp, { { "", "--differential", &diff, nullptr } });
	if (!pos)
		return 0;
	if (pos->empty() || (*pos)[0] != "read")
		throw UsageError(pos->empty() ? "adc: read? (adc read [CH])"
					      : "adc: unknown operation '" + (*pos)[0] + "' (read)");
	if (pos->size() > 2)
		throw UsageError("adc: read takes [CH] (try 'ecmxf-util adc --help')");
	std::vector<unsigned> channels;
	if (pos->size() == 2)
		channels.push_back(static_cast<unsigned>(parseUnsigned("adc", "CH", (*pos)[1], 15)));
	else
		for (unsigned c = 0; c < 16; c++)
			channels.push_back(c);

	const DevicePtr dev = openDevice(g);
	dev->peripherals().adcOpen(diff ? ecmxf::AdcInputMode::Differential : ecmxf::AdcInputMode::SingleEnded);
	std::vector<std::uint16_t> raw;
	for (const unsigned c : channels) {
		dev->peripherals().adcConfigureModule(ecmxf::kAdcDefaultModule, c);
		raw.push_back(dev->peripherals().adcConvert(ecmxf::kAdcDefaultModule));
	}
	const auto volts = [](std::uint16_t r) { return r * 3.3 / 4095.0; };
	if (g.json) {
		const bool one = channels.size() == 1;
		std::printf("%s", one ? "" : "[");
		for (std::size_t i = 0; i < channels.size(); i++)
			std::printf("%s{\"channel\": %u, \"raw\": %u, \"volts\": %.4f}", i ? ", " : "", channels[i],
				    raw[i], volts(raw[i]));
		std::printf("%s\n", one ? "" : "]");
		return 0;
	}
	if (channels.size() == 1) {
		std::printf("%u (%.4f V)\n", raw[0], volts(raw[0]));
		return 0;
	}
	std::printf("CH   RAW   VOLTS\n");
	for (std::size_t i = 0; i < channels.size(); i++)
		std::printf("%-3u  %4u  %.4f\n", channels[i], raw[i], volts(raw[i]));
	return 0;
}

} // namespace ecmxf_util
