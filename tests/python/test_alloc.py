# SPDX-License-Identifier: MIT
"""Cyclic.cycle() allocates nothing in C++: operator new is counted by an
LD_PRELOAD shim (alloc_shim.cpp over tests/common/alloc_counter.cpp) that
ctest puts in front of python3."""

import ctypes
import os

import pytest

import ecmxf


def allocations():
    try:
        f = ctypes.CDLL(None).ecmxf_test_allocations
    except AttributeError:
        pytest.fail("the allocation-counting shim is not loaded (ctest runs this file with "
                    "LD_PRELOAD=" + os.environ.get("ECMXF_ALLOC_SHIM", "libecmxf-alloc-shim.so") + ")")
    f.restype = ctypes.c_ulonglong
    return f()


def test_the_counter_counts():
    # the check can fail: a call that allocates in C++ is seen
    with ecmxf.open("sim:") as dev:
        before = allocations()
        dev.sdo.upload(0, 0x2001, 0)
        assert allocations() > before


def test_cycle_allocates_nothing():
    with ecmxf.open("sim:") as dev:
        dev.bring_up(motion=[0])
        with ecmxf.Cyclic(dev) as cyc:
            cyc.start()
            cycle = cyc.cycle
            for _ in range(100):                              # warm up
                cycle()
            before = allocations()
            for _ in range(2000):
                cycle()
            after = allocations()
            assert after - before == 0
            # and the same count of cycles through a call that allocates is seen
            before = allocations()
            for _ in range(10):
                cyc.last_result
            assert allocations() > before
