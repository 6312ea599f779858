"""The command line: ``modbus-edu`` (or ``python -m modbus_edu``).

Subcommands::

    modbus-edu crc HEX...            CRC-16/MODBUS of some bytes, and the two bytes in wire order
    modbus-edu lrc HEX...            LRC of some bytes (Modbus ASCII)
    modbus-edu decode FRAME...       a frame dissected field by field (or as JSON)
    modbus-edu build ...             a frame built from its fields, in hex, with its dissection
    modbus-edu serve DEVICE ...      a simulated device (power meter, Arduino, plain bank) on TCP or serial
    modbus-edu poll ...              read a real device again and again, with statistics and CSV

Every subcommand has ``--help``.  ``--verbose`` (``-v``) shows the traffic (or the CRC step by step).

Everything here is a thin layer over the library -- the same functions a notebook calls -- so what
the command line prints is what the course teaches.  Bad input never ends in a traceback: the
library's :class:`~modbus_edu.errors.ModbusError` (and an operating-system error such as "connection
refused") becomes one line on stderr, ``modbus-edu: error: ...``, and a non-zero exit status
(1; 2 for a command line that does not parse).
"""

from __future__ import annotations

import argparse
import csv
import json
import signal
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from datetime import datetime
from pathlib import Path
from typing import Any, NoReturn, TextIO

from . import __version__
from . import pdu as _pdu
from .clock import RealClock
from .codes import _hex, _printable
from .crc import crc16, crc16_table_trace, crc_bytes, lrc
from .datamodel import DataBank
from .devices.arduino import ArduinoSlave
from .devices.generators import increment_fill, random_fill
from .devices.meter import PowerMeter
from .errors import ConfigError, FrameError, ModbusError, ModbusExceptionError, ModbusTimeoutError
from .explain import explain
from .framing import encode_frame, parse_hex
from .gateway import TcpGateway
from .links.serial import SerialServer, serial_link
from .links.tcp import TcpServer, tcp_link
from .master import Master
from .scan import scan
from .slave import Slave
from .traffic import Traffic, TrafficLog
from .values import FORMATS, TYPES, format_registers

PROG = "modbus-edu"
DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 5020

__all__ = ["main", "build_parser", "parse_endpoint"]


class CliError(Exception):
    """A usage problem found after parsing; printed as one line, exit status 2."""


# --------------------------------------------------------------------------------------------------
# small helpers
# --------------------------------------------------------------------------------------------------
def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def _hex_arg(parts: Sequence[str]) -> bytes:
    """The bytes of hex typed as one or several arguments (``01 03 00 00`` or ``"0103 0000"``)."""
    text = " ".join(parts)
    if not text.strip():
        raise ConfigError("no bytes given: type them in hex, e.g. 01 03 00 00 00 01")
    return parse_hex(text)


def parse_endpoint(text: str, default_host: str = DEFAULT_HOST) -> tuple[str, int]:
    """``"HOST:PORT"``, ``"PORT"`` or ``"[::1]:PORT"`` -> ``(host, port)``; a bare port means 127.0.0.1."""
    text = text.strip()
    host, port_text = default_host, text
    if text.startswith("["):
        end = text.find("]")
        if end == -1 or not text[end + 1 :].startswith(":"):
            raise ConfigError(f"bad address {text!r}: write an IPv6 address as [::1]:5020")
        host, port_text = text[1:end], text[end + 2 :]
    elif ":" in text:
        host, _, port_text = text.rpartition(":")
        if not host:
            host = default_host
    try:
        port = int(port_text)
    except ValueError:
        raise ConfigError(f"bad address {text!r}: expected HOST:PORT such as 127.0.0.1:5020") from None
    if not 0 <= port <= 65535:
        raise ConfigError(f"bad port {port}: a TCP port is 0..65535")
    return host, port


def _int(text: str, what: str, low: int = 0, high: int = 65535) -> int:
    try:
        value = int(text, 0)
    except (TypeError, ValueError):
        raise ConfigError(f"{what} must be a whole number (decimal or 0x hex), got {text!r}") from None
    if not low <= value <= high:
        raise ConfigError(f"{what} must be {low}..{high}, got {value}")
    return value


_TRUE = {"1", "on", "true", "yes", "ff00", "0xff00"}
_FALSE = {"0", "off", "false", "no", "0000", "0x0000"}


def _bit(text: str, what: str = "coil value") -> bool:
    key = text.strip().lower()
    if key in _TRUE:
        return True
    if key in _FALSE:
        return False
    raise ConfigError(f"{what} must be on/off (1/0, true/false, FF00/0000), got {text!r}")


def _baud(text: str) -> int:
    """argparse type of --baud: a whole number 50..4000000."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"baud rate must be a whole number such as 9600, got {text!r}"
        ) from None
    if not 50 <= value <= 4_000_000:
        raise argparse.ArgumentTypeError(
            f"{value} is not a serial speed: use a baud rate such as 9600, 19200 or 115200 (50..4000000)"
        )
    return value


def _split_values(text: str) -> list[str]:
    items = [v for v in text.replace(",", " ").split() if v]
    if not items:
        raise ConfigError("--values is empty: give values separated by commas, e.g. 1,2,3")
    return items


def _function(text: str) -> int:
    """``3``, ``0x03``, ``fc3``, ``read_holding_registers`` or ``read-holding-registers`` -> 3."""
    key = text.strip().lower().replace("-", "_").replace(" ", "_")
    if key.startswith("fc"):
        key = key[2:]
    try:
        code = int(key, 0)
    except ValueError:
        names = {f.name.lower(): int(f) for f in _pdu.FunctionCode}
        if key in names:
            return names[key]
        raise ConfigError(
            f"unknown function {text!r}: give a code (1, 2, 3, 4, 5, 6, 7, 15, 16, 17, 22, 23) or a name "
            f"such as read_holding_registers"
        ) from None
    if code not in _pdu.REQUEST_CLASSES:
        raise ModbusError(
            f"function {code} (0x{code:02X}) is not one of the eight this library builds: "
            f"1, 2, 3, 4, 5, 6, 15, 16"
        )
    return code


class _EchoLog(TrafficLog):
    """A traffic log that also prints every entry to a stream (``--verbose``)."""

    def __init__(self, stream: TextIO, maxlen: int | None = 1000) -> None:
        super().__init__(maxlen=maxlen)
        self.stream = stream

    def append(self, entry: Traffic) -> None:
        super().append(entry)
        self._echo(entry)

    def add(self, time: float, direction: str, mode: str, data: bytes, **kwargs: Any) -> Traffic:
        entry = super().add(time, direction, mode, data, **kwargs)
        self._echo(entry)
        return entry

    def _echo(self, entry: Traffic) -> None:
        arrow = "->" if entry.direction == "tx" else "<-"
        note = f"  ({entry.note})" if entry.note else ""
        print(f"{entry.direction} {arrow} {entry.text}{note}", file=self.stream, flush=True)


# --------------------------------------------------------------------------------------------------
# crc, lrc
# --------------------------------------------------------------------------------------------------
def _ascii_arg(text: str) -> bytes:
    """The bytes of ASCII ``text``; other characters are refused, never replaced by '?'."""
    for index, char in enumerate(text):
        if ord(char) > 127:
            utf8 = _hex(char.encode())
            raise ConfigError(f"--text takes ASCII text: {char!r} (character {index + 1}) is not ASCII; give "
                              f"the bytes in hex instead (its UTF-8 bytes are {utf8})")
    return text.encode("ascii")


def _check_seconds(value: float, option: str, low: float, high: float) -> float:
    """A finite number of seconds within ``low..high`` (inclusive of ``high``), or a ConfigError."""
    if not low <= value <= high:  # also false for nan
        raise ConfigError(f"{option} must be a number of seconds from {low:g} to {high:g}, got {value:g}")
    return value


def cmd_crc(args: argparse.Namespace) -> int:
    data = _ascii_arg(" ".join(args.hex)) if args.text else _hex_arg(args.hex)
    if args.text and not data:
        raise ConfigError("no text given")
    value = crc16(data)
    wire = crc_bytes(data)
    print(f"CRC-16/MODBUS of {len(data)} byte{'s' if len(data) != 1 else ''}: 0x{value:04X} ({value})")
    print(f"on the wire, low byte first: {_hex(wire)}")
    print(f"message with its CRC: {_hex(data + wire)}")
    if args.verbose:
        print("\nbyte  index  table value  CRC before -> after")
        for step in crc16_table_trace(data):
            print(
                f"  {step.byte:02X}     {step.index:02X}       0x{step.table_value:04X}      "
                f"0x{step.before:04X} -> 0x{step.after:04X}"
            )
    return 0


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


# --------------------------------------------------------------------------------------------------
# decode, build
# --------------------------------------------------------------------------------------------------
def _mode_or_none(mode: str) -> str | None:
    return None if mode == "auto" else mode


def _dissect(data: bytes, mode: str | None, role: str | None) -> Any:
    return explain(data, mode=mode, role=role)


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


def _request_pdu(fc: int, args: argparse.Namespace) -> _pdu.Pdu:
    cls = _pdu.REQUEST_CLASSES[fc]
    if cls.fixed_size == 1:  # the function code alone (FC 7, 11, 12, 17)
        return cls()
    if fc == 0x08:  # Diagnostics: --value SUB_FUNCTION [--values DATA_WORDS]
        return cls(_int(_need(args, "value", fc, raw=True), "--value"), _words(args))
    if fc in (0x14, 0x15):  # file records: --file, --address (the record), --count or --values
        file, record = _int(_need(args, "file", fc, raw=True), "--file", 1, 65535), _need(args, "address", fc)
        if fc == 0x14:
            return cls(((file, record, _need(args, "count", fc)),))
        values = [_int(v, "each of --values") for v in _split_values(_need(args, "values", fc, raw=True))]
        return cls(((file, record, tuple(values)),))
    address = _need(args, "address", fc)
    if fc == 0x16:  # Mask Write Register: --values AND_MASK,OR_MASK
        masks = [_int(v, "each of --values") for v in _split_values(_need(args, "values", fc, raw=True))]
        if len(masks) != 2:
            raise ConfigError("Mask Write Register takes --values AND_MASK,OR_MASK (two numbers)")
        return cls(address, *masks)
    if fc == 0x17:  # Read/Write Multiple Registers: read --count from --address, write --values there
        items = _split_values(_need(args, "values", fc, raw=True))
        return cls(address, _need(args, "count", fc), address, [_int(v, "each of --values") for v in items])
    if fc in (1, 2, 3, 4):
        return cls(address=address, count=_need(args, "count", fc))
    if fc == 5:
        return cls(address=address, value=_bit(_need(args, "value", fc, raw=True)))
    if fc == 6:
        return cls(address=address, value=_int(_need(args, "value", fc, raw=True), "--value"))
    items = _split_values(_need(args, "values", fc, raw=True))
    if fc == 15:
        return cls(address=address, values=[_bit(v, "each of --values") for v in items])
    return cls(address=address, values=[_int(v, "each of --values") for v in items])


def _response_pdu(fc: int, args: argparse.Namespace) -> _pdu.Pdu:
    if args.exception is not None:
        return _pdu.ExceptionResponse(function=fc, code=_int(args.exception, "--exception", 1, 255))
    cls = _pdu.RESPONSE_CLASSES[fc]
    if fc in (0x08, 0x15):
        request = _request_pdu(fc, args)  # the echo (FC 8: with --values as the answer's data)
        return cls(request.sub_function, request.data) if fc == 0x08 else cls(request.records)
    if fc == 0x0B:
        return cls(0, _int(_need(args, "value", fc, raw=True), "--value"))
    if fc == 0x14:
        items = _split_values(_need(args, "values", fc, True))
        return cls((tuple(_int(v, "each of --values") for v in items),))
    if fc == 0x07:
        return cls(_int(_need(args, "value", fc, raw=True), "--value", 0, 255))
    if fc == 0x11:
        return cls(_ascii_arg(_need(args, "value", fc, raw=True)), True)
    if fc in (1, 2):
        items = _split_values(_need(args, "values", fc, True))
        return cls(bits=[_bit(v, "each of --values") for v in items])
    if fc in (3, 4, 0x17):
        items = _split_values(_need(args, "values", fc, True))
        return cls(registers=[_int(v, "each of --values") for v in items])
    address = _need(args, "address", fc)
    if fc == 0x16:
        request = _request_pdu(fc, args)
        return _pdu.MaskWriteRegisterResponse(request.address, request.and_mask, request.or_mask)
    if fc == 5:
        return cls(address=address, value=_bit(_need(args, "value", fc, raw=True)))
    if fc == 6:
        return cls(address=address, value=_int(_need(args, "value", fc, raw=True), "--value"))
    return cls(address=address, count=_need(args, "count", fc))


def _words(args: argparse.Namespace) -> bytes:
    """FC 8's data: --values as 16-bit words (default one word 0x0000)."""
    if args.values is None:
        return b"\x00\x00"
    return b"".join(_int(v, "each of --values").to_bytes(2, "big") for v in _split_values(args.values))


def _need(args: argparse.Namespace, name: str, fc: int, raw: bool = False) -> Any:
    value = getattr(args, name)
    if value is None:
        title = _pdu.FunctionCode(fc).title
        raise ConfigError(f"{title} {args.role} needs --{name}")
    if raw:
        return value
    return _int(value, f"--{name}")


def cmd_build(args: argparse.Namespace) -> int:
    fc = _function(args.function)
    if args.exception is not None and args.role != "response":
        raise ConfigError("--exception builds an exception response: add --role response")
    pdu = _request_pdu(fc, args) if args.role == "request" else _response_pdu(fc, args)
    high = 255 if args.mode == "tcp" else 247
    unit = _int(args.unit, "--unit", 0, high)
    tid = _int(args.transaction_id, "--transaction-id")
    frame = encode_frame(args.mode, unit, pdu, tid)
    dissection = _dissect(frame, args.mode, args.role)
    text = frame.decode("ascii").replace("\r\n", "\\r\\n") if args.mode == "ascii" else _hex(frame)
    if args.json:
        print(json.dumps({"frame": text, "hex": _hex(frame), "dissection": dissection.to_dict()}, indent=2))
    else:
        print(text)
        print()
        print(dissection.to_text())
    return 0


# --------------------------------------------------------------------------------------------------
# serve
# --------------------------------------------------------------------------------------------------
def _make_device(args: argparse.Namespace) -> Any:
    unit = _int(args.unit, "--unit", 1, 247)
    if args.device == "meter":
        device = PowerMeter(unit=unit, trial=args.trial, live=args.live, seed=args.seed)
    elif args.device == "arduino":
        device = ArduinoSlave(unit=unit, baudrate=args.baud or 9600, parity=args.parity,
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


def _install_stop_signals() -> None:
    """Ctrl-C (SIGINT) and SIGTERM end serve/poll cleanly, even when started where SIGINT is ignored
    (a shell's background job)."""

    def _raise(signum: int, frame: Any) -> NoReturn:
        raise KeyboardInterrupt

    for sig in (signal.SIGINT, signal.SIGTERM):
        try:
            signal.signal(sig, _raise)
        except (ValueError, OSError):  # pragma: no cover - not the main thread
            pass


def cmd_serve(args: argparse.Namespace) -> int:
    if args.tcp is not None and args.serial is not None:
        raise ConfigError("choose one wire: --tcp HOST:PORT or --serial URL, not both")
    device = _make_device(args)
    if args.verbose:
        device.log = _EchoLog(sys.stderr)
    _install_stop_signals()
    if args.serial is not None:
        _tls_context(args, "serial")  # refuses --tls-* on a serial line
        server: Any = SerialServer(device, args.serial, baudrate=_default_baud(args), parity=args.parity,
                                   stopbits=args.stopbits, mode=args.mode)
        bits = 7 if args.mode == "ascii" else 8  # what SerialServer opens: ASCII carries 7 data bits
        where = (f"serial {args.serial}, {_default_baud(args)} baud {bits}{args.parity}{args.stopbits}, "
                 f"{args.mode.upper()}")
    else:
        host, port = parse_endpoint(args.tcp or f"{DEFAULT_HOST}:{DEFAULT_PORT}")
        server = TcpServer(device, host=host, port=port, tls=_tls_context(args, "server"))
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


# --------------------------------------------------------------------------------------------------
# poll
# --------------------------------------------------------------------------------------------------
_READERS = {
    1: "read_coils",
    2: "read_discrete_inputs",
    3: "read_holding_registers",
    4: "read_input_registers",
}


def _open_link(args: argparse.Namespace) -> Any:
    if args.tcp is not None and args.serial is not None:
        raise ConfigError("choose one wire: --tcp HOST:PORT or --serial URL, not both")
    if args.serial is not None:
        return serial_link(args.serial, baudrate=args.baud or 9600, parity=args.parity,
                           stopbits=args.stopbits, mode=args.mode)
    if args.tcp is None:
        raise ConfigError("which device? give --tcp HOST:PORT or --serial URL")

    host, port = parse_endpoint(args.tcp)
    return tcp_link(host, port, timeout=args.timeout, tls=_tls_context(args, "client"))


def cmd_identify(args: argparse.Namespace) -> int:
    unit = _int(args.unit, "--unit", 0 if args.tcp is not None else 1, 255 if args.tcp is not None else 247)
    _check_seconds(args.timeout, "--timeout", 0.001, 3_600)
    link = _open_link(args)
    try:
        master = Master(link, timeout=args.timeout)
        try:
            objects = master.read_device_identification(unit, read_code=3)
        except ModbusExceptionError as exc:
            if exc.code != 1:
                raise
            print(f"unit {unit} does not answer Read Device Identification (FC 43/14): exception 01; "
                  "asking Report Server ID (FC 17)")
            print(_server_id_text(master.report_server_id(unit)))
            return 0
        for object_id, value in sorted(objects.items()):
            name = _pdu.DEVICE_ID_OBJECTS.get(object_id, f"object 0x{object_id:02X}")
            print(f"{object_id:#04x}  {name:<20} {_printable(value)}")
    finally:
        link.close()
    return 0


def _server_id_text(report: _pdu.ReportServerIdResponse) -> str:
    """FC 17's answer on one line: each field in hex and as escaped text."""
    def both(data: bytes) -> str:
        return f"{_hex(data)} ({data!r})"

    if report.run_indicator is None:
        return f"server ID (no run indicator found, not split): {both(report.server_id)}"
    text = f"server ID: {both(report.server_id)}, run indicator: {'ON' if report.run_indicator else 'OFF'}"
    return text + (f", additional data: {both(report.additional_data)}" if report.additional_data else "")


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


# --------------------------------------------------------------------------------------------------
# the parser
# --------------------------------------------------------------------------------------------------
class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``modbus-edu: error: ...`` and exit status 2."""

    def error(self, message: str) -> NoReturn:
        sub = self.prog[len(PROG):].strip()
        hint = f" (see: {PROG} {sub} --help)" if sub else f" (see: {PROG} --help)"
        raise CliError(_one_line(message) + hint)


# --------------------------------------------------------------------------------------------------
# gateway, scan
# --------------------------------------------------------------------------------------------------
def cmd_gateway(args: argparse.Namespace) -> int:
    if args.serial is None or args.tcp is None:
        raise ConfigError("a gateway needs both sides: --tcp HOST:PORT to listen on and --serial URL behind")
    _check_seconds(args.timeout, "--timeout", 0.001, 3_600)

    host, port = parse_endpoint(args.tcp)
    tls = _tls_context(args, "server")
    link = serial_link(args.serial, baudrate=args.baud or 9600, parity=args.parity,
                       stopbits=args.stopbits, mode=args.mode)
    _install_stop_signals()
    gateway = TcpGateway(link, host=host, port=port, timeout=args.timeout, tls=tls)
    try:
        gateway.start()
        bound_host, bound_port = gateway.address[:2]
        print(f"gateway: {_tcp_name(gateway.server)} {bound_host}:{bound_port} -> {link.description}; "
              "Ctrl-C to stop", flush=True)
        while True:
            time.sleep(0.2)
    except KeyboardInterrupt:
        pass
    finally:
        gateway.close()
        link.close()
    c = gateway.counters
    print(f"stopped: {c['forwarded']} forwarded, {c['no_response']} answered 0B, "
          f"{c['path_unavailable']} answered 0A", flush=True)
    return 0


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
    parities = [args.parity]
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
    if args.serial is not None and args.tcp is None:
        settings = _line_settings(args)

        def opener(**setting: Any) -> Any:
            return serial_link(args.serial, stopbits=args.stopbits, mode=args.mode, **setting)

        report = scan(opener, units, settings=settings, timeout=args.timeout, budget=args.budget,
                      progress=True)
    else:
        link = _open_link(args)
        try:
            report = scan(link, units, timeout=args.timeout, budget=args.budget, progress=True)
        finally:
            link.close()
    for hit in report:
        where = ", ".join(f"{k} {v}" for k, v in hit.settings.items())
        print(f"unit {hit.unit:3d}{'  ' + where if where else ''}: {hit.answer}")
    tail = "" if report.complete else f" (stopped at the {args.budget:g} s budget)"
    print(f"{len(report)} found, {report.asked} asked{tail}")
    return 0


def _common(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-v", "--verbose", action="store_true", default=argparse.SUPPRESS,
                        help="show the traffic (crc/lrc: the calculation step by step)")


def _wire_options(parser: argparse.ArgumentParser, serve: bool) -> None:
    wire = parser.add_argument_group("wire")
    if serve:
        wire.add_argument("--tcp", metavar="HOST:PORT",
                          help=f"listen for Modbus/TCP (default {DEFAULT_HOST}:{DEFAULT_PORT}; a bare PORT "
                               f"means {DEFAULT_HOST}; port 0 picks a free one; another host must be given "
                               f"explicitly)")
    else:
        wire.add_argument("--tcp", metavar="HOST:PORT", help="a Modbus/TCP device, e.g. 127.0.0.1:502")
    wire.add_argument("--serial", metavar="URL",
                      help="a serial port or pyserial URL: /dev/ttyUSB0, COM3, rfc2217://host:port")
    wire.add_argument("--baud", type=_baud, metavar="N",
                      help="serial baud rate (default 9600; serve meter: 19200, as in the power-meter paper)")
    wire.add_argument("--parity", choices=["N", "E", "O"], default="N", type=str.upper,
                      help="serial parity (default N)")
    wire.add_argument("--stopbits", type=int, choices=[1, 2], default=1, help="serial stop bits (default 1)")
    wire.add_argument("--mode", choices=["rtu", "ascii"], default="rtu",
                      help="serial framing (default rtu)")


def _tls_options(parser: argparse.ArgumentParser, serve: bool) -> None:
    """--tls-cert/--tls-key/--tls-ca: Modbus/TCP Security (mutual TLS) on the TCP side."""
    whose = "the server's" if serve else "the client's"
    other = "clients" if serve else "the server"
    tls = parser.add_argument_group("Modbus/TCP Security (TLS 1.2+, port 802 by convention)")
    tls.add_argument("--tls-cert", metavar="PEM", help=f"{whose} certificate; turns TLS on")
    tls.add_argument("--tls-key", metavar="PEM", help=f"{whose} private key")
    tls.add_argument("--tls-ca", metavar="PEM", help=f"the certificate authority that signs {other}")


def _tls_context(args: argparse.Namespace, side: str) -> Any:
    """The TLS context the --tls-* options ask for (None without them); all three or none."""
    given = {name: getattr(args, f"tls_{name}", None) for name in ("cert", "key", "ca")}
    if not any(given.values()):
        return None
    if side == "serial":
        raise ConfigError("--tls-cert/--tls-key/--tls-ca secure Modbus/TCP (--tcp), not a serial line")
    missing = [f"--tls-{name}" for name, value in given.items() if not value]
    if missing:
        raise ConfigError(f"Modbus/TCP Security is mutual: give --tls-cert, --tls-key and --tls-ca "
                          f"together ({', '.join(missing)} missing)")
    from . import security

    make = security.server_context if side == "server" else security.client_context
    return make(**given)


def _tcp_name(server: Any) -> str:
    return "Modbus/TCP Security (TLS)" if getattr(server, "tls", None) is not None else "Modbus/TCP"


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of the command line (for documentation tools and tests)."""
    parser = _Parser(
        prog=PROG,
        description="Modbus from the command line: checksums, frames dissected and built, a simulated "
                    "device to serve, a real device to poll.",
        epilog="Examples:\n"
               "  modbus-edu crc 01 03 00 00 00 01\n"
               "  modbus-edu decode 01 03 00 00 00 01 84 0A\n"
               "  modbus-edu build --mode tcp --unit 1 --function 3 --address 0 --count 1\n"
               "  modbus-edu serve meter --tcp 127.0.0.1:5020\n"
               "  modbus-edu poll --tcp 127.0.0.1:5020 --unit 1 --function 3 --address 0 --count 4 "
               "--format uint32_ABCD",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("-v", "--verbose", action="store_true", default=False,
                        help="show the traffic (crc/lrc: the calculation step by step)")
    parser.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    subs = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for add, command in (
        (_options_crc, cmd_crc),
        (_options_lrc, cmd_lrc),
        (_options_decode, cmd_decode),
        (_options_build, cmd_build),
        (_options_serve, cmd_serve),
        (_options_poll, cmd_poll),
        (_options_identify, cmd_identify),
        (_options_gateway, cmd_gateway),
        (_options_scan, cmd_scan),
        (_options_grade, cmd_grade),
    ):
        sub = add(subs)
        _common(sub)
        sub.set_defaults(func=command)
    return parser


def _options_crc(subs: Any) -> argparse.ArgumentParser:
    """The ``crc`` subcommand's options."""
    p = subs.add_parser("crc", help="CRC-16/MODBUS of bytes given in hex",
                        description="The CRC-16/MODBUS of some bytes, and its two bytes in wire order "
                                    "(low byte first). Example: modbus-edu crc 01 03 00 00 00 01")
    p.add_argument("hex", nargs="+", metavar="HEX", help="the bytes, e.g. 01 03 00 00 00 01 or 010300000001")
    p.add_argument("--text", action="store_true",
                   help="take the arguments as ASCII text (crc --text 123456789)")
    return p


def _options_lrc(subs: Any) -> argparse.ArgumentParser:
    """The ``lrc`` subcommand's options."""
    p = subs.add_parser("lrc", help="LRC (Modbus ASCII) of bytes given in hex",
                        description="The LRC of some bytes (unit, function code, data), as Modbus ASCII "
                                    "sends it. Example: modbus-edu lrc 05 06 10 01 02 00")
    p.add_argument("hex", nargs="+", metavar="HEX", help="the bytes, e.g. 05 06 10 01 02 00")
    return p


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


def _options_build(subs: Any) -> argparse.ArgumentParser:
    """The ``build`` subcommand's options."""
    p = subs.add_parser("build", help="build a frame from its fields",
                        description="Build a request (or, with --role response, a response) and print it "
                                    "in hex with its dissection. Example: modbus-edu build --mode rtu "
                                    "--unit 1 --function 3 --address 0 --count 2")
    p.add_argument("--mode", choices=["rtu", "ascii", "tcp"], default="rtu", help="framing (default rtu)")
    p.add_argument("--unit", default="1",
                   help="unit identifier / slave address (default 1; 0 = broadcast on rtu/ascii, "
                        "the device itself on tcp)")
    p.add_argument("--function", required=True,
                   help="function code 1, 2, 3, 4, 5, 6, 15, 16 or its name (read_holding_registers)")
    p.add_argument("--role", choices=["request", "response"], default="request", help="default request")
    p.add_argument("--address", help="starting address, 0-based (0x hex accepted)")
    p.add_argument("--count", help="quantity of coils or registers")
    p.add_argument("--value", help="FC 5: on/off; FC 6: a register value 0..65535")
    p.add_argument("--values", help="FC 15: bits such as 1,0,1; FC 16 (and read responses): 10,20,0x30")
    p.add_argument("--file", help="FC 20/21: the file number (1-65535); --address is then the record")
    p.add_argument("--exception", metavar="CODE",
                   help="with --role response: an exception response, code 1..255")
    p.add_argument("--transaction-id", default="1", help="TCP transaction identifier (default 1)")
    p.add_argument("--json", action="store_true", help="print the frame and its dissection as JSON")
    return p


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


def _options_identify(subs: Any) -> argparse.ArgumentParser:
    """The ``identify`` subcommand's options."""
    p = subs.add_parser("identify", help="ask a device what it is (FC 43/14, else FC 17)",
                        description="Ask a device for its identification: Read Device Identification (FC "
                                    "43 with MEI type 14), all the objects it has, and where the device does "
                                    "not know that function, Report Server ID (FC 17). Example: modbus-edu "
                                    "identify --tcp 127.0.0.1:5020")
    _wire_options(p, serve=False)
    p.add_argument("--unit", default="1", help="unit identifier / slave address (default 1)")
    p.add_argument("--timeout", type=float, default=1.0, help="response timeout, seconds (default 1)")
    return p


def _options_gateway(subs: Any) -> argparse.ArgumentParser:
    """The ``gateway`` subcommand's options."""
    p = subs.add_parser("gateway", help="Modbus/TCP in front of a serial bus",
                        description="Serve Modbus/TCP and forward each request to the serial slave of its "
                                    "unit id; 0x0B when it stays silent, 0x0A for unit 0 or 248-255. "
                                    "Example: modbus-edu gateway --tcp 127.0.0.1:5020 --serial /dev/ttyUSB0 "
                                    "--baud 19200 --parity E")
    _wire_options(p, serve=False)
    _tls_options(p, serve=True)
    p.add_argument("--timeout", type=float, default=0.5, help="wait for a slave, seconds (default 0.5)")
    return p


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


def cmd_grade(args: argparse.Namespace) -> int:
    from .course.grade import grade

    summary = grade(args.submissions, args.out, timeout=args.timeout, memory_mb=args.memory, jobs=args.jobs,
                    progress=not args.quiet, container=args.container)
    print(f"graded {summary['learners']} learner(s) in {summary['seconds']:.1f} s: {args.out}/gradebook.csv, "
          f"{args.out}/summary.html, {args.out}/learners/")
    for row in summary["exercises"]:
        print(f"  {row['exercise']:>6}  {row['success rate']:4.0%} right")
    for learner, flags in summary["flags"].items():
        print(f"  {learner}: {'; '.join(flags)}")
    return 0


def _options_grade(subs: Any) -> argparse.ArgumentParser:
    """The ``grade`` subcommand's options."""
    p = subs.add_parser("grade", help="grade a class's notebooks into a gradebook",
                        description="Run every learner's notebooks in fresh kernels, each learner sealed "
                                    "off, every answer judged by the grader's own checkers, and write a CSV "
                                    "gradebook, a "
                                    "feedback page per learner and a class summary. SUBMISSIONS: folders of "
                                    "learners' folders, a learner's folder, or notebooks named by learner "
                                    "(ada_03_rtu_and_crc.ipynb). Example: modbus-edu grade class --out out")
    p.add_argument("submissions", nargs="+", type=Path, metavar="SUBMISSIONS")
    p.add_argument("--out", type=Path, default=Path("grades"), help="folder to write into (default grades)")
    p.add_argument("--timeout", type=float, default=300.0, help="seconds per notebook (default 300)")
    p.add_argument("--memory", type=int, default=1024, help="MB of memory per learner (default 1024)")
    p.add_argument("--jobs", type=int, default=None, help="learners graded at once (default: the CPU count)")
    p.add_argument("--container", metavar="IMAGE", help="run each kernel in a docker or podman container of "
                                                        "IMAGE (Python, ipykernel and modbus_edu inside)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    return p


def _version() -> str:
    return __version__


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 1 error, 2 bad command line)."""
    parser = build_parser()
    verbose = False
    try:
        args = parser.parse_args(argv)
        verbose = bool(getattr(args, "verbose", False))
        if args.command is None:
            parser.print_help()
            return 2
        return args.func(args)
    except CliError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    except ModbusError as exc:
        print(f"{PROG}: error: {_one_line(exc)}", file=sys.stderr)
        return 1
    except OSError as exc:
        if isinstance(exc, BrokenPipeError):
            return 1
        what = exc.strerror or str(exc)
        where = f": {exc.filename}" if getattr(exc, "filename", None) else ""
        print(f"{PROG}: error: {_one_line(what)}{where}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    except Exception as exc:  # noqa: BLE001 - a bug: still no traceback unless asked
        if verbose:
            raise
        print(f"{PROG}: error: unexpected {type(exc).__name__}: {_one_line(exc)} "
              f"(run with --verbose to see where)", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
