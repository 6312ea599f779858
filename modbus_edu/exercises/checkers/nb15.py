"""Exercises of notebook 15: Gateways and converters.

15.1 times a transaction on the serial side of a gateway (a variant of the notebook's measurement),
15.2 builds what a gateway does to a frame (RTU over TCP in, Modbus/TCP out), 15.3 predicts what a
client behind the notebook's gateway sees.
"""

from __future__ import annotations

import random
import re
from typing import Any

from ...crc import crc16
from ...framing import RtuFrame, TcpFrame
from ...gateway import GATEWAY_PATH_UNAVAILABLE, GATEWAY_TARGET_FAILED
from ...links.wire import SerialTiming
from ...pdu import (
    ExceptionCode,
    ReadHoldingRegistersRequest,
    ReadInputRegistersRequest,
    WriteMultipleRegistersRequest,
    WriteSingleRegisterRequest,
)
from ..build import build_exercise
from ..core import Raised, exercise, number_answer, real_answer, show, tcp_frame_diagnosis
from ..diagnosis.gateway import GATEWAY, separating_frames
from ..diagnosis.misconceptions import diagnose
from ..diagnosis.timing import TRANSACTION_MS


# --- 15.1: one transaction at 19200 baud 8E1 -------------------------------------------------------------
def _transaction_ms() -> float:
    """FC 3 for two registers (request 8 bytes, response 9) at 19200 baud 8E1, in milliseconds."""
    return SerialTiming(19200, "E", 1).transaction_time(8, 9) * 1000


@exercise("15.1", "one transaction behind a gateway at 19200 baud 8E1",
          hint="request 8 characters + 3.5 of silence + response 9 characters + 3.5 of silence; with even "
               "parity a character is 11 bits (start, 8 data, parity, stop); at 19200 baud. Milliseconds.",
          accepts=[13.75, "13.75", "13.75 ms"],
          refuses=[(24 * 10 / 19200 * 1000, "parity-bit-forgotten"),
                   (17 * 11 / 19200 * 1000, "silences-forgotten"), (0.01375, "seconds-for-milliseconds"),
                   (23 * 11 / 19200 * 1000, None), (15.0, None)])
def _check_15_1(answer: Any) -> str | None:
    if isinstance(answer, str):   # "13.75" or "13.75 ms"
        text = answer.strip().lower().removesuffix("ms").strip()
        try:
            answer = float(text)
        except ValueError:
            return f"give the time as a number of milliseconds, such as 12.5, not {show(answer)}."
    got = real_answer(answer, "a time in milliseconds")
    if isinstance(got, str):
        return got
    expected = _transaction_ms()
    named = (TRANSACTION_MS.explain([((19200, "E", 1, 8, 9), got)])
             or diagnose("parity-bit-forgotten", got, 24 * 10 / 19200 * 1000)
             or diagnose("silences-forgotten", got, 17 * 11 / 19200 * 1000))
    if round(got, 2) == round(23 * 11 / 19200 * 1000, 2):  # 23 characters: which of the candidates, check
        return f"{named + ' ' if named else ''}The response to two registers is 9 bytes: unit, function, " \
            "byte count, 4 data bytes, 2 CRC; the silences are 3.5 characters each."
    if named:
        return named
    return number_answer(answer, expected, decimals=2, unit="ms", what="the time in milliseconds")


# --- 15.2: build: RTU over TCP in, Modbus/TCP out -----------------------------------------------------------
def rtu_to_tcp(frame: bytes, transaction_id: int) -> bytes:
    """What a gateway does to an RTU request before it goes out as Modbus/TCP (the reference of 15.2).

    The CRC is checked and dropped, the unit and the PDU are kept, and the MBAP header goes in front:
    the transaction id, protocol id 0, and the length of what follows it (unit + PDU)."""

    decoded = RtuFrame.decode(frame, role="request")
    return TcpFrame(transaction_id=transaction_id, unit=decoded.unit, pdu=decoded.pdu).encode()


def _rtu_request(rng: random.Random) -> tuple[bytes, int]:

    address = rng.randrange(0, 60000)
    kind = rng.randrange(4)
    if kind == 0:
        pdu = ReadHoldingRegistersRequest(address=address, count=rng.randrange(1, 126))
    elif kind == 1:
        pdu = ReadInputRegistersRequest(address=address, count=rng.randrange(1, 126))
    elif kind == 2:
        pdu = WriteSingleRegisterRequest(address=address, value=rng.randrange(0x10000))
    else:
        values = [rng.randrange(0x10000) for _ in range(rng.randrange(1, 20))]
        pdu = WriteMultipleRegistersRequest(address=address, values=values)
    frame = RtuFrame(unit=rng.randrange(1, 248), pdu=pdu).encode()
    if rng.random() < 0.2:   # damaged on the way: the gateway must not forward it
        index = rng.randrange(len(frame))
        frame = frame[:index] + bytes([frame[index] ^ (1 << rng.randrange(8))]) + frame[index + 1:]
    return frame, rng.randrange(0x10000)


def _diagnose_15_2(args: Any, expected: Any, got: Any) -> str | None:
    if isinstance(got, Raised):
        return _crc_read_big_endian(args[0], got)
    return tcp_frame_diagnosis(got, expected) if isinstance(expected, bytes) else None


def _crc_read_big_endian(frame: bytes, raised: Raised) -> str | None:
    """A gateway that refuses a frame whose CRC is right: what the frame carries, and what its CRC is (which
    CRC slip makes the learner's check refuse it is the procedure's to say, :data:`GATEWAY`, from every
    frame the function refused or forwarded)."""
    carried = frame[-2:].hex(" ").upper()
    if crc16(frame[:-2]) != int.from_bytes(frame[-2:], "little"):
        return None
    about = "; your error speaks of it" if re.search(r"crc|checksum", f"{raised.name} {raised.message}",
                                                     re.IGNORECASE) else ""
    return (f"your function refuses a frame whose CRC is right: it carries {carried}, the CRC "
            f"0x{crc16(frame[:-2]):04X} sent low byte first{about}.")


def _crc_kept(frame: bytes, tid: int) -> bytes:
    """A plausible wrong gateway: the RTU frame behind an MBAP header, CRC and all."""
    return tid.to_bytes(2, "big") + b"\x00\x00" + len(frame).to_bytes(2, "big") + frame


def _tid_little_endian(frame: bytes, tid: int) -> bytes:
    """A plausible wrong gateway: the transaction id written low byte first."""
    return tid.to_bytes(2, "little") + rtu_to_tcp(frame, tid)[2:]


def _length_without_unit(frame: bytes, tid: int) -> bytes:
    """A plausible wrong gateway: a length that counts the PDU alone."""
    right = rtu_to_tcp(frame, tid)
    return right[:4] + (len(right) - 7).to_bytes(2, "big") + right[6:]


_EXAMPLE = bytes.fromhex("01 03 00 00 00 02 C4 0B")

build_exercise(
    "15.2", "RTU over TCP in, Modbus/TCP out: what a gateway does to a frame",
    reference=rtu_to_tcp,
    inputs=_rtu_request,
    edge_cases=[(_EXAMPLE, 1), (_EXAMPLE, 0x1234), (_EXAMPLE, 0), (_EXAMPLE[:-1] + b"\x0A", 1),
                (bytes.fromhex("11 06 00 01 00 03 9A 9B"), 0xFFFF),
                # the shortest request (unit, function 7, CRC), and a unit and its CRC with no function
                (bytes.fromhex("01 07 41 E2"), 7), (bytes.fromhex("01 7E 80"), 7),
                # frames that only a wrong CRC check forwards: one for each slip of the CRC's procedure
                *((frame, 5) for frame in separating_frames(_EXAMPLE[:-2]))],
    diagnose=_diagnose_15_2,
    hint="check the CRC over all bytes but the last two (raise if it is wrong), then build transaction id "
         "(2 bytes), 00 00, length = 1 + len(PDU) (2 bytes), the unit, the PDU: all big-endian.",
    refuses=[(_crc_kept, "crc-on-tcp"), (_tid_little_endian, "mbap-little-endian"),
             (_length_without_unit, "mbap-length")],
    procedure=GATEWAY)


# --- 15.3: what the client sees ----------------------------------------------------------------------
TIMEOUT_WORDS = ("timeout", "time-out", "time out", "timed out", "a timeout", "no answer", "nothing")
"""Spellings of "the client times out" accepted in 15.3 (lower case)."""

_CASE_NOTES = {
    "a": {GATEWAY_TARGET_FAILED: "case a: 248 is a reserved address on a serial line, so this gateway does "
                                 "not even ask the bus: no path, 0A.",
          "timeout": "case a: this gateway answers a unit it cannot reach at once, with an exception."},
    "b": {GATEWAY_PATH_UNAVAILABLE: "case b: the path is there (the bus and its port work); the meter just "
                                    "does not answer: 0B.",
          "timeout": "case b: the client waits 5 s, longer than the gateway's 0.2 s: the gateway's 0B "
                     "arrives first."},
    "c": {GATEWAY_TARGET_FAILED: "case c: a function the meter does not implement (0x41 is a user-defined "
                                 "code) gets an answer: exception 01, illegal function, passed on unchanged.",
          GATEWAY_PATH_UNAVAILABLE: "case c: the meter is there and answers; a function it does not "
                                    "implement is exception 01.",
          "timeout": "case c: a function the meter does not implement is answered at once, with exception "
                     "01."},
    "d": {GATEWAY_TARGET_FAILED: "case d: the gateway answers 0B after 0.2 s of waiting, but this client "
                                 "gave up after 0.1 s: it sees a timeout.",
          GATEWAY_PATH_UNAVAILABLE: "case d: the client gives up before any answer comes."},
}


def expected_15_3() -> dict[str, int | str]:
    """What a client behind notebook 15's gateway sees in each case of 15.3."""
    return {"a": GATEWAY_PATH_UNAVAILABLE, "b": GATEWAY_TARGET_FAILED,
            "c": int(ExceptionCode.ILLEGAL_FUNCTION), "d": "timeout"}


def _read_outcome(value: Any) -> int | str | None:
    """An exception code (int) or "timeout" from the learner's spelling, or None if unreadable."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int):
        return value
    if isinstance(value, str):
        text = value.strip().lower().rstrip(".")
        if text in TIMEOUT_WORDS:
            return "timeout"
        for prefix in ("exception ", "code "):
            if text.startswith(prefix):
                text = text[len(prefix):]
        try:
            return int(text, 16)
        except ValueError:
            return None
    return None


@exercise("15.3", "what a client behind the gateway sees",
          hint="0B: the gateway asked the bus and nobody answered in its timeout; 0A: no path at all (this "
               "gateway: unit 0 and the reserved units); an exception passes through unchanged; a client "
               "that gives up first sees a timeout.",
          accepts=[{"a": 0x0A, "b": 0x0B, "c": 0x01, "d": "timeout"},
                   {"A": "0A", "b": "exception 0B", "c": "01", "d": "no answer"}],
          refuses=[({"a": 0x0B, "b": 0x0B, "c": 0x01, "d": 0x0B}, "gateway-codes-swapped"),
                   ({"a": 0x0A, "b": "timeout", "c": 0x01, "d": "timeout"}, "gateway-silence"),
                   ({"a": 0x0A, "b": 0x0B, "c": 0x0B, "d": "timeout"}, None), ("0B", None)])
def _check_15_3(answer: Any) -> str | None:
    expected = expected_15_3()
    if not isinstance(answer, dict):
        return (f"give a dict with one entry per case, {{'a': ..., 'b': ..., 'c': ..., 'd': ...}}, not "
                f"{show(answer)}.")
    keys = {str(key).strip().lower(): value for key, value in answer.items()}
    missing = sorted(set(expected) - set(keys))
    if missing:
        return f"give an answer for every case: {', '.join(missing)} missing."
    for case, want in expected.items():
        got = _read_outcome(keys[case])
        if got is None:
            return (f"case {case}: {show(keys[case])} is neither an exception code (0x0B, '0B') nor "
                    "'timeout'.")
        if got == want:
            continue
        note = _CASE_NOTES.get(case, {}).get(got)
        named = diagnose(("gateway-codes-swapped", "gateway-silence"), got, want)
        if named:
            return f"{named} {note}" if note else f"case {case}: {named}"
        if note:
            return note
        return f"case {case}: {show(keys[case])} is not what the client sees."
    return None
