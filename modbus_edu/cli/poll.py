"""``modbus-edu poll``: read a device again and again: one or several blocks, or a register map by name;
a live table on a terminal, lines elsewhere; statistics and CSV."""

from __future__ import annotations

import argparse
import sys
import time
from datetime import datetime
from typing import Any

from rich.console import Console
from rich.live import Live

from ..datamodel import format_reference
from ..errors import ConfigError, ModbusError
from ..registermap import check_scale, load_map
from ..values import FORMATS
from .common import (
    ADDRESS_HELP,
    READ_FUNCTION,
    _address,
    _check_seconds,
    _check_table,
    _csv_options,
    _function,
    _install_stop_signals,
    _int,
    _master,
    _master_options,
    _open_csv,
    _open_link,
    _tls_options,
    _wire_options,
)
from .live import Block, Poller, line_of, map_blocks, plain_block, stats_line, table_of

_READS = (1, 2, 3, 4)


def _read_function(args_function: str | None, kind: str | None, text: str) -> int:
    """The read function: --function, else the one the reference names, else 3."""
    if args_function is None:
        return READ_FUNCTION[kind] if kind is not None else 3
    fc = _function(args_function)
    if fc not in _READS:
        raise ConfigError(f"poll reads: use --function 1, 2, 3 or 4 (got {fc}); to write, use "
                          f"'modbus-edu write'")
    _check_table(fc, kind, text)
    return fc


def _check_format(fmt: str) -> str:
    if fmt.lower() not in {f.lower() for f in FORMATS}:
        raise ConfigError(f"unknown --format {fmt!r}: expected one of {', '.join(FORMATS)}")
    return next(f for f in FORMATS if f.lower() == fmt.lower())


def _one_block(fc_text: str | None, address_text: str, count_text: str, fmt: str, scale: float) -> Block:
    address, kind = _address(address_text)
    fc = _read_function(fc_text, kind, address_text)
    count = _int(count_text, "--count", 1, 2000 if fc in (1, 2) else 125)
    if address + count > 65536:
        raise ConfigError(f"--address {address_text} --count {count} runs past the last address, 65535: "
                          f"at most {65536 - address} from that address")
    if scale != 1 and fmt in ("hex", "binary", "ascii_char", "ascii_value"):
        raise ConfigError(f"--scale multiplies numbers: it does not apply to --format {fmt}")
    return plain_block(fc, address, count, fmt, scale)


def _blocks(args: argparse.Namespace) -> list[Block]:
    if args.map:
        if args.block or args.address is not None:
            raise ConfigError("--map reads the map's points: leave out --address and --block")
        return map_blocks(load_map(args.map), max_gap=_int(args.max_gap, "--max-gap", 0, 124))
    fmt = _check_format(args.format)
    scale = check_scale(args.scale, "--scale") if args.scale != 1 else 1.0
    blocks = [_one_block(args.function, args.address or "0", args.count, fmt, scale)]
    for spec in args.block or []:
        parts = spec.split(":")
        if not 1 <= len(parts) <= 3 or not parts[0]:
            raise ConfigError(f"--block {spec!r}: expected ADDRESS[:COUNT[:FORMAT]], e.g. "
                              f"30001:4:float32_CDAB")
        fmt_b = _check_format(parts[2]) if len(parts) > 2 else fmt
        blocks.append(_one_block(None, parts[0], parts[1] if len(parts) > 1 else "1", fmt_b, 1.0))
    if len(blocks) > 1:  # the same address in two tables: each value is named by its reference number
        for block in blocks:
            kind = next(k for k, f in READ_FUNCTION.items() if f == block.function)
            for cell in block.cells:
                address = block.address + cell.offset
                cell.label = format_reference(kind, address, digits=5 if address <= 9998 else 6)
    return blocks


def _interval(args: argparse.Namespace) -> float:
    if args.rate is not None:
        _check_seconds(args.rate, "--rate", 0.001, 1000)
        return 1.0 / args.rate
    return _check_seconds(args.interval, "--interval", 0, 86_400)


def cmd_poll(args: argparse.Namespace) -> int:
    high = 255 if args.tcp is not None else 247
    unit = _int(args.unit, "--unit", 0 if args.tcp is not None else 1, high)
    blocks = _blocks(args)
    interval = _interval(args)
    _check_seconds(args.timeout, "--timeout", 0.001, 3_600)
    if args.polls < 0:
        raise ConfigError("--polls must be 0 (until Ctrl-C) or more")
    cells = [(b, c) for b in blocks for c in b.cells]
    header = ["time", "poll", "status", *[c.label for _, c in cells]]
    _install_stop_signals()
    csv_file, writer = _open_csv(args.csv, header, args.overwrite, args.append) if args.csv else (None, None)
    link = None
    try:
        link = _open_link(args)
        master = _master(args, link)
        poller = Poller(master, unit, blocks)
        live = _live_view(args)
        where = args.tcp or args.serial
        valid = 0
        try:
            if live is not None:
                live.start()
            while args.polls == 0 or poller.cycles < args.polls:
                if poller.cycles:
                    time.sleep(interval)
                stamp = datetime.now().isoformat(timespec="milliseconds")
                poller.cycle()
                valid += all(b.status == "ok" for b in blocks)
                if live is not None:
                    live.update(table_of(poller, unit, where), refresh=True)
                else:
                    line_of(poller, sys.stdout)
                    print(stats_line(master.stats, poller), flush=True)
                if writer is not None:
                    statuses = sorted({b.status for b in blocks})
                    texts = [c.text(b.function, b.values) if b.values else "" for b, c in cells]
                    writer.writerow([stamp, poller.cycles, ";".join(statuses), *texts])
                    csv_file.flush()  # type: ignore[union-attr]
        except KeyboardInterrupt:
            pass
        finally:
            if live is not None:
                live.stop()
        if live is not None or poller.cycles == 0 or args.polls == 0:
            print(stats_line(master.stats, poller), flush=True)
        if poller.cycles and not valid:
            n = poller.cycles
            raise ModbusError(f"no valid response in {n} poll{'s' if n != 1 else ''} of unit {unit}")
        return 0
    finally:
        if csv_file is not None:
            csv_file.close()
        if link is not None:
            link.close()


def _live_view(args: argparse.Namespace) -> Any:
    """A rich Live display when standard output is a terminal (and --lines was not asked), else None."""
    if args.lines or not sys.stdout.isatty():
        return None
    return Live(console=Console(), auto_refresh=False, transient=False, redirect_stderr=False)


def _options_poll(subs: Any) -> argparse.ArgumentParser:
    """The ``poll`` subcommand's options."""
    p = subs.add_parser("poll", help="read a real device repeatedly (a live table on a terminal)",
                        description="Read a device again and again (until Ctrl-C, or --polls times). On a "
                                    "terminal a table is refreshed in place (names, raw and scaled values, "
                                    "status, response time, error counts, polls per second); elsewhere one "
                                    "line per poll. Examples: modbus-edu poll --tcp 127.0.0.1:5020 "
                                    "--address 40001 --count 4 --format uint32_ABCD --polls 5;  modbus-edu "
                                    "poll --tcp 127.0.0.1:5020 --map meter.csv",
                        formatter_class=argparse.RawDescriptionHelpFormatter)
    _wire_options(p, serve=False)
    _tls_options(p, serve=False)
    p.add_argument("--unit", default="1", help="unit identifier / slave address (default 1)")
    p.add_argument("--function", default=None,
                   help="1, 2, 3 or 4 (default: the reference number's table, else 3)")
    p.add_argument("--address", default=None, help=ADDRESS_HELP + " (default 0)")
    p.add_argument("--count", default="1", help="how many coils or registers (default 1)")
    p.add_argument("--format", default="unsigned",
                   help="hex, binary, unsigned, signed, ascii_char, ascii_value, or a wide type such as "
                        "int32_ABCD, uint32_CDAB, float32_ABCD, float64_DCBA (default unsigned)")
    p.add_argument("--scale", type=float, default=1.0, help="multiply each value by this (0.1 for x10)")
    p.add_argument("--block", action="append", metavar="ADDRESS[:COUNT[:FORMAT]]",
                   help="another block to read each poll, e.g. --block 30001:2:float32_CDAB (repeatable; "
                        "a reference number chooses the function)")
    p.add_argument("--map", metavar="FILE", help="read every point of a register map CSV, by name, scaled")
    p.add_argument("--max-gap", default="0", help="--map: read across gaps of up to N registers (default 0)")
    p.add_argument("--interval", type=float, default=1.0, help="seconds between polls (default 1)")
    p.add_argument("--rate", type=float, default=None, metavar="HZ", help="polls per second (instead of "
                   "--interval)")
    p.add_argument("--polls", type=int, default=0, help="how many polls (default 0: until Ctrl-C)")
    _master_options(p)
    p.add_argument("--lines", action="store_true", help="one line per poll even on a terminal")
    _csv_options(p)
    return p
