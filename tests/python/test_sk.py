# SPDX-License-Identifier: MIT
"""ecmxf against the ECM-SK: sk-sim: (in-process) and sk-unix:PATH (an
ecmxf-sim --board ecm-sk server), through the verbs both masters have."""

import pytest

import ecmxf


@pytest.fixture
def sk():
    with ecmxf.open("sk-sim:") as d:
        yield d


def test_sk_open_and_slaves(sk):
    assert sk.kind == "ECM-SK"
    assert sk.state == ecmxf.State.PREOP                      # brought up from INIT by open()
    s = sk.slaves()
    assert len(s) == sk.slave_count and len(s) >= 1
    assert s[0].position == 0 and s[0].name
    assert s[0].al_status is None and s[0].revision is None


def test_sk_sdo(sk):
    assert isinstance(sk.sdo.upload(1, 0x1018, 2, "u32"), int)
    sk.sdo.download(1, 0x6098, 0, 37, "i8")
    assert sk.sdo.upload(1, 0x6098, 0, "i8") == 37
    sk.sdo.download(1, 0x6098, 0, 35)                         # the type from the object's size
    assert sk.sdo.upload(1, 0x6098, 0) == 35
    with pytest.raises(ValueError, match="300 is outside the range of i8"):
        sk.sdo.download(1, 0x6098, 0, 300, "i8")
    with pytest.raises(ecmxf.NotSupportedError, match="1, 2 or 4 bytes"):
        sk.sdo.download(1, 0x6098, 0, b"\x01\x02\x03")
    with pytest.raises(ValueError, match="slave position 128"):
        sk.sdo.upload(128, 0x6060, 0)


def test_sk_sdo_abort(sk):
    with pytest.raises(ecmxf.SdoAbort) as e:
        sk.sdo.upload(0, 0x5FFF, 0)
    assert e.value.code != 0 and e.value.text


def test_sk_drives_and_io(sk):
    sk.bring_up()                                             # axes detected, drives in CSP, OP
    assert sk.state == ecmxf.State.OP
    sw = sk.drive_enable(1)
    assert sw & 0x6F == 0x27
    sk.drive_disable(1)
    sk.fault_reset(1)
    with pytest.raises(ecmxf.Error, match="refused SV_ON"):
        sk.drive_enable(2)                                    # the I/O slave
    sk.io_write(2, 0x5)
    assert isinstance(sk.io_read(2), int)
    with pytest.raises(ValueError, match="outputs"):
        sk.io_write(2, -1)


def test_sk_refuses_the_ecm_xf_calls(sk):
    for call in (lambda: sk.bring_up(motion=[0]), lambda: sk.pdo_mapping(0), lambda: sk.firmware_version(),
                 lambda: sk.start_trace("/tmp/x")):
        with pytest.raises(ecmxf.NotSupportedError, match="ECM-SK"):
            call()
    with pytest.raises(ecmxf.NotSupportedError):
        ecmxf.Cyclic(sk)


def test_sk_unix(sk_server):
    with ecmxf.open("sk-unix:" + sk_server.path) as d:
        assert d.kind == "ECM-SK"
        assert d.slave_count >= 1
        d.sdo.download(1, 0x6098, 0, 35, "i8")
    with ecmxf.open("sk-unix:" + sk_server.path) as d:
        assert d.sdo.upload(1, 0x6098, 0, "i8") == 35


# ---------------------------------------------------------------- the board's own calls (dev.board)

def test_board_setup_and_status(sk):
    b = sk.board
    assert (b.slot_size, b.max_slaves) == (12, 40)
    st = b.status()
    assert st.state == ecmxf.State.PREOP and st.crc_errors == 0
    assert b.detect_axes() == [ecmxf.SkSlaveType.DRIVE, ecmxf.SkSlaveType.STEP, ecmxf.SkSlaveType.IO]
    assert b.set_axes([ecmxf.SkSlaveType.DRIVE, ecmxf.SkSlaveType.STEP, ecmxf.SkSlaveType.IO]) == 3
    # slave 0 is the drive: the first type that does not match is named
    with pytest.raises(ecmxf.Error, match=r"slave 0 \(STEP\) is not of that type"):
        b.set_axes([ecmxf.SkSlaveType.STEP, ecmxf.SkSlaveType.STEP, ecmxf.SkSlaveType.IO])
    with pytest.raises(ecmxf.Error, match=r"slave 2 \(STEP\) is not of that type"):
        b.set_axes([ecmxf.SkSlaveType.DRIVE, ecmxf.SkSlaveType.STEP, ecmxf.SkSlaveType.STEP])
    with pytest.raises(ecmxf.InvalidArgument):
        b.set_cycle_time(750)                                # not 250 * 2^n us
    with pytest.raises(ValueError, match="cycle time -1"):
        b.set_cycle_time(-1)
    with pytest.raises(ecmxf.InvalidArgument):
        b.set_extensions(4)
    with pytest.raises(TypeError):
        b.set_axes([0, 1])                                   # SkSlaveType values, not ints


def test_board_drives_local_io_and_homing():
    with ecmxf.open("sk-sim:?lio=33") as d:
        b = d.board
        d.bring_up()                                         # OP, the drives in CSP
        assert b.status().state == ecmxf.State.OP and b.status().fifo_remaining == 160   # the simulated board's FIFO, empty
        assert b.read_local() == 33
        b.write_local(0x12)
        d.drive_enable(0)
        b.wait_enabled(0)
        assert b.axis(0).statusword & 0x6F == 0x27
        ax = b.halt(0)                                       # SV_OFF until the power stage is off
        assert ax.statusword & 0x6F not in (0x27, 0x07, 0x23)
        d.drive_enable(1)
        b.wait_enabled(1)
        d.sdo.download(1, 0x607C, 0, 500, "i32")             # home offset
        b.home(1, 37)
        assert b.axis(1).position == 500
        with pytest.raises(ecmxf.Error):
            b.home(2, 37)                                    # the I/O slave has no homing
        with pytest.raises(ValueError, match="homing method 200"):
            b.home(1, 200)
        with pytest.raises(ecmxf.InvalidArgument, match="needs 16-byte slots"):
            b.hsp2(0)
        with pytest.raises(ecmxf.Error, match="DRIVE_MODE|IO"):
            b.set_mode(2, ecmxf.SkMode.CSP)                  # an I/O slave has no mode


def test_board_cyclic_stage_and_cycle():
    with ecmxf.open("sk-sim:") as d:
        b = d.board
        d.bring_up()
        d.drive_enable(0)
        b.wait_enabled(0)
        start = b.axis(0).position
        assert b.stage(0, ecmxf.SkMode.CSP, start + 100)
        assert not b.stage(0, ecmxf.SkMode.CSP, start + 200)  # already staged for this exchange
        r = b.cycle()
        assert r["status"] == "ok" and r["staged"] == 1 and "error" not in r
        for _ in range(20):
            b.cycle()
        assert b.axis(0).position == start + 100
        with pytest.raises(ecmxf.InvalidArgument, match="slave position 40 is outside 0..39"):
            b.stage(40, ecmxf.SkMode.CSP, 0)
        with pytest.raises(ValueError, match="target 2147483648"):
            b.stage(0, ecmxf.SkMode.CSP, 1 << 31)
        with pytest.raises(TypeError):
            b.stage(0, 8, 0)
        assert not b.stage2(0, ecmxf.SkMode.CSP, 1, 2)        # 12-byte slots: no 2-channel commands


def test_board_bad_input_closed_and_not_on_the_ecm_xf():
    with ecmxf.open("sim:") as xf:
        with pytest.raises(ecmxf.NotSupportedError, match="ECM-SK"):
            xf.board
    d = ecmxf.open("sk-sim:")
    b = d.board
    with pytest.raises(ValueError, match="slave position -1"):
        b.axis(-1)
    with pytest.raises(ValueError, match="timeout"):
        b.wait_enabled(0, timeout=0)
    d.close()
    for call in (lambda: d.board, lambda: b.status(), lambda: b.read_local(), lambda: b.cycle(),
                 lambda: b.slot_size):
        with pytest.raises(ecmxf.ClosedError):
            call()
    for cls in (ecmxf.Board, ecmxf.BoardStatus, ecmxf.AxisStatus, ecmxf.Hsp2Status):
        with pytest.raises(TypeError, match="made by ecmxf"):
            cls()


def test_board_over_sk_unix(sk_server):
    with ecmxf.open("sk-unix:" + sk_server.path) as d:
        assert d.board.detect_axes()[2] == ecmxf.SkSlaveType.IO
        d.board.write_local(5)
        assert d.board.status().state == ecmxf.State.PREOP
