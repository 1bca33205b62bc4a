# SPDX-License-Identifier: MIT
"""ecmxf.Cyclic on sim:: the process image through the buffer protocol
(memoryview and numpy, no copies), typed entries, CiA-402 axes, the loops
in C++ and a cycle loop in Python."""

import numpy as np
import pytest

import ecmxf


@pytest.fixture
def cyc(op_dev):
    with ecmxf.Cyclic(op_dev) as c:
        c.start()
        yield c


def enabled_axis(cyc, mode, modes=None):
    """Slave 0's axis in mode, OPERATION ENABLED."""
    ax = cyc.axis(0, modes=modes or [mode])
    ax.set_mode(mode)
    cyc.run_until_done([ax], 1.0)
    ax.enable()
    cyc.run_until_done([ax], 2.0)
    assert ax.enabled and ax.state == "OPERATION ENABLED"
    return ax


def test_image_sizes_and_offsets(cyc, op_dev):
    m = op_dev.pdo_mapping(0)
    assert len(cyc.outputs) >= m["output_bytes"]
    assert cyc.output_offset(0) == 0 and cyc.input_offset(0) == 0
    assert cyc.output_offset(1) == m["output_bytes"]
    assert cyc.outputs.readonly is False and cyc.inputs.readonly is True
    assert cyc.outputs.format == "B" and cyc.outputs.itemsize == 1


def test_buffers_share_memory_without_copies(cyc):
    out = np.frombuffer(cyc.outputs, dtype=np.uint8)
    assert out.flags.writeable and not out.flags.owndata
    cw = cyc.output(0, 0x6040, 0, "u16")
    cw.value = 0x1234
    off = cw.bit_offset // 8
    assert out[off] == 0x34 and out[off + 1] == 0x12          # the entry's write is seen by numpy
    out[off] = 0x0F
    assert cw.value == 0x120F                                 # numpy's write by the entry
    mv = cyc.outputs
    mv[off + 1] = 0
    assert cw.value == 0x0F
    inp = np.frombuffer(cyc.inputs, dtype=np.uint8)
    assert not inp.flags.writeable


def test_entries_by_name_and_index(cyc, op_dev):
    names = {e["index"]: e["name"] for e in op_dev.pdo_mapping(0)["inputs"]}
    by_index = cyc.input(0, 0x6064, 0, "i32")
    by_name = cyc.input(0, names[0x6064], type="i32")
    assert by_index.bit_offset == by_name.bit_offset and by_index.bits == 32
    assert "0x6064:00" in repr(by_index)
    sw = cyc.input(0, 0x6041)                                 # no type: unsigned of its width
    cyc.run(5)
    assert isinstance(sw.value, int) and sw.value == sw.get()


def test_inputs_arrive(cyc):
    sw = cyc.input(0, 0x6041, 0, "u16")
    before = bytes(cyc.inputs)
    cyc.run(20)
    assert sw.value != 0 and bytes(cyc.inputs) != before
    assert cyc.stats["cycles"] == 20 and cyc.stats["failed_cycles"] == 0
    r = cyc.last_result
    assert r["error"] == 0 and r["wkc_ok"]


def test_python_cycle_loop_and_pp_move(cyc):
    ax = enabled_axis(cyc, 1)
    start = ax.position
    ax.move_to(start + 2000)
    for _ in range(5000):                                     # the loop in Python
        assert cyc.cycle() == 0
        ax.update()
        assert cyc.wait_next_cycle() == 0
        if ax.done:
            break
    assert ax.done and not ax.failed
    assert ax.position == start + 2000


def test_csp_move_records_the_positions(cyc):
    ax = enabled_axis(cyc, 8)
    pos = cyc.input(0, 0x6064, 0, "i32")
    start = ax.position
    rows = cyc.csp_move([ax], [start + 50000], 0.5, sample=[pos])
    assert len(rows) >= 500                                   # one row per 1 ms cycle
    t = [r[0] for r in rows]
    assert t == sorted(t)
    assert rows[0][1] == pytest.approx(start, abs=100)
    assert rows[-1][1] == start + 50000
    assert ax.position == start + 50000
    ax.disable()
    cyc.run_until_done([ax], 1.0)
    assert not ax.enabled


def test_pv_and_homing(cyc):
    ax = enabled_axis(cyc, 3, [3, 6])
    p0 = ax.position
    ax.set_velocity(10000)
    cyc.run_until_done([ax], 5.0)
    cyc.run(100)
    assert ax.position > p0
    ax.set_velocity(0)
    cyc.run_until_done([ax], 5.0)
    ax.set_mode(6)
    cyc.run_until_done([ax], 1.0)
    ax.home(37)                                               # on the current position
    cyc.run_until_done([ax], 30.0)
    assert ax.done
    with pytest.raises(ecmxf.SdoAbort):
        ax.home(1)                                            # a method the drive refuses


def test_run_samples_in_cpp(cyc):
    sw = cyc.input(0, 0x6041, 0, "u16")
    pos = cyc.input(0, 0x6064, 0, "i32")
    rows = cyc.run(10, sample=[sw, pos])
    assert len(rows) == 10 and all(len(r) == 3 for r in rows)
    assert rows[-1][1] == sw.value


def test_buffers_outlive_the_cyclic(op_dev):
    c = ecmxf.Cyclic(op_dev)
    a = np.frombuffer(c.inputs, dtype=np.uint8)
    c.close()
    del c
    assert a.sum() >= 0                                       # still valid memory
