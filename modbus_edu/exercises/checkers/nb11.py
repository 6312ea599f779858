"""Exercises of notebook 11: Real sockets and real libraries."""

from __future__ import annotations

import re
from typing import Any

try:
    import serial
    from serial.urlhandler.protocol_socket import Serial as SocketSerial
except (ImportError, AttributeError):  # pragma: no cover - a dependency; a browser (Pyodide) may lack it
    serial = SocketSerial = None

from ...framing import RtuFrame, TcpFrame, parse_hex
from ...pdu import ReadHoldingRegistersRequest
from ..build import build_exercise
from ..core import (
    Raised,
    address_diagnosis,
    as_bytes,
    compare_bytes,
    exercise,
    named_then,
    pdu_envelope_diagnosis,
    tcp_frame_diagnosis,
)
from ..diagnosis.misconceptions import diagnose, name
from ..diagnosis.procedures import field_value_procedure

_11_1_FRAME = "00 2A 00 00 00 06 11 06 00 10 01 F4"


@exercise("11.1", "decode a captured Modbus/TCP request",
          hint=("MBAP: transaction id (2 bytes, big-endian), protocol id (2), length (2), unit (1); then "
                "the PDU: function code, address (2), value (2).",
                "mb.TcpFrame.decode(mb.parse_hex(...), role='request') reads it: .transaction_id, and .pdu "
                "with its fields."),
          accepts=[(42, 6, 16, 500), [0x2A, 6, 0x10, 0x01F4]],
          refuses=[((0x2A00, 6, 16, 500), "mbap-little-endian"), ((42, 6, 17, 500), "one-based-address"),
                   ((42, 6, 10, 500), "hex-read-as-decimal"), ((42, 17, 16, 500), "another-field"),
                   ((42, 6, 16, 0xF401), "field-low-byte-first")])
def _check_11_1(answer: Any) -> str | None:
    frame = TcpFrame.decode(parse_hex(_11_1_FRAME), role="request")
    expected = (frame.transaction_id, frame.pdu.function_code, frame.pdu.address, frame.pdu.value)
    if not isinstance(answer, (tuple, list)) or len(answer) != 4:
        return "answer with four ints: (transaction_id, function, address, value)."
    if any(isinstance(x, bool) or not isinstance(x, int) for x in answer):
        return "all four should be ints."
    tid, function, address, value = answer
    if tid != expected[0]:
        return (diagnose("mbap-little-endian", tid, expected[0])
                or f"the transaction id is in bytes 0-1; {tid} is not it.")
    if function != expected[1]:
        if function == frame.unit:
            return (diagnose("another-field", function, {"unit identifier": frame.unit})
                    + " The function code is byte 7, right after it.")
        return f"the function code is byte 7, right after the unit identifier; it is not {function}."
    if address != expected[2]:
        return (address_diagnosis(address, expected[2]) or diagnose("hex-read-as-decimal", address,
                                                                    f"{expected[2]:X}")
                or f"the address is the two bytes after the function code; {address} is not it.")
    if value != expected[3]:
        named = field_value_procedure(frame.pdu.value.to_bytes(2, "big"), "value", {
            "unit identifier": frame.unit, "function code": expected[1], "address": expected[2],
            "transaction id": expected[0], "length field": len(frame.pdu.encode()) + 1}, register=True)
        said = f"the value is the last two bytes, read high byte first; {value} is not it."
        named = named.explain([((), value)])
        return named_then(named, said)
    return None


@exercise("11.2", "what a gateway does: RTU in, Modbus/TCP out",
          hint=("a gateway keeps the unit and the PDU, drops the CRC, and puts an MBAP header in front: "
                "transaction id, protocol 0, length = 1 + the PDU's length, unit.",
                "mb.RtuFrame.decode(..., role='request') gives .unit and .pdu; mb.TcpFrame builds the frame "
                "from them and the transaction id.",
                "the RTU request 01 06 00 01 00 03 98 0B, with transaction id 1: 00 01 00 00 00 06 01 06 00 "
                "01 00 03."),
          accepts=["00 07 00 00 00 06 03 03 00 00 00 03", "000700000006030300000003",
                   bytes.fromhex("00 07 00 00 00 06 03 03 00 00 00 03")],
          refuses=[("00 07 00 00 00 08 03 03 00 00 00 03 04 29", "crc-on-tcp"),
                   ("00 07 00 00 00 06 03 03 00 00 00 03 04 29", "crc-on-tcp"),
                   ("07 00 00 00 00 06 03 03 00 00 00 03", "mbap-little-endian"),
                   ("00 07 00 00 00 05 03 03 00 00 00 03", "mbap-length"),
                   ("00 07 00 00 00 06 01 03 00 00 00 03", None)])
def _check_11_2(answer: Any) -> str | None:
    rtu = RtuFrame.decode(parse_hex("03 03 00 00 00 03 04 29"), role="request")
    expected = TcpFrame(transaction_id=7, unit=rtu.unit, pdu=rtu.pdu).encode()
    got = as_bytes(answer)
    named = tcp_frame_diagnosis(got, expected)
    if named:
        return named
    if got.endswith(parse_hex("04 29")):
        return diagnose("crc-on-tcp", expected + b"\x04\x29", expected)
    return compare_bytes(got, expected, "your Modbus/TCP frame")


@exercise("11.3", "a pyserial URL for a serial device server",
          hint="pyserial's URL for a serial line carried over raw TCP is socket://<host>:<port>.",
          accepts=["socket://192.168.1.60:4001", " socket://192.168.1.60:4001 "],
          refuses=[("tcp://192.168.1.60:4001", "url-not-socket"),
                   ("rfc2217://192.168.1.60:4001", "url-not-socket"),
                   ("socket://192.168.1.60:502", "modbus-tcp-port-for-server"), ("/dev/ttyUSB0", None),
                   ("socket://192.168.1.60", "url-without-port"),
                   ("socket://192.168.1.60:99999", "port-out-of-range")])
def _check_11_3(answer: Any) -> str | None:
    if serial is None:
        raise ImportError("exercise 11.3 asks pyserial, which is not installed: pip install pyserial")
    if not isinstance(answer, str):
        return "answer with a string, the URL."
    named = diagnose("url-not-socket", answer)
    if named:
        rfc2217 = answer.strip().startswith("rfc2217://")
        return named + (" rfc2217:// is for device servers in RFC 2217 (telnet) mode." if rfc2217 else "")
    try:
        port = serial.serial_for_url(answer.strip(), do_not_open=True)
    except (ValueError, serial.SerialException) as exc:
        return f"pyserial does not accept {answer!r} as a port or URL ({exc})."
    except Exception:  # pyserial fails in its own ways on some text: the URL is not one it reads
        return f"pyserial does not accept {answer!r} as a port or URL."
    if not isinstance(port, SocketSerial):
        return f"{answer!r} is a local port name; a device on the network needs a URL."
    named = diagnose("url-without-port", answer)
    if named:
        return named
    whole = re.fullmatch(r"socket://[^:/]+:(\d+)/?", answer.strip())
    if not whole:
        return (f"{answer.strip()!r} is not a whole socket URL: pyserial needs socket://<host>:<port>, the "
                "device server's TCP port included.")
    named = diagnose("port-out-of-range", int(whole.group(1)))
    if named:
        return named
    try:
        host, number = port.from_url(answer.strip())
    except Exception:  # pyserial's own refusal of a port outside 0..65535 fails in a format string
        return f"pyserial cannot read host and port from {answer!r}: a TCP port is a number 0..65535."
    expected = SocketSerial().from_url("socket://192.168.1.60:4001")
    if (host, number) != expected:
        return (diagnose("modbus-tcp-port-for-server", number, expected[1])
                or f"that URL reaches {host}, TCP port {number}, not the device server.")
    return None


def _split_mbap(frame: bytes) -> tuple:
    decoded = TcpFrame.decode(frame, "request")
    pdu = decoded.pdu.encode()
    return decoded.transaction_id, 0, len(pdu) + 1, decoded.unit, pdu


def _diagnose_split(got: Any, expected: Any) -> str | None:
    """Name the slip of a function that takes an MBAP header apart: a field read low byte first, a length
    that counts the wrong bytes (or a valid length refused), the unit kept in the PDU."""
    if isinstance(got, Raised):
        if "length" not in got.message.lower():
            return None
        return (name("mbap-length") + " Your function refuses a frame whose length field is right: it equals "
                "len(frame) - 6.")
    if not (isinstance(got, (tuple, list)) and isinstance(expected, tuple)) or len(got) != len(expected):
        return None
    if got[0] != expected[0]:
        return diagnose("mbap-little-endian", got[0], expected[0])
    if got[2] != expected[2]:
        return diagnose("mbap-length", got[2], expected[2])
    if got[3] != expected[3]:
        return diagnose("another-field", got[3], {"function code": expected[4][0]})
    if got[4] != expected[4] and isinstance(got[4], (bytes, bytearray, list)):
        return pdu_envelope_diagnosis(bytes(got[4]), expected[4], expected[3])
    return None


def _mbap_frames(rng) -> tuple:
    pdu = ReadHoldingRegistersRequest(address=rng.randrange(65000), count=rng.randrange(1, 126))
    frame = TcpFrame(transaction_id=rng.randrange(65536), unit=rng.randrange(256), pdu=pdu).encode()
    if rng.random() < 0.2:  # a length field that does not match: not a valid frame
        frame = frame[:4] + (frame[5] + rng.randrange(1, 5)).to_bytes(2, "big") + frame[6:]
    return (frame,)


build_exercise(
    "11.4", "take an MBAP header apart",
    reference=_split_mbap, inputs=_mbap_frames,
    edge_cases=[(bytes.fromhex("01 18 00 00 00 06 01 03 00 00 00 01"),),
                (bytes.fromhex("00 01 00 00 00 06 FF 03 00 6B 00 03"),),
                (bytes.fromhex("00 01 00 00 00 09 01 03 00 00 00 01"),),
                # a protocol id or a length wrong in one byte of two, the shortest frame, one byte short of it
                (bytes.fromhex("01 18 00 01 00 06 01 03 00 00 00 01"),),
                (bytes.fromhex("01 18 01 00 00 06 01 03 00 00 00 01"),),
                (bytes.fromhex("01 18 00 00 01 06 01 03 00 00 00 01"),),
                (bytes.fromhex("00 05 00 00 00 02 01 07"),), (bytes.fromhex("00 05 00 00 00 01 01"),)],
    hint=("the MBAP header is seven bytes: transaction id (2), protocol id (2), length (2), unit (1), each "
          "2-byte field high byte first; the PDU is what follows. The length counts the unit and the PDU: "
          "raise an exception when the frame says otherwise.",
          "int.from_bytes(two_bytes, 'big') reads a 2-byte field; a slice picks bytes out of the frame.",
          "in 00 2A 00 00 00 06 11 06 00 10 01 F4 the transaction id is 0x002A = 42, and the length 6 is "
          "the 12 bytes minus the 6 before the unit."),
    refuses=[(lambda frame: (int.from_bytes(frame[0:2], "little"), 0, int.from_bytes(frame[4:6], "big"),
                             frame[6],
                             frame[7:]), "mbap-little-endian"),
             (lambda frame: (int.from_bytes(frame[0:2], "big"), 0, int.from_bytes(frame[4:6], "big"),
                             frame[6],
                             frame[7:]), "invalid-input-accepted")],
    diagnose=lambda args, expected, got: _diagnose_split(got, expected))
