// SPDX-License-Identifier: MIT
/*
 * Read and write a slave's objects over SDO, and handle an SDO abort.
 *
 *   ecmxf-example-sdo-read-write [URI]    (default "sim:"; slave 0 is a
 *                                          CiA-402 drive there)
 */
#include <cstdint>
#include <cstdio>
#include <exception>

#include <ecmxf/ecmxf.hpp>

int main(int argc, char **argv)
try {
	if (argc > 2) {
		std::fprintf(stderr, "usage: %s [URI]\n", argv[0]);
		return 2;
	}
	auto dev = ecmxf::Device::open(argc > 1 ? argv[1] : "sim:");
	// SDO needs the mailbox: the bus scanned and in PRE-OP
	dev->bus().initNetwork();
	dev->bus().stateSet(ecmxf::kAllSlaves, ecmxf::State::PreOp);

	const ecmxf::Sdo sdo = dev->sdo();
	const auto vendor = sdo.read<std::uint32_t>(0, 0x1018, 1);
	std::printf("slave 0: vendor id 0x%08x, device \"%s\"\n", vendor, sdo.readString(0, 0x1008, 0).c_str());

	// 0x6081: profile velocity; write it and read it back
	sdo.write<std::uint32_t>(0, 0x6081, 0, 120000);
	std::printf("slave 0: 0x6081 = %u\n", sdo.read<std::uint32_t>(0, 0x6081, 0));

	// an object the slave does not have: the slave aborts the transfer
	try {
		(void)sdo.read<std::uint32_t>(0, 0x2fff, 0);
	} catch (const ecmxf::SdoError &e) {
		std::printf("slave 0: 0x2fff: abort 0x%08x (%s)\n", e.abortCode(),
			    std::string(ecmxf::sdoAbortText(e.abortCode())).c_str());
	}
	return 0;
} catch (const std::exception &e) {
	// any other failure: ecmxf::Error (SdoError too) says which command and why
	std::fprintf(stderr, "sdo-read-write: %s\n", e.what());
	return 1;
}
