"""``modbus-edu scan``: find who answers on a bus (unit ids, baud rates, parities)."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from ..links.serial import serial_link
from ..scan import scan
from .common import (
    CliError,
    _baud,
    _check_seconds,
    _EchoLog,
    _install_stop_signals,
    _int,
    _open_link,
    _parity,
    _split_values,
    _wire_options,
)


def _units(text: str) -> range:
    """``--units FIRST-LAST`` (or one unit) as a range, first <= last, within 1..247."""
    first, _, last = text.partition("-")
    low = _int(first, "--units: the first unit", 1, 247)
    high = _int(last, "--units: the last unit", 1, 247) if last else low
    if low > high:
        raise CliError(f"--units {text}: the first unit, {low}, comes after the last, {high}: write "
                       f"FIRST-LAST, e.g. --units {high}-{low}")
    return range(low, high + 1)


def _line_settings(args: argparse.Namespace) -> list[dict[str, Any]]:
    """Every (baud rate, parity) pair ``scan --bauds --parities`` asks for: all checked first."""
    bauds = [args.baud or 9600]
    if args.bauds:
        try:
            bauds = [_baud(item) for item in _split_values(args.bauds)]
        except argparse.ArgumentTypeError as exc:
            raise CliError(f"--bauds: {exc}") from None
    parities = [_parity(args)]
    if args.parities:
        parities = [item.upper() for item in _split_values(args.parities)]
        wrong = [item for item in parities if item not in ("N", "E", "O")]
        if wrong:
            raise CliError(f"--parities: {wrong[0]!r} is not a parity: use N (none), E (even) or O (odd), "
                           "e.g. --parities N,E")
    return [{"baudrate": b, "parity": p} for b in bauds for p in parities]


def cmd_scan(args: argparse.Namespace) -> int:
    units = _units(args.units)
    _check_seconds(args.timeout, "--timeout", 0.001, 3_600)
    _check_seconds(args.budget, "--budget", 0.001, 86_400)
    log = _EchoLog(sys.stderr) if args.verbose else None
    _install_stop_signals()  # Ctrl-C, and SIGINT to a background job, stop the scan and keep what it found
    if args.serial is not None and args.tcp is None:
        settings = _line_settings(args)

        def opener(**setting: Any) -> Any:
            return serial_link(args.serial, stopbits=args.stopbits, mode=args.mode, **setting)

        report = scan(opener, units, settings=settings, timeout=args.timeout, budget=args.budget,
                      progress=True, log=log)
    else:
        link = _open_link(args)
        try:
            report = scan(link, units, timeout=args.timeout, budget=args.budget, progress=True, log=log)
        finally:
            link.close()
    for hit in report:
        where = ", ".join(f"{k} {v}" for k, v in hit.settings.items())
        print(f"unit {hit.unit:3d}{'  ' + where if where else ''}: {hit.answer}")
    if report.interrupted:
        tail = " (interrupted)"
    else:
        tail = "" if report.complete else f" (stopped at the {args.budget:g} s budget)"
    print(f"{len(report)} found, {report.asked} asked{tail}", flush=True)
    if report.late:
        print(f"note: {report.late} answer(s) came after --timeout {args.timeout:g} s had run out (each with "
              f"the transaction id of an earlier question, so not counted): a slow device or gateway; scan "
              f"again with a longer --timeout", flush=True)
    return 130 if report.interrupted else 0


def _options_scan(subs: Any) -> argparse.ArgumentParser:
    """The ``scan`` subcommand's options."""
    p = subs.add_parser("scan", help="find who answers on a bus (unit ids, baud rates, parities)",
                        description="Ask every unit id (read holding register 0) and report who answers, "
                                    "with a progress bar, within a time budget. Example: modbus-edu scan "
                                    "--serial /dev/ttyUSB0 --bauds 9600,19200 --parities N,E --units 1-32")
    _wire_options(p, serve=False)
    p.add_argument("--units", default="1-247", help="unit ids to try, FIRST-LAST (default 1-247)")
    p.add_argument("--bauds", help="serial baud rates to try, comma-separated (default --baud)")
    p.add_argument("--parities", help="serial parities to try, e.g. N,E (default --parity)")
    p.add_argument("--timeout", type=float, default=0.1, help="wait per question, seconds (default 0.1)")
    p.add_argument("--budget", type=float, default=120.0, help="stop after this many seconds (default 120)")
    return p
