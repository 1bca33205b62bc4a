// SPDX-License-Identifier: MIT
//
// libbench-python.so: the C++ side of bench-python.py (`make bench`),
// loaded by the script with ctypes into the same process as the Python
// module, so that both run the same shared libecmxf in the same process
// in turns. Wall time per operation in ns, best of 5 runs:
//
//  - ecmxf_bench_sdo_upload(n): MasterVerbs::upload() of 0x2001:00 from
//    slave 0 on "sim:" (the bus in PRE-OP), the call
//    ecmxf.Device.sdo.upload() makes;
//  - ecmxf_bench_cycle_128(dir, n, wait): Cyclic::cycle() on the 128-slave
//    network (DIR/slaves128.net) in OP with a 1408-byte SPI data section,
//    back to back, or with waitNextCycle() (1 ms, virtual time).
// A negative result is a failure (its message on stderr).

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <string>

#include <ecmxf/bus/master.hpp>
#include <ecmxf/chip/chip.hpp>
#include <ecmxf/device.hpp>
#include <ecmxf/pdo/cyclic.hpp>
#include <ecmxf/pdo/process_image.hpp>
#include <ecmxf/verbs.hpp>

namespace {

template <class F>
double best(int n, F &&f)
{
	double b = 1e300;
	for (int run = 0; run < 5; run++) {
		const auto t0 = std::chrono::steady_clock::now();
		for (int i = 0; i < n; i++)
			f();
		const std::chrono::duration<double, std::nano> d = std::chrono::steady_clock::now() - t0;
		b = std::min(b, d.count() / n);
	}
	return b;
}

} // namespace

extern "C" __attribute__((visibility("default"))) double ecmxf_bench_sdo_upload(int n)
{
	try {
		auto m = ecmxf::MasterVerbs::open("sim:");
		(void)ecmxf::ensureBusUp(*m->device(), true);
		return best(n, [&] { (void)m->upload(0, 0x2001, 0); });
	} catch (const std::exception &e) {
		std::fprintf(stderr, "bench-python: %s\n", e.what());
		return -1;
	}
}

extern "C" __attribute__((visibility("default"))) double ecmxf_bench_cycle_128(const char *dir, int n, int wait)
{
	try {
		auto dev = ecmxf::Device::open("sim:" + std::string(dir) + "/slaves128.net");
		dev->chip().setDataSize(1408); // the 128 slaves' frames do not fit 112 bytes
		ecmxf::Master master(*dev);
		master.bringUp({});
		ecmxf::ProcessImage image(master.pdos());
		ecmxf::Cyclic cyc(*dev, image, ecmxf::CyclicConfig::motion());
		cyc.start();
		const double ns = best(n, [&] {
			(void)cyc.cycle();
			if (wait)
				(void)cyc.waitNextCycle();
		});
		return cyc.stats().failedCycles ? -1 : ns;
	} catch (const std::exception &e) {
		std::fprintf(stderr, "bench-python: %s\n", e.what());
		return -1;
	}
}
