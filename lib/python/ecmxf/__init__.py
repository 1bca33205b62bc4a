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
    AlStatusError,
    Axis,
    BusyError,
    ClosedError,
    Cyclic,
    Device,
    Entry,
    Error,
    Events,
    InvalidArgument,
    NotSupportedError,
    Sdo,
    SdoAbort,
    Slave,
    State,
    Timeout,
    al_status_text,
    decode_trace,
    open,
    sdo_abort_text,
)

__all__ = [
    "AlStatusError", "Axis", "BusyError", "ClosedError", "Cyclic", "Device", "Entry", "Error", "Events",
    "InvalidArgument", "NotSupportedError", "Sdo", "SdoAbort", "Slave", "State", "Timeout",
    "al_status_text", "decode_trace", "open", "sdo_abort_text",
]
