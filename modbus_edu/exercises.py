"""Checkers for the course's exercises.

Each exercise in a notebook ends with a cell like::

    answer = ...          # replace ... with your answer
    check("03.1", answer)

Run unanswered, ``check`` prints a hint and raises nothing, so the notebook still runs from top to
bottom.  With an answer it says whether it is right and, if not, why.  The expected values are computed
here with the library itself, never typed in.  Worked solutions live in ``notebooks/solutions/`` and
load into a cell with ``%load solutions/03_1.py``.

Adding an exercise: write a function that takes the learner's answer and returns ``None`` when it is
right or a sentence saying what is wrong, and register it with :func:`exercise`, giving the hint and
one wrong answer (the test suite checks that the solution passes and the wrong answer fails).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from .errors import ModbusError

PLACEHOLDER = ...
"""What an unanswered exercise cell holds: the Ellipsis, ``...``."""


@dataclass(frozen=True)
class Exercise:
    """One exercise: its key (``"NN.k"``: notebook and number), a hint, a checker and a wrong answer."""

    key: str
    title: str
    hint: str
    checker: Callable[[Any], str | None]
    wrong: Any


@dataclass(frozen=True)
class Result:
    """What :func:`check` found.  ``ok`` is None while the exercise is unanswered."""

    key: str
    ok: bool | None
    message: str

    def __str__(self) -> str:
        return self.message

    def __bool__(self) -> bool:
        return bool(self.ok)

    def _ipython_display_(self) -> None:
        """As the last line of a notebook cell: nothing more to show, check() has printed the verdict."""


EXERCISES: dict[str, Exercise] = {}


def exercise(key: str, title: str, *, hint: str, wrong: Any) -> Callable:
    """Register a checker under ``key`` (decorator)."""

    def register(checker: Callable[[Any], str | None]) -> Callable[[Any], str | None]:
        if key in EXERCISES:
            raise ValueError(f"exercise {key} is registered twice")
        EXERCISES[key] = Exercise(key, title, hint, checker, wrong)
        return checker

    return register


def evaluate(key: str, answer: Any) -> Result:
    """Check ``answer`` against exercise ``key`` without printing anything."""
    if key not in EXERCISES:
        known = ", ".join(sorted(EXERCISES))
        return Result(key, False, f"There is no exercise {key!r}; the exercises are {known}.")
    item = EXERCISES[key]
    if answer is PLACEHOLDER:
        return Result(key, None, f"Exercise {key} ({item.title}) is not answered yet. Hint: {item.hint}")
    try:
        problem = item.checker(answer)
    except ModbusError as exc:
        problem = f"the library could not use your answer: {exc}"
    except (TypeError, ValueError, KeyError, IndexError, AttributeError) as exc:
        problem = f"your answer has the wrong shape ({type(exc).__name__}: {exc})"
    if problem is None:
        return Result(key, True, f"Right! Exercise {key} ({item.title}) is solved.")
    return Result(key, False, f"Not yet: {problem} Hint: {item.hint}")


def check(key: str, answer: Any) -> Result:
    """Check an answer, print the verdict, and return it (falsy unless right)."""
    result = evaluate(key, answer)
    print(result.message)
    return result


# --- helpers for checkers ---------------------------------------------------------------------------

def as_bytes(answer: Any) -> bytes:
    """Accept bytes, a bytearray, a list of ints or a hex string ("01 03 00 ...") as a byte answer."""
    if isinstance(answer, (bytes, bytearray)):
        return bytes(answer)
    if isinstance(answer, str):
        from .framing import parse_hex

        return parse_hex(answer)
    return bytes(answer)


def compare_bytes(answer: Any, expected: bytes, what: str) -> str | None:
    """None if ``answer`` is exactly ``expected``; otherwise which byte differs first."""
    got = as_bytes(answer)
    if got == expected:
        return None
    for index, (mine, theirs) in enumerate(zip(got, expected)):
        if mine != theirs:
            return (f"{what} differs at byte {index}: you have 0x{mine:02X}, it should be 0x{theirs:02X} "
                    f"({len(got)} bytes given, {len(expected)} expected).")
    return f"{what} has {len(got)} bytes, it should have {len(expected)}."


# --- notebook 00: Welcome ---------------------------------------------------------------------------

def _int_answer(answer: Any, what: str) -> int | str:
    """The answer as an int, or a sentence saying why it is not one."""
    if isinstance(answer, bool) or not isinstance(answer, int):
        return (f"{what} is a whole number (an int such as 5 or 0x05), "
                f"you gave {type(answer).__name__} {answer!r}.")
    return answer


@exercise("00.1", "the slave address of a frame",
          hint="the first byte of an RTU frame is the slave address; the bytes are written in hexadecimal.",
          wrong=11)
def _check_00_1(answer: Any) -> str | None:
    from .framing import RtuFrame, parse_hex

    text = "11 03 00 6B 00 03 76 87"
    expected = RtuFrame.decode(parse_hex(text)).unit
    got = _int_answer(answer, "a slave address")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    first = text.split()[0]
    if got == int(first):
        return (f"{got} reads the hex digits '{first}' as a decimal number; the byte is 0x{first}, "
                f"which is {expected} in decimal (int('{first}', 16)).")
    return f"the first byte is 0x{first}; {got} is 0x{got:02X}."


@exercise("00.2", "the PDU inside a Modbus/TCP frame",
          hint="a Modbus/TCP frame is a 7-byte MBAP header (transaction, protocol, length, unit) followed by "
               "the PDU; the PDU starts with the function code.",
          wrong="01 03 00 00 00 01")
def _check_00_2(answer: Any) -> str | None:
    from .framing import TcpFrame, parse_hex

    frame = parse_hex("01 18 00 00 00 06 01 03 00 00 00 01")
    expected = TcpFrame.decode(frame).pdu.encode()
    got = as_bytes(answer)
    if got == frame[6:]:
        return "you included the unit identifier (byte 6): it belongs to the MBAP header, not to the PDU."
    return compare_bytes(got, expected, "the PDU")


@exercise("00.3", "build your first RTU frame",
          hint="RtuFrame(unit=..., pdu=mb.ReadHoldingRegistersRequest(address=..., count=...)).encode()",
          wrong="02 03 00 00 00 02 38 C4")
def _check_00_3(answer: Any) -> str | None:
    from .framing import RtuFrame
    from .pdu import ReadHoldingRegistersRequest

    expected = RtuFrame(unit=2, pdu=ReadHoldingRegistersRequest(address=0, count=2)).encode()
    got = as_bytes(answer)
    if len(got) == len(expected) and got[:-2] == expected[:-2] and got[-2:] == expected[-2:][::-1]:
        return "the CRC bytes are in the wrong order: the low byte goes first."
    return compare_bytes(got, expected, "your frame")


# --- notebook 01: The data model --------------------------------------------------------------------

@exercise("01.1", "the address behind a reference number",
          hint="a reference number is the table prefix (4 = holding registers) followed by address + 1.",
          wrong=108)
def _check_01_1(answer: Any) -> str | None:
    from .datamodel import parse_reference

    ref = "40108"
    expected = parse_reference(ref).address
    got = _int_answer(answer, "an address")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == expected + 1:
        return f"{got} is the element number; the address in the frame is the number minus one."
    if got == int(ref):
        return ("the prefix 4 (holding registers) never travels in the frame: "
                "the function code says which table.")
    return f"{got} is not the address of holding register {ref}."


@exercise("01.2", "the reference number of an address",
          hint="input registers have the prefix 3; the number after the prefix is address + 1, written with "
               "four digits.",
          wrong="30009")
def _check_01_2(answer: Any) -> str | None:
    from .datamodel import format_reference

    expected = format_reference("input_registers", 9)
    got = str(answer).strip()
    if got == expected:
        return None
    if got == format_reference("input_registers", 8):
        return "numbers start at 1: address 0 is 30001, so address 9 is one more than you wrote."
    if got[:1] != expected[:1]:
        return f"input registers use the prefix {expected[0]} (3x), your answer starts with {got[:1]!r}."
    return f"{got!r} is not the 5-digit reference number of input register address 9."


@exercise("01.3", "which table a function code reaches",
          hint="answer a pair (table name, may a master write it?), e.g. ('coils', True); "
               "modbus_edu.datamodel.table_kind(code) names the table.",
          wrong=("holding_registers", True))
def _check_01_3(answer: Any) -> str | None:
    from .datamodel import DataBank, table_kind

    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair: (table name, True or False)."
    kind, writable = answer
    expected_kind = table_kind(4)
    try:
        got_kind = table_kind(str(kind))
    except ModbusError:
        return f"{kind!r} is not a table name; the tables are coils, discrete_inputs, input_registers, " \
               f"holding_registers."
    if got_kind != expected_kind:
        return f"function code 4 does not reach the {got_kind.replace('_', ' ')}."
    expected_writable = DataBank(sparse=True).table(expected_kind).writable
    if bool(writable) != expected_writable or not isinstance(writable, bool):
        return f"the table is right, but may a master write the {expected_kind.replace('_', ' ')}? " \
               f"Answer True or False."
    return None


@exercise("01.4", "counting the registers of a sparse bank",
          hint="holding registers 150 to 175 means numbers 150, 151, ..., 175: count both ends. "
               "Or declare them in DataBank(sparse=True) and ask len(bank.holding_registers).",
          wrong=50)
def _check_01_4(answer: Any) -> str | None:
    from .datamodel import DataBank

    bank = DataBank(sparse=True)
    for first, last in ((150, 175), (200, 225)):
        bank.holding_registers.declare(first - 1, last - first + 1)
    expected = len(bank.holding_registers)
    got = _int_answer(answer, "a count")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == expected - 2:
        return "you subtracted first from last in each range; a range from 150 to 175 includes both ends."
    return f"{got} registers is not right."
