#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Scan the bus and print the slaves.

    scan_bus.py [URI]        (default "sim:"; any URI of Documentation/python.rst)
"""
import sys

import ecmxf

uri = sys.argv[1] if len(sys.argv) > 1 else "sim:"
try:
    with ecmxf.open(uri) as dev:                 # a fresh bus is brought to PRE-OP
        print(f"{dev.kind} ({uri}): {dev.slave_count} slaves, {dev.state.name}")
        for s in dev.slaves():
            ident = f"0x{s.vendor:08x}:0x{s.product:08x}" if s.vendor is not None else "?"
            print(f"  {s.position:3}  {s.state.name:7}  {ident}  {s.name}")
except ecmxf.Error as e:
    sys.exit(f"scan_bus: {e}")
