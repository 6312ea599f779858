"""``modbus-edu build``: a request or a response built from its fields, in hex, with its dissection."""

from __future__ import annotations

import argparse
import json
from typing import Any

from .. import pdu as _pdu
from ..codes import _hex
from ..errors import ConfigError
from ..framing import encode_frame
from .common import _ascii_arg, _bit, _dissect, _function, _int, _split_values


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
