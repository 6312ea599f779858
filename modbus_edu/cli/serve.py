"""``modbus-edu serve``: a simulated device (power meter, Arduino, plain bank) on TCP or serial."""

from __future__ import annotations

import argparse
import sys
import time
from typing import Any, TextIO

from ..clock import RealClock
from ..datamodel import DataBank
from ..devices.arduino import ArduinoSlave
from ..devices.generators import increment_fill, random_fill
from ..devices.meter import PowerMeter
from ..errors import ConfigError
from ..links.serial import SerialServer
from ..links.tcp_server import TcpServer
from ..slave import Slave
from .common import (
    _parity,
    DEFAULT_HOST,
    DEFAULT_PORT,
    _authorization,
    _EchoLog,
    _install_stop_signals,
    _int,
    _tcp_name,
    _tls_context,
    _tls_options,
    _wire_options,
    parse_endpoint,
)


def _make_device(args: argparse.Namespace) -> Any:
    unit = _int(args.unit, "--unit", 1, 247)
    if args.device == "meter":
        device = PowerMeter(unit=unit, trial=args.trial, live=args.live, seed=args.seed)
    elif args.device == "arduino":
        device = ArduinoSlave(unit=unit, baudrate=args.baud or 9600, parity=_parity(args),
                              stopbits=args.stopbits, seed=args.seed)
    else:
        device = Slave(unit=unit, bank=DataBank(), name=f"bank {unit}")
        if args.fill == "random":
            random_fill(device.bank.holding_registers, 0, 1000, seed=args.seed)
            random_fill(device.bank.input_registers, 0, 1000, seed=args.seed + 1)
        elif args.fill == "increment":
            increment_fill(device.bank.holding_registers, 0, 1000)
            increment_fill(device.bank.input_registers, 0, 1000)
    device.clock = RealClock()  # a real port: live values follow the wall clock
    return device


def _default_baud(args: argparse.Namespace) -> int:
    if args.baud:
        return args.baud
    return 19200 if args.device == "meter" else 9600


class _Counter:
    """The live request count on stderr: one line, rewritten in place on a terminal."""

    def __init__(self, device: Any, stream: TextIO) -> None:
        self.device = device
        self.stream = stream
        self.tty = stream.isatty()
        self.last: tuple[int, ...] | None = None

    def text(self) -> str:
        c = self.device.counters
        return (f"requests: {c.requests}  responses: {c.responses}  exceptions: {c.exceptions}  "
                f"checksum errors: {c.checksum_errors}")

    def show(self, force: bool = False) -> None:
        c = self.device.counters
        key = (c.requests, c.responses, c.exceptions, c.checksum_errors)
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


def cmd_serve(args: argparse.Namespace) -> int:
    if args.tcp is not None and args.serial is not None:
        raise ConfigError("choose one wire: --tcp HOST:PORT or --serial URL, not both")
    device = _make_device(args)
    if args.verbose:
        device.log = _EchoLog(sys.stderr)
    _install_stop_signals()
    if args.serial is not None:
        _tls_context(args, "serial")  # refuses --tls-* on a serial line
    authorization, roles = _authorization(args)  # with TLS on, roles apply
    if args.serial is not None:
        server: Any = SerialServer(device, args.serial, baudrate=_default_baud(args), parity=_parity(args),
                                   stopbits=args.stopbits, mode=args.mode)
        bits = 7 if args.mode == "ascii" else 8  # what SerialServer opens: ASCII carries 7 data bits
        where = (f"serial {args.serial}, {_default_baud(args)} baud {bits}{_parity(args)}{args.stopbits}, "
                 f"{args.mode.upper()}")
    else:
        host, port = parse_endpoint(args.tcp or f"{DEFAULT_HOST}:{DEFAULT_PORT}")
        server = TcpServer(device, host=host, port=port, tls=_tls_context(args, "server"),
                           authorization=authorization)
        where = None
    counter = _Counter(device, sys.stderr)
    started = False
    try:
        server.start()
        started = True
        if where is None:
            bound_host, bound_port = server.address[:2]
            where = f"{_tcp_name(server)} {bound_host}:{bound_port}"
        print(f"serving {device.name} (unit {device.unit}) on {where}; Ctrl-C to stop", flush=True)
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
                                    "paper's board), "
                                    "bank (a plain dense data bank). The request count is shown on stderr.")
    p.add_argument("device", choices=["meter", "arduino", "bank"], help="what to simulate")
    p.add_argument("--unit", default="1", help="unit identifier (default 1)")
    _wire_options(p, serve=True)
    _tls_options(p, serve=True)
    p.add_argument("--trial", type=int, choices=[1, 2], default=1, help="meter: Table 6 trial (default 1)")
    p.add_argument("--live", action="store_true", help="meter: values drift with time (seeded)")
    p.add_argument("--seed", type=int, default=0, help="seed of the simulated values (default 0)")
    p.add_argument("--fill", choices=["zero", "increment", "random"], default="increment",
                   help="bank: registers 0..999 of both register tables (default increment: 0, 1, 2, ...)")
    return p
