#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A CSP move of slave 0 with ecmxf.Cyclic; the positions of every cycle
are written to OUT.csv and, when matplotlib is installed, plotted to
OUT.png.

    csp_move.py [URI] [OUT]  (default "sim:" and "csp_move")
"""
import csv
import sys

import ecmxf

uri = sys.argv[1] if len(sys.argv) > 1 else "sim:"
out = sys.argv[2] if len(sys.argv) > 2 else "csp_move"
try:
    with ecmxf.open(uri) as dev:
        dev.bring_up(motion=[0])                 # OP, DC at 1 ms, the motion PDOs on slave 0
        with ecmxf.Cyclic(dev, period=0.001) as cyc:
            cyc.start()
            axis = cyc.axis(0, modes=[8])
            axis.set_mode(8)
            cyc.run_until_done([axis], 1.0)
            axis.enable()
            cyc.run_until_done([axis], 2.0)
            try:
                position = cyc.input(0, 0x6064, 0, "i32")
                target = cyc.output(0, 0x607A, 0, "i32")
                start = axis.position
                # the loop runs in C++ (GIL released); Python gets the samples
                rows = cyc.csp_move([axis], [start + 50000], 0.5, sample=[target, position])
            finally:
                axis.disable()
                cyc.run_until_done([axis], 1.0)
except ecmxf.Error as e:
    sys.exit(f"csp_move: {e}")

with open(out + ".csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["t_s", "target", "position"])
    w.writerows((f"{t:.6f}", int(tg), int(p)) for t, tg, p in rows)
print(f"moved from {start} to {int(rows[-1][2])} in {len(rows)} cycles; {out}.csv", end="")
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print(" (no matplotlib: no plot)")
else:
    t = [r[0] for r in rows]
    plt.plot(t, [r[1] for r in rows], label="target")
    plt.plot(t, [r[2] for r in rows], label="position actual")
    plt.xlabel("s")
    plt.ylabel("counts")
    plt.legend()
    plt.savefig(out + ".png")
    print(f", {out}.png")
