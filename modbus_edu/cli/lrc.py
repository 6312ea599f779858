"""``modbus-edu lrc``: the LRC of some bytes, as Modbus ASCII sends it."""

from __future__ import annotations

import argparse
from typing import Any

from ..crc import lrc
from ..errors import ConfigError
from .common import _hex_arg


def cmd_lrc(args: argparse.Namespace) -> int:
    text = " ".join(args.hex).strip()
    if text.startswith(":"):
        raise ConfigError(
            "give the bytes the LRC covers (unit, function code, data) in hex, without ':' -- "
            "to check a whole ASCII frame use: modbus-edu decode"
        )
    data = _hex_arg(args.hex)
    value = lrc(data)
    print(f"LRC of {len(data)} byte{'s' if len(data) != 1 else ''}: 0x{value:02X} ({value})")
    print(f"on the wire, as two ASCII hex characters: {value:02X}")
    frame = ":" + data.hex().upper() + f"{value:02X}"
    print(f"ASCII frame: {frame}\\r\\n")
    if args.verbose:
        total = 0
        print("\nbyte  running sum (mod 256)")
        for b in data:
            total = (total + b) & 0xFF
            print(f"  {b:02X}   0x{total:02X}")
        print(f"two's complement of 0x{total:02X}: 0x{value:02X}")
    return 0


def _options_lrc(subs: Any) -> argparse.ArgumentParser:
    """The ``lrc`` subcommand's options."""
    p = subs.add_parser("lrc", help="LRC (Modbus ASCII) of bytes given in hex",
                        description="The LRC of some bytes (unit, function code, data), as Modbus ASCII "
                                    "sends it. Example: modbus-edu lrc 05 06 10 01 02 00")
    p.add_argument("hex", nargs="+", metavar="HEX", help="the bytes, e.g. 05 06 10 01 02 00")
    return p
