#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Read objects by SDO: typed values, a whole object, and an abort.

    read_object.py [URI]     (default "sim:"; slave 0 is an EST-584)
"""
import sys

import ecmxf

uri = sys.argv[1] if len(sys.argv) > 1 else "sim:"
try:
    with ecmxf.open(uri) as dev:
        print("device name     ", dev.sdo.upload(0, 0x1008, 0, "str"))
        print("0x2001:00       ", dev.sdo.upload(0, 0x2001, 0))          # type from the size: 50000
        print("identity 0x1018 ", [hex(v) for v in dev.sdo.upload_object(0, 0x1018)])
        dev.sdo.download(0, 0x6081, 0, 20000)                         # profile velocity
        print("0x6081:00       ", dev.sdo.upload(0, 0x6081, 0, "u32"))
        try:
            dev.sdo.upload(0, 0x2FFF, 0)
        except ecmxf.SdoAbort as e:
            print(f"0x2FFF:00        abort 0x{e.code:08X} {e.text}")
except ecmxf.Error as e:
    sys.exit(f"read_object: {e}")
