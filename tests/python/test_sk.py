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
