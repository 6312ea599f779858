"""``modbus-edu identify``: ask a device what it is (FC 43/14, else FC 17)."""

from __future__ import annotations

import argparse
from typing import Any

from .. import pdu as _pdu
from ..codes import _hex, _printable
from ..errors import ModbusExceptionError
from .common import _int, _master, _master_options, _open_link, _wire_options


def cmd_identify(args: argparse.Namespace) -> int:
    unit = _int(args.unit, "--unit", 0 if args.tcp is not None else 1, 255 if args.tcp is not None else 247)
    link = _open_link(args)
    try:
        master = _master(args, link)
        try:
            objects = master.read_device_identification(unit, read_code=3)
        except ModbusExceptionError as exc:
            if exc.code != 1:
                raise
            print(f"unit {unit} does not answer Read Device Identification (FC 43/14): exception 01; "
                  "asking Report Server ID (FC 17)")
            print(_server_id_text(master.report_server_id(unit)))
            return 0
        if not objects:
            print(f"unit {unit} answers Read Device Identification (FC 43/14) with no objects at all (even "
                  "the three basic ones, vendor, product code and revision, are mandatory); asking Report "
                  "Server ID (FC 17)", flush=True)
            print(_server_id_text(master.report_server_id(unit)))
            return 0
        for object_id, value in sorted(objects.items()):
            name = _pdu.DEVICE_ID_OBJECTS.get(object_id, f"object 0x{object_id:02X}")
            print(f"{object_id:#04x}  {name:<20} {_printable(value)}")
    finally:
        link.close()
    return 0


def _server_id_text(report: _pdu.ReportServerIdResponse) -> str:
    """FC 17's answer on one line: each field in hex and as escaped text."""
    def both(data: bytes) -> str:
        return f"{_hex(data)} ({data!r})"

    if report.run_indicator is None:
        return f"server ID (no run indicator found, not split): {both(report.server_id)}"
    text = f"server ID: {both(report.server_id)}, run indicator: {'ON' if report.run_indicator else 'OFF'}"
    return text + (f", additional data: {both(report.additional_data)}" if report.additional_data else "")


def _options_identify(subs: Any) -> argparse.ArgumentParser:
    """The ``identify`` subcommand's options."""
    p = subs.add_parser("identify", help="ask a device what it is (FC 43/14, else FC 17)",
                        description="Ask a device for its identification: Read Device Identification (FC "
                                    "43 with MEI type 14), all the objects it has, and where the device does "
                                    "not know that function, Report Server ID (FC 17). Example: modbus-edu "
                                    "identify --tcp 127.0.0.1:5020")
    _wire_options(p, serve=False)
    p.add_argument("--unit", default="1", help="unit identifier / slave address (default 1)")
    _master_options(p)
    return p
