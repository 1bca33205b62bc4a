// SPDX-License-Identifier: MIT
//
// libbench-python.so: the C++ side of bench-python.py (`make bench`),
// loaded by the script with ctypes into the same process as the Python
// module, so that both run the same shared libecmxf in the same process
// in turns. Wall time per operation in ns:
//
//  - ecmxf_bench_sdo_open(), ecmxf_bench_sdo_block(h, n),
//    ecmxf_bench_sdo_close(h): n MasterVerbs::upload() of 0x2001:00 from
//    slave 0 on "sim:" (the bus in PRE-OP), the call
//    ecmxf.Device.sdo.upload() makes, one block of n per call (the script
//    interleaves the blocks with Python's);
//  - ecmxf_bench_call(f): calls f (a Python loop through ctypes): the span
//    callgrind's --toggle-collect counts for the Python side, as it counts
//    ecmxf_bench_sdo_block() for C++'s;
//  - ecmxf_bench_cycle_128(dir, n, wait), best of 5 runs: Cyclic::cycle()
//    on the 128-slave network (DIR/slaves128.net) in OP with a 1408-byte
//    SPI data section, back to back, or with waitNextCycle() (1 ms,
//    virtual time); ecmxf_bench_cycle_open/_block/_close: the same held
//    open, for the script's callgrind children.
// A negative result is a failure (its message on stderr).

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <memory>
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

#define ECMXF_BENCH_API extern "C" __attribute__((visibility("default")))

ECMXF_BENCH_API void *ecmxf_bench_sdo_open()
{
	try {
		auto m = ecmxf::MasterVerbs::open("sim:");
		(void)ecmxf::ensureBusUp(*m->device(), true);
		return m.release();
	} catch (const std::exception &e) {
		std::fprintf(stderr, "bench-python: %s\n", e.what());
		return nullptr;
	}
}

ECMXF_BENCH_API double ecmxf_bench_sdo_block(void *h, int n)
{
	try {
		auto *m = static_cast<ecmxf::MasterVerbs *>(h);
		const auto t0 = std::chrono::steady_clock::now();
		for (int i = 0; i < n; i++)
			(void)m->upload(0, 0x2001, 0);
		const std::chrono::duration<double, std::nano> d = std::chrono::steady_clock::now() - t0;
		return n > 0 ? d.count() / n : 0;
	} catch (const std::exception &e) {
		std::fprintf(stderr, "bench-python: %s\n", e.what());
		return -1;
	}
}

ECMXF_BENCH_API void ecmxf_bench_sdo_close(void *h)
{
	delete static_cast<ecmxf::MasterVerbs *>(h);
}

ECMXF_BENCH_API void ecmxf_bench_call(void (*f)())
{
	f();
}

namespace {

/// Cyclic at 128 slaves: a device on slaves128.net in OP with a 1408-byte
/// data section, its process image and a started Cyclic.
struct Cycle128 {
	explicit Cycle128(const std::string &dir)
		: dev(ecmxf::Device::open("sim:" + dir + "/slaves128.net"))
	{
		dev->chip().setDataSize(1408); // the 128 slaves' frames do not fit 112 bytes
		master = std::make_unique<ecmxf::Master>(*dev);
		master->bringUp({});
		image = std::make_unique<ecmxf::ProcessImage>(master->pdos());
		cyc = std::make_unique<ecmxf::Cyclic>(*dev, *image, ecmxf::CyclicConfig::motion());
		cyc->start();
	}
	void run(int n, bool wait)
	{
		for (int i = 0; i < n; i++) {
			(void)cyc->cycle();
			if (wait)
				(void)cyc->waitNextCycle();
		}
	}
	std::unique_ptr<ecmxf::Device> dev;
	std::unique_ptr<ecmxf::Master> master;
	std::unique_ptr<ecmxf::ProcessImage> image;
	std::unique_ptr<ecmxf::Cyclic> cyc;
};

} // namespace

ECMXF_BENCH_API double ecmxf_bench_cycle_128(const char *dir, int n, int wait)
{
	try {
		Cycle128 c(dir);
		const double ns = best(n, [&] { c.run(1, wait != 0); });
		return c.cyc->stats().failedCycles ? -1 : ns;
	} catch (const std::exception &e) {
		std::fprintf(stderr, "bench-python: %s\n", e.what());
		return -1;
	}
}

// ecmxf_bench_cycle_open(dir), ecmxf_bench_cycle_block(h, n, wait),
// ecmxf_bench_cycle_close(h): the same Cyclic held open, n cycles per call
// (the callgrind children of the script); block returns the failed
// cycles so far, or -1.
ECMXF_BENCH_API void *ecmxf_bench_cycle_open(const char *dir)
{
	try {
		return new Cycle128(dir);
	} catch (const std::exception &e) {
		std::fprintf(stderr, "bench-python: %s\n", e.what());
		return nullptr;
	}
}

ECMXF_BENCH_API int ecmxf_bench_cycle_block(void *h, int n, int wait)
{
	auto *c = static_cast<Cycle128 *>(h);
	c->run(n, wait != 0);
	return static_cast<int>(c->cyc->stats().failedCycles);
}

ECMXF_BENCH_API void ecmxf_bench_cycle_close(void *h)
{
	delete static_cast<Cycle128 *>(h);
}
