#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Write the seed corpus of the fuzz targets (tests/fuzz/corpus/).

Two kinds of seeds:
  rsp-*   valid (and one "not ready") response packets, for the codec part
          of fuzz_response.cpp: every check type, several sizes;
  eng-*   scripts for its engine part, in the input format documented at
          the top of fuzz_response.cpp: a command sequence and the chip's
          answers, with the frame repaired and (index, code) filled in so
          the engine really completes commands.

The output is deterministic; re-run after changing the input format:
    tests/fuzz/make-seeds.py [OUTDIR]
"""
import os
import struct
import sys
import zlib

HDR, TRAILER = 24, 8
START, END, FIXED, NOT_READY = 0xA1A2A3A4, 0x56575859, 0x12345678, 0x87654321
CHECK_FIXED, CHECK_CRC8, CHECK_CCITT, CHECK_CRC32 = 0, 1, 2, 3


def crc8(b):
    crc = 0
    for x in b:
        crc ^= x
        for _ in range(8):
            crc = ((crc << 1) ^ 0x07) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc


def crc_ccitt(b):
    crc = 0xFFFF
    for x in b:
        crc ^= x << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def check_word(check, b):
    if check == CHECK_CRC8:
        return crc8(b)
    if check == CHECK_CCITT:
        return crc_ccitt(b)
    if check == CHECK_CRC32:
        return zlib.crc32(b) & 0xFFFFFFFF
    return FIXED


assert crc8(b"123456789") == 0xF4
assert crc_ccitt(b"123456789") == 0x29B1
assert zlib.crc32(b"123456789") == 0xCBF43926


def rsp_packet(n, check, *, ecat=0, err=0, ecm=0, index=0, code=0, ret=0,
               data=b"", int_flags=0, not_ready=False):
    """A response packet with an n-byte data section."""
    hdr = struct.pack("<IBBBBBBBBBBHIBBBB", START, 1, 0, 3, 2, ecat, err,
                      ecm | check, index, code, ret, len(data), int_flags,
                      0, 0, 0x5A, 0xA5)
    assert len(hdr) == HDR
    body = hdr + data + bytes(n - len(data))
    word = NOT_READY if not_ready else check_word(check, body)
    return body + struct.pack("<II", word, END)


# ---- engine scripts -------------------------------------------------------
# ctl bits (see fuzz_response.cpp)
STEP_US, STEP_MS, STEP_100MS, STEP_DEADLINE = 0, 1, 2, 3
REPAIR, ANSWER_PREV, WHOLE, CLAMP_LEN, OP, PREV_CHECK = 4, 8, 16, 32, 64, 128
# script op kinds
K_IMM, K_ASYNC, K_LINK, K_RAW, K_CANCEL, K_CLR_ERR, K_CLR_INT, K_CANCEL_CUR = range(8)
# ECM status bits
STS_NOP, STS_BUSY = 0x20, 0x80
ERR_ASYNC, ERR_CMD = 0x08, 0x80


def rx_tx(rx_sel, tx_sel, short_timeout=False):
    """The c byte of a submit op: rx size choice, tx length choice."""
    return rx_sel | (tx_sel << 3) | (0x40 if short_timeout else 0)


def script(data_size, check, retries, ops):
    v = data_size - 32
    return struct.pack("<HBB", v, check | (retries << 2), len(ops)) + \
        b"".join(bytes(op) for op in ops)


def answer(ctl, aux=10, *, ecm=0, err=0, ret=0, length=0, ecat=2):
    """One exchange: ctl, aux and the 24 response header bytes."""
    hdr = struct.pack("<IBBBBBBBBBBHIBBBB", START, 0, 0, 0, 0, ecat, err, ecm,
                      0, 0, ret, length, 0, 0, 0, 0, 0)
    return bytes([ctl, aux]) + hdr


GOOD = REPAIR | ANSWER_PREV | CLAMP_LEN


def seeds():
    out = {}
    # codec seeds: each check type, minimum/default/maximum sizes
    out["rsp-fixed-nop-144"] = rsp_packet(112, CHECK_FIXED, ecm=STS_NOP)
    out["rsp-crc32-fwver-144"] = rsp_packet(
        112, CHECK_CRC32, ecat=8, index=7, code=56, ret=0x32,
        data=bytes([0, 1, 0, 1]) + b"XF-build-0001abcd")
    out["rsp-crc8-64"] = rsp_packet(32, CHECK_CRC8, index=3, code=13, ret=8,
                                    data=bytes(range(32)))
    out["rsp-ccitt-200"] = rsp_packet(168, CHECK_CCITT, index=9, code=5,
                                      ret=2, data=bytes(range(48)))
    out["rsp-crc32-1440"] = rsp_packet(
        1408, CHECK_CRC32, ecat=8, index=200, code=5, ret=2,
        data=bytes((i * 13) & 0xFF for i in range(1408)))
    out["rsp-not-ready-144"] = rsp_packet(112, CHECK_CRC32, not_ready=True)

    # engine: sync, an immediate read, an async command that runs busy
    # for a while, then its *_GET partner
    s = script(112, CHECK_CRC32, 0, [
        (K_RAW, 56, 0, rx_tx(4, 0)),          # FW_VERSION_GET, rx 20
        (K_RAW, 12, 2, rx_tx(0, 2)),          # STATE_SET PRE_OP (async)
        (K_RAW, 13, 0, rx_tx(3, 0)),          # STATE_GET, rx 8
        (K_RAW, 10, 0, rx_tx(5, 3)),          # SDO_REQ (async), tx 24
        (K_RAW, 11, 0, rx_tx(2, 0)),          # SDO_GET, rx 1 (-EMSGSIZE)
    ])
    s += answer(GOOD | OP, ecm=STS_NOP)                   # sync
    s += answer(GOOD, length=20)                          # FW_VERSION
    s += answer(GOOD, ecm=STS_BUSY)                       # STATE_SET
    s += answer(GOOD | OP, ecm=STS_BUSY)                  # busy...
    s += answer(GOOD, ecm=STS_BUSY, length=1)
    s += answer(GOOD, ecm=0, length=1)                    # done
    s += answer(GOOD | OP, length=8)
    s += answer(GOOD, ecm=STS_BUSY)
    s += answer(GOOD, ecm=0, err=ERR_ASYNC)               # SDO failed
    s += answer(GOOD | OP, length=4)
    s += answer(GOOD, length=4)
    out["eng-crc32-async"] = s

    # engine: CRC_TYPE_SET, SPI_RECONFIG to the maximum size, WARM_RESET
    s = script(112, CHECK_FIXED, 3, [
        (K_LINK, 1, CHECK_CRC32, rx_tx(0, 0)),   # CRC_TYPE_SET CRC-32
        (K_LINK, 0, 0x60, 0x05 | rx_tx(0, 0)),   # SPI_RECONFIG (len 32+0x560%1377)
        (K_RAW, 20, 0, rx_tx(6, 0)),             # SPI_PACK_SIZE_GET
        (K_LINK, 2, 0, rx_tx(0, 0)),             # WARM_RESET
        (K_RAW, 0, 0, rx_tx(1, 0)),              # INFO_UPDATE, zero-size rx
    ])
    s += answer(GOOD | OP, ecm=STS_NOP)
    s += answer(GOOD)
    s += answer(GOOD | OP | PREV_CHECK)
    s += answer(GOOD | STEP_DEADLINE)
    s += answer(GOOD | STEP_100MS, 2)
    s += answer(GOOD | WHOLE, length=2) + bytes(1300)
    s += answer(GOOD | OP)
    s += answer(GOOD | STEP_100MS, 2, ecm=STS_BUSY)
    s += answer(GOOD, ecm=STS_NOP)
    s += answer(GOOD | OP)
    out["eng-reconfig-crc-reset"] = s

    # engine: garbage answers until the retry bound runs out, a cancel,
    # a timeout
    s = script(64, CHECK_CCITT, 2, [
        (K_RAW, 4, 0, rx_tx(3, 1)),
        (K_RAW, 1, 0, rx_tx(5, 4, short_timeout=True)),
        (K_CANCEL_CUR, 0, 0, 0),
        (K_CLR_ERR, 0xFA, 0, 0),
        (K_CLR_INT, 0x80, 0x01, 0x02),
        (K_RAW, 19, 0, rx_tx(7, 0, short_timeout=True)),
    ])
    s += answer(GOOD | OP, ecm=STS_NOP)
    for _ in range(4):
        s += answer(ANSWER_PREV)                 # bad frame
    s += answer(GOOD | OP)
    s += answer(GOOD, ecm=STS_BUSY)
    s += answer(GOOD | OP)
    s += answer(GOOD | OP)
    s += answer(GOOD | OP)
    s += answer(REPAIR | STEP_DEADLINE)          # never answered: timeout
    s += answer(GOOD | STEP_MS, 200)
    out["eng-retries-timeout"] = s

    # engine: a busy reject and a chip reset
    s = script(1408, CHECK_CRC8, 0, [
        (K_RAW, 7, 0, rx_tx(0, 5)),               # PDO_CONFIG_SET, full tx
        (K_RAW, 8, 0, rx_tx(6, 0)),               # PDO_CONFIG_REQ
        (K_RAW, 5, 1, rx_tx(6, 4)),               # PDO_DATA_FIFO_OP
    ])
    s += answer(GOOD | OP, ecm=STS_NOP)
    s += answer(GOOD, ecm=STS_BUSY)
    s += answer(GOOD | OP, ecm=STS_BUSY)
    s += answer(GOOD, ecm=STS_BUSY, err=ERR_CMD)
    s += answer(GOOD | OP, ecm=STS_BUSY)
    s += answer(GOOD | WHOLE, ecm=STS_BUSY, length=700) + bytes(1416)
    s += answer(GOOD, ecm=STS_NOP)
    out["eng-crc8-busy-reset"] = s

    # engine: the script loops, exchanges reuse the previous header (2
    # bytes each): several hundred commands, so the 8-bit index wraps
    s = script(32, CHECK_CRC32, 0, [
        (K_RAW, 13, 0, rx_tx(3, 1)),          # STATE_GET
        (K_RAW, 4, 0, rx_tx(2, 0)),           # PDO_WC_GET
    ])
    s = s[:3] + bytes([s[3] | 0x80]) + s[4:]  # loop the script
    s += answer(GOOD, ecm=STS_NOP)
    s += answer(GOOD, length=1)
    s += bytes([GOOD, 0x80]) * 1100
    out["eng-index-wrap"] = s
    return out


def main():
    outdir = sys.argv[1] if len(sys.argv) > 1 else \
        os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")
    os.makedirs(outdir, exist_ok=True)
    for name, data in sorted(seeds().items()):
        with open(os.path.join(outdir, name), "wb") as f:
            f.write(data)
        print(f"{name}: {len(data)} bytes")


if __name__ == "__main__":
    main()
