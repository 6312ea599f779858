"""``modbus-edu serve``: a simulated device (power meter, Arduino, plain bank, a register map) on TCP or
serial, at one or several unit ids, with values set from the command line or a file."""

from __future__ import annotations

import argparse
import logging
import sys
import time
from pathlib import Path
from typing import Any, TextIO

from ..clock import RealClock
from ..datamodel import DataBank
from ..devices.arduino import ArduinoSlave
from ..devices.generators import increment_fill, random_fill
from ..devices.meter import PowerMeter
from ..errors import ConfigError
from ..links.serial import SerialServer
from ..links.tcp_server import TcpServer
from ..registermap import load_map
from ..slave import Slave
from ..values import encode_value, parse_formatted
from .common import (
    DEFAULT_HOST,
    DEFAULT_PORT,
    _address,
    _authorization,
    _bit,
    _EchoLog,
    _install_stop_signals,
    _int,
    _parity,
    _tcp_name,
    _tls_context,
    _tls_options,
    _wire_options,
    parse_endpoint,
)

MAX_SETTINGS = 65536
"""The most NAME=VALUE settings read from --values FILE (a bank has 4 x 65536 elements)."""


def _make_device(args: argparse.Namespace, unit: int) -> Any:
    if args.device == "meter":
        device = PowerMeter(unit=unit, trial=args.trial, live=args.live, seed=args.seed)
    elif args.device == "arduino":
        device = ArduinoSlave(unit=unit, baudrate=args.baud or 9600, parity=_parity(args),
                              stopbits=args.stopbits, seed=args.seed)
    else:
        device = Slave(unit=unit, bank=DataBank(), name=f"bank {unit}")
        fill = args.fill or ("zero" if args.map or args.set or args.values else "increment")
        if fill == "random":
            random_fill(device.bank.holding_registers, 0, 1000, seed=args.seed + unit)
            random_fill(device.bank.input_registers, 0, 1000, seed=args.seed + unit + 1)
        elif fill == "increment":
            increment_fill(device.bank.holding_registers, 0, 1000)
            increment_fill(device.bank.input_registers, 0, 1000)
    device.clock = RealClock()  # a real port: live values follow the wall clock
    return device


def _settings(args: argparse.Namespace) -> list[tuple[str, str, str]]:
    """Every NAME=VALUE (or REFERENCE[:FORMAT]=VALUE) of --set and --values FILE, with where it came from."""
    items = [(text, "--set") for text in args.set or []]
    if args.values:
        path = Path(args.values)
        try:
            lines = path.read_text(encoding="utf-8").splitlines()
        except OSError as exc:
            raise ConfigError(f"cannot read --values {args.values!r}: {exc.strerror}") from None
        except UnicodeDecodeError:
            raise ConfigError(f"--values {args.values!r} is not UTF-8 text (lines NAME=VALUE)") from None
        if len(lines) > MAX_SETTINGS:
            raise ConfigError(f"--values {args.values!r} has {len(lines)} lines; at most {MAX_SETTINGS}")
        for number, line in enumerate(lines, 1):
            line = line.strip()
            if line and not line.startswith("#"):
                text = line.replace(",", "=", 1) if "=" not in line else line
                items.append((text, f"{args.values} line {number}"))
    out = []
    for text, where in items:
        name, sep, value = text.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise ConfigError(f"{where}: {text!r} is not NAME=VALUE (e.g. voltage=230.5, 40001=1234, "
                              f"40011:float32_CDAB=1.5, 00001=on)")
        out.append((name.strip(), value.strip(), where))
    return out


def _apply(device: Any, register_map: Any, settings: list[tuple[str, str, str]]) -> None:
    """Set each value in ``device``'s bank: a map point by name (engineering units), or a reference."""
    bank = device.bank
    for name, value, where in settings:
        if register_map is not None and name in register_map.points:
            try:
                number = float(value)
            except ValueError:
                raise ConfigError(f"{where}: {name}={value!r}: the value must be a number") from None
            register_map.store(bank, {name: number})
            continue
        ref, _, fmt = name.partition(":")
        if not (ref[:1].isdigit()):
            known = f": the map has {', '.join(register_map.points)}" if register_map is not None else \
                " (give --map FILE to set points by name)"
            raise ConfigError(f"{where}: {name!r} is neither a point name nor a reference number{known}")
        address, kind = _address(ref, where)
        if kind is None:
            raise ConfigError(f"{where}: {ref!r} is a plain address: say which table with a reference number "
                              f"(40001 holding, 30001 input, 10001 discrete input, 00001 coil)")
        table = bank.table(kind)
        if kind in ("coils", "discrete_inputs"):
            table[address] = _bit(value, f"{where}: {name}")
            continue
        registers = parse_formatted(value, fmt or "unsigned") if fmt or not value.startswith("-") else \
            encode_value(int(value), "int16")
        if address + len(registers) > 65536:
            raise ConfigError(f"{where}: {name}={value} runs past address 65535")
        for i, r in enumerate(registers):
            table[address + i] = r


def _default_baud(args: argparse.Namespace) -> int:
    if args.baud:
        return args.baud
    return 19200 if args.device == "meter" else 9600


class _Counter:
    """The live request count on stderr: one line, rewritten in place on a terminal."""

    def __init__(self, devices: list[Any], stream: TextIO, server: Any = None) -> None:
        self.devices = devices
        self.stream = stream
        self.server = server
        self.tty = stream.isatty()
        self.last: tuple[int, ...] | None = None

    def key(self) -> tuple[int, ...]:
        c = [d.counters for d in self.devices]
        other = getattr(getattr(self.server, "counters", None), "unknown_unit", 0)
        return (sum(x.requests for x in c) + other, sum(x.responses for x in c) + other,
                sum(x.exceptions for x in c) + other, sum(x.checksum_errors for x in c), other)

    def text(self) -> str:
        requests, responses, exceptions, checksum, other = self.key()
        tail = f"  other units (0x0B): {other}" if isinstance(self.server, TcpServer) else ""
        return (f"requests: {requests}  responses: {responses}  exceptions: {exceptions}  "
                f"checksum errors: {checksum}{tail}")

    def show(self, force: bool = False) -> None:
        key = self.key()
        if key == self.last and not force:
            return
        self.last = key
        if self.tty:
            self.stream.write("\r" + self.text() + "\x1b[K")
        else:
            self.stream.write(self.text() + "\n")
        self.stream.flush()

    def done(self) -> None:
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()


class _EchoHandler(logging.Handler):
    """-v: the server's note of a request for a unit nobody serves (answered 0x0B), as a traffic line."""

    def __init__(self, stream: TextIO) -> None:
        super().__init__(logging.DEBUG)
        self.stream = stream

    def emit(self, record: logging.LogRecord) -> None:
        if record.levelno == logging.DEBUG:
            print(f"server: {record.getMessage()}", file=self.stream, flush=True)


def _units(args: argparse.Namespace) -> list[int]:
    units = [_int(u, "--unit", 1, 247) for text in (args.unit or ["1"]) for u in text.split(",") if u.strip()]
    if len(set(units)) != len(units):
        raise ConfigError("each --unit once: two devices at one unit would both answer")
    if len(units) > 1 and args.serial is not None and args.device == "arduino":
        raise ConfigError("the Arduino board is one device: serve it at one --unit")
    return units


def cmd_serve(args: argparse.Namespace) -> int:
    if args.tcp is not None and args.serial is not None:
        raise ConfigError("choose one wire: --tcp HOST:PORT or --serial URL, not both")
    if (args.map or args.set or args.values) and args.device != "bank":
        raise ConfigError("--map, --set and --values fill a bank: use 'serve bank'")
    register_map = load_map(args.map) if args.map else None
    settings = _settings(args)
    units = _units(args)
    devices = [_make_device(args, unit) for unit in units]
    for device in devices:
        _apply(device, register_map, settings)
        if args.verbose:
            device.log = _EchoLog(sys.stderr)
    _install_stop_signals()
    if args.serial is not None:
        _tls_context(args, "serial")  # refuses --tls-* on a serial line
    authorization, roles = _authorization(args)  # with TLS on, roles apply
    if args.serial is not None:
        server: Any = SerialServer(devices, args.serial, baudrate=_default_baud(args), parity=_parity(args),
                                   stopbits=args.stopbits, mode=args.mode)
        bits = 7 if args.mode == "ascii" else 8  # what SerialServer opens: ASCII carries 7 data bits
        where = (f"serial {args.serial}, {_default_baud(args)} baud {bits}{_parity(args)}{args.stopbits}, "
                 f"{args.mode.upper()}")
    else:
        host, port = parse_endpoint(args.tcp or f"{DEFAULT_HOST}:{DEFAULT_PORT}")
        logger = logging.getLogger(f"modbus_edu.cli.serve.{id(args)}")
        if args.verbose:
            logger.setLevel(logging.DEBUG)
            logger.addHandler(_EchoHandler(sys.stderr))
        server = TcpServer(devices, host=host, port=port, tls=_tls_context(args, "server"),
                           authorization=authorization, logger=logger)
        where = None
    counter = _Counter(devices, sys.stderr, server)
    started = False
    try:
        server.start()
        started = True
        if where is None:
            bound_host, bound_port = server.address[:2]
            where = f"{_tcp_name(server)} {bound_host}:{bound_port}"
        what = devices[0].name if len(devices) == 1 else f"{len(devices)} devices"
        which = f"unit {units[0]}" if len(units) == 1 else f"units {', '.join(map(str, units))}"
        print(f"serving {what} ({which}) on {where}; Ctrl-C to stop", flush=True)
        if register_map is not None:
            print(f"map: {register_map.name}: {', '.join(register_map.points)}", flush=True)
        if roles:
            print(roles, flush=True)
        counter.show(force=True)
        while True:
            time.sleep(0.2)
            counter.show()
    except KeyboardInterrupt:
        pass
    finally:
        server.close()
        if started:
            counter.show()  # the last count, also when Ctrl-C came before the first refresh
        counter.done()
    print(f"stopped: {counter.text()}", flush=True)
    return 0


def _options_serve(subs: Any) -> argparse.ArgumentParser:
    """The ``serve`` subcommand's options."""
    p = subs.add_parser("serve", help="serve a simulated device until Ctrl-C",
                        description="Serve a simulated device on Modbus/TCP (default 127.0.0.1:5020) or on a "
                                    "serial port, until Ctrl-C. Devices: meter (the power-meter paper's "
                                    "meter, Table 5 map, Table 6 values), arduino (the Arduino slave "
                                    "paper's board), bank (a plain dense data bank: settable with --set, "
                                    "--values, --map). The request count is shown on stderr. Example: "
                                    "modbus-edu serve bank --unit 1 --unit 2 --set 40001=1234 "
                                    "--set 40011:float32_CDAB=230.5")
    p.add_argument("device", choices=["meter", "arduino", "bank"], help="what to simulate")
    p.add_argument("--unit", action="append", metavar="UNIT",
                   help="unit identifier (default 1); repeat it (or 1,2,3) to serve several devices")
    _wire_options(p, serve=True)
    _tls_options(p, serve=True)
    p.add_argument("--trial", type=int, choices=[1, 2], default=1, help="meter: Table 6 trial (default 1)")
    p.add_argument("--live", action="store_true", help="meter: values drift with time (seeded)")
    p.add_argument("--seed", type=int, default=0, help="seed of the simulated values (default 0)")
    p.add_argument("--fill", choices=["zero", "increment", "random"], default=None,
                   help="bank: registers 0..999 of both register tables (default increment: 0, 1, 2, ...; "
                        "zero when values are set)")
    p.add_argument("--map", metavar="FILE", help="bank: a register map CSV, whose points --set names")
    p.add_argument("--set", action="append", metavar="NAME=VALUE",
                   help="bank: a value, by map point (voltage=230.5) or reference (40001=1234, "
                        "40011:float32_CDAB=1.5, 00001=on); repeatable")
    p.add_argument("--values", metavar="FILE", help="bank: NAME=VALUE lines, as --set")
    return p
