# SPDX-License-Identifier: MIT
"""Bad input never crashes the interpreter: wrong types are TypeError,
out-of-range values ValueError naming what was wrong, a closed device
ClosedError, the library's refusals its own exceptions."""

import inspect

import pytest

import ecmxf


def test_the_hierarchy():
    for cls in (ecmxf.SdoAbort, ecmxf.AlStatusError, ecmxf.Timeout, ecmxf.InvalidArgument,
                ecmxf.NotSupportedError, ecmxf.ClosedError, ecmxf.BusyError):
        assert issubclass(cls, ecmxf.Error)
    assert issubclass(ecmxf.Error, Exception)
    assert issubclass(ecmxf.Timeout, TimeoutError)
    assert issubclass(ecmxf.InvalidArgument, ValueError)
    assert issubclass(ecmxf.ClosedError, ValueError)


@pytest.mark.parametrize("uri", ["", "nonsense:", "sim:/no/such/network.net", "unix:", "sk-sim:?slot=3",
                                 "spidev:/dev/spidev0.0?speed=fast"])
def test_bad_uris(uri):
    with pytest.raises(ecmxf.Error) as e:
        ecmxf.open(uri)
    assert str(e.value)


def test_bad_uri_is_a_value_error():
    with pytest.raises(ValueError, match="nonsense"):
        ecmxf.open("nonsense:")


def test_wrong_argument_types(dev):
    with pytest.raises(TypeError):
        dev.sdo.upload("0", 0x2001, 0)
    with pytest.raises(TypeError):
        dev.sdo.upload(0, float(0x2001), 0)
    with pytest.raises(TypeError):
        dev.sdo.upload(0, None, 0)
    with pytest.raises(TypeError):
        dev.sdo.upload(0, 0x2001, 0, 32)
    with pytest.raises(TypeError, match="int, float, str or bytes"):
        dev.sdo.download(0, 0x6081, 0, [1, 2])
    with pytest.raises(TypeError, match="integer value must be int"):
        dev.sdo.download(0, 0x6081, 0, "12", "u32")
    with pytest.raises(TypeError, match="must be bytes"):
        dev.sdo.download(0, 0x6081, 0, 12, "bytes")
    with pytest.raises(TypeError):
        dev.request_state("OP")
    with pytest.raises(TypeError):
        ecmxf.open(42)
    with pytest.raises(TypeError, match="ecmxf.Device"):
        ecmxf.Cyclic("sim:")


@pytest.mark.parametrize("args, what", [
    ((128, 0x2001, 0), "slave position 128 is outside 0..127"),
    ((-1, 0x2001, 0), "slave position -1"),
    ((0, 0x10000, 0), "object index 65536"),
    ((0, -1, 0), "object index -1"),
    ((0, 0x2001, 256), "subindex 256"),
])
def test_out_of_range_arguments(dev, args, what):
    with pytest.raises(ValueError, match=what):
        dev.sdo.upload(*args)
    with pytest.raises(ValueError, match=what):
        dev.sdo.download(*args, 1, "u8")


def test_values_out_of_their_type(dev):
    with pytest.raises(ValueError, match="300 is outside the range of u8"):
        dev.sdo.download(0, 0x6081, 0, 300, "u8")
    with pytest.raises(ValueError, match="outside the range of i8"):
        dev.sdo.download(0, 0x6081, 0, -129, "i8")
    with pytest.raises(ValueError, match="outside the range of u32"):
        dev.sdo.download(0, 0x6081, 0, -1, "u32")
    with pytest.raises(ValueError, match="outside the range of u64"):
        dev.sdo.download(0, 0x6081, 0, 1 << 64, "u64")
    with pytest.raises(ValueError, match="unknown value type 'int32'"):
        dev.sdo.upload(0, 0x2001, 0, "int32")
    with pytest.raises(ValueError, match="has 2 bytes, not the 4"):
        dev.sdo.upload(0, 0x2001, 0, "u32")
    with pytest.raises(ValueError, match="at least one byte"):
        dev.sdo.download(0, 0x6081, 0, b"")
    with pytest.raises(ValueError, match="outside 0..4294967295"):
        ecmxf.sdo_abort_text(-1)
    assert dev.sdo.upload(0, 0x6081, 0) == 50000              # nothing was written


def test_slave_positions_beyond_the_bus(dev):
    with pytest.raises(ecmxf.Error):
        dev.sdo.upload(50, 0x2001, 0)
    with pytest.raises(ValueError):
        dev.pdo_mapping(200)


def test_the_library_refuses(dev):
    with pytest.raises(ecmxf.NotSupportedError, match="ECM-XF"):
        dev.io_read(0)
    with pytest.raises(ValueError, match="bring_up"):
        ecmxf.Cyclic(dev)
    with pytest.raises(ValueError, match="cycle_us"):
        dev.bring_up(cycle_us=1)


def test_closed_device():
    d = ecmxf.open("sim:")
    sdo = d.sdo
    d.close()
    for call in (lambda: d.sdo, lambda: sdo.upload(0, 0x2001, 0), lambda: d.state, lambda: d.slaves(),
                 lambda: d.kind, lambda: d.drive_enable(0), lambda: d.bring_up(), lambda: d.pdo_mapping(0),
                 lambda: d.request_state(ecmxf.State.OP), lambda: d.reset(), lambda: d.start_trace("/tmp/x"),
                 lambda: ecmxf.Cyclic(d)):
        with pytest.raises(ecmxf.ClosedError, match="closed"):
            call()


def test_closed_device_in_with_block():
    with ecmxf.open("sim:") as d:
        pass
    with pytest.raises(ecmxf.ClosedError):
        d.sdo.upload(0, 0x2001, 0)


def test_cyclic_bad_input(op_dev):
    with pytest.raises(ValueError, match="period"):
        ecmxf.Cyclic(op_dev, period=0)
    with pytest.raises(ValueError, match="period"):
        ecmxf.Cyclic(op_dev, period=float("nan"))
    with ecmxf.Cyclic(op_dev) as cyc:
        with pytest.raises(ecmxf.Error, match="0x6999"):
            cyc.output(0, 0x6999, 0)
        with pytest.raises(ecmxf.Error, match="No Such Entry"):
            cyc.input(0, "No Such Entry")
        with pytest.raises(TypeError, match="name .str. or its object index"):
            cyc.output(0, 1.5)
        with pytest.raises(ValueError, match="slave position 128"):
            cyc.output(128, 0x6040)
        with pytest.raises(ecmxf.Error, match="does not fit a 8-bit"):
            cyc.output(0, 0x6040, 0, "u8")                   # a 16-bit entry
        with pytest.raises(ValueError, match="unknown value type"):
            cyc.output(0, 0x6040, 0, "word")
        cw = cyc.output(0, 0x6040, 0, "u16")
        with pytest.raises(ValueError, match="70000"):
            cw.value = 70000
        with pytest.raises(TypeError):
            cw.value = "x"
        sw = cyc.input(0, 0x6041, 0, "u16")
        with pytest.raises(TypeError, match="read-only"):
            sw.value = 1
        with pytest.raises(TypeError):
            cyc.inputs[0] = 1                                  # a read-only memoryview
        with pytest.raises(ValueError, match="cycles"):
            cyc.run(-1)
        with pytest.raises(ValueError, match="one target per axis"):
            cyc.csp_move([cyc.axis(0)], [1, 2], 0.1)
        with pytest.raises(ValueError, match="mode"):
            cyc.axis(0, modes=[300])


def test_use_after_close_of_cyclic_and_device(op_dev):
    cyc = ecmxf.Cyclic(op_dev)
    ax = cyc.axis(0)
    cw = cyc.output(0, 0x6040, 0, "u16")
    out = cyc.outputs
    cyc.close()
    cyc.close()
    assert cyc.closed
    with pytest.raises(ecmxf.ClosedError):
        cyc.cycle()
    with pytest.raises(ecmxf.ClosedError):
        cyc.start()
    with pytest.raises(ecmxf.ClosedError):
        ax.enable()
    with pytest.raises(ecmxf.ClosedError):
        cyc.outputs
    # what was handed out stays valid memory: the image outlives the Cyclic
    cw.value = 6
    assert out[cw.bit_offset // 8] == 6
    # the device closes the Cyclics over it first
    cyc2 = ecmxf.Cyclic(op_dev)
    op_dev.close()
    assert cyc2.closed
    with pytest.raises(ecmxf.ClosedError):
        cyc2.cycle()


def test_cycle_unbound_is_a_type_error():
    with pytest.raises(TypeError):
        ecmxf.Cyclic.cycle(object())


@pytest.mark.parametrize("cls", [ecmxf.Device, ecmxf.Cyclic, ecmxf.Sdo, ecmxf.Slave, ecmxf.Entry, ecmxf.Axis,
                                 ecmxf.Events])
def test_no_half_made_objects(cls):
    # T.__new__(T) without __init__ would hand pybind11 uninitialised memory
    with pytest.raises(TypeError):
        cls.__new__(cls)
    with pytest.raises(TypeError):
        object.__new__(cls)
    with pytest.raises(TypeError):
        cls()


def test_the_constructors_construct_whole():
    d = ecmxf.Device.__new__(ecmxf.Device, "sim:")          # __new__ alone makes a whole object
    assert d.sdo.upload(0, 0x2001, 0) == 50000
    d.__init__("sim:")                                       # and __init__ changes nothing
    assert not d.closed
    d.close()


def test_sdo_upload_arguments(dev):
    """Sdo.upload() is a plain CPython method (no pybind11 dispatch): its
    own argument handling, checked here as pybind11's is elsewhere."""
    up = dev.sdo.upload
    assert up(position=0, index=0x2001, sub=0) == 50000
    assert up(0, 0x2001, sub=0, type="u16") == 50000
    assert up(0, 0x2001, 0, None) == 50000
    with pytest.raises(TypeError, match="missing argument 'sub'"):
        up(0, 0x2001)
    with pytest.raises(TypeError, match="5 arguments given"):
        up(0, 0x2001, 0, "u16", 1)
    with pytest.raises(TypeError, match="keyword argument 'subindex'"):
        up(0, 0x2001, subindex=0)
    with pytest.raises(TypeError, match="keyword argument 'position'"):
        up(0, 0x2001, 0, position=0)                     # given twice
    with pytest.raises(TypeError, match="index must be int, not float"):
        up(0, 8193.0, 0)
    with pytest.raises(TypeError, match="type must be str or None, not int"):
        up(0, 0x2001, 0, 16)
    with pytest.raises(ValueError, match="position is out of range"):
        up(1 << 70, 0x2001, 0)
    with pytest.raises(ValueError, match="slave position 128"):
        up(128, 0x2001, 0)
    with pytest.raises(TypeError):
        ecmxf.Sdo.upload(object(), 0, 0x2001, 0)        # not an Sdo
    assert str(inspect.signature(up)) == "(position, index, sub, type=None)"
    assert "SdoAbort" in up.__doc__
    d = ecmxf.open("sim:")
    u = d.sdo.upload
    d.close()
    with pytest.raises(ecmxf.ClosedError):
        u(0, 0x2001, 0)
