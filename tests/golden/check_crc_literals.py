#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Re-derive the CRC-32 check words of the golden packets independently.

Reads the byte arrays of test_golden.cpp, and for every CRC-32 packet
(an array whose name ends in "Crc32", plus the N=1408 packet assembled
from kInfoUpdate1408Header + 1408 zero bytes + kInfoUpdate1408Trailer)
computes

    zlib.crc32(bytes(pkt[:len(pkt) - 8])) & 0xFFFFFFFF

i.e. over header + data, every byte before the check word, and compares it
with the little-endian check word literal and its "CRC-32 = 0x..." comment.
It also checks the frame words of every packet.  Exit status 0 when all
literals are right.

--write fills in placeholders (check word bytes 0xEE 0xEE 0xEE 0xEE with a
"@CRC@" comment) with the computed values; it was used once to paste the
literals and never touches a literal that is already filled in.
"""
import re
import sys
import zlib
from pathlib import Path

SRC = Path(__file__).with_name("test_golden.cpp")
ARRAY_RE = re.compile(
    r"constexpr std::uint8_t (k\w+)\[\] = \{(.*?)\n\};", re.DOTALL)
START = bytes.fromhex("A4A3A2A1")
END = bytes.fromhex("59585756")
FIXED = bytes.fromhex("78563412")
NOT_READY = bytes.fromhex("21436587")
PLACEHOLDER = bytes.fromhex("EEEEEEEE")


def parse(body):
    body = re.sub(r"//[^\n]*", "", body)
    return bytes(int(tok, 16) for tok in re.findall(r"0x[0-9A-Fa-f]{2}\b", body))


def crc_of(pkt):
    return zlib.crc32(pkt[:len(pkt) - 8]) & 0xFFFFFFFF


def main():
    write = "--write" in sys.argv[1:]
    text = SRC.read_text()
    arrays = {m.group(1): (m, parse(m.group(2))) for m in ARRAY_RE.finditer(text)}
    errors = 0
    fixes = {}  # array name -> crc

    packets = {}
    for name, (_, data) in arrays.items():
        if len(data) >= 64 and data[:4] == START:
            packets[name] = data
    hdr = arrays["kInfoUpdate1408Header"][1]
    trl = arrays["kInfoUpdate1408Trailer"][1]
    packets["kInfoUpdate1408Trailer"] = hdr + bytes(1408) + trl

    for name, pkt in packets.items():
        n = len(pkt) - 32
        if not 32 <= n <= 1408 or pkt[:4] != START or pkt[-4:] != END:
            print(f"{name}: bad frame (length {len(pkt)})")
            errors += 1
            continue
        word = pkt[-8:-4]
        if name.endswith("Crc32") or name == "kInfoUpdate1408Trailer":
            crc = crc_of(pkt)
            want = crc.to_bytes(4, "little")
            if word == want:
                body = arrays[name][0].group(2)
                if f"CRC-32 = 0x{crc:08X}" not in body:
                    print(f"{name}: comment does not say CRC-32 = 0x{crc:08X}")
                    errors += 1
                else:
                    print(f"{name}: N={n} CRC-32 0x{crc:08X} ok")
            elif word == PLACEHOLDER and write:
                fixes[name] = crc
            else:
                print(f"{name}: N={n} check word {word.hex(' ')} but "
                      f"zlib.crc32 gives 0x{crc:08X} ({want.hex(' ')})")
                errors += 1
        elif word not in (FIXED, NOT_READY):
            print(f"{name}: check word {word.hex(' ')} is neither fixed nor not-ready")
            errors += 1

    for name, crc in fixes.items():
        m = arrays[name][0]
        body = m.group(2)
        lit = ", ".join(f"0x{b:02X}" for b in crc.to_bytes(4, "little"))
        body = body.replace("0xEE, 0xEE, 0xEE, 0xEE", lit, 1)
        body = re.sub(r"@CRC(?:1408)?@ {0,5}", f"0x{crc:08X}  ", body, count=1)
        text = text.replace(m.group(2), body, 1)
        print(f"{name}: wrote CRC-32 0x{crc:08X} ({lit})")
    if fixes:
        SRC.write_text(text)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
