# SPDX-License-Identifier: MIT
"""ecmxf: NEXTW's ECM-XF and ECM-SK EtherCAT masters from Python.

A binding of the C++ library libecmxf (Documentation/python.rst)::

    import ecmxf
    with ecmxf.open("sim:") as dev:
        for s in dev.slaves():
            print(s.position, s.name, hex(s.vendor or 0))
        print(dev.sdo.upload(0, 0x2001, 0))     # 50000 on the simulator

Errors are exceptions under ecmxf.Error: SdoAbort (.code, .text),
AlStatusError (.code), Timeout (also a TimeoutError), InvalidArgument (also
a ValueError), NotSupportedError, ClosedError, BusyError; bad arguments are
ValueError or TypeError.
"""

from ._ecmxf import (  # noqa: F401
    AdcInputMode,
    AlStatusError,
    Axis,
    AxisStatus,
    Board,
    BoardStatus,
    BusyError,
    Chip402,
    Chip402Flags,
    Chip402State,
    Cia402State,
    ClosedError,
    Cyclic,
    DacTrigger,
    DatagramCommand,
    DatagramResult,
    DebounceClock,
    Device,
    Entry,
    Error,
    Events,
    GpioEdge,
    GpioMode,
    GpioPull,
    Header,
    Hsp2Status,
    InvalidArgument,
    NotSupportedError,
    Peripherals,
    QeiMode,
    Response,
    Sdo,
    SdoAbort,
    SkMode,
    SkSlaveType,
    SkSync,
    Slave,
    State,
    Timeout,
    al_status_text,
    auto_increment_address,
    decode_event_message,
    decode_trace,
    kernel_events,
    open,
    sdo_abort_text,
)

__all__ = [
    "AdcInputMode", "AlStatusError", "Axis", "AxisStatus", "Board", "BoardStatus", "BusyError", "Chip402",
    "Chip402Flags", "Chip402State", "Cia402State", "ClosedError", "Cyclic", "DacTrigger", "DatagramCommand",
    "DatagramResult", "DebounceClock", "Device", "Entry", "Error", "Events", "GpioEdge", "GpioMode",
    "GpioPull", "Header", "Hsp2Status", "InvalidArgument", "NotSupportedError", "Peripherals", "QeiMode",
    "Response", "Sdo", "SdoAbort", "SkMode", "SkSlaveType", "SkSync", "Slave", "State", "Timeout",
    "al_status_text", "auto_increment_address", "decode_event_message", "decode_trace", "kernel_events", "open",
    "sdo_abort_text",
]
