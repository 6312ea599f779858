"""``modbus-edu capture FILE``: the Modbus exchanges of a pcap or pcapng capture, decoded, each request
paired with its response (TCP: same connection and transaction id; serial: the next answer of the same
unit and function), with their times and the response time."""

from __future__ import annotations

import argparse
from typing import Any

from ..capture import read_pcap
from ..codes import _hex
from ..errors import ModbusError
from ..framing import decode_frame
from ..traffic import pdu_note
from .common import _dissect, _int

MAX_WAITING = 4096
"""The most unanswered requests remembered while reading (a capture of requests only stays bounded)."""


def _key(entry: Any, tid: int | None, swap: bool) -> tuple:
    a, b = (entry.dest, entry.source) if swap else (entry.source, entry.dest)
    return (a, b, tid)


def _summary(entry: Any) -> tuple[str, int | None, int | None, int | None]:
    """(the frame in words, transaction id, unit, function) -- or its decoding error in words."""
    roles = [entry.role] if entry.role else ["request", "response"]
    error: Exception | None = None
    for role in roles:
        try:
            frame = decode_frame(entry.data, entry.mode, role)
        except ModbusError as exc:
            error = exc
            continue
        return (pdu_note(frame.pdu), getattr(frame, "transaction_id", None), frame.unit,
                frame.pdu.function_code & 0x7F)
    return f"not decodable: {error}", None, None, None


def cmd_capture(args: argparse.Namespace) -> int:
    port = _int(args.port, "--port", 1, 65535) if args.port else None
    log = read_pcap(args.file, port=port)
    entries = list(log)
    if not entries:
        print(f"{args.file}: no Modbus frames found")
        return 0
    start = entries[0].time
    waiting: dict[tuple, tuple[int, Any]] = {}
    exchanges = unanswered = orphans = bad = 0
    for number, entry in enumerate(entries, 1):
        text, tid, unit, function = _summary(entry)
        when = f"{entry.time - start:10.6f}"
        where = f"{entry.source} -> {entry.dest}" if entry.source or entry.dest else entry.mode.upper()
        note = f"  ({entry.note})" if entry.note else ""
        request = entry.role == "request" or (entry.role is None and entry.direction == "tx")
        ident = (tid, unit, function) if entry.mode == "tcp" else (unit, function)
        if unit is None:
            bad += 1
            print(f"#{number} {when}  {where}  {text}{note}\n    {_hex(entry.data)}")
            continue
        if request:
            key = _key(entry, None, False) + ident
            if key in waiting:
                unanswered += 1
            if len(waiting) >= MAX_WAITING:
                waiting.pop(next(iter(waiting)))
                unanswered += 1
            waiting[key] = (number, entry)
            print(f"#{number} {when}  {where}  request   {text}{note}")
        else:
            key = _key(entry, None, True) + ident
            asked = waiting.pop(key, None)
            if asked is None:
                orphans += 1
                print(f"#{number} {when}  {where}  response  {text}  (no request for it in the capture)"
                      f"{note}")
            else:
                exchanges += 1
                ms = (entry.time - asked[1].time) * 1000
                print(f"#{number} {when}  {where}  response  {text}  (answers #{asked[0]} after {ms:.3f} ms)"
                      f"{note}")
        if args.full:
            print("\n".join("    " + line for line in _dissect(entry.data, entry.mode,
                                                                 entry.role).to_text().splitlines()))
    unanswered += len(waiting)
    print(f"{len(entries)} frames: {exchanges} exchanges, {unanswered} requests without a response, "
          f"{orphans} responses without a request, {bad} not decodable")
    return 0


def _options_capture(subs: Any) -> argparse.ArgumentParser:
    """The ``capture`` subcommand's options."""
    p = subs.add_parser("capture", help="the Modbus exchanges of a pcap/pcapng file, decoded and paired",
                        description="Read a pcap or pcapng capture (tcpdump, Wireshark, or the library's "
                                    "write_pcap) and print each Modbus frame decoded, each response with "
                                    "the request it answers and the time it took. Example: modbus-edu "
                                    "capture plant.pcapng --port 5020")
    p.add_argument("file", metavar="FILE", help="the capture (pcap or pcapng; unpack a .gz first)")
    p.add_argument("--port", help="the Modbus/TCP server's port, when it is not 502")
    p.add_argument("--full", action="store_true", help="also dissect every frame field by field")
    return p
