# SPDX-License-Identifier: MIT
"""The ECM-XF's own views from Python: the peripherals (GPIO, QEI, DAC,
ADC, MDIO; the simulator's model of Documentation/sim-peripherals.rst),
the chip's CiA-402 engine, raw commands and datagrams, the SII EEPROM,
FoE and the staging flash; each with its bad input."""

import errno
import os
import re
import struct

import pytest

import ecmxf


# ---------------------------------------------------------------- peripherals

def test_gpio_outputs_read_back_inputs_float_low_pulls_high(dev):
    p = dev.peripherals
    assert p.gpio_read() == 0x0000                           # power-on: floating inputs
    p.gpio_set_mode(0x000F, ecmxf.GpioMode.OUTPUT)
    assert p.gpio_read() == 0x000F                           # latches power up at 1
    p.gpio_write(0x0005)
    assert p.gpio_read() == 0x0005
    assert dev.last_header.gpio_in == 0x0005                 # the response header's inputs too
    p.gpio_set_mode(0x00F0, ecmxf.GpioMode.INPUT, ecmxf.GpioPull.UP)
    assert p.gpio_read() == 0x00F5
    p.gpio_set_mode(0xF0000, ecmxf.GpioMode.OUTPUT)          # GPIO 16..19, the extended commands
    p.gpio_write_all(0xA0005)
    assert p.gpio_read_all() == 0xA00F5
    assert p.gpio_read() == 0x00F5


def test_gpio_interrupts(dev):
    p = dev.peripherals
    p.gpio_set_mode(0x0001, ecmxf.GpioMode.OUTPUT)
    p.gpio_write(0)
    p.gpio_set_interrupt(0, ecmxf.GpioEdge.RISING)
    assert p.gpio_interrupt_flags() == 0
    p.gpio_write(1)                                          # rising edge
    assert p.gpio_interrupt_flags() == 1 and p.gpio_interrupt_flags_all() == 1
    assert dev.last_header.gpio_int_flags == 1
    p.gpio_clear_interrupts(1)
    assert p.gpio_interrupt_flags() == 0
    p.gpio_set_debounce_clock(0, ecmxf.DebounceClock.CORE_192MHZ)
    p.gpio_set_debounce(0x0001, True)


def test_qei_dac_adc_mdio(dev):
    p = dev.peripherals
    p.qei_open(ecmxf.QeiMode.X2_FREE)
    p.qei_start()
    assert p.qei_count() == 0                                # no shaft motion on the simulator
    p.qei_stop()
    p.dac_open(ecmxf.DacTrigger.START_CONV)
    p.dac_set_delay(960)
    p.dac_write(4095)
    p.dac_start_conversion()
    p.dac_close()
    with pytest.raises(ecmxf.Timeout, match="sample module 12 had no valid result"):
        p.adc_convert()                                      # the ADC is not open
    p.adc_open(ecmxf.AdcInputMode.SINGLE_ENDED)
    p.adc_configure_module(0, 0)
    p.adc_start(0x1000)
    assert p.adc_valid_flags(0x1000) == 0x1000
    assert p.adc_read(12) == 0                               # unconnected: 0 V
    p.adc_open(ecmxf.AdcInputMode.DIFFERENTIAL)
    assert p.adc_convert() == 2048                           # 0 V difference
    p.adc_close()
    assert p.mdio_read(1, 2) == 0x0243                       # the IP101G's PHY identifier 1
    assert p.mdio_read(0, 2) == 0xFFFF                       # no PHY: the idle line
    p.mdio_write(1, 4, 0x0061)
    assert p.mdio_read(1, 4) == 0x0061


def test_peripherals_bad_input(dev):
    p = dev.peripherals
    with pytest.raises(ecmxf.InvalidArgument, match="no GPIO line selected"):
        p.gpio_set_mode(0, ecmxf.GpioMode.OUTPUT)            # the library's check
    with pytest.raises(ecmxf.InvalidArgument, match="names lines above GPIO 19"):
        p.gpio_set_mode(1 << 20, ecmxf.GpioMode.OUTPUT)
    with pytest.raises(ValueError, match="lines -1 is outside 0..4294967295"):
        p.gpio_set_mode(-1, ecmxf.GpioMode.OUTPUT)           # the binding's: no wrap-around
    with pytest.raises(ValueError, match="values 65536 is outside 0..65535"):
        p.gpio_write(0x10000)
    with pytest.raises(TypeError):
        p.gpio_set_mode(1, 1)                                # a mode is a GpioMode, not an int
    with pytest.raises(TypeError):
        p.gpio_set_mode(1, ecmxf.GpioPull.UP)
    with pytest.raises(TypeError):
        p.gpio_write("1")
    with pytest.raises(ecmxf.InvalidArgument, match="line 20 is out of range"):
        p.gpio_set_interrupt(20, ecmxf.GpioEdge.BOTH)
    with pytest.raises(ecmxf.InvalidArgument, match="cycle 16 is out of range"):
        p.gpio_set_debounce_clock(16, ecmxf.DebounceClock.CORE_192MHZ)
    with pytest.raises(ValueError, match="value 4096 is out of range"):
        p.dac_write(4096)
    with pytest.raises(ValueError, match="delay 1024 is out of range"):
        p.dac_set_delay(1024)
    with pytest.raises(ValueError, match="sample module 16 is out of range"):
        p.adc_configure_module(16, 0)
    with pytest.raises(ValueError, match="no sample module selected"):
        p.adc_start(0)
    with pytest.raises(ValueError, match="PHY address 32 is out of range"):
        p.mdio_read(32, 0)
    with pytest.raises(ValueError, match="value 65536 is outside"):
        p.mdio_write(1, 4, 0x10000)
    assert p.gpio_read() == 0                                # nothing of it reached the chip's GPIO


def test_peripherals_over_unix(sim_server):
    with ecmxf.open("unix:" + sim_server.path) as d:
        d.peripherals.gpio_set_mode(0x3, ecmxf.GpioMode.OUTPUT)
        d.peripherals.gpio_write(0x2)
    with ecmxf.open("unix:" + sim_server.path) as d:          # the server's chip kept its latches
        assert d.peripherals.gpio_read() & 0x3 == 0x2
        assert d.peripherals.mdio_read(1, 3) == 0x0C54


# ---------------------------------------------------------------- the chip's CiA-402 engine

def test_chip402_engine_enables_and_disables_a_drive():
    with ecmxf.open("sim:") as d:
        d.bring_up(motion=[0, 1])
        e = d.chip402
        e.configure(0, slave=0)
        e.configure(1, slave=1)
        assert e.control(0).engine and not e.control(0).auto_fault_reset
        st = e.state(0)
        assert st.code == 0x40 and st.state == ecmxf.Cia402State.SWITCH_ON_DISABLED
        e.request_state(0, ecmxf.Cia402State.OPERATION_ENABLED)
        assert e.await_state(0, ecmxf.Cia402State.OPERATION_ENABLED, 0.1) == ecmxf.Cia402State.OPERATION_ENABLED
        assert e.state(0).code == 0x27
        assert e.statusword(0) & 0x6F == 0x27
        assert e.state(1).state == ecmxf.Cia402State.SWITCH_ON_DISABLED   # motor 1 left alone
        e.request_state(0, ecmxf.Cia402State.SWITCHED_ON)
        e.await_state(0, ecmxf.Cia402State.SWITCHED_ON, 0.1)
        assert e.statusword(0) & 0x6F == 0x23
        e.set_control(0, motor_count=2, slave=0, auto_fault_reset=True)
        assert e.control(0).auto_fault_reset


def test_chip402_bad_input_and_refusals(dev):
    e = dev.chip402
    with pytest.raises(ValueError, match="motor 128 is outside 0..127"):
        e.state(128)
    with pytest.raises(ValueError, match="motor -1"):
        e.statusword(-1)
    with pytest.raises(ValueError, match="slave position 200"):
        e.configure(0, slave=200)
    with pytest.raises(ValueError, match="motor_count 0 is outside 1..128"):
        e.set_control(0, motor_count=0, slave=0)
    with pytest.raises(TypeError):
        e.request_state(0, 0x27)                             # a Cia402State, not its code
    with pytest.raises(ValueError, match="timeout"):
        e.await_state(0, ecmxf.Cia402State.OPERATION_ENABLED, -1)
    with pytest.raises(ecmxf.InvalidArgument):
        e.request_state(0, ecmxf.Cia402State.FAULT)          # not a state the engine walks to
    d = ecmxf.open("sim:", bring_up=False)                   # the bus not initialised
    try:
        with pytest.raises(ecmxf.Error) as x:
            d.chip402.configure(0, slave=0)
        assert x.value.errno == errno.EREMOTEIO
    finally:
        d.close()


def test_chip402_times_out_naming_the_state():
    with ecmxf.open("sim:") as d:
        d.bring_up(motion=[0])
        d.chip402.configure(0, slave=0)
        with pytest.raises(ecmxf.Timeout, match="stays in SWITCH ON DISABLED"):
            d.chip402.await_state(0, ecmxf.Cia402State.OPERATION_ENABLED, 0.02)


# ---------------------------------------------------------------- raw commands and datagrams

def test_raw_command(dev):
    r = dev.command(16)                                      # ECAT_SLV_CNT_GET: the count as return value
    assert r.ret == dev.slave_count == 3
    assert r.header.code == 16 and r.header.ret == 3
    assert isinstance(r.data, bytes)
    assert dev.last_header.ecat_state == 0x02                # PRE-OP
    with pytest.raises(ValueError, match="command code 256"):
        dev.command(256)
    with pytest.raises(ValueError, match="parametric data is 4 bytes"):
        dev.command(16, data=b"12345")
    with pytest.raises(TypeError, match="payload must be bytes"):
        dev.command(16, payload=[1, 2])
    with pytest.raises(ValueError, match="timeout"):
        dev.command(16, timeout=-1)


def test_raw_datagrams(dev):
    r = dev.datagram(ecmxf.DatagramCommand.FPRD, adp=0x1001, ado=0x0130, length=2)   # AL status of slave 0
    assert (r.working_counter, r.data) == (1, b"\x02\x00")
    r = dev.datagram(ecmxf.DatagramCommand.APRD, adp=ecmxf.auto_increment_address(2), ado=0x0010, length=2)
    assert r.data == b"\x03\x10"                             # station address 0x1003
    assert ecmxf.auto_increment_address(2) == 0xFFFE
    assert dev.datagram(ecmxf.DatagramCommand.BRD, ado=0x0130, length=1).working_counter == 3
    dev.datagram(ecmxf.DatagramCommand.FPWR, adp=0x1001, ado=0x0120, data=b"\x01\x00")  # slave 0 to INIT
    assert dev.datagram(ecmxf.DatagramCommand.FPRD, adp=0x1001, ado=0x0130, length=1).data == b"\x01"


def test_datagram_bad_input(dev):
    D = ecmxf.DatagramCommand
    with pytest.raises(ValueError, match="not both"):
        dev.datagram(D.BRD, data=b"\x00", length=1)
    with pytest.raises(ValueError, match="needs data"):
        dev.datagram(D.BRD)
    with pytest.raises(ValueError, match="length 0 is outside 1..256"):
        dev.datagram(D.BRD, length=0)
    with pytest.raises(ValueError, match="datagram length 257 is out of range"):
        dev.datagram(D.BRD, data=bytes(257))                 # the library's check
    with pytest.raises(ValueError, match="adp 65536"):
        dev.datagram(D.FPRD, adp=0x10000, length=1)
    with pytest.raises(TypeError):
        dev.datagram(4, adp=0x1001, length=1)
    with pytest.raises(ValueError, match="slave position 128"):
        ecmxf.auto_increment_address(128)


# ---------------------------------------------------------------- EEPROM, FoE, flash

def test_eeprom(dev):
    vendor = dev.slaves()[0].vendor
    assert dev.eeprom_read(0, 0x0008) == vendor & 0xFFFF
    lo, hi = dev.eeprom_read_words(0, 0x0008, 2)
    assert lo | hi << 16 == vendor
    dev.eeprom_write(1, 0x0004, 0x1234)
    assert dev.eeprom_read(1, 0x0004) == 0x1234
    with pytest.raises(ValueError, match="slave position 128"):
        dev.eeprom_read(128, 0)
    with pytest.raises(ValueError, match="word address 65536"):
        dev.eeprom_read(0, 0x10000)
    with pytest.raises(ValueError, match="count 0 is outside"):
        dev.eeprom_read_words(0, 0, 0)
    with pytest.raises(ValueError, match="do not fit the EEPROM's address space"):
        dev.eeprom_read_words(0, 0xFFFF, 2)
    with pytest.raises(ecmxf.InvalidArgument, match="slave 5 does not exist"):
        dev.eeprom_read(5, 0)
    with pytest.raises(ValueError, match="value -1"):
        dev.eeprom_write(0, 4, -1)


def boot(d, position=0):
    """The servo at position to BOOT as a master does it: SM0/SM1 to the
    SII's bootstrap mailbox (words 0x14..0x17), AL control INIT -> BOOT."""
    d.request_state(ecmxf.State.INIT)
    out0, outlen, in0, inlen = d.eeprom_read_words(position, 0x0014, 4)
    sm = (out0.to_bytes(2, "little") + outlen.to_bytes(2, "little") + b"\x26\x00\x01\x00" +
          in0.to_bytes(2, "little") + inlen.to_bytes(2, "little") + b"\x22\x00\x01\x00")
    station = 0x1001 + position
    assert d.datagram(ecmxf.DatagramCommand.FPWR, adp=station, ado=0x0800, data=sm).working_counter == 1
    d.datagram(ecmxf.DatagramCommand.FPWR, adp=station, ado=0x0120, data=b"\x03\x00")
    assert d.datagram(ecmxf.DatagramCommand.FPRD, adp=station, ado=0x0130, length=1).data == b"\x03"


@pytest.fixture
def servo():
    with ecmxf.open("sim:" + os.path.join(os.environ["ECMXF_NETWORK_DIR"], "servo-io.net")) as d:
        yield d


def test_foe_round_trip_in_boot(servo):
    boot(servo)
    fw = bytes(i * 7 % 251 for i in range(1000))
    seen = []
    servo.foe_write(0, "firmware.bin", fw, progress=lambda done, total: seen.append((done, total)))
    assert seen and seen[-1] == (1000, 1000) and len(seen) > 1
    assert servo.flash_read(0, 1000) == fw                   # staged in the chip's flash at 0
    log = servo.foe_read(0, "log.txt", flash_address=0x2000)
    assert b"firmware.bin written (1000 bytes)\n" in log
    servo.flash_write(0x3000, b"abc")
    assert servo.flash_read(0x3000, 3) == b"abc"


def test_foe_failures_and_bad_input(servo):
    with pytest.raises(ecmxf.Error, match="access denied") as e:
        servo.foe_read(0, "firmware.bin")                    # PRE-OP, not BOOT
    assert e.value.errno == errno.EREMOTEIO
    with pytest.raises(ecmxf.Error, match="file not found"):
        servo.foe_read(1, "nothing.txt")
    with pytest.raises(ecmxf.Error, match="empty file name"):
        servo.foe_read(0, "")
    with pytest.raises(TypeError, match="data must be bytes"):
        servo.foe_write(0, "firmware.bin", "text")
    with pytest.raises(TypeError, match="progress must be callable"):
        servo.foe_write(0, "firmware.bin", b"x", progress=5)
    with pytest.raises(ValueError, match="flash_address 262144"):
        servo.foe_read(0, "log.txt", flash_address=0x40000)
    with pytest.raises(ValueError, match="password -1"):
        servo.foe_read(0, "log.txt", password=-1)
    with pytest.raises(ValueError, match="length 0"):
        servo.flash_read(0, 0)
    boot(servo)

    class Stop(Exception):
        pass

    def stop(done, total):
        raise Stop(f"{done} of {total}")
    with pytest.raises(Stop):                                # the callback's exception ends the transfer
        servo.foe_write(0, "firmware.bin", bytes(1000), progress=stop)
    servo.foe_write(0, "firmware.bin", b"\x01\x02")          # the device works on


def test_a_call_from_inside_a_call_is_busy(servo):
    """The device serves one call at a time: a progress callback that calls
    the device gets BusyError (deterministic: the same thread, inside the
    library's call), and the transfer ends with it."""
    boot(servo)
    with pytest.raises(ecmxf.BusyError, match="busy with another call"):
        servo.foe_write(0, "firmware.bin", bytes(500), progress=lambda done, total: servo.slave_count)
    assert servo.slave_count >= 2                             # free again afterwards


# ---------------------------------------------------------------- closed, ECM-SK

def test_the_chip_views_after_close():
    d = ecmxf.open("sim:")
    p, e = d.peripherals, d.chip402
    d.close()
    for call in (lambda: d.peripherals, lambda: d.chip402, lambda: p.gpio_read(), lambda: e.state(0),
                 lambda: d.command(16), lambda: d.last_header, lambda: d.eeprom_read(0, 8),
                 lambda: d.datagram(ecmxf.DatagramCommand.BRD, length=1), lambda: d.foe_read(0, "x"),
                 lambda: d.flash_read(0, 1)):
        with pytest.raises(ecmxf.ClosedError):
            call()


def test_the_chip_views_are_not_the_ecm_sks():
    with ecmxf.open("sk-sim:") as sk:
        for call in (lambda: sk.peripherals, lambda: sk.chip402, lambda: sk.command(16),
                     lambda: sk.eeprom_read(1, 8), lambda: sk.datagram(ecmxf.DatagramCommand.BRD, length=1),
                     lambda: sk.foe_read(1, "x"), lambda: sk.last_header):
            with pytest.raises(ecmxf.NotSupportedError, match="ECM-XF"):
                call()


def test_views_are_made_by_ecmxf_only():
    for cls in (ecmxf.Peripherals, ecmxf.Chip402, ecmxf.Header, ecmxf.Response, ecmxf.DatagramResult,
                ecmxf.Chip402State, ecmxf.Chip402Flags):
        with pytest.raises(TypeError, match="made by ecmxf"):
            cls()
        with pytest.raises(TypeError):
            cls.__new__(cls)


# ---------------------------------------------------------------- the kernel's events

def test_kernel_events_bad_input(tmp_path):
    with pytest.raises(ValueError, match="not a character device"):
        ecmxf.kernel_events(str(tmp_path), 1)
    with pytest.raises(ValueError, match="duration"):
        ecmxf.kernel_events("/dev/null", -1)


def test_kernel_events_without_the_module():
    """On a host without ecmxf.ko the netlink family is missing: ENOENT,
    not a crash; with the module loaded, an iterator that ends."""
    try:
        ev = ecmxf.kernel_events("/dev/null", 0.05)
    except ecmxf.Error as e:
        assert e.errno == errno.ENOENT
        return
    minor = os.minor(os.stat("/dev/null").st_rdev)
    assert all(e["device"] == f"ecmxf{minor}" for e in ev)   # only that minor's, and the iterator ends


def uapi_enum(name):
    """The values of enum @name of <linux/ecmxf_netlink.h>, read from the
    header (so the test follows the ABI rather than restating it)."""
    header = os.path.join(os.path.dirname(__file__), "..", "..", "include", "uapi", "linux", "ecmxf_netlink.h")
    text = open(header).read()
    body = re.search(r"enum " + name + r" \{(.*?)\};", text, re.S).group(1)
    values, n = {}, 0
    for item in body.split(","):
        item = item.strip()
        if not item:
            continue
        if "=" in item:
            item, v = (x.strip() for x in item.split("="))
            n = int(v, 0)
        values[item] = n
        n += 1
    return values


def nl_message(family, cmd, attrs):
    def nla(t, payload):
        a = struct.pack("=HH", 4 + len(payload), t) + payload
        return a + b"\0" * (-len(a) % 4)
    body = struct.pack("=BBH", cmd, 1, 0) + b"".join(nla(t, p) for t, p in attrs)
    return struct.pack("=IHHII", 16 + len(body), family, 0, 0, 0) + body


def test_decode_event_message_gives_the_kernels_fields():
    A, EV, LOSS = uapi_enum("ecmxf_nl_attr"), uapi_enum("ecmxf_nl_event"), uapi_enum("ecmxf_nl_loss")
    CMD = uapi_enum("ecmxf_nl_cmd")
    u32 = lambda v: struct.pack("=I", v)                      # noqa: E731
    msg = nl_message(0x20, CMD["ECMXF_NL_CMD_EVENT"], [
        (A["ECMXF_NL_A_DEV_MINOR"], u32(0)),
        (A["ECMXF_NL_A_DEV_NAME"], b"ecmxf0\0"),
        (A["ECMXF_NL_A_EVENT_TYPE"], u32(EV["ECMXF_NL_EV_PDO_LOSS"])),
        (A["ECMXF_NL_A_PAD"], b""),
        (A["ECMXF_NL_A_TIMESTAMP_NS"], struct.pack("=Q", 1_500_000_000)),
        (A["ECMXF_NL_A_SEQ"], u32(7)),
        (A["ECMXF_NL_A_SUPPRESSED"], u32(2)),
        (A["ECMXF_NL_A_LOSS"], struct.pack("=B", LOSS["ECMXF_NL_LOSS_IN_RING_OVERRUN"])),
        (A["ECMXF_NL_A_INCREASE"], u32(3)),
        (A["ECMXF_NL_A_PAD"], b""),
        (A["ECMXF_NL_A_TOTAL"], struct.pack("=Q", 12)),
    ])
    e = ecmxf.decode_event_message(msg)
    assert e["type"] == "pdo_loss" and e["device"] == "ecmxf0" and e["seq"] == 7
    assert e["time"] == 1.5 and e["suppressed"] == 2
    assert (e["loss"], e["increase"], e["total"]) == ("in_ring_overrun", 3, 12)
    with pytest.raises(ecmxf.Error) as x:
        ecmxf.decode_event_message(msg[:10])                 # not a whole message
    assert x.value.errno == errno.EPROTO
    with pytest.raises(TypeError, match="msg must be bytes"):
        ecmxf.decode_event_message("text")
