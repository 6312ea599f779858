"""``modbus-edu decode``: a frame (or every frame of a log on standard input) dissected field by field.

Logs as tools write them are read as they are: a timestamp, a counter and a direction in front
(``000001-Tx:``, ``Rx:``, ``[12:00:01.250]``), hex separated by spaces, colons or commas, and a request
and its response on one line (split by their direction tags, or where the first frame's CRC or MBAP
length ends it). A line that holds no frame is reported and skipped; the exit status says so at the end.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections.abc import Iterator
from typing import Any

from ..codes import MAX_MBAP_LENGTH, MBAP_HEADER_SIZE, MIN_MBAP_LENGTH
from ..crc import crc16
from ..errors import ConfigError, ModbusError
from ..framing import decode_frame, parse_hex
from ..pdu import REQUEST_CLASSES
from ..values import FORMATS, format_registers
from .common import _dissect, _hex_arg, _one_line


def _mode_or_none(mode: str) -> str | None:
    return None if mode == "auto" else mode


MAX_DECODE_LINE = 4096
"""The longest line ``decode -`` reads, in characters: the longest frame, ASCII, is 513 characters."""

_STAMP = re.compile(
    r"^\s*(?:\[[^\]]{1,40}\]"                                  # [anything short]: a timestamp or a tag
    r"|\d{4}[-/]\d{2}[-/]\d{2}(?:[T ]\d{1,2}:\d{2}:\d{2}(?:[.,]\d+)?)?(?=\s|$|[A-Za-z])"  # a date (time)
    r"|\d{1,2}:\d{2}:\d{2}(?:[.,]\d+)(?=\s|$)"                   # a time with fractions
    r"|\d{1,2}:\d{2}:\d{2}(?=\s)(?!\s+[0-9A-Fa-f]{2}:)"         # a time, unless colon-hex goes on
    r"|\d+\s*-\s*(?=[TtRr][Xx])"                                # 000001- (a counter before Tx/Rx)
    r"|(?:[TtRr][Xx]|req(?:uest)?|resp(?:onse)?|send|recv|sent|received|in|out)\s*[:>]"  # a direction
    r"|(?:->|<-|>>|<<|>|<)"                                     # an arrow
    r")\s*",
    re.IGNORECASE,
)
_DIRECTION = re.compile(r"\s(?:\d+\s*-\s*)?(?:[TtRr][Xx]|req(?:uest)?|resp(?:onse)?)\s*[:>]\s*",
                        re.IGNORECASE)


def _strip_prefixes(text: str) -> str:
    """The line without its timestamps, counters and direction tags in front."""
    for _ in range(8):
        match = _STAMP.match(text)
        if not match or not match.group(0):
            break
        text = text[match.end():]
    return text.strip()


def _hex_of(text: str) -> bytes:
    """Hex as logs write it: spaced, colon-, comma- or semicolon-separated, with or without 0x."""
    stripped = text.strip()
    if stripped.startswith(":") and re.fullmatch(r":[0-9A-Fa-f]+(\\r\\n|\r\n|\s)*", stripped):
        return parse_hex(stripped)  # a Modbus ASCII frame, as typed
    return parse_hex(stripped.replace(":", " "))


def _rtu_split(data: bytes) -> list[bytes]:
    """An RTU request and response run together: cut where the first part's CRC is right and so is the
    rest's. One frame if the whole already checks."""
    if len(data) >= 4 and crc16(data[:-2]) == int.from_bytes(data[-2:], "little"):
        return [data]
    for cut in range(4, len(data) - 3):
        head, tail = data[:cut], data[cut:]
        if (crc16(head[:-2]) == int.from_bytes(head[-2:], "little")
                and crc16(tail[:-2]) == int.from_bytes(tail[-2:], "little")):
            return [head, tail]
    return [data]


def _tcp_split(data: bytes) -> list[bytes]:
    """TCP frames run together: each MBAP length says where its frame ends."""
    frames, rest = [], data
    while len(rest) > MBAP_HEADER_SIZE and rest[2:4] == b"\x00\x00":
        length = int.from_bytes(rest[4:6], "big")
        end = 6 + length
        if not MIN_MBAP_LENGTH <= length <= MAX_MBAP_LENGTH or end > len(rest):
            break
        frames.append(rest[:end])
        rest = rest[end:]
    if not frames or rest:
        return [data]
    return frames


def frames_of_line(line: str, mode: str | None) -> list[bytes]:
    """The frames a log line holds (one, or a request and its response)."""
    text = _strip_prefixes(line)
    if not text:
        return []
    parts = [p for p in _DIRECTION.split(" " + text) if p.strip()]
    frames: list[bytes] = []
    for part in parts:
        data = _hex_of(_strip_prefixes(part))
        if data.startswith(b":") or mode == "ascii":
            frames.append(data)
        elif mode == "tcp" or (mode is None and len(_tcp_split(data)) > 1):
            frames.extend(_tcp_split(data))
        elif mode == "rtu" or mode is None:
            frames.extend(_rtu_split(data))
    return frames


def _stdin_lines() -> Iterator[tuple[int, str]]:
    """The lines of standard input, one at a time (memory stays flat)."""
    number = 0
    while True:
        line = sys.stdin.buffer.readline(MAX_DECODE_LINE + 1)
        if not line:
            return
        number += 1
        if len(line) > MAX_DECODE_LINE and not line.endswith(b"\n"):
            raise ConfigError(f"line {number} of standard input is longer than {MAX_DECODE_LINE} characters: "
                              "give one frame in hex per line")
        yield number, line.decode("ascii", "replace").strip()


def _mbap_with_wrong_length(data: bytes) -> bool:
    """Protocol 0, a length field of 2..254 (high byte 0) that does not count the bytes that follow, and
    a known function code in byte 7: a TCP frame with a wrong length field, not an RTU frame with a bad
    CRC (an RTU frame starting 00 00 would be unit 0, function 0, which does not exist)."""
    return (len(data) >= MBAP_HEADER_SIZE + 2 and data[2:4] == b"\x00\x00" and data[4] == 0
            and MIN_MBAP_LENGTH <= data[5] <= MAX_MBAP_LENGTH and data[5] != len(data) - 6
            and (data[7] & 0x7F) in REQUEST_CLASSES)


def _dissect_auto(data: bytes, mode: str | None, role: str | None) -> Any:
    dissection = _dissect(data, mode, role)
    if mode is None and dissection.error is not None and getattr(dissection, "mode", "") != "tcp" \
            and _mbap_with_wrong_length(data):
        return _dissect(data, "tcp", role)  # protocol 0 and a function code: a TCP frame, its length wrong
    return dissection


def _as_text(data: bytes, dissection: Any, fmt: str) -> str | None:
    """--as FORMAT: the registers of a register-carrying frame shown in another format."""
    mode = getattr(dissection, "mode", None)
    for role in ("response", "request"):
        try:
            pdu = decode_frame(data, mode, role).pdu
        except (ModbusError, TypeError, ValueError):
            continue
        registers = getattr(pdu, "registers", None) or getattr(pdu, "values", None)
        if registers and all(isinstance(r, int) and not isinstance(r, bool) for r in registers):
            texts = [t for t in format_registers(list(registers), fmt) if t and t != "—"]
            if not texts:
                return f"as {fmt}: {len(registers)} register(s), too few for one value"
            return f"as {fmt}: " + "  ".join(texts)
    return None


def cmd_decode(args: argparse.Namespace) -> int:
    mode, role = _mode_or_none(args.mode), _mode_or_none(args.role)
    fmt = None
    if args.as_format:
        match = [f for f in FORMATS if f.lower() == args.as_format.lower()]
        if not match:
            raise ConfigError(f"unknown --as {args.as_format!r}: expected one of {', '.join(FORMATS)}")
        fmt = match[0]
    if args.frame == ["-"]:
        return _decode_lines(args, mode, role, fmt)
    data = _hex_arg(args.frame)
    dissection = _dissect_auto(data, mode, role)
    if args.json:
        print(json.dumps(dissection.to_dict(), indent=2))
    else:
        print(dissection.to_text())
        extra = _as_text(data, dissection, fmt) if fmt else None
        if extra:
            print(extra)
    if dissection.error is not None:
        raise ModbusError(str(dissection.error))
    return 0


def _decode_lines(args: argparse.Namespace, mode: str | None, role: str | None, fmt: str | None) -> int:
    count, first_error, held, bad_lines = 0, None, None, 0
    for number, line in _stdin_lines():  # each result is printed as it comes: flat memory
        try:
            frames = frames_of_line(line, mode)
        except ModbusError as exc:
            bad_lines += 1
            print(f"line {number}: skipped, no frame in it: {_one_line(exc)}", file=sys.stderr, flush=True)
            continue
        for data in frames:
            dissection = _dissect_auto(data, mode, role)
            count += 1
            if first_error is None and dissection.error is not None:
                first_error = (count, number, dissection.error)
            if args.json:
                if count == 1:
                    held = dissection.to_dict()  # one frame prints as an object, several as an array
                    continue
                if count == 2:
                    print("[\n" + json.dumps(held, indent=2), end="")
                print(",\n" + json.dumps(dissection.to_dict(), indent=2), end="")
            else:
                print(("\n" if count > 1 else "") + f"line {number}:\n" + dissection.to_text(), flush=False)
                extra = _as_text(data, dissection, fmt) if fmt else None
                if extra:
                    print(extra)
    if count == 0:
        raise ConfigError("no frames on standard input (one frame in hex per line)")
    if args.json:
        print(json.dumps(held, indent=2) if count == 1 else "\n]")
    if first_error is not None:
        where = f"frame {first_error[0]} (line {first_error[1]}): " if count > 1 else ""
        raise ModbusError(f"{where}{first_error[2]}")  # the table above shows where; stderr gets one line
    if bad_lines:
        raise ModbusError(f"{bad_lines} line{'s' if bad_lines != 1 else ''} held no frame (see above); "
                          f"{count} frame{'s' if count != 1 else ''} decoded")
    return 0


def _options_decode(subs: Any) -> argparse.ArgumentParser:
    """The ``decode`` subcommand's options."""
    p = subs.add_parser("decode", help="dissect a frame field by field (or a whole log)",
                        description="Dissect an RTU, ASCII or TCP frame: every byte, its field, value and "
                                    "meaning. With '-', every line of standard input: logs as tools write "
                                    "them (timestamps, 000001-Tx:, Rx:, colon- or comma-separated hex, a "
                                    "request and its response on one line). Exit status 1 when a frame is "
                                    "not valid or a line held none. Example: modbus-edu decode 01 03 00 00 "
                                    "00 01 84 0A")
    p.add_argument("frame", nargs="+", metavar="FRAME",
                   help="the frame in hex (an ASCII frame as typed, ':0103...'), or '-' to read a log "
                        "from standard input")
    p.add_argument("--mode", choices=["rtu", "ascii", "tcp", "auto"], default="auto",
                   help="framing (default: auto, guessed from the bytes)")
    p.add_argument("--role", choices=["request", "response", "auto"], default="auto",
                   help="request or response (default: auto, whichever decodes)")
    p.add_argument("--as", dest="as_format", metavar="FORMAT",
                   help="also show the registers a frame carries as float32_ABCD, int32_CDAB, signed, "
                        "hex ... (any --format of poll)")
    p.add_argument("--json", action="store_true", help="print the dissection as JSON")
    return p
