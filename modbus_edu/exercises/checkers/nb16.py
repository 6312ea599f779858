"""Exercises of notebook 16: The bench day (your first real device).

16.1 and 16.2 are the worksheet: the bench meter's datasheet excerpt
(:data:`modbus_edu.devices.bench.DATASHEET`) becomes a register map file, then the request frames the
poll planner sends for it.  16.3 diagnoses a silent meter on the troubleshooting flowchart.  16.4 is
the build exercise: take an adapter's echo off the bytes read back.
"""

from __future__ import annotations

import random
import re
from typing import Any

from ...devices.bench import bench_map, bench_map_path
from ...framing import RtuFrame
from ...links.echo import strip_echo
from ...pdu import ReadHoldingRegistersRequest, ReadInputRegistersRequest, ReadInputRegistersResponse
from ...registermap import RegisterMapError, load_map
from ..build import build_exercise
from ..core import AnswerError, address_diagnosis, as_bytes, exercise, show
from ..diagnosis.misconceptions import CATALOGUE, ORDER_WORDS, detect, diagnose, name

WORKSHEET_UNIT = 1
"""The bench meter's address in the worksheet (its factory setting)."""


# --- 16.1: the map file -------------------------------------------------------------------------------
_WORKSHEET_MAP = "".join(line + "\n" for line in bench_map_path().read_text(encoding="utf-8").splitlines()
                         if line and not line.startswith("#"))
"""Exercise 16.1's answer: the bench meter's datasheet excerpt as a map file (the library's own, without
its comment lines)."""


def _expected_map() -> list[Any]:
    return sorted(bench_map(), key=lambda p: p.address)


def _map_problem(points: list[Any]) -> str | None:
    """What is wrong with the learner's points (sorted by address) against the bench meter's map."""
    expected = _expected_map()
    if len(points) != len(expected):
        return (f"your file has {len(points)} points; the datasheet lists {len(expected)} values (voltage, "
                "current, active power, frequency, import energy), one row each.")
    for mine, theirs in zip(points, expected):
        label = f"the row for register {30001 + theirs.address}"
        if mine.table != "input":
            return (f"{label} says table {mine.table!r}. " + name("holding-for-input")
                    + " Registers numbered 3xxxx are input registers: the table is 'input'.")
        if mine.address != theirs.address:
            slip = address_diagnosis(mine.address, theirs.address)
            if mine.address == theirs.address + 1:
                slip = ("it is one too high: keep the datasheet's reference number as it is (30001); "
                        "numbering='reference' already subtracts the 30001.")
            return f"{label} loads as address {mine.address}, expected {theirs.address}. " + (slip or "")
        if mine.type != theirs.type:
            named = diagnose("integer-for-float", mine.type) if theirs.type.startswith("float") else None
            return (f"{label} has type {mine.type}: " + (f"{named} " if named else "")
                    + "Each value is a 32-bit IEEE 754 float in two registers, type float32.")
        if mine.order != theirs.order:
            named = name("word-order", used=mine.order, used_words=ORDER_WORDS.get(mine.order, mine.order),
                         right=theirs.order)
            return (f"{label} has word order {mine.order}: {named} The datasheet says 'low word first', so "
                    "the register at the lower address holds the low word: order CDAB.")
        if mine.scale != theirs.scale:
            return (f"{label} has scale {mine.scale:g}: the floats already carry volts, amperes, watts, "
                    "hertz and kWh, so the scale is 1.")
    return None


@exercise("16.1", "the bench meter's datasheet as a register map file",
          hint=("a header row name,table,address,type,order,scale,unit, then one row per value of the "
                "datasheet's table; each name is a Python identifier (letters, digits and _, not starting "
                "with a digit).",
                "numbers 3xxxx are input registers: table input, and the datasheet's number (30001 ...) as "
                "the address; the datasheet says the type (float32), the word order (CDAB) and whether a "
                "value is scaled (scale 1: it is not).",
                "a holding register 40005 with a uint16 voltage in tenths of a volt: "
                "V_L1,holding,40005,uint16,ABCD,0.1,V."),
          accepts=[_WORKSHEET_MAP, _WORKSHEET_MAP.replace(",1,", ",1.0,"),
                   "name,table,address,type,order\n" + "".join(
                       f"{row.split(',')[0]},input,{row.split(',')[2]},float32,CDAB\n"
                       for row in _WORKSHEET_MAP.splitlines()[1:])],
          refuses=[(_WORKSHEET_MAP.replace("CDAB", "ABCD"), "word-order"),
                   (_WORKSHEET_MAP.replace(",input,", ",holding,"), "holding-for-input"),
                   (_WORKSHEET_MAP.replace(",30001,", ",0,").replace(",30007,", ",6,").replace(
                       ",30013,", ",12,").replace(",30071,", ",70,").replace(",30073,", ",72,"), None),
                   ("voltage,input,30001", None),
                   (_WORKSHEET_MAP.replace("float32", "uint32"), "integer-for-float")])
def _check_16_1(answer: Any) -> str | None:
    if not isinstance(answer, str):
        return (f"give the file's text as a str (a header row, then one row per value), not {show(answer)}: "
                'for example """name,table,address,type,order,scale,unit\\n..."""')
    answer = answer if "\n" in answer else answer + "\n"  # always the file's text, never a path to a file
    try:
        points = sorted(load_map(answer, numbering="reference", name="your map"), key=lambda p: p.address)
    except RegisterMapError as exc:
        for numbering, what in (("0-based", "protocol addresses (0, 6, ...)"),
                                ("1-based", "register numbers counted from 1 (1, 7, ...)")):
            try:
                other = sorted(load_map(answer, numbering=numbering, name="your map"),
                               key=lambda p: p.address)
            except RegisterMapError:
                continue
            if not _map_problem(other):
                return (f"your rows hold {what}; the file keeps the datasheet's numbers (30001, 30007, ...) "
                        "and mb.load_map(..., numbering='reference') turns them into addresses, so the file "
                        "and the datasheet can be compared line by line.")
        return f"mb.load_map cannot read it with numbering='reference': {exc}"
    return _map_problem(points)


# --- 16.2: the request frames -------------------------------------------------------------------------
def expected_frames(unit: int = WORKSHEET_UNIT) -> list[bytes]:
    """The RTU requests the poll planner sends to read the bench meter's whole map, in order."""
    return [RtuFrame(unit=unit, pdu=ReadInputRegistersRequest(address=poll.address, count=poll.count))
            .encode() for poll in bench_map().plan()]


def _wrong_frames() -> list[bytes]:
    """One request per value, as a first plan often has: five frames."""
    return [RtuFrame(unit=WORKSHEET_UNIT, pdu=ReadInputRegistersRequest(address=p.address, count=p.count))
            .encode() for p in sorted(bench_map(), key=lambda p: p.address)]


def _frames_with(request: type, shift: int = 0) -> list[bytes]:
    """The planner's requests made with another request class or addresses moved by ``shift``."""
    return [RtuFrame(unit=WORKSHEET_UNIT, pdu=request(address=poll.address + shift, count=poll.count))
            .encode() for poll in bench_map().plan()]


def _frame_slip(got: bytes, expected: bytes) -> str:
    """Name what differs between one learner frame and the expected one (same length)."""
    if got[:-2] == expected[:-2]:
        return (diagnose(("crc-swapped", "checksum-without-address"), got, expected)
                or "its CRC is wrong: compute it over the six bytes before it (mb.crc16), low byte first.")
    if got[0] != expected[0]:
        return f"it is addressed to unit {got[0]}; the meter's Addr is {expected[0]}."
    if got[1] != expected[1]:
        return (diagnose("holding-for-input", got[1], expected[1])
                or f"it uses function {got[1]}; input registers (3xxxx) are read with function 04.")
    address, count = int.from_bytes(got[2:4], "big"), int.from_bytes(got[4:6], "big")
    want_address, want_count = int.from_bytes(expected[2:4], "big"), int.from_bytes(expected[4:6], "big")
    if address != want_address:
        return f"it starts at address {address}, expected {want_address}. " + (
            address_diagnosis(address, want_address) or "")
    named = diagnose("one-register-for-32-bits", count, want_count, want_count // 2)
    return named or f"it asks for {count} registers, expected {want_count}: a float32 takes two registers."


@exercise("16.2", "the request frames that read the bench meter's map",
          hint=("the planner puts neighbouring values of one table in one request (30071 and 30073 follow "
                "each other); each request is unit, 04, start address, count (2 bytes each), then the CRC "
                "low byte first.",
                "a float32 takes two registers; 30001 is address 0. mb.RtuFrame(unit=..., "
                "pdu=mb.ReadInputRegistersRequest(address=..., count=...)).encode() builds one frame.",
                "four registers from address 10 of unit 2: 02 04 00 0A 00 04 D1 F8."),
          accepts=[expected_frames(), [frame.hex(" ").upper() for frame in expected_frames()]],
          refuses=[(_wrong_frames(), None),
                   ([frame[:-2] + frame[:-3:-1] for frame in expected_frames()], "crc-swapped"),
                   (_frames_with(ReadHoldingRegistersRequest), "holding-for-input"),
                   (_frames_with(ReadInputRegistersRequest, shift=1), "one-based-address"),
                   (expected_frames()[:3], None)])
def _check_16_2(answer: Any) -> str | None:
    expected = expected_frames()
    if isinstance(answer, (bytes, bytearray, str)) or not isinstance(answer, (list, tuple)):
        return (f"give a list of frames, one per request, in the order they are sent (each bytes or a hex "
                f"string), not {show(answer)}.")
    try:
        frames = [as_bytes(item) for item in answer]
    except AnswerError as exc:
        return str(exc)
    if frames == expected:
        return None
    if frames == _wrong_frames():
        return ("that is one request per value; frequency (30071-30072) and import energy (30073-30074) "
                "sit side by side, so one request reads both: the planner sends 4 requests.")
    if len(frames) != len(expected):
        given = f"{len(frames)} frame" + ("s" if len(frames) != 1 else "")
        return f"you give {given}; the planner sends {len(expected)} requests for this map."
    for index, (got, want) in enumerate(zip(frames, expected)):
        if got == want:
            continue
        if got in expected:
            return (f"frame {index + 1} is right but out of place: give the frames in the planner's order, "
                    "by address.")
        if len(got) != len(want):
            return f"frame {index + 1}: " + (
                diagnose("crc-forgotten", len(got), len(want))
                or f"it has {len(got)} bytes; an RTU read request has {len(want)}.")
        return f"frame {index + 1}: " + _frame_slip(got, want)
    return None  # pragma: no cover - frames == expected was handled above


# --- 16.3: a silent meter -------------------------------------------------------------------------------
ACCEPTED_AB = ("a/b", "ab", "a b", "b/a", "swap a and b", "swap a/b", "swap the wires", "swap the pair",
               "a and b swapped", "a/b swapped", "swapped a/b", "swapped wires", "polarity", "a/b polarity",
               "wiring polarity", "reverse a and b", "reversed a/b", "d0/d1", "d+/d-")
"""Spellings accepted for 16.3's answer (compared lower-case, spaces squeezed, final full stop dropped)."""

_AB_PATTERN = re.compile(r"\bswap|\bpolarity\b|\ba\s*/\s*b\b|\bb\s*/\s*a\b|\ba and b\b|\brevers"
                         r"|\bd0\s*/\s*d1\b")
"""Free spellings of the same answer: swap ..., polarity, A/B, A and B, reversed ..."""

RULED_OUT_16_3 = ("port", "baud", "parity", "settings", "unit", "address", "timeout")
"""The checks of 16.3's flowchart that the LED, the scan and the menu have already ruled out."""

REFUSED_16_3 = {
    "wiring": "you checked that A, B and the common wire are connected; the question is which way round.",
    "common": "you checked that the common wire is connected; the question is about the other two.",
    "port": "the port is right: the adapter's TX LED flashes at every request, so your script reaches it.",
    "baud": "the scan tried every baud rate the meter offers, and its menu says 9600 like your script.",
    "parity": "the scan tried none, even and odd, and the menu's EvEn matches your script.",
    "settings": "the scan tried every baud rate and parity, and the menu matches your script.",
    "unit": "the scan asked every unit from 1 to 247; a wrong unit would have been found.",
    "address": "the scan asked every unit from 1 to 247; a wrong address would have been found.",
    "termination": ("on a short bench cable termination hardly matters, and a missing terminator garbles "
                    "frames (CRC errors), it does not silence a meter on every setting."),
    "timeout": "a longer timeout would not help: with every setting tried, the meter never answered at all.",
    "echo": "an echo brings your own request back; here nothing comes back at all.",
    "word order": "word order makes values absurd; here no value arrives at all.",
}
"""Known wrong answers to 16.3 and what each gets told."""


def _squeeze(text: str) -> str:
    return re.sub(r"\s+", " ", text.strip().lower()).rstrip(".")


@exercise("16.3", "a silent meter: the next check on the flowchart",
          hint="follow the timeout row of the flowchart: port, wiring, A/B, settings, unit. Which one have "
               "the LED, the scan and the menu not ruled out yet?",
          accepts=["swap A and B", "A/B", "polarity", "the A and B wires are reversed"],
          refuses=[("parity", "check-ruled-out"), ("baud rate", "check-ruled-out"),
                   ("termination", "termination-for-silence"),
                   ("the unit", "check-ruled-out"), ("echo", None)])
def _check_16_3(answer: Any) -> str | None:
    if not isinstance(answer, str):
        return f"name the check in a few words (a str), not {show(answer)}."
    text = _squeeze(answer)
    if text in ACCEPTED_AB or _AB_PATTERN.search(text):
        return None
    for key, message in REFUSED_16_3.items():
        if key in text:  # the misconception's name, then this check's own evidence (short: the hint follows)
            for slip, found in (("check-ruled-out", detect("check-ruled-out", text, RULED_OUT_16_3)),
                                ("termination-for-silence", detect("termination-for-silence", text))):
                if found:
                    return f"{CATALOGUE[slip].label}: {message}"
            return message
    return f"{show(answer)} is not the check the flowchart leads to here."


# --- 16.4: build: strip the echo ------------------------------------------------------------------------
def _echo_case(rng: random.Random) -> tuple[bytes, bytes]:
    unit = rng.randrange(1, 248)
    count = rng.randrange(1, 9)
    request = RtuFrame(unit=unit, pdu=ReadInputRegistersRequest(address=rng.randrange(0, 1000), count=count))
    request_bytes = request.encode()
    answer = RtuFrame(unit=unit, pdu=ReadInputRegistersResponse(
        registers=[rng.randrange(0x10000) for _ in range(count)])).encode()
    shape = rng.random()
    if shape < 0.6:
        received = request_bytes + answer            # echo, then the answer
    elif shape < 0.7:
        received = request_bytes                     # echo only: the answer has not come (yet)
    elif shape < 0.8:
        received = answer                            # no echo at all: the adapter does not echo
    elif shape < 0.9:
        damaged = bytearray(request_bytes)           # the echo came back damaged: the line is bad
        damaged[rng.randrange(len(damaged))] ^= 1 << rng.randrange(8)
        received = bytes(damaged) + answer
    else:
        received = request_bytes[: rng.randrange(len(request_bytes))]   # cut short
    return request_bytes, received


def _echo_anywhere(sent: bytes, received: bytes) -> bytes:
    """A plausible wrong answer: the echo looked for anywhere in the bytes read back, not at their start."""
    if bytes(sent) not in bytes(received):
        raise ValueError("no echo")
    return received[len(sent):]


_REQUEST = bytes.fromhex("01 04 00 00 00 02 71 CB")
_ANSWER = bytes.fromhex("01 04 04 99 9A 43 65 04 2C")
_WRITE = bytes.fromhex("01 06 00 01 00 03 98 0B")
"""Write single register 3 at address 1, to unit 1: its answer is the same eight bytes."""


def _every_echo(sent: bytes, received: bytes) -> bytes:
    """A plausible wrong answer: every copy of the request taken off, the answer that repeats it too."""
    if not bytes(received).startswith(bytes(sent)):
        raise ValueError("no echo")
    return bytes(received).replace(bytes(sent), b"")


build_exercise(
    "16.4", "take an adapter's echo off the bytes read back",
    reference=strip_echo,
    inputs=_echo_case,
    edge_cases=[(_REQUEST, _REQUEST + _ANSWER), (_REQUEST, _REQUEST), (_REQUEST, _ANSWER),
                (_REQUEST, _REQUEST[:5]), (_REQUEST, b""), (_REQUEST, _REQUEST[:-1] + b"\xCA" + _ANSWER),
                # a stray byte before the echo: the echo is there, but it does not come first
                (_REQUEST, b"\x00" + _REQUEST + _ANSWER),
                # a write's answer repeats its request byte for byte: only the echo at the start comes off
                (_WRITE, _WRITE + _WRITE)],
    hint="the first len(sent) bytes must be exactly sent (else raise an error: no echo, or a damaged one); "
         "return what follows them.",
    refuses=[(lambda sent, received: received[len(sent):], "echo-unchecked"),
             (lambda sent, received: received, None), (_echo_anywhere, "echo-unchecked"),
             (_every_echo, None)],
    diagnose=lambda args, expected, got: _echo_accepted(*args, got) or _copies_taken(*args, got))


def _echo_accepted(sent: bytes, received: bytes, got: Any) -> str | None:
    """A missing or damaged echo taken off all the same: an invalid input accepted, the echo unchecked."""
    named = diagnose("echo-unchecked", sent, received, got)
    return f"{CATALOGUE['invalid-input-accepted'].label.capitalize()}, {named}" if named else None


def _copies_taken(sent: bytes, received: bytes, got: Any) -> str | None:
    """Where the answer repeats the request (a write's echo), a function that took every copy off."""
    sent, received = bytes(sent), bytes(received)
    if (isinstance(got, (bytes, bytearray)) and received.count(sent) > 1
            and bytes(got) == received.replace(sent, b"")):
        return ("Your function took off every copy of the request, the answer's too: a write's answer "
                "repeats its request byte for byte, so only the echo at the start comes off.")
    return None
