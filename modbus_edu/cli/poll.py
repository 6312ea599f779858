"""``modbus-edu poll``: read a device again and again, with statistics and CSV."""

from __future__ import annotations

import argparse
import csv
import sys
import time
from collections.abc import Callable
from datetime import datetime
from typing import Any

from ..errors import ConfigError, FrameError, ModbusError, ModbusExceptionError, ModbusTimeoutError
from ..master import Master
from ..values import FORMATS, TYPES, format_registers
from .common import (
    _check_seconds,
    _EchoLog,
    _function,
    _install_stop_signals,
    _int,
    _one_line,
    _open_link,
    _tls_options,
    _wire_options,
)

_READERS = {
    1: "read_coils",
    2: "read_discrete_inputs",
    3: "read_holding_registers",
    4: "read_input_registers",
}


def _stats_line(stats: Any) -> str:
    latencies = list(getattr(stats, "latencies", []) or [])
    parts = [
        f"requests {stats.requests}",
        f"valid {stats.valid_responses}",
        f"timeouts {stats.timeouts}",
        f"checksum errors {stats.checksum_errors}",
        f"exceptions {stats.exceptions}",
    ]
    if latencies:
        avg = sum(latencies) / len(latencies) * 1000
        parts.append(f"latency avg {avg:.1f} ms, max {max(latencies) * 1000:.1f} ms")
    return "stats: " + ", ".join(parts)


def _format_width(fmt: str) -> int:
    """Registers per value of a display format: 1, or 2/4 for the wide types (``float64_ABCD``: 4)."""
    kind = fmt.lower().rpartition("_")[0]
    return TYPES[kind].registers if kind in TYPES else 1


def _format_values(fc: int, values: list, fmt: str) -> list[str]:
    if fc in (1, 2):
        return ["1" if v else "0" for v in values]
    return format_registers(values, fmt)


def cmd_poll(args: argparse.Namespace) -> int:
    fc = _function(args.function)
    if fc not in _READERS:
        raise ConfigError(f"poll reads: use --function 1, 2, 3 or 4 (got {fc}); writes are for 'build'")
    high = 255 if args.tcp is not None else 247
    unit = _int(args.unit, "--unit", 0 if args.tcp is not None else 1, high)
    address = _int(args.address, "--address")
    count = _int(args.count, "--count", 1, 2000 if fc in (1, 2) else 125)
    if args.format.lower() not in {f.lower() for f in FORMATS}:
        raise ConfigError(f"unknown --format {args.format!r}: expected one of {', '.join(FORMATS)}")
    _check_seconds(args.interval, "--interval", 0, 86_400)
    _check_seconds(args.timeout, "--timeout", 0.001, 3_600)
    if address + count > 65536:
        raise ConfigError(f"--address {address} --count {count} runs past the last address, 65535: "
                          f"at most {65536 - address} from that address")
    if args.polls < 0:
        raise ConfigError("--polls must be 0 (until Ctrl-C) or more")
    _install_stop_signals()
    link = _open_link(args)
    csv_file = None
    try:
        master = Master(link, timeout=args.timeout)
        if args.verbose:
            master.log = _EchoLog(sys.stderr)
        read: Callable[..., list] = getattr(master, _READERS[fc])
        writer = None
        if args.csv:
            csv_file = open(args.csv, "w", newline="", encoding="utf-8")  # noqa: SIM115 - closed below
            writer = csv.writer(csv_file)
            width = 1 if fc in (1, 2) else _format_width(args.format)
            columns = [address + i for i in range(0, count - count % width, width)]
            writer.writerow(["time", "poll", "status", *[str(a) for a in columns]])
        n = 0
        valid = 0
        try:
            while args.polls == 0 or n < args.polls:
                if n:
                    time.sleep(args.interval)
                n += 1
                stamp = datetime.now().isoformat(timespec="milliseconds")
                try:
                    values = read(unit=unit, address=address, count=count)
                except ModbusTimeoutError as exc:
                    status, texts = "timeout", []
                    print(f"#{n} timeout: {_one_line(exc)}")
                except ModbusExceptionError as exc:
                    status, texts = f"exception {exc.code:02X}", []
                    print(f"#{n} exception {exc.code:02X}: {exc.meaning}")
                except (FrameError, ModbusError) as exc:
                    if isinstance(exc, ConfigError):
                        raise
                    status, texts = "error", []
                    print(f"#{n} error: {_one_line(exc)}")
                else:
                    valid += 1
                    status = "ok"
                    texts = _format_values(fc, values, args.format)
                    shown = "  ".join(f"[{address + i}] {t}" for i, t in enumerate(texts) if t != "")
                    print(f"#{n} {shown}")
                print(_stats_line(master.stats), flush=True)
                if writer is not None:
                    cells = [texts[a - address] for a in columns] if texts else [""] * len(columns)
                    writer.writerow([stamp, n, status, *cells])
                    csv_file.flush()  # type: ignore[union-attr]
        except KeyboardInterrupt:
            print(_stats_line(master.stats), flush=True)
        if n and not valid:
            raise ModbusError(f"no valid response in {n} poll{'s' if n != 1 else ''} of unit {unit}")
        return 0
    finally:
        if csv_file is not None:
            csv_file.close()
        link.close()


def _options_poll(subs: Any) -> argparse.ArgumentParser:
    """The ``poll`` subcommand's options."""
    p = subs.add_parser("poll", help="read a real device repeatedly",
                        description="Read a device again and again (until Ctrl-C, or --polls times), print "
                                    "the values and running statistics, and log to CSV if asked. Example: "
                                    "modbus-edu poll --tcp 127.0.0.1:5020 --unit 1 --function 3 --address 0 "
                                    "--count 4 --format uint32_ABCD --polls 5")
    _wire_options(p, serve=False)
    _tls_options(p, serve=False)
    p.add_argument("--unit", default="1", help="unit identifier / slave address (default 1)")
    p.add_argument("--function", default="3", help="1, 2, 3 or 4 (default 3, read holding registers)")
    p.add_argument("--address", default="0", help="starting address, 0-based (default 0)")
    p.add_argument("--count", default="1", help="how many coils or registers (default 1)")
    p.add_argument("--interval", type=float, default=1.0, help="seconds between polls (default 1)")
    p.add_argument("--polls", type=int, default=0, help="how many polls (default 0: until Ctrl-C)")
    p.add_argument("--timeout", type=float, default=1.0, help="response timeout, seconds (default 1)")
    p.add_argument("--format", default="unsigned",
                   help="hex, binary, unsigned, signed, ascii_char, ascii_value, or a wide type such as "
                        "int32_ABCD, uint32_CDAB, float32_ABCD, float64_DCBA (default unsigned)")
    p.add_argument("--csv", metavar="FILE", help="also write every poll to this CSV file")
    return p
