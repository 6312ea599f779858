"""``modbus-edu write``: write coils or registers (FC 5, 6, 15, 16, 22, 23), values in any display format
``poll`` reads (or a register map's point by name), then read them back."""

from __future__ import annotations

import argparse
from typing import Any

from ..codes import _hex
from ..errors import ConfigError
from ..registermap import check_scale, load_map
from ..values import FORMATS, TYPES, encode_value, format_registers, parse_formatted
from .common import (
    ADDRESS_HELP,
    TABLE_OF_FUNCTION,
    _address,
    _bit,
    _check_table,
    _function,
    _int,
    _master,
    _master_options,
    _open_link,
    _tls_options,
    _wire_options,
)

_WRITES = (5, 6, 15, 16, 22, 23)


def _registers(values: list[str], fmt: str, scale: float) -> list[int]:
    """The registers of every value typed, in ``fmt`` (``--scale``: the value is divided by it first)."""
    registers: list[int] = []
    for text in values:
        if scale != 1:
            try:
                number = float(text) / scale
            except ValueError:
                raise ConfigError(f"{text!r} is not a number (--scale {scale:g} divides it)") from None
            type_, _, order = fmt.rpartition("_") if "_" in fmt and not fmt.startswith("ascii") else (
                "int16" if fmt == "signed" else "uint16", "", "ABCD")
            if not TYPES[type_].is_float:
                number = round(number)
            registers += encode_value(number, type_, order)
        else:
            registers += parse_formatted(text, fmt)
    return registers


def _format(fmt: str) -> str:
    for name in FORMATS:
        if name.lower() == fmt.lower():
            return name
    raise ConfigError(f"unknown --format {fmt!r}: expected one of {', '.join(FORMATS)}")


def _from_map(args: argparse.Namespace) -> tuple[int, int, list[Any], str]:
    """--map FILE NAME=VALUE: the point's function, address and registers."""
    if len(args.values) != 1 or "=" not in args.values[0]:
        raise ConfigError("with --map, give one NAME=VALUE, e.g. setpoint=21.5")
    name, _, text = args.values[0].partition("=")
    point = load_map(args.map)[name.strip()]
    if point.table != "holding":
        raise ConfigError(f"{point.name} is an input register: input registers are read-only (FC 4 reads "
                          f"them; no function writes them)")
    try:
        value = float(text)
    except ValueError:
        raise ConfigError(f"{name}={text!r}: the value must be a number") from None
    raw = value / point.scale if point.scale != 1 else value
    if not TYPES[point.type].is_float:
        raw = round(raw)
    registers = encode_value(raw, point.type, point.order)
    shown = {"int16": "signed", "uint16": "unsigned"}.get(point.type, f"{point.type}_{point.order}")
    return (6 if len(registers) == 1 else 16), point.address, registers, shown


def _plan(args: argparse.Namespace) -> tuple[int, int, list[Any], str]:
    """(function, address, values to write, display format)."""
    if args.map:
        if args.address is not None:
            raise ConfigError("--map names the point: leave out --address")
        return _from_map(args)
    if args.address is None:
        raise ConfigError("where? give --address (e.g. 40001 or 0) or --map FILE NAME=VALUE")
    address, kind = _address(args.address)
    fc = _function(args.function) if args.function is not None else None
    if fc is not None and fc not in _WRITES:
        raise ConfigError(f"write uses --function 5, 6, 15, 16, 22 or 23 (got {fc}); to read, use 'poll'")
    if kind in ("input_registers", "discrete_inputs"):
        raise ConfigError(f"{args.address} is a reference to the {kind.replace('_', ' ')}, which are "
                          f"read-only: write coils (0x, 00001) or holding registers (4x, 40001)")
    if fc is not None:
        _check_table(fc, kind, args.address)
    coils = kind == "coils" or fc in (5, 15)
    if coils:
        values: list[Any] = [_bit(v, "a coil value") for v in args.values]
        fc = fc or (5 if len(values) == 1 else 15)
        if fc == 5 and len(values) != 1:
            raise ConfigError(f"FC 5 writes one coil; {len(values)} values need FC 15 (or leave out "
                              f"--function)")
        return fc, address, values, "bits"
    fmt = _format(args.format)
    if fc == 22:
        if len(args.values) != 2:
            raise ConfigError("FC 22 (Mask Write Register) takes two values: AND_MASK OR_MASK, e.g. "
                              "0xFF00 0x0012")
        return 22, address, [_int(v, "a mask") for v in args.values], "hex"
    scale = check_scale(args.scale, "--scale") if args.scale != 1 else 1.0
    registers = _registers(args.values, fmt, scale)
    if len(registers) > 123:
        raise ConfigError(f"{len(registers)} registers: one request writes at most 123 (FC 16)")
    fc = fc or (6 if len(registers) == 1 else 16)
    if fc == 6 and len(registers) != 1:
        raise ConfigError(f"FC 6 writes one register; these values take {len(registers)}: use FC 16 (or "
                          f"leave "
                          f"out --function)")
    if address + len(registers) > 65536:
        raise ConfigError(f"{len(registers)} registers from address {address} run past address 65535")
    return fc, address, registers, fmt


def _shown(values: list[Any], fmt: str) -> str:
    if fmt == "bits":
        return " ".join("1" if v else "0" for v in values)
    return " ".join(t for t in format_registers(values, fmt) if t)


def cmd_write(args: argparse.Namespace) -> int:
    fc, address, values, fmt = _plan(args)
    high = 255 if args.tcp is not None else 247
    unit = _int(args.unit, "--unit", 0, high)
    link = _open_link(args)
    try:
        master = _master(args, link)
        table = TABLE_OF_FUNCTION[fc].replace("_", " ")
        if fc == 5:
            master.write_single_coil(unit, address, values[0])
        elif fc == 15:
            master.write_multiple_coils(unit, address, values)
        elif fc == 6:
            master.write_single_register(unit, address, values[0])
        elif fc == 16:
            master.write_multiple_registers(unit, address, values)
        elif fc == 22:
            master.mask_write_register(unit, address, values[0], values[1])
        else:
            count = _int(args.read_count or str(len(values)), "--read-count", 1, 125)
            got = master.read_write_multiple_registers(unit, address, count, address, values)
            print(f"FC 23 wrote {len(values)} and read {count} {table} at address {address}: "
                  f"{_shown(got, fmt)}")
            return 0
        what = f"{values[0]:#06x} AND, {values[1]:#06x} OR" if fc == 22 else _shown(values, fmt)
        if args.scale != 1 and not args.map:
            what = f"{' '.join(args.values)} at scale {args.scale:g}: {what}"
        words = "" if fmt in ("bits", "hex") else f" ({_hex(b''.join(v.to_bytes(2, 'big') for v in values))})"
        print(f"FC {fc} wrote {table} at address {address}: {what}{words}")
        if args.no_read_back or (unit == 0 and args.tcp is None):
            return 0
        count = 1 if fc == 22 else len(values)
        if fc in (5, 15):
            back: list[Any] = master.read_coils(unit, address, count)
        else:
            back = master.read_holding_registers(unit, address, count)
        same = fc == 22 or list(back) == list(values)
        differs = "" if same else "  (differs from what was written)"
        print(f"read back: {_shown(back, 'hex' if fc == 22 else fmt)}{differs}")
        if not same:
            raise ConfigError("the read-back differs from what was written: the device changed the value "
                              "(a limit? a read-only register?) or another master wrote in between")
    finally:
        link.close()
    return 0


def _options_write(subs: Any) -> argparse.ArgumentParser:
    """The ``write`` subcommand's options."""
    p = subs.add_parser("write", help="write coils or registers, then read them back",
                        description="Write coils (FC 5, 15) or holding registers (FC 6, 16; 22 mask write, "
                                    "23 read/write), values in any --format poll reads, then read them back. "
                                    "The function follows from the reference number and the number of "
                                    "values unless --function says. Examples: modbus-edu write --tcp "
                                    "127.0.0.1:5020 --address 40001 1234;  ... --address 40011 --format "
                                    "float32_CDAB 230.5;  ... --address 00001 on;  ... --map meter.csv "
                                    "setpoint=21.5")
    _wire_options(p, serve=False)
    _tls_options(p, serve=False)
    p.add_argument("values", nargs="+", metavar="VALUE",
                   help="values to write (registers in --format; coils on/off, 1/0), or NAME=VALUE with "
                        "--map")
    p.add_argument("--unit", default="1", help="unit identifier / slave address (default 1)")
    p.add_argument("--address", default=None, help=ADDRESS_HELP)
    p.add_argument("--function", default=None, help="5, 6, 15, 16, 22 or 23 (default: from the reference "
                                                     "and the number of values)")
    p.add_argument("--format", default="unsigned",
                   help="how the values are written: unsigned, signed, hex, binary, int32_ABCD, uint32_CDAB, "
                        "float32_ABCD ... (default unsigned)")
    p.add_argument("--scale", type=float, default=1.0,
                   help="the device's scale: the value is divided by it (0.1: 23.5 goes as 235)")
    p.add_argument("--map", metavar="FILE", help="write a register map's point: NAME=VALUE")
    p.add_argument("--read-count", default=None, help="FC 23: how many registers to read (default as many "
                                                      "as written)")
    p.add_argument("--no-read-back", action="store_true", help="do not read the values back")
    _master_options(p)
    return p
