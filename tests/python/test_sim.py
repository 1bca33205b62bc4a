# SPDX-License-Identifier: MIT
"""ecmxf against sim: (the in-process simulated ECM-XF, default network:
2 x EST-584 + 1 digital I/O): open, slaves, SDO, PDO mapping, states,
CiA-402 by SDO, the chip, the packet trace."""

import os

import pytest

import ecmxf


def test_the_issue_example():
    with ecmxf.open("sim:") as dev:
        assert dev.sdo.upload(0, 0x2001, 0) == 50000
        with pytest.raises(ecmxf.SdoAbort) as e:
            dev.sdo.upload(0, 0x2FFF, 0)
        assert e.value.code == 0x06020000
        assert e.value.text == "Object not existing"
        assert "0x2FFF:00" in str(e.value)
        assert isinstance(e.value, ecmxf.Error)
    assert dev.closed


def test_device_class_is_open_and_a_context_manager():
    d = ecmxf.Device("sim:")
    assert d.kind == "ECM-XF" and d.uri == "sim:" and not d.closed
    assert d.state == ecmxf.State.PREOP
    d.close()
    d.close()  # twice is fine
    assert d.closed and "closed" in repr(d)


def test_open_without_bring_up_leaves_the_bus_down():
    with ecmxf.open("sim:", bring_up=False) as d:
        assert d.slave_count == 0
        assert d.state == ecmxf.State.NONE


def test_slaves_are_objects_with_attributes(dev):
    s = dev.slaves()
    assert [x.position for x in s] == [0, 1, 2]
    assert s[0].name == "EST-584" and s[0].vendor == 0x0E5C and s[0].product == 0x0584
    assert s[2].product == 0x1088
    assert all(x.state == ecmxf.State.PREOP for x in s)
    assert all(x.al_status == 0 for x in s)
    assert "EST-584" in repr(s[0])
    assert dev.slave_count == 3


def test_sdo_typed_uploads(dev):
    assert dev.sdo.upload(0, 0x1008, 0) == b"EST-584"          # 7 bytes: bytes
    assert dev.sdo.upload(0, 0x1008, 0, "str") == "EST-584"
    assert dev.sdo.upload(0, 0x1018, 1, "u32") == 0x0E5C
    assert dev.sdo.upload(0, 0x1018, 1, "bytes") == bytes([0x5C, 0x0E, 0, 0])
    assert dev.sdo.upload(0, 0x6060, 0, "i8") == 8
    assert dev.sdo.upload(0, 0x1000, 0) == 197010
    assert dev.sdo.upload(0, 0x2001, 0, "bytes") == (50000).to_bytes(2, "little")
    assert dev.sdo.upload(0, 0x2001, 0, "i16") == 50000 - 65536


def test_sdo_download_and_read_back(dev):
    dev.sdo.download(0, 0x6081, 0, 1234)                      # the type from the object's size
    assert dev.sdo.upload(0, 0x6081, 0, "u32") == 1234
    dev.sdo.download(0, 0x6081, 0, 4321, "u32")
    assert dev.sdo.upload(0, 0x6081, 0) == 4321
    dev.sdo.download(0, 0x607A, 0, -5)                        # negative: signed
    assert dev.sdo.upload(0, 0x607A, 0, "i32") == -5
    dev.sdo.download(0, 0x607A, 0, (-7).to_bytes(4, "little", signed=True))
    assert dev.sdo.upload(0, 0x607A, 0, "i32") == -7


def test_sdo_whole_object(dev):
    assert dev.sdo.upload_object(0, 0x1018) == [4, 0x0E5C, 0x0584, 0x10000, 1]


def test_sdo_abort_texts():
    assert ecmxf.sdo_abort_text(0x06020000) == "Object not existing"
    assert ecmxf.al_status_text(0x001D).startswith("Invalid output configuration")


def test_pdo_mapping(dev):
    m = dev.pdo_mapping(0)
    assert m["outputs"] and m["inputs"]
    outs = {e["index"] for e in m["outputs"]}
    ins = {e["index"] for e in m["inputs"]}
    assert 0x6040 in outs and 0x6041 in ins
    assert m["output_bytes"] * 8 == sum(e["bits"] for e in m["outputs"])


def test_states_and_bring_up(dev):
    dev.request_state(ecmxf.State.SAFEOP)
    assert dev.state == ecmxf.State.SAFEOP
    dev.bring_up(motion=[0])
    assert dev.state == ecmxf.State.OP


def test_cia402_by_sdo(dev):
    sw = dev.drive_enable(0)
    assert sw & 0x6F == 0x27                                 # OPERATION ENABLED
    sw = dev.drive_disable(0)
    assert sw & 0x4F == 0x40                                 # SWITCH ON DISABLED
    sw = dev.fault_reset(0)
    assert sw & 0x4F == 0x40


def test_chip_firmware_and_data_size(dev):
    fw = dev.firmware_version()
    assert fw["version"] > 0
    dev.set_data_size(1408)
    assert dev.sdo.upload(0, 0x2001, 0) == 50000              # the exchanges in the new format
    with pytest.raises(ValueError, match="data section size 31 is outside 32..1408"):
        dev.set_data_size(31)


def test_trace_and_decoder(dev, tmp_path):
    path = str(tmp_path / "trace.txt")
    dev.start_trace(path)
    assert dev.sdo.upload(0, 0x2001, 0) == 50000
    dev.stop_trace()
    text = ecmxf.decode_trace(path)
    assert "ECAT_SDO_REQ" in text
    with pytest.raises(ecmxf.Error):
        ecmxf.decode_trace(str(tmp_path / "missing.txt"))


def test_reset(dev):
    dev.reset()                                              # WARM_RESET: the chip answers again
    assert dev.firmware_version()["version"] > 0


def test_network_file():
    net = os.path.join(os.environ["ECMXF_NETWORK_DIR"], "servo-io.net")
    with ecmxf.open("sim:" + net) as d:
        assert d.slave_count >= 2
        assert d.slaves()[0].name != "EST-584"


def test_a_refused_state_is_an_al_status_error(dev):
    with pytest.raises(ecmxf.AlStatusError) as e:
        dev.request_state(ecmxf.State.BOOT)                  # PRE-OP -> BOOT: not a valid change
    assert e.value.code == 0x0011 and e.value.text == "Invalid requested state change"
    assert e.value.slave == 0 and e.value.requested == "BOOT" and e.value.reached == "PRE-OP"
    assert e.value.errno > 0 and isinstance(e.value, ecmxf.Error)
    assert [(s.state, s.al_status) for s in dev.slaves()] == [(ecmxf.State.PREOP, 0x0011)] * 3


def test_events_as_an_iterator(dev):
    ev = dev.events(0.5)                                     # the baseline: PRE-OP
    dev.request_state(ecmxf.State.SAFEOP)
    got = list(ev)                                           # ends after 0.5 s of link time
    states = [(e["old"], e["new"]) for e in got if e["type"] == "state"]
    assert states == [("PRE-OP", "SAFE-OP")]
    assert all(e["time"] > 0 for e in got)


def test_events_of_a_state_that_went_down_name_the_slaves(dev):
    ev = dev.events(0.5)
    dev.request_state(ecmxf.State.INIT)
    down = [e for e in ev if e["type"] == "state"]
    assert down and down[0]["new"] == "INIT"
    assert [p for p, _ in down[0]["slaves"]] == [0, 1, 2]    # the slaves not in OP, read as the kernel does


def test_events_bad_input(dev):
    with pytest.raises(ValueError, match="duration"):
        dev.events(-1)
    with pytest.raises(ValueError, match="poll_interval"):
        dev.events(1, poll_interval=0)
    ev = dev.events(1)
    dev.close()
    with pytest.raises(ecmxf.ClosedError):
        next(ev)
    with ecmxf.open("sk-sim:") as sk:
        with pytest.raises(ecmxf.NotSupportedError):
            sk.events(1)


def test_events_close_and_with(dev):
    with dev.events(1) as ev:
        assert not ev.closed
        dev.request_state(ecmxf.State.SAFEOP)
        assert next(ev)["type"] == "state"
    assert ev.closed
    with pytest.raises(ecmxf.ClosedError, match="events"):
        next(ev)
    ev.close()                                               # twice is fine
    assert dev.state == ecmxf.State.SAFEOP                   # the device stays open
