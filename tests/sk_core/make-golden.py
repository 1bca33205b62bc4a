#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
#
# Golden frames for tests/sk_core/test_sk_frame.cpp, built from the
# ECM-SK quick start (seed 002, tables 2.2-2.24 and 2.2 "CRC"), not from
# lib/core: the byte positions are typed in from the tables, the CRC-8 is
# a bitwise loop (x^8+x^2+x+1, init 0x5A, MSB first, no final xor) over
# the whole frame with byte 3 taken as 0.  Prints the C++ arrays (only
# the non-zero bytes, as index/value pairs) and the CRCs.
import struct

def crc8(frame, init=0x5A):
    c = init
    for i, b in enumerate(frame):
        if i == 3:
            b = 0
        c ^= b
        for _ in range(8):
            c = ((c << 1) ^ 0x07) & 0xFF if c & 0x80 else (c << 1) & 0xFF
    return c

# self-check of the loop: CRC-8 (init 0) of "123456789" is 0xF4
c = 0
for b in b"123456789":
    c ^= b
    for _ in range(8):
        c = ((c << 1) ^ 0x07) & 0xFF if c & 0x80 else (c << 1) & 0xFF
assert c == 0xF4

def frame(size):
    return bytearray(size)

def emit(name, f):
    f[3] = crc8(f)
    nz = [(i, b) for i, b in enumerate(f) if b]
    print("// %s: %d bytes, CRC 0x%02X" % (name, len(f), f[3]))
    print("static const Golden %s{ %d, {" % (name, len(f)))
    line = "\t"
    for i, b in nz:
        item = "{ %d, 0x%02X }, " % (i, b)
        if len(line) + len(item) > 96:
            print(line.rstrip())
            line = "\t"
        line += item
    print(line.rstrip())
    print("} };")

# 1. 12-byte slots: SET_STATE (0x0001) to PRE-OP (0x02) in slot 0 (table 2.2)
f = frame(504)
f[0:2] = struct.pack("<H", 0x0001)
f[4:8] = struct.pack("<I", 0x02)
emit("kSetStatePreop", f)

# 2. 16-byte slots: SET_AXIS (0x0002) group 1 (byte 2), topology (bytes 4-7):
# slave 9 STEP (3), slave 10 Drive (0), slave 11 IO (1), slave 12 HSP (2),
# slaves 13-16 none (0xF) -> 0xFFFF2103 (table 2.3)
f = frame(512)
f[0:2] = struct.pack("<H", 0x0002)
f[2] = 1
f[4:8] = struct.pack("<I", 0xFFFF2103)
emit("kSetAxis16", f)

# 3. 12-byte slots: SET_DC (0x0003) 500 us, FIX 0x0000FFFF (table 2.4);
# slave 1 CSP (0x15) index 7 target -1000, output 0x5 (table 2.15);
# slave 40 (slot 40, bytes 480-491) IO_WR (0x14) index 0xA5 output 0x0F0F;
# SDO slot (41, bytes 492-503): SDO_WR (0x0008) slave 2, size 1, sub 0,
# index 0x6060, value 6 (digest's layout: 2 slave, 3 size, 4 sub, 6-7 idx)
f = frame(504)
f[0:2] = struct.pack("<H", 0x0003)
f[4:8] = struct.pack("<I", 500)
f[8:12] = struct.pack("<I", 0x0000FFFF)
s = 12
f[s] = 0x15; f[s + 1] = 7
f[s + 4:s + 8] = struct.pack("<i", -1000)
f[s + 8:s + 12] = struct.pack("<I", 5)
s = 40 * 12
f[s] = 0x14; f[s + 1] = 0xA5
f[s + 4:s + 8] = struct.pack("<I", 0x0F0F)
s = 41 * 12
f[s:s + 2] = struct.pack("<H", 0x0008)
f[s + 2] = 2; f[s + 3] = 1; f[s + 4] = 0
f[s + 6:s + 8] = struct.pack("<H", 0x6060)
f[s + 8:s + 12] = struct.pack("<I", 6)
emit("kCspSdoWr", f)

# 4. A response in OP, 12-byte slots (2.2 and table 2.15's "Master Cyclic
# Response"): 0xBF, Error Code 2, state 0x08, FIFO remaining 200 (8-9),
# FIFO full count 3 (10-11); slave 1: CSP 0x15, index 7, statusword 0x1237,
# position 123456, torque -5, ALM code 0x7500; SDO slot: SDO_RD answer
# (status 0 = done), slave 1, sub 0, index 0x6041, value 0x1237.
f = frame(504)
f[0] = 0xBF; f[1] = 2; f[2] = 0x08
f[8:10] = struct.pack("<H", 200)
f[10:12] = struct.pack("<H", 3)
s = 12
f[s] = 0x15; f[s + 1] = 7
f[s + 2:s + 4] = struct.pack("<H", 0x1237)
f[s + 4:s + 8] = struct.pack("<i", 123456)
f[s + 8:s + 10] = struct.pack("<h", -5)
f[s + 10:s + 12] = struct.pack("<H", 0x7500)
s = 41 * 12
f[s] = 0x07; f[s + 2] = 1
f[s + 6:s + 8] = struct.pack("<H", 0x6041)
f[s + 8:s + 12] = struct.pack("<I", 0x1237)
emit("kOpResponse", f)

# 5. 16-byte slots, slave 3 a 2-channel HSP, CSV (table 2.18): target
# velocity 1 = 1000 (4-7), output 1 = 0x0001 (8-9), target velocity 2 =
# -2000 (10-13), output 2 = 0x0002 (14-15); slot 3 = bytes 48-63.
f = frame(512)
s = 48
f[s] = 0x16; f[s + 1] = 9
f[s + 4:s + 8] = struct.pack("<i", 1000)
f[s + 8:s + 10] = struct.pack("<H", 1)
f[s + 10:s + 14] = struct.pack("<i", -2000)
f[s + 14:s + 16] = struct.pack("<H", 2)
emit("kHsp2Csv", f)

# 6. the all-zero frames (GET_STATUS everywhere): their CRCs
print("// all-zero 504: 0x%02X, all-zero 512: 0x%02X" % (crc8(bytes(504)), crc8(bytes(512))))
# 7. CRC-8 init 0x5A over "123456789" as a 9-byte buffer (byte 3 = '4' -> 0)
print("// '123456789' (byte 3 as 0): 0x%02X" % crc8(b"123456789"))
