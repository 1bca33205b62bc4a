# SPDX-License-Identifier: MIT
"""Fixtures of the Python binding's suite (tests/python, Documentation/python.rst).

ctest runs each test_*.py file as one test with PYTHONPATH at the built
package (build/python) and ECMXF_SIM_BINARY at the built ecmxf-sim.
"""

import os
import socket
import subprocess
import tempfile
import time

import pytest

import ecmxf


@pytest.fixture
def dev():
    """sim: with the bus in PRE-OP (what open() does to a fresh bus)."""
    with ecmxf.open("sim:") as d:
        yield d


@pytest.fixture
def op_dev():
    """sim: in OP with the motion PDOs on slave 0 (EST-584)."""
    with ecmxf.open("sim:") as d:
        d.bring_up(motion=[0])
        yield d


class SimServer:
    """An ecmxf-sim --socket server, killed at the end (as tests/common/sim_server.hpp)."""

    def __init__(self, extra=()):
        self.dir = tempfile.TemporaryDirectory(prefix="ecmxf-pytest-")
        self.path = os.path.join(self.dir.name, "sim.sock")
        binary = os.environ.get("ECMXF_SIM_BINARY")
        if not binary:
            pytest.fail("ECMXF_SIM_BINARY is not set (ctest sets it to the built ecmxf-sim)")
        self.proc = subprocess.Popen([binary, "--socket", self.path, *extra],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        # serving once a connection is accepted (no timed assertion: the
        # bound is only against a server that never comes up)
        for _ in range(2000):
            if self.proc.poll() is not None:
                pytest.fail("ecmxf-sim exited: " + self.proc.stderr.read().decode(errors="replace"))
            try:
                with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as s:
                    s.connect(self.path)
                break
            except OSError:
                time.sleep(0.005)
        else:
            pytest.fail("ecmxf-sim did not start serving on " + self.path)

    def close(self):
        self.proc.kill()
        self.proc.wait()
        self.proc.stderr.close()
        self.dir.cleanup()


@pytest.fixture
def sim_server():
    s = SimServer()
    yield s
    s.close()


@pytest.fixture
def sk_server():
    s = SimServer(["--board", "ecm-sk"])
    yield s
    s.close()
