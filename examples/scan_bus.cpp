// SPDX-License-Identifier: MIT
/*
 * Scan the EtherCAT bus behind an ECM-XF and print its slaves.
 *
 *   ecmxf-example-scan-bus [URI]    (default "sim:", the in-process simulator;
 *                                    "/dev/ecmxf0", "spidev:...", "unix:...")
 */
#include <cstdio>
#include <exception>

#include <ecmxf/ecmxf.hpp>

int main(int argc, char **argv)
{
	if (argc > 2) {
		std::fprintf(stderr, "usage: %s [URI]\n", argv[0]);
		return 2;
	}
	const char *uri = argc > 1 ? argv[1] : "sim:";

	try {
		auto dev = ecmxf::Device::open(uri);
		const ecmxf::Bus bus = dev->bus();

		// ECAT_INIT_OP: the chip scans the network; every slave ends in INIT
		bus.initNetwork();

		const unsigned count = bus.slaveCount();
		std::printf("%u slave(s) on %s\n", count, uri);
		for (unsigned pos = 0; pos < count; pos++) {
			const ecmxf::SlaveInfo s = bus.slaveInfo(static_cast<std::uint8_t>(pos));
			std::printf("%3u  vendor 0x%08x  product 0x%08x  %-6s  %s\n", pos, s.vendorId,
				    s.productCode, ecmxf::stateName(s.state).c_str(), s.name.c_str());
		}
	} catch (const std::exception &e) {
		// ecmxf::Error: the failing command and why, in the field's words
		std::fprintf(stderr, "scan-bus: %s\n", e.what());
		return 1;
	}
	return 0;
}
