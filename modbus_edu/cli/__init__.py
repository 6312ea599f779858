"""The command line: ``modbus-edu`` (or ``python -m modbus_edu``).

Subcommands::

    modbus-edu crc HEX...            CRC-16/MODBUS of some bytes, and the two bytes in wire order
    modbus-edu lrc HEX...            LRC of some bytes (Modbus ASCII)
    modbus-edu decode FRAME...       a frame dissected field by field (or as JSON)
    modbus-edu build ...             a frame built from its fields, in hex, with its dissection
    modbus-edu serve DEVICE ...      a simulated device (power meter, Arduino, plain bank) on TCP or serial
    modbus-edu poll ...              read a real device again and again: a live table, statistics, CSV
    modbus-edu write ...             write coils or registers (FC 5, 6, 15, 16, 22, 23) and read them back
    modbus-edu capture FILE          the Modbus exchanges of a pcap/pcapng capture, decoded and paired
    modbus-edu ports                 the serial ports of this computer

Every subcommand has ``--help``.  ``--verbose`` (``-v``) shows the traffic (or the CRC step by step).

Everything here is a thin layer over the library -- the same functions a notebook calls -- so what
the command line prints is what the course teaches.  Bad input never ends in a traceback: the
library's :class:`~modbus_edu.errors.ModbusError` (and an operating-system error such as "connection
refused") becomes one line on stderr, ``modbus-edu: error: ...``, and a non-zero exit status
(1; 2 for a command line that does not parse).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from .. import __version__
from ..errors import ModbusError
from .build import _options_build, cmd_build
from .capture import _options_capture, cmd_capture
from .common import (
    PROG,
    CliError,
    _common,
    _one_line,
    _Parser,
    parse_endpoint,
    restore_stop_signal_handlers,
    stop_signal_handlers,
)
from .crc import _options_crc, cmd_crc
from .decode import _options_decode, cmd_decode
from .gateway import _options_gateway, cmd_gateway
from .grade import _options_grade, cmd_grade
from .identify import _options_identify, cmd_identify
from .lrc import _options_lrc, cmd_lrc
from .poll import _options_poll, cmd_poll
from .ports import _options_ports, cmd_ports
from .scan import _options_scan, cmd_scan
from .serve import _options_serve, cmd_serve
from .write import _options_write, cmd_write

__all__ = ["main", "build_parser", "parse_endpoint"]

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
        (_options_write, cmd_write),
        (_options_identify, cmd_identify),
        (_options_gateway, cmd_gateway),
        (_options_scan, cmd_scan),
        (_options_capture, cmd_capture),
        (_options_ports, cmd_ports),
        (_options_grade, cmd_grade),
    ):
        sub = add(subs)
        _common(sub)
        sub.set_defaults(func=command)
    return parser


def _version() -> str:
    return __version__


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 1 error, 2 bad command line)."""
    parser = build_parser()
    verbose = False
    handlers = stop_signal_handlers()
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
    finally:
        restore_stop_signal_handlers(handlers)
