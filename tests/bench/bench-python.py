#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""bench-python: the Python binding against the same calls from C++
(`make bench`; Documentation/python.rst, "Performance").

    tests/bench/bench-python.py BUILD_DIR

Loads BUILD_DIR/tests/bench/libbench-python.so (the C++ side, with
ctypes) and runs the same operations from Python with BUILD_DIR/python on
the path, in the same process, through the same libecmxf:

 - an SDO upload of 0x2001:00 on sim: (target: Python <= 5 % over C++),
   measured two ways:
     * wall time: ROUNDS rounds, each a block of N uploads from C++ and a
       block of N from Python, one after the other (which goes first
       alternates), on one device each opened once; the figure is the
       median of the rounds' Python/C++ ratios (a machine busy with
       something else slows a round's pair together, not one side), with
       the quartiles and the ratio of the fastest blocks beside it; the
       same of each block's thread CPU time (what preemption by the
       machine's other work does not add to);
     * instructions (when valgrind is installed): callgrind counts the
       instructions of three child processes that open the same devices
       and warm up the same way, then run N_COUNTED uploads from C++, the
       same from a Python loop, or none; a side's count minus the last,
       over N_COUNTED, is its instructions per upload: a figure that does
       not depend on the machine's load;
 - Cyclic.cycle() at 128 slaves (slaves128.net), back to back, and with
   wait_next_cycle(): the Python loop's overhead per cycle over C++, wall
   time best of 5 rounds, and instructions per cycle counted as for the
   upload.

The script prints figures; it fails (exit 1) only when a side fails, never
on a figure.
"""
import ctypes
import os
import re
import shutil
import statistics
import subprocess
import sys
import time

build = sys.argv[1] if len(sys.argv) > 1 else "build-bench"
sys.path.insert(0, os.path.join(build, "python"))
import ecmxf  # noqa: E402

nets = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "lib", "sim", "networks")

cpplib = ctypes.CDLL(os.path.join(build, "tests", "bench", "libbench-python.so"))
cpplib.ecmxf_bench_sdo_open.restype = ctypes.c_void_p
cpplib.ecmxf_bench_sdo_block.restype = ctypes.c_double
cpplib.ecmxf_bench_sdo_block.argtypes = [ctypes.c_void_p, ctypes.c_int]
cpplib.ecmxf_bench_sdo_close.argtypes = [ctypes.c_void_p]
CALLBACK = ctypes.CFUNCTYPE(None)
cpplib.ecmxf_bench_call.argtypes = [CALLBACK]
cpplib.ecmxf_bench_cycle_128.restype = ctypes.c_double
cpplib.ecmxf_bench_cycle_128.argtypes = [ctypes.c_char_p, ctypes.c_int, ctypes.c_int]
cpplib.ecmxf_bench_cycle_open.restype = ctypes.c_void_p
cpplib.ecmxf_bench_cycle_open.argtypes = [ctypes.c_char_p]
cpplib.ecmxf_bench_cycle_block.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_int]
cpplib.ecmxf_bench_cycle_close.argtypes = [ctypes.c_void_p]

ROUNDS = 61        # blocks per side (wall time)
N = 2000           # uploads per block
N_COUNTED = 5000   # uploads callgrind counts per side
CYCLES_COUNTED = 1000
WARMUP = 200


def py_uploads(dev, n):
    up = dev.sdo.upload
    for _ in range(n):
        up(0, 0x2001, 0)


class CppSdo:
    def __init__(self):
        self.h = cpplib.ecmxf_bench_sdo_open()
        if not self.h:
            sys.exit("bench-python: the C++ side failed to open sim:")

    def block(self, n):
        """Wall and thread CPU ns per upload, measured here as for Python's
        blocks (the one ctypes call per block is within the noise)."""
        t0, c0 = time.perf_counter_ns(), time.thread_time_ns()
        if cpplib.ecmxf_bench_sdo_block(self.h, n) < 0:
            sys.exit("bench-python: the C++ side failed")
        return (time.perf_counter_ns() - t0) / n, (time.thread_time_ns() - c0) / n

    def close(self):
        cpplib.ecmxf_bench_sdo_close(self.h)


def py_block(dev, n):
    t0, c0 = time.perf_counter_ns(), time.thread_time_ns()
    py_uploads(dev, n)
    return (time.perf_counter_ns() - t0) / n, (time.thread_time_ns() - c0) / n


def sdo_wall():
    """Per-round C++ and Python (wall, thread CPU) ns per upload, interleaved."""
    cpp, dev = CppSdo(), ecmxf.open("sim:")
    try:
        cpp.block(WARMUP)
        py_uploads(dev, WARMUP)
        c, p = [], []
        for r in range(ROUNDS):
            if r % 2:
                p.append(py_block(dev, N))
                c.append(cpp.block(N))
            else:
                c.append(cpp.block(N))
                p.append(py_block(dev, N))
        return c, p
    finally:
        dev.close()
        cpp.close()


def counted_child(what, side):
    """In a callgrind child: the same setup and warm-up on both sides, then
    the counted operations from side ('cpp', 'py'), or none ('base'):
    what is 'sdo' (N_COUNTED uploads), 'cycle' or 'cycle_wait'
    (CYCLES_COUNTED cycles, the latter with wait_next_cycle())."""
    cpp_n = py_n = 0
    if what == "sdo":
        cpp, dev = CppSdo(), ecmxf.open("sim:")
        cpp.block(WARMUP)
        py_uploads(dev, WARMUP)
        # both calls in every child, with 0 on the sides not counted: the
        # children differ only in what is counted
        if side == "cpp":
            cpp_n = N_COUNTED
        elif side == "py":
            py_n = N_COUNTED
        if cpplib.ecmxf_bench_sdo_block(cpp.h, cpp_n) < 0:
            sys.exit("bench-python: the C++ side failed")
        cb = CALLBACK(lambda: py_uploads(dev, py_n))
        cpplib.ecmxf_bench_call(cb)
        dev.close()
        cpp.close()
        return
    wait = what == "cycle_wait"
    h = cpplib.ecmxf_bench_cycle_open(nets.encode())
    if not h:
        sys.exit("bench-python: the C++ side failed to open slaves128.net")
    with ecmxf.open("sim:" + os.path.join(nets, "slaves128.net")) as dev:
        dev.set_data_size(1408)
        dev.bring_up()
        with ecmxf.Cyclic(dev) as cyc:
            cyc.start()
            loop = cycle_loop(cyc, wait)
            cpplib.ecmxf_bench_cycle_block(h, 200, int(wait))
            loop(200)
            if side == "cpp":
                cpp_n = CYCLES_COUNTED
            elif side == "py":
                py_n = CYCLES_COUNTED
            failed = cpplib.ecmxf_bench_cycle_block(h, cpp_n, int(wait))
            cb = CALLBACK(lambda: loop(py_n))
            cpplib.ecmxf_bench_call(cb)
            if failed or cyc.stats["failed_cycles"]:
                sys.exit("bench-python: failed cycles")
    cpplib.ecmxf_bench_cycle_close(h)


def instructions(what, n):
    """Instructions per operation (C++, Python) of counted_child(what), or
    None without valgrind: each side's whole-process count minus that of
    the same process without the counted operations, over n."""
    if not shutil.which("valgrind"):
        return None
    total = {}
    env = dict(os.environ, PYTHONHASHSEED="0")
    for side in ("base", "cpp", "py"):
        r = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null",
                            sys.executable, os.path.abspath(__file__), build, "--counted-child", what, side],
                           capture_output=True, text=True, timeout=3600, env=env)
        m = re.search(r"Collected : (\d+)", r.stderr)
        if r.returncode != 0 or not m:
            sys.exit(f"bench-python: callgrind of {what} on the {side} side failed:\n" + r.stderr[-2000:])
        total[side] = int(m.group(1))
    return ((total["cpp"] - total["base"]) / n, (total["py"] - total["base"]) / n)


def best(n, f):
    b = float("inf")
    for _ in range(5):
        t0 = time.perf_counter()
        f(n)
        b = min(b, (time.perf_counter() - t0) / n * 1e9)
    return b


def cycle_loop(cyc, wait):
    cycle, w = cyc.cycle, cyc.wait_next_cycle

    def f(n):
        if wait:
            for _ in range(n):
                cycle()
                w()
        else:
            for _ in range(n):
                cycle()
    return f


def py_cycle_128(wait):
    """As ecmxf_bench_cycle_128(): a fresh device, OP, then the timed loop."""
    with ecmxf.open("sim:" + os.path.join(nets, "slaves128.net")) as dev:
        dev.set_data_size(1408)              # the 128 slaves' frames do not fit 112 bytes
        dev.bring_up()
        with ecmxf.Cyclic(dev) as cyc:
            cyc.start()
            ns = best(2000, cycle_loop(cyc, wait))
            if cyc.stats["failed_cycles"]:
                sys.exit("bench-python: failed cycles from Python")
            return ns


def cycles():
    cpp, py = {}, {}
    for _ in range(5):
        for wait in (0, 1):
            k = "cycle_wait_128" if wait else "cycle_128"
            c = cpplib.ecmxf_bench_cycle_128(nets.encode(), 2000, wait)
            if c < 0:
                sys.exit("bench-python: the C++ side failed")
            cpp[k] = min(c, cpp.get(k, float("inf")))
            py[k] = min(py_cycle_128(bool(wait)), py.get(k, float("inf")))
    return cpp, py


def pct(x):
    return f"{(x - 1) * 100:+.1f} %"


def main():
    c, p = sdo_wall()
    print(f"bench-python: SDO upload 0x2001:00 on sim:, {ROUNDS} rounds of {N} from C++ and {N} from Python, "
          "interleaved")
    med = {}
    for i, clock in ((0, "wall time"), (1, "thread CPU time")):
        cs, ps = [x[i] for x in c], [x[i] for x in p]
        ratios = sorted(pi / ci for pi, ci in zip(ps, cs))
        q1, med[i], q3 = statistics.quantiles(ratios, n=4)
        print(f"  {clock}: C++ median {statistics.median(cs):.0f} ns (fastest block {min(cs):.0f}), "
              f"Python median {statistics.median(ps):.0f} ns (fastest {min(ps):.0f})")
        print(f"    Python/C++ per round: median {pct(med[i])} (quartiles {pct(q1)} .. {pct(q3)}); "
              f"fastest blocks {pct(min(ps) / min(cs))}")
    ins = instructions("sdo", N_COUNTED)
    if ins:
        ci, pi = ins
        print(f"  instructions per upload (callgrind, {N_COUNTED} each): C++ {ci:.0f}, Python {pi:.0f}: "
              f"{pi - ci:+.0f} ({pct(pi / ci)})")
    else:
        print("  instructions: valgrind is not installed")
    verdict = ins[1] / ins[0] if ins else med[0]
    print(f"bench-python: SDO upload from Python {'within' if verdict <= 1.05 else 'OVER'} 5 % of C++ "
          f"({'instructions' if ins else 'median wall-time ratio'}: {pct(verdict)})")

    cpp, py = cycles()
    print("bench-python: Cyclic at 128 slaves, wall time per cycle (ns), best of 5 x 2000")
    print(f"  {'operation':34} {'C++':>10} {'Python':>10} {'overhead':>10}")
    for k, what in (("cycle_128", "Cyclic.cycle(), 128 slaves"),
                    ("cycle_wait_128", "cycle() + wait_next_cycle(), 128")):
        d = py[k] - cpp[k]
        print(f"  {what:34} {cpp[k]:10.0f} {py[k]:10.0f} {d:+8.0f} ns ({d / cpp[k] * 100:+.1f} %)")
    for what, label in (("cycle", "cycle()"), ("cycle_wait", "cycle() + wait_next_cycle()")):
        ins = instructions(what, CYCLES_COUNTED)
        if ins:
            ci, pi = ins
            print(f"  instructions per {label} (callgrind, {CYCLES_COUNTED} each): C++ {ci:.0f}, "
                  f"Python {pi:.0f}: {pi - ci:+.0f} ({pct(pi / ci)})")


if __name__ == "__main__":
    if len(sys.argv) > 4 and sys.argv[2] == "--counted-child":
        counted_child(sys.argv[3], sys.argv[4])
    else:
        main()
