// SPDX-License-Identifier: MIT
// The consumer of tests/install: opens the in-process simulator and asks
// it for the slave count before the network is scanned.
#include <cstdio>
#include <ecmxf/device.hpp>
#include <ecmxf/protocol.hpp>

int main()
{
	const auto dev = ecmxf::Device::open("sim:");
	ecmxf::Command c;
	c.code = 16; // ECAT_SLV_CNT_GET: no network before ECAT_INIT_OP
	const ecmxf::Response r = dev->command(c);
	std::printf("libecmxf %.*s: %u slaves, error status 0x%02x\n",
		    static_cast<int>(ecmxf::version().size()), ecmxf::version().data(), r.ret,
		    dev->lastHeader().errStatus);
	return 0;
}
