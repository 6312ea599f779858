"""What the subcommands share: the program's name and defaults, the parsing of numbers, hex, endpoints
and options, the wire and TLS options, the link a client subcommand opens, and the echo of traffic.
"""

from __future__ import annotations

import argparse
import csv
import os
import signal
import sys
from collections.abc import Sequence
from typing import Any, NoReturn, TextIO

from .. import pdu as _pdu
from .. import security
from ..codes import _hex
from ..datamodel import parse_address_text
from ..errors import ConfigError, ModbusError, shown
from ..explain import explain
from ..framing import parse_hex
from ..links.serial import serial_link
from ..links.tcp_client import tcp_link
from ..master import Master
from ..traffic import Traffic, TrafficLog

PROG = "modbus-edu"
DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 5020


class CliError(Exception):
    """A usage problem found after parsing; printed as one line, exit status 2."""


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
            raise ConfigError(f"bad address {shown(text)}: write an IPv6 address as [::1]:5020")
        host, port_text = text[1:end], text[end + 2 :]
    elif ":" in text:
        host, _, port_text = text.rpartition(":")
        if not host:
            host = default_host
    try:
        port = int(port_text)
    except ValueError:
        raise ConfigError(f"bad address {shown(text)}: expected HOST:PORT such as 127.0.0.1:5020") from None
    if not 0 <= port <= 65535:
        raise ConfigError(f"bad port {port}: a TCP port is 0..65535")
    return host, port


def _int(text: str, what: str, low: int = 0, high: int = 65535) -> int:
    try:
        value = int(text, 0)
    except (TypeError, ValueError):
        raise ConfigError(f"{what} must be a whole number (decimal or 0x hex), got {shown(text)}") from None
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
    raise ConfigError(f"{what} must be on/off (1/0, true/false, FF00/0000), got {shown(text)}")


def _baud(text: str) -> int:
    """argparse type of --baud: a whole number 50..4000000."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"baud rate must be a whole number such as 9600, got {shown(text)}"
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
    codes = ", ".join(str(c) for c in sorted(_pdu.REQUEST_CLASSES))
    try:
        code = int(key, 0)
    except ValueError:
        names = {f.name.lower(): int(f) for f in _pdu.FunctionCode}
        if key in names:
            return names[key]
        raise ConfigError(
            f"unknown function {shown(text)}: give a code ({codes}) or a name such as read_holding_registers"
        ) from None
    if code not in _pdu.REQUEST_CLASSES:
        raise ModbusError(
            f"function {code} (0x{code:02X}) is not one of the {len(_pdu.REQUEST_CLASSES)} this library "
            f"builds: {codes}"
        )
    return code


#: The table each function code reads or writes, in reference-number words.
TABLE_OF_FUNCTION = {1: "coils", 2: "discrete_inputs", 3: "holding_registers", 4: "input_registers",
                     5: "coils", 15: "coils", 6: "holding_registers", 16: "holding_registers",
                     22: "holding_registers", 23: "holding_registers"}
#: The function that reads each table.
READ_FUNCTION = {"coils": 1, "discrete_inputs": 2, "holding_registers": 3, "input_registers": 4}
ADDRESS_HELP = ("0-based address (0, 100, 0x64), or a reference number: 5 or 6 digits with the table's "
                "digit first (40001 = holding register 0, 30001 input, 10001 discrete input, 00001 coil; "
                "400001; 4x0001), which also chooses the function")


def _address(text: str, option: str = "--address") -> tuple[int, str | None]:
    """``--address``: (0-based address, the table a reference number names or None); a plain address
    that looks like a mistyped reference is read as given, with a warning on stderr."""
    parsed = parse_address_text(text, option)
    if parsed.warning:
        print(f"{PROG}: warning: {parsed.warning}", file=sys.stderr, flush=True)
    return parsed.address, parsed.reference.kind if parsed.reference is not None else None


def _table_words(kind: str) -> str:
    return kind.replace("_", " ")


def _check_table(fc: int, kind: str | None, text: str, option: str = "--address") -> None:
    """A reference number's table must be the one ``fc`` works on: a clear error when they differ."""
    if kind is None or TABLE_OF_FUNCTION.get(fc) == kind:
        return
    want = _table_words(TABLE_OF_FUNCTION.get(fc, "no table"))
    raise ConfigError(f"{option} {text.strip()} is a reference to the {_table_words(kind)}, but --function "
                      f"{fc} works on the {want}: drop --function (the reference chooses it) or give a "
                      f"{want} reference")


def _parity(args: argparse.Namespace) -> str:
    """--parity, or the line's usual one: 7E1 for Modbus ASCII, 8N1 for RTU."""
    if args.parity:
        return args.parity
    return "E" if getattr(args, "mode", "rtu") == "ascii" else "N"


def _open_csv(path: str, header: list[str], overwrite: bool = False,
              append: bool = False) -> tuple[TextIO, Any]:
    """A CSV log: refuses to replace a file with data unless ``overwrite``; with ``append`` adds rows
    to it (the header is written once, and must match the file's)."""
    if overwrite and append:
        raise ConfigError("--append or --overwrite, not both")
    exists = os.path.exists(path) and os.path.getsize(path) > 0
    if exists and not (overwrite or append):
        raise ConfigError(f"{path} already exists: add --append to add rows to it or --overwrite to "
                          f"replace it")
    if exists and append:
        with open(path, newline="", encoding="utf-8") as old:
            first = next(csv.reader([old.readline()]), [])
        if first != header:
            raise ConfigError(f"{path} has other columns ({','.join(first)[:80]}); --append needs the same "
                              f"header ({','.join(header)[:80]}): choose another file or --overwrite")
    file = open(path, "a" if append else "w", newline="", encoding="utf-8")  # noqa: SIM115 - caller closes
    writer = csv.writer(file)
    if not (exists and append):
        writer.writerow(header)
        file.flush()
    return file, writer


def _csv_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--csv", metavar="FILE", help="also write every poll to this CSV file")
    parser.add_argument("--append", action="store_true", help="--csv: add rows to an existing file")
    parser.add_argument("--overwrite", action="store_true", help="--csv: replace an existing file")


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


def _dissect(data: bytes, mode: str | None, role: str | None) -> Any:
    return explain(data, mode=mode, role=role)


def _install_stop_signals() -> None:
    """Ctrl-C (SIGINT) and SIGTERM end serve/poll cleanly, even when started where SIGINT is ignored
    (a shell's background job)."""

    def _raise(signum: int, frame: Any) -> NoReturn:
        raise KeyboardInterrupt

    for sig in _STOP_SIGNALS:
        try:
            signal.signal(sig, _raise)
        except (ValueError, OSError):  # pragma: no cover - not the main thread
            pass


_STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def stop_signal_handlers() -> list[Any]:
    """The handlers of SIGINT and SIGTERM now: :func:`main` gives them back after a command, so that a
    command run inside another program (a test, a notebook) leaves that program's signals as they were."""
    return [signal.getsignal(sig) for sig in _STOP_SIGNALS]


def restore_stop_signal_handlers(handlers: list[Any]) -> None:
    for sig, handler in zip(_STOP_SIGNALS, handlers):
        try:
            signal.signal(sig, handler)
        except (ValueError, OSError, TypeError):  # pragma: no cover - not the main thread, or not settable
            pass


def _open_link(args: argparse.Namespace) -> Any:
    if args.tcp is not None and args.serial is not None:
        raise ConfigError("choose one wire: --tcp HOST:PORT or --serial URL, not both")
    if args.serial is not None:
        return serial_link(args.serial, baudrate=args.baud or 9600, parity=_parity(args),
                           stopbits=args.stopbits, mode=args.mode)
    if args.tcp is None:
        raise ConfigError("which device? give --tcp HOST:PORT or --serial URL")

    host, port = parse_endpoint(args.tcp)
    return tcp_link(host, port, timeout=args.timeout, tls=_tls_context(args, "client"))


def _master_options(parser: argparse.ArgumentParser, timeout: float = 1.0) -> None:
    """--timeout and --retries of a subcommand that asks a device."""
    parser.add_argument("--timeout", type=float, default=timeout,
                        help=f"response timeout, seconds (default {timeout:g})")
    parser.add_argument("--retries", type=int, default=0, metavar="N",
                        help="ask again up to N times after a timeout or a bad answer (default 0)")


def _master(args: argparse.Namespace, link: Any) -> Any:
    """The Master a client subcommand asks through: --timeout, --retries, and -v's traffic on stderr."""
    _check_seconds(args.timeout, "--timeout", 0.001, 3_600)
    if not 0 <= args.retries <= 100:
        raise ConfigError(f"--retries must be 0..100, got {args.retries}")
    master = Master(link, timeout=args.timeout, retries=args.retries)
    if getattr(args, "verbose", False):
        master.log = _EchoLog(sys.stderr)
    return master


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``modbus-edu: error: ...`` and exit status 2."""

    def error(self, message: str) -> NoReturn:
        sub = self.prog[len(PROG):].strip()
        hint = f" (see: {PROG} {sub} --help)" if sub else f" (see: {PROG} --help)"
        raise CliError(_one_line(message) + hint)


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
    wire.add_argument("--parity", choices=["N", "E", "O"], default=None, type=str.upper,
                      help="serial parity (default N for rtu, E for ascii: 8N1 and 7E1)")
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
    if serve:
        tls.add_argument("--roles", metavar="JSON",
                         help="the role table clients' certificates are judged by (default with TLS: the "
                              "course's: viewer reads, operator also writes 0..99, engineer everything)")


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
    make = security.server_context if side == "server" else security.client_context
    return make(**given)


def _authorization(args: argparse.Namespace) -> tuple[Any, str | None]:
    """With TLS on (--tls-*), the role table every request is judged by (--roles FILE, else the
    course's) and the start-up line that says so; without TLS, (None, None)."""
    tls_on = any(getattr(args, f"tls_{name}", None) for name in ("cert", "key", "ca"))
    path = getattr(args, "roles", None)
    if not tls_on:
        if path:
            raise ConfigError("--roles needs TLS (--tls-cert, --tls-key, --tls-ca): a role is read from the "
                              "client's certificate, and plain Modbus/TCP has none")
        return None, None
    table = security.load_roles(path) if path else security.course_roles()
    name = path if path else "the course's table"
    return table, f"roles: {name}: {table.describe()}"


def _tcp_name(server: Any) -> str:
    return "Modbus/TCP Security (TLS)" if getattr(server, "tls", None) is not None else "Modbus/TCP"
