"""``modbus-edu gateway``: Modbus/TCP in front of a serial bus."""

from __future__ import annotations

import argparse
import time
from typing import Any

from ..errors import ConfigError
from ..gateway import TcpGateway
from ..links.serial import serial_link
from .common import (
    _authorization,
    _check_seconds,
    _install_stop_signals,
    _parity,
    _tcp_name,
    _tls_context,
    _tls_options,
    _wire_options,
    parse_endpoint,
)


def cmd_gateway(args: argparse.Namespace) -> int:
    if args.serial is None or args.tcp is None:
        raise ConfigError("a gateway needs both sides: --tcp HOST:PORT to listen on and --serial URL behind")
    _check_seconds(args.timeout, "--timeout", 0.001, 3_600)

    host, port = parse_endpoint(args.tcp)
    authorization, roles = _authorization(args)
    tls = _tls_context(args, "server")
    link = serial_link(args.serial, baudrate=args.baud or 9600, parity=_parity(args),
                       stopbits=args.stopbits, mode=args.mode)
    _install_stop_signals()
    gateway = TcpGateway(link, host=host, port=port, timeout=args.timeout, tls=tls,
                         authorization=authorization)
    try:
        gateway.start()
        bound_host, bound_port = gateway.address[:2]
        print(f"gateway: {_tcp_name(gateway.server)} {bound_host}:{bound_port} -> {link.description}; "
              "Ctrl-C to stop", flush=True)
        if roles:
            print(roles, flush=True)
        while True:
            time.sleep(0.2)
    except KeyboardInterrupt:
        pass
    finally:
        gateway.close()
        link.close()
    c = gateway.counters
    print(f"stopped: {c['forwarded']} forwarded, {c['no_response']} answered 0B, "
          f"{c['path_unavailable'] + c['overloaded']} answered 0A ({c['overloaded']} of them overloaded)",
          flush=True)
    return 0


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
