"""``modbus-edu decode``: a frame (or one per line of standard input) dissected field by field."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Iterator
from typing import Any

from ..errors import ConfigError, ModbusError
from ..framing import parse_hex
from .common import _dissect, _hex_arg


def _mode_or_none(mode: str) -> str | None:
    return None if mode == "auto" else mode


MAX_DECODE_LINE = 4096
"""The longest line ``decode -`` reads, in characters: the longest frame, ASCII, is 513 characters."""


def _stdin_frames() -> Iterator[bytes]:
    """The frames on standard input, one in hex per line, read one line at a time (memory stays flat)."""
    number = 0
    while True:
        line = sys.stdin.buffer.readline(MAX_DECODE_LINE + 1)
        if not line:
            return
        number += 1
        if len(line) > MAX_DECODE_LINE and not line.endswith(b"\n"):
            raise ConfigError(f"line {number} of standard input is longer than {MAX_DECODE_LINE} characters: "
                              "give one frame in hex per line")
        text = line.decode("ascii", "replace").strip()
        if text:
            yield parse_hex(text)


def cmd_decode(args: argparse.Namespace) -> int:
    frames = _stdin_frames() if args.frame == ["-"] else iter([_hex_arg(args.frame)])
    mode, role = _mode_or_none(args.mode), _mode_or_none(args.role)
    count, first_error, held = 0, None, None
    for data in frames:  # each result is printed as it comes: any number of frames in flat memory
        dissection = _dissect(data, mode, role)
        count += 1
        if first_error is None and dissection.error is not None:
            first_error = (count, dissection.error)
        if args.json:
            if count == 1:
                held = dissection.to_dict()  # one frame prints as an object, several as an array
                continue
            if count == 2:
                print("[\n" + json.dumps(held, indent=2), end="")
            print(",\n" + json.dumps(dissection.to_dict(), indent=2), end="")
        else:
            print(("\n" if count > 1 else "") + dissection.to_text(), flush=False)
    if count == 0:
        raise ConfigError("no frames on standard input (one frame in hex per line)")
    if args.json:
        print(json.dumps(held, indent=2) if count == 1 else "\n]")
    if first_error is not None:
        where = f"frame {first_error[0]}: " if count > 1 else ""
        raise ModbusError(f"{where}{first_error[1]}")  # the table above shows where; stderr gets one line
    return 0


def _options_decode(subs: Any) -> argparse.ArgumentParser:
    """The ``decode`` subcommand's options."""
    p = subs.add_parser("decode", help="dissect a frame field by field",
                        description="Dissect an RTU, ASCII or TCP frame: every byte, its field, value and "
                                    "meaning. Exit status 1 when the frame is not valid (the table shows "
                                    "where). Example: modbus-edu decode 01 03 00 00 00 01 84 0A")
    p.add_argument("frame", nargs="+", metavar="FRAME",
                   help="the frame in hex (an ASCII frame as typed, ':0103...'), or '-' to read one "
                        "frame per line from standard input")
    p.add_argument("--mode", choices=["rtu", "ascii", "tcp", "auto"], default="auto",
                   help="framing (default: auto, guessed from the bytes)")
    p.add_argument("--role", choices=["request", "response", "auto"], default="auto",
                   help="request or response (default: auto, whichever decodes)")
    p.add_argument("--json", action="store_true", help="print the dissection as JSON")
    return p
