"""``modbus-edu crc``: the CRC-16/MODBUS of some bytes, and its two bytes in wire order."""

from __future__ import annotations

import argparse
from typing import Any

from ..codes import _hex
from ..crc import crc16, crc16_table_trace, crc_bytes
from ..errors import ConfigError
from .common import _ascii_arg, _hex_arg


def cmd_crc(args: argparse.Namespace) -> int:
    data = _ascii_arg(" ".join(args.hex)) if args.text else _hex_arg(args.hex)
    if args.text and not data:
        raise ConfigError("no text given")
    value = crc16(data)
    wire = crc_bytes(data)
    print(f"CRC-16/MODBUS of {len(data)} byte{'s' if len(data) != 1 else ''}: 0x{value:04X} ({value})")
    print(f"on the wire, low byte first: {_hex(wire)}")
    print(f"message with its CRC: {_hex(data + wire)}")
    if args.verbose:
        print("\nbyte  index  table value  CRC before -> after")
        for step in crc16_table_trace(data):
            print(
                f"  {step.byte:02X}     {step.index:02X}       0x{step.table_value:04X}      "
                f"0x{step.before:04X} -> 0x{step.after:04X}"
            )
    return 0


def _options_crc(subs: Any) -> argparse.ArgumentParser:
    """The ``crc`` subcommand's options."""
    p = subs.add_parser("crc", help="CRC-16/MODBUS of bytes given in hex",
                        description="The CRC-16/MODBUS of some bytes, and its two bytes in wire order "
                                    "(low byte first). Example: modbus-edu crc 01 03 00 00 00 01")
    p.add_argument("hex", nargs="+", metavar="HEX", help="the bytes, e.g. 01 03 00 00 00 01 or 010300000001")
    p.add_argument("--text", action="store_true",
                   help="take the arguments as ASCII text (crc --text 123456789)")
    return p
