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
  good, and the header's named bits equal the bits of decode --json's
  numbers (masks from the manual); a packet whose data byte is flipped
  shows bad;
- decode --pcapng of bad input names the line, writes nothing; /dev/full
  and an unwritable directory fail with a message;
- the ECM-SK (sk-sim:, LINKTYPE_USER2): `states OP` and an SDO upload
  recorded with --trace x.pcapng and with a text trace (ex=3: CRC-8 both
  ways, ex=0: none, slot=16); decode --pcapng of the text trace is the
  live pcapng byte for byte; tshark shows for every frame the fields
  decode --json shows (direction, slot size, CRC-8 status, slot 0, the
  slave slots); a frame with a flipped byte shows the CRC-8 bad in both.

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


def tshark(pcap, fields=None, occurrence=("-E", "occurrence=f")):
    """One dict per packet: FIELDS (default FIELDS) as tshark with ecmxf.lua
    shows them; a Lua error is a failure."""
    fields = fields or FIELDS
    args = ["tshark", "-n", "-X", "lua_script:" + LUA, "-r", pcap, "-T", "fields",
            "-E", "separator=|", *occurrence]
    for f in fields:
        args += ["-e", f]
    p = run(*args)
    if "Lua" in p.stderr and "rror" in p.stderr:
        fail("tshark reported a Lua error: " + p.stderr)
    return [dict(zip(fields, line.split("|"))) for line in p.stdout.splitlines()]


# named header bits (ECM-XF manual ver. 050, the header tables): the
# dissector's field, the decode --json number it is a bit of, the mask
BITS = [
    ("ecmxf.ecm_status.nop", "ecm_status", 0x20),
    ("ecmxf.ecm_status.fifo_enabled", "ecm_status", 0x40),
    ("ecmxf.ecm_status.busy", "ecm_status", 0x80),
    ("ecmxf.ecm_status.dc_stable", "ecm_status", 0x04),
    ("ecmxf.err_status.link", "err_status", 0x01),
    ("ecmxf.err_status.command_error", "err_status", 0x80),
    ("ecmxf.control.refresh_state", "control", 0x01),
    ("ecmxf.control.clear_crc_count", "control", 0x02),
    ("ecmxf.reserved.lrw", "reserved", 0x0800),
    ("ecmxf.reserved.bus_shift", "reserved", 0x1000),
    ("ecmxf.reserved.gpio_out_valid", "reserved", 0x8000),
    ("ecmxf.int_clear.wkc_error", "int_clear", 1 << 22),
    ("ecmxf.int_clear.ethercat_packet", "int_clear", 1 << 31),
    ("ecmxf.int_flags.wkc_error", "int_flags", 1 << 22),
    ("ecmxf.int_flags.ethercat_packet", "int_flags", 1 << 31),
]


def compare_bits(label, pcap, records):
    """Every named bit tshark shows equals the bit of decode --json's number."""
    rows = tshark(pcap, [f for f, _, _ in BITS])
    if len(rows) != len(records):
        fail(f"{label} bits: tshark shows {len(rows)} packets, the trace has {len(records)}")
        return
    shown = 0
    for i, (row, rec) in enumerate(zip(rows, records)):
        for field, key, mask in BITS:
            got = row.get(field, "")
            if key not in rec:
                if got != "":
                    fail(f"{label}: packet {i + 1} shows {field} = {got!r}, which its kind has not")
                continue
            want = "1" if rec[key] & mask else "0"
            shown += 1
            if got != want:
                fail(f"{label}: packet {i + 1} {field} = {got!r}, expected {want!r} ({key} {rec[key]:#x})")
    if shown == 0:
        fail(f"{label}: no named header bit compared")


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


SK_FIELDS = ["ecmsk.dir", "ecmsk.slot_size", "ecmsk.crc.status", "ecmsk.cmd", "ecmsk.cmd.name",
             "ecmsk.param", "ecmsk.crc_errors", "ecmsk.state", "ecmsk.data1", "ecmsk.data2", "ecmsk.data3",
             "ecmsk.slot.index", "ecmsk.slave.cmd", "ecmsk.slave.index", "ecmsk.slave.target",
             "ecmsk.slave.value", "frame.len"]

# every occurrence of the slave-slot fields, comma-separated
SK_OCCURRENCE = ("-E", "occurrence=a", "-E", "aggregator=,")


def compare_sk(label, rows, records):
    if len(rows) != len(records):
        fail(f"{label}: tshark shows {len(rows)} frames, the trace has {len(records)}")
        return
    num = lambda v: str(int(v, 0)) if v else ""
    nums = lambda v: ",".join(num(x) for x in v.split(",")) if v else ""
    for i, (row, rec) in enumerate(zip(rows, records)):
        if not rec.get("sk"):
            fail(f"{label}: record {i + 1} is not an ECM-SK frame")
            continue
        mosi = rec["dir"] == "mosi"
        slaves = rec["slaves"]
        want = {
            "ecmsk.dir": "host>board" if mosi else "board>host",
            "ecmsk.slot_size": str(rec["slot_size"]),
            "ecmsk.crc.status": {"ok": "good", "bad": "bad", "none": "not checked"}[rec["crc"]],
            "ecmsk.cmd": str(rec["cmd"]),
            "ecmsk.cmd.name": rec["name"],
            "ecmsk.param": str(rec["param"]) if mosi else "",
            "ecmsk.crc_errors": "" if mosi else str(rec["crc_errors"]),
            "ecmsk.state": "" if mosi else str(rec["state"]),
            "ecmsk.data1": str(rec["data1"]),
            "ecmsk.data2": str(rec["data2"]),
            "ecmsk.data3": str(rec["data3"]) if "data3" in rec else "",
            "ecmsk.slot.index": ",".join(str(x["slot"]) for x in slaves),
            "ecmsk.slave.cmd": ",".join(str(x["cmd"]) for x in slaves),
            "ecmsk.slave.index": ",".join(str(x["index"]) for x in slaves),
            "ecmsk.slave.target": ",".join(str(x["target"]) for x in slaves),
            "ecmsk.slave.value": ",".join(str(x["value"]) for x in slaves),
            "frame.len": str(rec["size"]),
        }
        for k, v in want.items():
            got = row.get(k, "")
            if k in ("ecmsk.cmd", "ecmsk.param", "ecmsk.crc_errors", "ecmsk.state", "ecmsk.data1",
                     "ecmsk.data2", "ecmsk.data3"):
                got = num(got)
            elif k.startswith("ecmsk.slave.") or k == "ecmsk.slot.index":
                got = nums(got)
            if got != v:
                fail(f"{label}: frame {i + 1} {k} = {got!r}, expected {v!r}")


def check_sk(tmp):
    """The ECM-SK's frames: live pcapng = converted text trace; tshark = decode --json."""
    conv = os.path.join(tmp, "skconv.pcapng")
    runs = (("?ex=3", ["states", "OP"]), ("?ex=3", ["upload", "-p", "0", "0x1018:1"]),
            ("", ["upload", "-p", "1", "0x1018:2"]), ("?slot=16&ex=1", ["states", "OP"]))
    seen_slaves = seen_crc = seen_none = False
    for k, (opts, cmd) in enumerate(runs):
        label = f"sk-sim:{opts} {' '.join(cmd)}"
        live = os.path.join(tmp, f"sk{k}.pcapng")
        text = os.path.join(tmp, f"sk{k}.trace")
        run(UTIL, "-d", "sk-sim:" + opts, "--trace", live, *cmd)
        run(UTIL, "-d", "sk-sim:" + opts, "--trace", text, *cmd)
        want_format = "format ecm-sk %s %s" % ("16" if "slot=16" in opts else "12",
                                               {"?ex=3": "crc", "": "nocrc", "?slot=16&ex=1": "cmdcrc"}[opts])
        if want_format not in open(text).read().splitlines():
            fail(f"{label}: no line {want_format!r} in the text trace")
        run(UTIL, "decode", "--pcapng", conv, text)
        with open(live, "rb") as a, open(conv, "rb") as b:
            if a.read() != b.read():
                fail(f"{label}: --trace x.pcapng and decode --pcapng of the same run differ")
        records = decode_json(text)
        if not records:
            fail(f"{label}: nothing recorded")
            continue
        if any(r["crc"] == "bad" for r in records):
            fail(f"{label}: a recorded frame decodes with a bad CRC-8")
        seen_slaves |= any(r["slaves"] for r in records)
        seen_crc |= any(r["crc"] == "ok" for r in records)
        seen_none |= any(r["crc"] == "none" for r in records)
        compare_sk(label, tshark(live, SK_FIELDS, SK_OCCURRENCE), records)
        summary = run(UTIL, "decode", text).stdout.splitlines()[-1]
        if f"{len(records)} of them ECM-SK frames" not in summary:
            fail(f"{label}: decode's summary line {summary!r}")
    if not (seen_slaves and seen_crc and seen_none):
        fail(f"sk: slave slots {seen_slaves}, CRC-8 checked {seen_crc}, not checked {seen_none}: expected all")

    # a flipped byte in slot 0's data of a CRC-checked frame
    text = os.path.join(tmp, "sk0.trace")
    lines = open(text).read().splitlines()
    frames = [i for i, l in enumerate(lines) if " > " in l or " < " in l]
    pkt, k = frames[4], 4
    words = lines[pkt].split(" ")
    words[3] = "%08x" % (int(words[3], 16) ^ 0x01000000)  # bytes 4-7: data1's first byte
    lines[pkt] = " ".join(words)
    bad = os.path.join(tmp, "skbad.trace")
    open(bad, "w").write("\n".join(lines) + "\n")
    run(UTIL, "decode", "--pcapng", conv, bad)
    records = decode_json(bad)
    if records[k]["crc"] != "bad":
        fail("sk: the frame with a flipped byte decodes " + records[k]["crc"])
    rows = tshark(conv, SK_FIELDS, SK_OCCURRENCE)
    compare_sk("sk corrupted", rows, records)
    if len(rows) > k and rows[k]["ecmsk.crc.status"] != "bad":
        fail("sk: tshark shows the flipped frame's CRC-8 " + rows[k]["ecmsk.crc.status"])
    text_log = run(UTIL, "decode", bad).stdout
    if "[BAD]" not in text_log or "BAD (expected 0x" not in text_log:
        fail("sk: the text log does not show the bad CRC-8")

    # --trace with a URI that has options already, and a bad file
    p = run(UTIL, "-d", "sk-sim:?ex=3", "--trace", os.path.join(tmp, "no", "x.trace"), "info", ok=False)
    if p.returncode == 0 or "No such file or directory" not in p.stderr or "no/x.trace" not in p.stderr:
        fail(f"sk: --trace into a missing directory: exit {p.returncode}, stderr {p.stderr!r}")


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
            compare_bits(label, live, records)
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

        check_sk(tmp)

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
