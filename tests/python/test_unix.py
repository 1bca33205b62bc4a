# SPDX-License-Identifier: MIT
"""ecmxf against unix:PATH (an ecmxf-sim --socket server): the simulated
chip keeps its state between opens."""

import pytest

import ecmxf


def test_unix_sdo_and_slaves(sim_server):
    with ecmxf.open("unix:" + sim_server.path) as d:
        assert d.kind == "ECM-XF"
        assert d.sdo.upload(0, 0x2001, 0) == 50000
        assert [s.name for s in d.slaves()][:2] == ["EST-584", "EST-584"]
        d.sdo.download(1, 0x6081, 0, 777)
        with pytest.raises(ecmxf.SdoAbort) as e:
            d.sdo.upload(1, 0x2FFF, 0)
        assert e.value.code == 0x06020000


def test_unix_state_persists_between_opens(sim_server):
    with ecmxf.open("unix:" + sim_server.path) as d:
        d.sdo.download(1, 0x6081, 0, 777)
    with ecmxf.open("unix:" + sim_server.path) as d:
        assert d.state == ecmxf.State.PREOP                   # brought up by the first open
        assert d.sdo.upload(1, 0x6081, 0) == 777


def test_unix_cyclic(sim_server):
    with ecmxf.open("unix:" + sim_server.path) as d:
        d.bring_up(motion=[0])
        with ecmxf.Cyclic(d) as cyc:
            cyc.start()
            sw = cyc.input(0, 0x6041, 0, "u16")
            cyc.run(10)
            assert sw.value != 0
            assert cyc.cycle() == 0


def test_unix_server_gone(sim_server):
    d = ecmxf.open("unix:" + sim_server.path)
    sim_server.proc.kill()
    sim_server.proc.wait()
    with pytest.raises(ecmxf.Error):
        d.sdo.upload(0, 0x2001, 0)
    d.close()


def test_unix_no_server(tmp_path):
    with pytest.raises(ecmxf.Error):
        ecmxf.open("unix:" + str(tmp_path / "none.sock"))
