"""``modbus-edu ports``: the serial ports of this computer (pyserial's list), for ``--serial``."""

from __future__ import annotations

import argparse
from typing import Any

from serial.tools import list_ports


def cmd_ports(args: argparse.Namespace) -> int:
    ports = sorted(list_ports.comports(include_links=args.links), key=lambda p: p.device)
    if not ports:
        print("no serial ports found (a USB adapter shows up as /dev/ttyUSB0 or /dev/ttyACM0 on Linux, "
              "COM3 on Windows, /dev/cu.usbserial-... on macOS)")
        return 0
    for port in ports:
        described = port.description if port.description and port.description != "n/a" else ""
        hwid = port.hwid if port.hwid and port.hwid != "n/a" else ""
        print("  ".join(part for part in (port.device, described, hwid) if part))
    return 0


def _options_ports(subs: Any) -> argparse.ArgumentParser:
    """The ``ports`` subcommand's options."""
    p = subs.add_parser("ports", help="list the serial ports of this computer",
                        description="List the serial ports pyserial finds (device, description, hardware "
                                    "id): the names --serial takes.")
    p.add_argument("--links", action="store_true", help="also list symbolic links (/dev/serial/by-id/...)")
    return p
