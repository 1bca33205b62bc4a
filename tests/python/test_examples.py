# SPDX-License-Identifier: MIT
"""The Python examples of examples/python (Documentation/python.rst) run
against sim: and say what they should; a bad URI is one line and status 1."""

import csv
import os
import subprocess
import sys

import pytest

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python")


def run(name, *args, cwd=None):
    return subprocess.run([sys.executable, os.path.join(EXAMPLES, name), *args], capture_output=True,
                          text=True, cwd=cwd, timeout=120)


def test_scan_bus():
    r = run("scan_bus.py")
    assert r.returncode == 0, r.stderr
    assert "ECM-XF (sim:): 3 slaves, PREOP" in r.stdout
    assert r.stdout.count("EST-584") == 2


def test_read_object():
    r = run("read_object.py")
    assert r.returncode == 0, r.stderr
    assert "0x2001:00        50000" in r.stdout
    assert "abort 0x06020000 Object not existing" in r.stdout
    assert "0x6081:00        20000" in r.stdout


def test_csp_move(tmp_path):
    r = run("csp_move.py", "sim:", str(tmp_path / "move"))
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "move.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) >= 500
    assert int(rows[-1]["position"]) == int(rows[0]["position"]) + 50000
    assert "moved from" in r.stdout


@pytest.mark.parametrize("name", ["scan_bus.py", "read_object.py", "csp_move.py"])
def test_bad_uri(name, tmp_path):
    r = run(name, "nosuch:", str(tmp_path / "x"))
    assert r.returncode == 1
    assert r.stderr.startswith(name[:-3] + ": ") and r.stderr.count("\n") == 1
