// SPDX-License-Identifier: MIT
// LD_PRELOAD shim of the Python suite's allocation check (test_alloc.py):
// tests/common/alloc_counter.cpp's counting operator new, interposed on
// python3, libecmxf and the binding, and its count for ctypes.
#include "alloc_counter.hpp"

extern "C" __attribute__((visibility("default"))) unsigned long long ecmxf_test_allocations(void)
{
	return ecmxf_test::allocations();
}
