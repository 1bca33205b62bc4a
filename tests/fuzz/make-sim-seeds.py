#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Write the seed corpus of fuzz-sim (tests/fuzz/corpus/sim/).

Each seed is a record sequence in the input format described at the top of
fuzz_sim.cpp: op 1 = valid command, op 3 = advance time, op 4 = fault,
op 2 = repeat, op 0 = raw bytes, op 5 = wrong size, op 6 = corrupted command.
"""
import os
import struct

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "sim")


def cmd(code, param=0, d=(0, 0, 0, 0), length=None, control=0, rsv_hi=0, payload=b""):
    units = (len(payload) + 5) // 6
    payload = payload + bytes(units * 6 - len(payload))
    if length is None:
        length = len(payload)
    return bytes([1, code, param, *d]) + struct.pack("<H", length) + bytes([control, rsv_hi, units]) + payload


def advance(us10):
    return bytes([3]) + struct.pack("<H", us10)


def info():
    return cmd(0)


def init_op(sync0=1000000):
    data = bytes([0xFF, 0x81]) + struct.pack("<HIII", 0x0300, sync0, 0, 0)
    return cmd(1, payload=data, length=16)


def state(st, slave=0xFF):
    return cmd(12, slave, (st, 0, 0, 0))


def wait(ms=20):
    return (advance(100) + info()) * ms


seeds = {
    "bringup-op": info() + init_op() + wait(30) + state(2) + wait(30) + state(4) + wait(30)
    + cmd(6, 0, (5, 0, 0, 0), payload=bytes(25)) + state(8) + wait(30) + cmd(18, 1)
    + (cmd(5, 1, (3, 0, 0, 0), payload=bytes(25)) + advance(100)) * 10,
    "sdo": info() + init_op() + wait(30) + state(2) + wait(30)
    + cmd(10, payload=bytes([1, 0]) + struct.pack("<HBBHI", 0x1018, 1, 0, 4, 100000)) + wait(10)
    + cmd(11) + cmd(69),
    "crc-reconfig": info() + cmd(25, 3) + info() + cmd(23, length=1408) + advance(10000) + info()
    + cmd(20) + cmd(56) + cmd(127) + advance(10000) + info(),
    "faults": info() + bytes([4, 0, 2]) + info() + bytes([4, 1, 1]) + info() + bytes([4, 2, 1])
    + info() + bytes([4, 4, 1]) + init_op() + wait(5) + bytes([4, 4, 0]) + bytes([5, 10, 0])
    + bytes([6]) + cmd(13, 0xFF)[1:] + struct.pack("<H", 30) + bytes([0x40]),
    "periph": info() + cmd(31, 0, (0xFF, 0, 1, 0)) + cmd(32, 0, (0x55, 0, 0, 0)) + cmd(32, 1)
    + cmd(33, 4) + cmd(33, 5) + cmd(33, 21) + cmd(34, 20) + cmd(35, 40) + cmd(81, 1, (1, 1, 0, 0)),
    "fifo-402": info() + init_op() + wait(30) + state(2) + wait(30) + cmd(26, 0, (0, 0, 0x10, 0))
    + cmd(29, 0, (0x10, 0x5A, 2, 0)) + cmd(27, 0, (0x27, 0, 0, 0)) + cmd(28) + cmd(74)
    + cmd(52, 16) + cmd(53) + cmd(54, 16) + cmd(55) + cmd(66) + cmd(70, 0, (4, 60, 0, 0)) + cmd(51),
}

os.makedirs(OUT, exist_ok=True)
for name, data in seeds.items():
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(data)
print(f"wrote {len(seeds)} seeds to {OUT}")
