#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""pcapng traces read by tshark with the generated dissector ecmxf.lua
(Documentation/trace.rst, "pcapng" and "Wireshark").

test-pcapng.py UTIL LUA

- records `info` on the simulator with --trace x.pcapng (fixed check word
  and sim:?check=crc32, crc8, ccitt) and with --trace x.trace; decode
  --pcapng of the text trace gives the same bytes as the live pcapng;
- tshark with ecmxf.lua shows for every packet the fields decode --json
  shows (direction, code, name, index, param or ret, len) and check word
  good; a packet whose data byte is flipped shows bad;
- decode --pcapng of bad input names the line, writes nothing; /dev/full
  and an unwritable directory fail with a message.

tshark missing is a failure, not a skip: scripts/install-deps.sh installs
it. As root, tshark runs Lua scripts because Debian's init.lua sets
run_user_scripts_when_superuser = true.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

UTIL, LUA = sys.argv[1], sys.argv[2]
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


def run(*args, ok=True):
    p = subprocess.run(args, capture_output=True, text=True)
    if ok and p.returncode != 0:
        raise SystemExit(f"{' '.join(args)} exited {p.returncode}: {p.stderr}")
    return p


FIELDS = ["ecmxf.dir", "ecmxf.code", "ecmxf.name", "ecmxf.index", "ecmxf.param", "ecmxf.ret",
          "ecmxf.len", "ecmxf.check.status", "ecmxf.check.type", "frame.len"]


def tshark(pcap):
    args = ["tshark", "-n", "-X", "lua_script:" + LUA, "-r", pcap, "-T", "fields",
            "-E", "separator=|", "-E", "occurrence=f"]
    for f in FIELDS:
        args += ["-e", f]
    p = run(*args)
    if "Lua" in p.stderr and "rror" in p.stderr:
        fail("tshark reported a Lua error: " + p.stderr)
    return [dict(zip(FIELDS, line.split("|"))) for line in p.stdout.splitlines()]


def decode_json(trace):
    return json.loads(run(UTIL, "decode", "--json", trace).stdout)


def compare(label, rows, records):
    if len(rows) != len(records):
        fail(f"{label}: tshark shows {len(rows)} packets, the trace has {len(records)}")
        return
    for i, (row, rec) in enumerate(zip(rows, records)):
        want = {
            "ecmxf.dir": "host>chip" if rec["dir"] == "mosi" else "chip>host",
            "ecmxf.code": str(rec["code"]),
            "ecmxf.name": rec["name"],
            "ecmxf.index": str(rec["index"]),
            "ecmxf.len": str(rec["len"]),
            "ecmxf.check.status": "good" if rec["check"] == "ok" else "bad",
            "frame.len": str(rec["size"]),
        }
        want["ecmxf.param" if rec["dir"] == "mosi" else "ecmxf.ret"] = str(
            rec["param"] if rec["dir"] == "mosi" else rec["ret"])
        for k, v in want.items():
            got = row.get(k, "")
            if k in ("ecmxf.code", "ecmxf.index", "ecmxf.param", "ecmxf.ret"):
                got = str(int(got, 0)) if got else ""
            if got != v:
                fail(f"{label}: packet {i + 1} {k} = {got!r}, expected {v!r}")


def main():
    if shutil.which("tshark") is None:
        print("FAIL: tshark is not installed (scripts/install-deps.sh installs it)")
        return 1
    tmp = tempfile.mkdtemp(prefix="ecmxf-pcapng-")
    try:
        for check in ("", "?check=crc32", "?check=crc8", "?check=ccitt"):
            label = "sim:" + check
            live = os.path.join(tmp, "live.pcapng")
            text = os.path.join(tmp, (check[7:] or "fixed") + ".trace")
            conv = os.path.join(tmp, "conv.pcapng")
            run(UTIL, "-d", "sim:" + check, "--trace", live, "info")
            run(UTIL, "-d", "sim:" + check, "--trace", text, "info")
            run(UTIL, "decode", "--pcapng", conv, text)
            with open(live, "rb") as a, open(conv, "rb") as b:
                if a.read() != b.read():
                    fail(f"{label}: --trace x.pcapng and decode --pcapng of the same run differ")
            records = decode_json(text)
            rows = tshark(live)
            compare(label, rows, records)
            want_type = {"": "fixed", "?check=crc32": "CRC-32", "?check=crc8": "CRC-8",
                         "?check=ccitt": "CRC-CCITT"}[check]
            if rows and rows[-1]["ecmxf.check.type"] != want_type:
                fail(f"{label}: last packet's check type {rows[-1]['ecmxf.check.type']!r}, expected {want_type!r}")

        # a corrupted packet, the last one (the CRC-32 trace starts with
        # the fixed word until CRC_TYPE_SET): of the CRC-32 trace one data
        # byte flipped; of the fixed one the check word (the fixed word
        # covers nothing)
        for name, word in (("crc32", 10), ("fixed", -2)):
            text = os.path.join(tmp, name + ".trace")
            lines = open(text).read().splitlines()
            pkts = [i for i, l in enumerate(lines) if " > " in l or " < " in l]
            pkt, k = pkts[-1], len(pkts) - 1
            words = lines[pkt].split(" ")
            words[word] = "%08x" % (int(words[word], 16) ^ 0x01)
            lines[pkt] = " ".join(words)
            bad = os.path.join(tmp, "bad.trace")
            open(bad, "w").write("\n".join(lines) + "\n")
            run(UTIL, "decode", "--pcapng", conv, bad)
            records = decode_json(bad)
            if records[k]["check"] == "ok":
                fail(name + ": the corrupted packet decodes ok")
            rows = tshark(conv)
            compare("corrupted " + name, rows, records)
            if rows[k]["ecmxf.check.status"] != "bad":
                fail(name + ": tshark shows the corrupted packet's check word " + rows[k]["ecmxf.check.status"])

        # bad input: the line named, no output file
        out = os.path.join(tmp, "never.pcapng")
        broken = os.path.join(tmp, "broken.trace")
        open(broken, "w").write("ecmxf-trace 1\nformat 112 fixed\n0.1 > a4a3a2a1 zz\n")
        p = run(UTIL, "decode", "--pcapng", out, broken, ok=False)
        if p.returncode == 0 or "trace line 3" not in p.stderr:
            fail(f"bad trace: exit {p.returncode}, stderr {p.stderr!r}")
        if os.path.exists(out) or [f for f in os.listdir(tmp) if f.startswith("never")]:
            fail("a bad trace left an output file: " + str(os.listdir(tmp)))
        p = run(UTIL, "decode", "--pcapng", out, os.path.join(tmp, "missing.trace"), ok=False)
        if p.returncode == 0 or os.path.exists(out):
            fail("a missing input trace: exit 0 or an output file")
        # an existing file is kept as it was when the conversion fails
        open(out, "w").write("old")
        run(UTIL, "decode", "--pcapng", out, broken, ok=False)
        if open(out).read() != "old":
            fail("a failed conversion replaced the existing output file")
        # unwritable output
        p = run(UTIL, "decode", "--pcapng", "/dev/full", text, ok=False)
        if p.returncode == 0 or "No space left on device" not in p.stderr:
            fail(f"/dev/full: exit {p.returncode}, stderr {p.stderr!r}")
        p = run(UTIL, "decode", "--pcapng", os.path.join(tmp, "no", "dir.pcapng"), text, ok=False)
        if p.returncode == 0 or "No such file or directory" not in p.stderr:
            fail(f"missing directory: exit {p.returncode}, stderr {p.stderr!r}")
        p = run(UTIL, "decode", "--pcapng", tmp, text, ok=False)
        if p.returncode == 0 or "directory" not in p.stderr:
            fail(f"a directory as output: exit {p.returncode}, stderr {p.stderr!r}")
        p = run(UTIL, "decode", "--pcapng", ok=False)
        if p.returncode == 0 or "needs an output file name" not in p.stderr:
            fail(f"--pcapng without a name: exit {p.returncode}, stderr {p.stderr!r}")
        p = run(UTIL, "decode", "--json", "--pcapng", out, text, ok=False)
        if p.returncode == 0:
            fail("--json with --pcapng accepted")
    finally:
        shutil.rmtree(tmp)
    if failures:
        print(f"{len(failures)} failures")
        return 1
    print("ok")
    return 0


sys.exit(main())
