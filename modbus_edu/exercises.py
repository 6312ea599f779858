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


def compare_rtu_frame(answer: Any, expected: bytes, what: str, swapped: str) -> str | None:
    """Like :func:`compare_bytes` for an RTU frame, with the message ``swapped`` for the classic slip:
    the right frame with its two CRC bytes the wrong way round."""
    got = as_bytes(answer)
    if len(got) == len(expected) > 2 and got == expected[:-2] + expected[-2:][::-1] and got != expected:
        return swapped
    return compare_bytes(got, expected, what)


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
          hint="mb.RtuFrame(unit=..., pdu=mb.ReadHoldingRegistersRequest(address=..., count=...)).encode()",
          wrong="02 03 00 00 00 02 38 C4")
def _check_00_3(answer: Any) -> str | None:
    from .framing import RtuFrame
    from .pdu import ReadHoldingRegistersRequest

    expected = RtuFrame(unit=2, pdu=ReadHoldingRegistersRequest(address=0, count=2)).encode()
    return compare_rtu_frame(answer, expected, "your frame", "the CRC bytes are in the wrong order: "
                             "the low byte goes first.")


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
               "mb.table_kind(code) names the table.",
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


# --- notebooks 07-13: shared helpers ------------------------------------------------------------------

def _real_answer(answer: Any, what: str) -> float | str:
    """The answer as a float, or a sentence saying why it is not a number."""
    if isinstance(answer, bool) or not isinstance(answer, (int, float)):
        return f"{what} is a number (such as 0.0125), you gave {type(answer).__name__} {answer!r}."
    return float(answer)


def _close(got: float, expected: float, rel: float = 1e-3) -> bool:
    return abs(got - expected) <= rel * abs(expected)


# --- notebook 08: Serial timing -----------------------------------------------------------------------

@exercise("08.1", "the silence that ends a frame at 4800 baud 8E1",
          hint="t3.5 is 3.5 character times; with even parity a character is 11 bits (start, 8 data, "
               "parity, stop). mb.SerialTiming(baudrate=..., parity=...).t35 gives it in seconds.",
          wrong=3.5 * 10 / 4800)
def _check_08_1(answer: Any) -> str | None:
    from .links.wire import SerialTiming

    timing = SerialTiming(baudrate=4800, parity="E", stopbits=1)
    expected = timing.t35
    got = _real_answer(answer, "a silence in seconds")
    if isinstance(got, str):
        return got
    if _close(got, expected):
        return None
    if _close(got, expected * 1000):
        return "that looks like milliseconds; give the time in seconds."
    if _close(got, 3.5 * SerialTiming(baudrate=4800).char_time):
        return "you counted 10 bits per character; even parity adds a bit: 11."
    if _close(got, timing.char_time):
        return "that is one character time; the silence that ends a frame is 3.5 of them."
    return f"{got!r} s is not 3.5 character times of an 8E1 character at 4800 baud."


@exercise("08.2", "transactions per second reading 10 registers at 19200 baud",
          hint="request 8 bytes, response 5 + 2 x 10 bytes, plus two silences of 3.5 characters; "
               "1 / mb.SerialTiming(19200).transaction_time(request_bytes, response_bytes).",
          wrong=19200 / 10 / (8 + 25))
def _check_08_2(answer: Any) -> str | None:
    from .links.wire import SerialTiming

    timing = SerialTiming(baudrate=19200)
    expected = 1 / timing.transaction_time(8, 5 + 2 * 10)
    got = _real_answer(answer, "a number of transactions per second")
    if isinstance(got, str):
        return got
    if _close(got, expected, rel=2e-3):
        return None
    if _close(got, 1 / timing.frame_time(8 + 25)):
        return "you left out the two silences of 3.5 characters (after the request and after the response)."
    if _close(got, 1 / timing.transaction_time(8, 7)):
        return "that is for one register; the response to a read of 10 registers has 5 + 2 x 10 bytes."
    if _close(got, 1 / expected):
        return "that is the time of one transaction in seconds; the question asks how many fit in a second."
    return f"{got:.2f} transactions per second is not right."


@exercise("08.3", "which pauses inside a frame leave it unanswered",
          hint="a pause of more than 1.5 character times breaks an RTU frame, and one of 3.5 or more cuts "
               "it in two; either way the slave gets no valid request.",
          wrong=[5.0])
def _check_08_3(answer: Any) -> str | None:
    from .errors import ModbusError as _Error
    from .links.loopback import loopback_serial
    from .master import Master
    from .slave import Slave

    pauses = [1.0, 1.4, 2.0, 3.0, 5.0]
    expected = []
    for chars in pauses:
        link = loopback_serial(Slave(unit=1), baudrate=9600)
        link.faults.insert_gap(at_byte=4, chars=chars, target="request")
        try:
            Master(link, timeout=0.1).read_holding_registers(unit=1, address=0, count=1)
        except _Error:
            expected.append(chars)
    if not isinstance(answer, (list, tuple, set)):
        return "give a list of pauses, e.g. [1.0, 2.0]."
    try:
        got = sorted(float(x) for x in answer)
    except (TypeError, ValueError):
        return "the list should hold numbers of character times taken from [1.0, 1.4, 2.0, 3.0, 5.0]."
    if got == expected:
        return None
    missing = [p for p in expected if p not in got]
    extra = [p for p in got if p not in expected]
    if extra:
        return (f"a pause of {extra[0]:g} characters is not more than 1.5: the frame stays whole and is "
                "answered.")
    return (f"a pause of {missing[0]:g} characters also leaves the request unanswered "
            "(more than 1.5 breaks the frame).")


# --- notebook 02: Function codes and the PDU ---------------------------------------------------------

@exercise("02.1", "build a Write Multiple Registers PDU",
          hint="function 16 (0x10): address (2 bytes), quantity (2 bytes), byte count (1 byte), then the "
               "values, each high byte first; mb.WriteMultipleRegistersRequest(address=..., values=[...]).",
          wrong="10 00 01 00 02 00 0A 01 02")
def _check_02_1(answer: Any) -> str | None:
    from .pdu import WriteMultipleRegistersRequest

    expected = WriteMultipleRegistersRequest(address=1, values=(10, 258)).encode()
    got = as_bytes(answer)
    if len(got) == len(expected) - 1 and got[:5] == expected[:5] and got[5:] == expected[6:]:
        return ("the byte count (one byte, the number of data bytes that follow) is missing after "
                "the quantity.")
    if got == expected[1:]:
        return "the PDU starts with the function code."
    return compare_bytes(got, expected, "your PDU")


@exercise("02.2", "how many requests to read 300 registers",
          hint="one Read Holding Registers request reads at most mb.MAX_READ_REGISTERS registers.",
          wrong=2)
def _check_02_2(answer: Any) -> str | None:
    from .pdu import MAX_READ_REGISTERS

    expected = -(-300 // MAX_READ_REGISTERS)
    got = _int_answer(answer, "a number of requests")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got < expected:
        return f"{got} requests can read at most {got * MAX_READ_REGISTERS} registers."
    return f"{got} requests work, but fewer are enough."


@exercise("02.3", "the exception response for a missing address",
          hint="an exception response is two bytes: the function code with its top bit set (+ 0x80), "
               "then the exception code; mb.ExceptionCode lists the codes.",
          wrong="03 02")
def _check_02_3(answer: Any) -> str | None:
    from .pdu import ExceptionCode, ExceptionResponse

    expected = ExceptionResponse(function=3, code=ExceptionCode.ILLEGAL_DATA_ADDRESS).encode()
    got = as_bytes(answer)
    if len(got) == 2 and got[0] == expected[0] & 0x7F:
        return ("the first byte must have its top bit set (function code + 0x80): that is what marks "
                "an exception.")
    if len(got) == 2 and got[0] == expected[0] and got[1] != expected[1]:
        return f"the function byte is right; exception code {got[1]:02X} is not 'illegal data address'."
    return compare_bytes(got, expected, "your exception response")


@exercise("02.4", "which coils are ON",
          hint="in a read-bits response the first coil is the least significant bit (the rightmost) of "
               "the first data byte; 0x05 = 0000 0101 in binary.",
          wrong=[5, 7])
def _check_02_4(answer: Any) -> str | None:
    from .pdu import ReadCoilsResponse

    bits = ReadCoilsResponse.decode(bytes([0x01, 0x01, 0x05])).bits
    expected = [address for address, bit in enumerate(bits) if bit]
    try:
        got = sorted(int(a) for a in answer)
    except TypeError:
        return "answer with a list of coil addresses, e.g. [1, 4]."
    if got == expected:
        return None
    if got == sorted(7 - a for a in expected):
        return "you read the bits from the left; the first coil is the rightmost (least significant) bit."
    return f"{got} are not the coils that are ON."


# --- notebook 07: Exceptions and errors ---------------------------------------------------------------

@exercise("07.1", "read an exception response",
          hint="in a response, a function code of 0x80 or more is an exception: subtract 0x80 to get the "
               "request's function; the next byte is the exception code. mb.RtuFrame.decode(..., "
               "role='response').pdu reads it for you.",
          wrong=(0x83, 2))
def _check_07_1(answer: Any) -> str | None:
    from .framing import RtuFrame, parse_hex

    pdu = RtuFrame.decode(parse_hex("11 83 02 C1 34"), role="response").pdu
    expected = (pdu.function, pdu.code)
    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair of ints: (function, code)."
    function, code = answer
    if isinstance(function, bool) or not isinstance(function, int) or not isinstance(code, int):
        return "both numbers should be ints, e.g. (1, 3)."
    if function == pdu.function_code:
        return (f"0x{function:02X} is the function code *of the response*, with the exception bit set; "
                "the request's function is that minus 0x80.")
    if function != expected[0]:
        return f"the request's function is not {function}."
    if code != expected[1]:
        return f"the exception code is the byte after the function code, not {code}."
    return None


@exercise("07.2", "build an exception response",
          hint="unit 17, function code 1 + 0x80, exception code 02 (illegal data address): "
               "mb.RtuFrame(unit=17, pdu=mb.ExceptionResponse(function=..., code=...)).encode()",
          wrong="11 01 02 C1 34")
def _check_07_2(answer: Any) -> str | None:
    from .framing import RtuFrame
    from .pdu import ExceptionCode, ExceptionResponse

    code = int(ExceptionCode.ILLEGAL_DATA_ADDRESS)
    expected = RtuFrame(unit=17, pdu=ExceptionResponse(function=1, code=code)).encode()
    got = as_bytes(answer)
    if got[:1] == b"\x17":
        return "17 is decimal: the slave address byte is 17 = 0x11, not 0x17."
    if len(got) > 1 and got[1] == 0x01:
        return "an exception response sets the top bit of the function code: 0x01 becomes 0x81."
    if len(got) > 2 and got[1] == 0x81 and got[2] != expected[2]:
        return f"exception code {got[2]:02X} is not the one for an address the slave does not have."
    return compare_bytes(got, expected, "your exception response")


_OUTCOMES = ("valid", "exception", "timeout", "checksum error", "mismatch")
_SITUATIONS = (
    "request for a unit nobody has",
    "one bit flipped in the request",
    "one bit flipped in the response",
    "read of an address the slave does not have",
    "response carries another unit id",
)


def _outcome_of(situation: str) -> str:
    """Run one situation of exercise 07.3 on a loopback wire and name what the master saw."""
    from .datamodel import DataBank
    from .errors import ChecksumError, ModbusExceptionError, ModbusTimeoutError, TransactionMismatchError
    from .links.loopback import loopback_serial
    from .master import Master
    from .slave import Slave

    bank = DataBank(sparse=True)
    bank.holding_registers.declare(0, 10)
    link = loopback_serial(Slave(unit=1, bank=bank), seed=0)
    master = Master(link, timeout=0.1)
    unit, address = 1, 0
    if situation == _SITUATIONS[0]:
        unit = 5
    elif situation == _SITUATIONS[1]:
        link.faults.flip_bits(1, target="request")
    elif situation == _SITUATIONS[2]:
        link.faults.flip_bits(1, target="response")
    elif situation == _SITUATIONS[3]:
        address = 100
    else:
        link.faults.answer_as(1, 2)
    try:
        master.read_holding_registers(unit=unit, address=address, count=1)
    except ModbusExceptionError:
        return "exception"
    except ChecksumError:
        return "checksum error"
    except TransactionMismatchError:
        return "mismatch"
    except ModbusTimeoutError:
        return "timeout"
    return "valid"


@exercise("07.3", "what the master sees",
          hint="silence (no answer) is a timeout; a damaged answer is a checksum error; a refusal is an "
               "exception; an answer from the wrong unit is a mismatch. Try each on mb.loopback_serial "
               "with link.faults.",
          wrong=dict.fromkeys(_SITUATIONS, "checksum error"))
def _check_07_3(answer: Any) -> str | None:
    if not isinstance(answer, dict):
        return "answer with a dict {situation: outcome}, using the five situations of the exercise."
    missing = [s for s in _SITUATIONS if s not in answer]
    if missing:
        return f"the dict has no entry for {missing[0]!r}."
    for situation in _SITUATIONS:
        got = str(answer[situation]).strip().lower()
        if got not in _OUTCOMES:
            return f"{answer[situation]!r} is not one of {', '.join(_OUTCOMES)}."
        expected = _outcome_of(situation)
        if got != expected:
            if expected == "timeout" and got == "checksum error":
                return (f"{situation}: the slave cannot trust a damaged request or ignores one for another "
                        "unit; it stays silent, so the master sees no frame to check.")
            return f"{situation}: the master does not see {got!r}."
    return None


# --- notebook 03: RTU frames and the CRC ------------------------------------------------------------

@exercise("03.1", "a CRC in wire order",
          hint="mb.crc16(data) gives the register value; on the wire its low byte goes first "
               "(mb.crc_bytes(data) gives both bytes in wire order).",
          wrong="87 76")
def _check_03_1(answer: Any) -> str | None:
    from .crc import crc_bytes
    from .framing import parse_hex

    expected = crc_bytes(parse_hex("11 03 00 6B 00 03"))
    if isinstance(answer, int) and not isinstance(answer, bool):
        return (f"0x{answer:04X} is a number; give the two bytes in the order they are sent, "
                f"e.g. \"12 34\" or bytes([0x12, 0x34]).")
    got = as_bytes(answer)
    if got == expected[::-1]:
        return "these are the right bytes in the wrong order: the low byte of the CRC goes first."
    return compare_bytes(got, expected, "your CRC")


@exercise("03.2", "build an RTU frame",
          hint="mb.RtuFrame(unit=..., pdu=mb.WriteSingleRegisterRequest(address=..., value=...)).encode(); "
               "the address goes in the frame as it is: 2 is sent as 00 02.",
          wrong="01 06 00 02 12 34 7D 25")
def _check_03_2(answer: Any) -> str | None:
    from .framing import RtuFrame
    from .pdu import WriteSingleRegisterRequest

    expected = RtuFrame(unit=1, pdu=WriteSingleRegisterRequest(address=2, value=0x1234)).encode()
    return compare_rtu_frame(answer, expected, "your frame", "the CRC bytes are in the wrong order: "
                             "the low byte goes first.")


@exercise("03.3", "will the slave answer?",
          hint="a slave answers only a frame whose CRC is right; check it with mb.RtuFrame.decode or "
               "mb.explain. Answer True or False.",
          wrong=True)
def _check_03_3(answer: Any) -> str | None:
    from .framing import RtuFrame, parse_hex

    try:
        RtuFrame.decode(parse_hex("11 03 00 6B 00 03 76 86"))
        expected = True
    except ModbusError:
        expected = False
    if not isinstance(answer, bool):
        return "answer True or False."
    if answer == expected:
        return None
    return ("look at the CRC: the frame carries 0x8676, but the CRC of its first six bytes is different. "
            "A slave cannot trust a frame with a wrong CRC, not even its address, so it stays silent.")


@exercise("03.4", "the length of an FC3 response",
          hint="an RTU response to read holding registers: address (1) + function (1) + byte count (1) "
               "+ 2 bytes per register + CRC (2).",
          wrong=23)
def _check_03_4(answer: Any) -> str | None:
    from .framing import RtuFrame
    from .pdu import ReadHoldingRegistersResponse

    expected = len(RtuFrame(unit=1, pdu=ReadHoldingRegistersResponse(registers=[0] * 10)).encode())
    got = _int_answer(answer, "a number of bytes")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == expected - 2:
        return "you forgot the two CRC bytes at the end."
    if got == expected - 10:
        return "each register is two bytes."
    return f"{got} bytes is not the length of that response."


# --- notebook 11: Real sockets and real libraries -----------------------------------------------------

@exercise("11.1", "decode a captured Modbus/TCP request",
          hint="MBAP: transaction id (2 bytes, big-endian), protocol id (2), length (2), unit (1); then the "
               "PDU: function code, address (2), value (2). mb.TcpFrame.decode(mb.parse_hex(...)) reads it.",
          wrong=(0x0200, 6, 5, 0x63))
def _check_11_1(answer: Any) -> str | None:
    from .framing import TcpFrame, parse_hex

    frame = TcpFrame.decode(parse_hex("00 02 00 00 00 06 01 06 00 05 00 63"), role="request")
    expected = (frame.transaction_id, frame.pdu.function_code, frame.pdu.address, frame.pdu.value)
    if not isinstance(answer, (tuple, list)) or len(answer) != 4:
        return "answer with four ints: (transaction_id, function, address, value)."
    if any(isinstance(x, bool) or not isinstance(x, int) for x in answer):
        return "all four should be ints."
    tid, function, address, value = answer
    if tid != expected[0]:
        if tid == int.from_bytes(bytes.fromhex("0002"), "little"):
            return "the transaction id is big-endian (high byte first): 00 02 is 2, not 512."
        return f"the transaction id is in bytes 0-1; {tid} is not it."
    if function != expected[1]:
        return f"the function code is byte 7, right after the unit identifier; it is not {function}."
    if address != expected[2]:
        return f"the address is the two bytes after the function code; {address} is not it."
    if value != expected[3]:
        return f"the value is the last two bytes, 0x0063; {value} is not it."
    return None


@exercise("11.2", "what a gateway does: RTU in, Modbus/TCP out",
          hint="keep the unit and the PDU (drop the CRC), put an MBAP header in front: "
               "mb.TcpFrame(transaction_id=7, unit=..., pdu=...).encode(); mb.RtuFrame.decode reads the RTU "
               "frame.",
          wrong="00 07 00 00 00 08 03 03 00 00 00 03 04 29")
def _check_11_2(answer: Any) -> str | None:
    from .framing import RtuFrame, TcpFrame, parse_hex

    rtu = RtuFrame.decode(parse_hex("03 03 00 00 00 03 04 29"), role="request")
    expected = TcpFrame(transaction_id=7, unit=rtu.unit, pdu=rtu.pdu).encode()
    got = as_bytes(answer)
    if got.endswith(parse_hex("04 29")):
        return "Modbus/TCP frames carry no CRC: TCP checks the bytes itself. Drop the last two bytes."
    if got[:2] == b"\x07\x00":
        return "the transaction id goes big-endian: 00 07."
    return compare_bytes(got, expected, "your Modbus/TCP frame")


@exercise("11.3", "a pyserial URL for a serial device server",
          hint="pyserial's URL for a serial line carried over raw TCP is socket://<host>:<port>.",
          wrong="tcp://192.168.1.60:4001")
def _check_11_3(answer: Any) -> str | None:
    import serial
    from serial.urlhandler.protocol_socket import Serial as SocketSerial

    if not isinstance(answer, str):
        return "answer with a string, the URL."
    try:
        port = serial.serial_for_url(answer.strip(), do_not_open=True)
    except (ValueError, serial.SerialException) as exc:
        return f"pyserial does not accept {answer!r} as a port or URL ({exc})."
    if not isinstance(port, SocketSerial):
        if "://" not in answer:
            return f"{answer!r} is a local port name; a device on the network needs a URL."
        scheme = answer.split("://")[0]
        if scheme == "rfc2217":
            return "rfc2217:// is for device servers in RFC 2217 (telnet) mode; this one runs raw TCP."
        return f"{scheme}:// is another kind of pyserial port, not a serial line over raw TCP."
    try:
        host, number = port.from_url(answer.strip())
    except serial.SerialException as exc:
        return f"pyserial cannot read host and port from {answer!r}: {exc}."
    expected = SocketSerial().from_url("socket://192.168.1.60:4001")
    if (host, number) != expected:
        return f"that URL reaches {host}, TCP port {number}, not the device server."
    return None


# --- notebook 04: ASCII frames and the LRC ----------------------------------------------------------

@exercise("04.1", "an LRC by hand",
          hint="add the bytes, keep the low 8 bits, then take the two's complement: (256 - sum) % 256; "
               "mb.lrc(data) does it all.",
          wrong=0x82)
def _check_04_1(answer: Any) -> str | None:
    from .crc import lrc
    from .framing import parse_hex

    data = parse_hex("11 03 00 6B 00 03")
    expected = lrc(data)
    got = _int_answer(answer, "an LRC")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == sum(data) & 0xFF:
        return f"0x{got:02X} is the 8-bit sum; the LRC is its two's complement (256 minus the sum)."
    if got == lrc(data.hex().upper().encode("ascii")):
        return "you added the hex characters; the LRC adds the bytes they stand for."
    return f"0x{got:02X} is not the LRC of 11 03 00 6B 00 03."


@exercise("04.2", "build an ASCII frame",
          hint="44097 is holding register number 4097, address 4096 = 0x1000; mb.AsciiFrame(unit=..., "
               "pdu=mb.ReadHoldingRegistersRequest(address=..., count=...)).encode().",
          wrong=":050310010002E5\r\n")
def _check_04_2(answer: Any) -> str | None:
    from .datamodel import parse_reference
    from .framing import AsciiFrame
    from .pdu import ReadHoldingRegistersRequest

    address = parse_reference("44097").address
    expected = AsciiFrame(unit=5, pdu=ReadHoldingRegistersRequest(address=address, count=2)).encode()
    got = as_bytes(answer)
    if got == expected[:-2]:
        return "an ASCII frame ends with CR LF (b'\\r\\n')."
    off_by_one = AsciiFrame(unit=5, pdu=ReadHoldingRegistersRequest(address=address + 1, count=2)).encode()
    if got.upper() == off_by_one:
        return "the address is the register number minus one: 44097 is number 4097, address 4096."
    if got.upper() == expected:
        return None  # lowercase hex digits are allowed too
    return compare_bytes(got, expected, "your frame")


@exercise("04.3", "a 32-bit value in two registers",
          hint="the first register holds the high 16 bits: value = first x 65536 + second; "
               "mb.decode_value(registers, 'uint32', 'ABCD').",
          wrong=57920)
def _check_04_3(answer: Any) -> str | None:
    from .values import decode_value

    registers = [0x0001, 0xE240]
    expected = decode_value(registers, "uint32", "ABCD")
    got = _int_answer(answer, "the value")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == registers[1]:
        return "that is only the second register; the first one holds the high 16 bits."
    if got == decode_value(registers, "uint32", "CDAB"):
        return "you took the second register as the high half; here the first register is the high one."
    return f"{got} is not the value of the registers 0x0001 0xE240."


@exercise("04.4", "the PDU inside an ASCII frame",
          hint="decode the frame (mb.AsciiFrame.decode(frame, role='response')) and encode its .pdu; "
               "the PDU starts with the function code, after the address.",
          wrong="05 03 04 FF 06 00 64")
def _check_04_4(answer: Any) -> str | None:
    from .framing import AsciiFrame, parse_hex

    frame = AsciiFrame.decode(parse_hex(":050304FF0600648B"), role="response")
    expected = frame.pdu.encode()
    got = as_bytes(answer)
    if got == bytes([frame.unit]) + expected:
        return "the first byte, 05, is the slave address: it belongs to the envelope, not to the PDU."
    if got == expected + b"\x8B":
        return "the last byte, 8B, is the LRC: it belongs to the envelope, not to the PDU."
    if got[:1] == b":":
        return "give the bytes of the PDU, not the ASCII characters of the frame."
    return compare_bytes(got, expected, "your PDU")


# --- notebook 05: Modbus/TCP and the MBAP header -----------------------------------------------------

@exercise("05.1", "read a transaction id",
          hint="the transaction identifier is bytes 0-1 of the MBAP header, big-endian (high byte first).",
          wrong=10752)
def _check_05_1(answer: Any) -> str | None:
    from .framing import TcpFrame, parse_hex

    frame = parse_hex("00 2A 00 00 00 06 11 03 00 6B 00 03")
    expected = TcpFrame.decode(frame).transaction_id
    got = _int_answer(answer, "a transaction id")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == int.from_bytes(frame[:2], "little"):
        return "you read the two bytes low byte first; every MBAP field is big-endian."
    return f"{got} is not the transaction id of that frame."


@exercise("05.2", "build a Modbus/TCP frame",
          hint="mb.TcpFrame(transaction_id=..., unit=..., pdu=mb.WriteSingleRegisterRequest(address=..., "
               "value=...)).encode(); the length field counts the unit identifier and the PDU.",
          wrong="07 00 00 00 00 06 01 06 00 00 04 D2")
def _check_05_2(answer: Any) -> str | None:
    from .framing import TcpFrame
    from .pdu import WriteSingleRegisterRequest

    pdu = WriteSingleRegisterRequest(address=0, value=1234)
    expected = TcpFrame(transaction_id=7, unit=1, pdu=pdu).encode()
    got = as_bytes(answer)
    if got == expected:
        return None
    if len(got) == len(expected) and got[2:] == expected[2:] and got[:2] == expected[1::-1]:
        return "the transaction id is written low byte first; every MBAP field is big-endian."
    if len(got) == len(expected) and got[:4] == expected[:4] and got[6:] == expected[6:]:
        return (f"the length field is wrong: it counts the bytes after it, the unit identifier and the PDU "
                f"({expected[5]} bytes), big-endian.")
    return compare_bytes(got, expected, "your frame")


@exercise("05.3", "the MBAP length of a response",
          hint="the length counts the bytes after the length field: unit identifier (1) + function code (1) "
               "+ byte count (1) + 2 bytes per register.",
          wrong=22)
def _check_05_3(answer: Any) -> str | None:
    from .framing import TcpFrame
    from .pdu import ReadHoldingRegistersResponse

    frame = TcpFrame(transaction_id=1, unit=1, pdu=ReadHoldingRegistersResponse(registers=[0] * 10)).encode()
    expected = int.from_bytes(frame[4:6], "big")
    got = _int_answer(answer, "a length")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == expected - 1:
        return "the length also counts the unit identifier."
    if got == len(frame):
        return "that is the whole frame; the length counts only the bytes after the length field."
    return f"{got} is not the length field of that response."


@exercise("05.4", "spot the wrong MBAP field",
          hint="decode the frame with mb.explain(frame, mode='tcp'): the row marked as a problem is the one. "
               "Answer with the field's name, e.g. 'protocol identifier'.",
          wrong="transaction identifier")
def _check_05_4(answer: Any) -> str | None:
    from .explain import explain

    dissection = explain("01 18 00 00 06 00 01 03 00 00 00 01", mode="tcp")
    expected = next(row.field for row in dissection.rows if not row.ok)
    if not isinstance(answer, str):
        return "answer with the name of a field, as a string."
    got = answer.strip().lower()
    if got and (got == expected or (got in expected and len(got) >= 4)):
        return None
    if "transaction" in got:
        return ("0x0118 is a perfectly good transaction id (big-endian, 280); look at the field that must "
                "count the bytes that follow.")
    return f"{answer!r} is right in that frame; another field is not."


# --- notebook 09: An Arduino-style slave ----------------------------------------------------------------

@exercise("09.1", "function and address for a reference number",
          hint="3xxxx are input registers, read with function 4; the address in the frame is the number "
               "after the prefix minus one. mb.parse_reference('30010') does it.",
          wrong=(4, 10))
def _check_09_1(answer: Any) -> str | None:
    from .datamodel import parse_reference, table_kind

    ref = parse_reference("30010")
    function = next(fc for fc in (1, 2, 3, 4) if table_kind(fc) == ref.kind)
    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair of ints: (function, address)."
    got_function, got_address = answer
    if got_function != function:
        if got_function == 3:
            return "function 3 reads holding registers (4xxxx); 3xxxx are input registers."
        return f"function {got_function!r} does not read the table 30010 is in."
    if got_address != ref.address:
        if got_address == ref.address + 1:
            return "that is the register's number; the frame carries the address, which is one less."
        if got_address == 30010 or got_address == 30009:
            return "the prefix 3 only names the table; it is not part of the address."
        return f"address {got_address!r} is not where 30010 is."
    return None


def _registers_150_175_and_200_225_off_by_one() -> Any:
    from .datamodel import DataBank

    bank = DataBank(sparse=True)
    for first in (150, 200):
        bank.holding_registers.declare(first, 26)
    return bank


@exercise("09.2", "a sparse bank with holding registers 150-175 and 200-225",
          hint="board = ArduinoSlave(unit=1, sketch=False); for number in range(150, 176): "
               "board.add(40000 + number); the same for 200-225.",
          wrong=_registers_150_175_and_200_225_off_by_one())
def _check_09_2(answer: Any) -> str | None:
    from .datamodel import DataBank, parse_reference

    bank = getattr(answer, "bank", answer)
    if not isinstance(bank, DataBank):
        return "give the board (an ArduinoSlave) or its DataBank."
    if not bank.sparse:
        return "the bank should be sparse: only the declared registers exist."
    expected = sorted(parse_reference(40000 + n).address for n in [*range(150, 176), *range(200, 226)])
    got = sorted(bank.holding_registers.addresses())
    for table in (bank.coils, bank.discrete_inputs, bank.input_registers):
        if len(table):
            kind = table.kind.replace("_", " ")
            return f"only holding registers were asked for, but the bank also has {kind}."
    if got == expected:
        return None
    if got == [a + 1 for a in expected]:
        return "off by one: register 150 is reference 40150, which is address 149."
    if len(got) != len(expected):
        return (f"the bank holds {len(got)} holding registers, it should hold {len(expected)} "
                "(150 to 175 and 200 to 225, both ends included).")
    return "the right number of registers, but not at the right addresses."


@exercise("09.3", "a master timeout that copes with the slow loop",
          hint="a request may wait up to the longest loop (1.65 s + 10%) plus the time of the reply; "
               "try loop_time_experiment([SLOW_LOOP], timeout=...) with a few values.",
          wrong=1.5)
def _check_09_3(answer: Any) -> str | None:
    from .devices.arduino import SLOW_LOOP, loop_time_experiment

    got = _real_answer(answer, "a timeout in seconds")
    if isinstance(got, str):
        return got
    if got > 2.5:
        return f"{got:g} s works, but it is longer than needed: stay at or below 2.5 s."
    if got <= 0:
        return "a timeout is a positive number of seconds."
    [(_loop, fraction)] = loop_time_experiment([SLOW_LOOP], timeout=got)
    if fraction < 1.0:
        return (f"with a timeout of {got:g} s, {fraction:.0%} of the requests are answered: the longest "
                "waits are longer than that.")
    return None


# --- notebook 06: Master and slave over a loopback wire ----------------------------------------------

def _float_answer(answer: Any, what: str) -> float | str:
    """The answer as a float, or a sentence saying why it is not a number."""
    if isinstance(answer, bool) or not isinstance(answer, (int, float)):
        return f"{what} is a number (e.g. 12.5), you gave {type(answer).__name__} {answer!r}."
    return float(answer)


def _one_read_time(baudrate: int, count: int) -> float:
    """Seconds of virtual time one FC3 read of ``count`` registers takes on a loopback line (8N1)."""
    from .links.loopback import loopback_serial
    from .master import Master
    from .slave import Slave

    link = loopback_serial(Slave(unit=1), baudrate=baudrate)
    Master(link).read_holding_registers(unit=1, address=0, count=count)
    return link.clock.now


@exercise("06.1", "the time of one transaction",
          hint="request characters + 3.5 characters of silence + response characters + 3.5 characters, "
               "each character 10 bits at 9600 baud; or measure link.clock.now around a read.",
          wrong=22.92)
def _check_06_1(answer: Any) -> str | None:
    expected = _one_read_time(9600, 10) * 1000
    got = _float_answer(answer, "a time in milliseconds")
    if isinstance(got, str):
        return got
    if abs(got - expected) <= 0.01:
        return None
    if abs(got - expected / 1000) <= 0.00001:
        return "that looks like seconds; give milliseconds."
    if abs(got - _one_read_time(9600, 1) * 1000) <= 0.01:
        return "22.92 ms is the time for 1 register; this response carries 10 (20 more data bytes)."
    return f"{got:g} ms is not the time of that transaction."


@exercise("06.2", "an exception the master reports",
          hint="try it: master.write_single_coil(unit=1, address=0, value=True) inside try/except "
               "mb.ModbusExceptionError as error, and look at error.code.",
          wrong=1)
def _check_06_2(answer: Any) -> str | None:
    from .datamodel import DataBank
    from .errors import ModbusExceptionError
    from .links.loopback import loopback_serial
    from .master import Master
    from .slave import Slave

    bank = DataBank(sparse=True)
    bank.holding_registers.declare(0, 20)
    master = Master(loopback_serial(Slave(unit=1, bank=bank)))
    try:
        master.write_single_coil(unit=1, address=0, value=True)
        return "the checker expected an exception response here and got none; please tell your teacher."
    except ModbusExceptionError as error:
        expected = error.code
    got = _int_answer(answer, "an exception code")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == 1:
        return ("01 (illegal function) would mean the slave does not implement function 5 at all; it does, "
                "but coil 0 does not exist in its bank.")
    return f"exception code {got:02X} is not what the slave answers."


@exercise("06.3", "the most transactions per second",
          hint="one transaction (FC3, 1 register) takes (8 + 3.5 + 7 + 3.5) characters; a character is "
               "10 bits at 8N1; at 19200 baud one bit takes 1/19200 s.",
          wrong=43.6)
def _check_06_3(answer: Any) -> str | None:
    expected = 1 / _one_read_time(19200, 1)
    got = _float_answer(answer, "a rate")
    if isinstance(got, str):
        return got
    if abs(got - expected) <= 0.1:
        return None
    if abs(got - 1 / _one_read_time(9600, 1)) <= 0.1:
        return "that is the rate at 9600 baud; at 19200 every character takes half the time."
    return f"{got:g} transactions per second is not right."


@exercise("06.4", "what a wrong unit looks like",
          hint="try it: read from unit 2 on a line where only slave 1 listens, inside try/except "
               "mb.ModbusError as error, and give type(error).",
          wrong=ModbusError)
def _check_06_4(answer: Any) -> str | None:
    from .links.loopback import loopback_serial
    from .master import Master
    from .slave import Slave

    master = Master(loopback_serial(Slave(unit=1)), timeout=0.5)
    try:
        master.read_holding_registers(unit=2, address=0, count=1)
        return "the checker expected an error here and got none; please tell your teacher."
    except ModbusError as error:
        expected = type(error)
    got = answer if isinstance(answer, type) else type(answer)
    if got is expected:
        return None
    if isinstance(got, type) and issubclass(expected, got):
        return f"{got.__name__} is too general: which subclass exactly?"
    return (f"{getattr(got, '__name__', got)} is not what the master raises: no slave 2 listens, so "
            f"what does the master get back?")


# --- notebook 10: A power meter ------------------------------------------------------------------------

@exercise("10.1", "a voltage from a register pair",
          hint="the two registers after the byte count form one 32-bit number, high word first; VL2 is in "
               "tenths of a volt. METER_BY_NAME['VL2'].value(registers) does both steps.",
          wrong=4105)
def _check_10_1(answer: Any) -> str | None:
    from .devices.meter import METER_BY_NAME
    from .framing import RtuFrame, parse_hex
    from .values import decode_value

    registers = RtuFrame.decode(parse_hex("01 03 04 00 00 10 09 37 F5"), role="response").pdu.registers
    expected = METER_BY_NAME["VL2"].value(registers)
    got = _real_answer(answer, "a voltage in volts")
    if isinstance(got, str):
        return got
    raw = decode_value(registers, "uint32", "ABCD")
    if _close(got, expected):
        return None
    if _close(got, raw):
        return "that is the raw register value; Table 5 says V x 10: divide by 10."
    if _close(got, decode_value(registers, "uint32", "CDAB") / 10):
        return "you put the words in the wrong order: the high word (0x0000) comes first."
    return f"{got:g} V is not what those registers carry."


@exercise("10.2", "the registers that carry a current",
          hint="288.9 A is 288 900 mA; split it into a high and a low 16-bit word, high word first: "
               "mb.encode_value(288900, 'uint32', 'ABCD'), or METER_BY_NAME['AL1'].registers(288.9).",
          wrong=[0x6884, 0x0004])
def _check_10_2(answer: Any) -> str | None:
    from .devices.meter import METER_BY_NAME

    expected = METER_BY_NAME["AL1"].registers(_al1_of_trial_2())
    if not isinstance(answer, (list, tuple)) or any(
            isinstance(x, bool) or not isinstance(x, int) for x in answer):
        return "answer with a list of two ints, e.g. [0x0001, 0x2345]."
    got = list(answer)
    if got == expected:
        return None
    if got == expected[::-1]:
        return "the words are swapped: this meter sends the high word at the lower address."
    if len(got) == 1:
        return f"{got[0]} does not fit in one 16-bit register (at most 65535): it takes two."
    if len(got) == 2 and got[0] * 65536 + got[1] == 2889:
        return "the current travels in milliamperes: 288.9 A is 288 900 mA."
    return f"{got} is not 288 900 mA split high word first."


def _al1_of_trial_2() -> float:
    """AL1 of trial 2 in 003's Table 6, from the library's copy of the table."""
    from .devices.meter import TRIALS

    return TRIALS[2]["AL1"]


@exercise("10.3", "one request for PF2, VL3 and AL3",
          hint="look up the three pairs in Table 5 (METER_BY_NAME[...].address): they are consecutive; "
               "one FC3 request from the first address, two registers each.",
          wrong=(3, 0x12, 3))
def _check_10_3(answer: Any) -> str | None:
    from .devices.meter import METER_BY_NAME, meter_blocks

    members = [METER_BY_NAME[name] for name in ("PF2", "VL3", "AL3")]
    [(address, count, _)] = meter_blocks(members)
    expected = (3, address, count)
    if not isinstance(answer, (tuple, list)) or len(answer) != 3:
        return "answer with three ints: (function, address, count)."
    function, got_address, got_count = answer
    if function != 3:
        return "the meter is read with function 3, read holding registers."
    if got_address != address:
        if got_address == address + 1:
            return "the address in the frame is 0-based: 0x12 is address 18, not reference 40019."
        return f"address {got_address!r} is not where PF2 starts."
    if got_count != count:
        if got_count == len(members):
            return "each quantity takes a pair of registers: count registers, not quantities."
        return f"{got_count!r} registers do not cover exactly the three pairs."
    return None if tuple(answer) == expected else "not quite."


# --- notebook 12: The test tool ---------------------------------------------------------------------------

@exercise("12.1", "a grid cell in hex",
          hint="the fill gives 100, 110, 120, ... so address 5 holds 100 + 5 x 10; "
               "mb.format_registers([...], 'hex') shows a register as the test tool's grid does.",
          wrong="0x008C")
def _check_12_1(answer: Any) -> str | None:
    from .datamodel import DataBank
    from .devices.generators import increment_fill
    from .values import format_registers

    bank = DataBank(sparse=False)
    increment_fill(bank.holding_registers, 0, 10, 100, 10)
    expected = format_registers(bank.holding_registers.read(5, 1), "hex")[0]
    if not isinstance(answer, str):
        return "answer with the text the grid shows, a string such as '0x0001'."
    got = answer.strip()
    if got.lower() == expected.lower():
        return None
    value = bank.holding_registers[5]
    if got == str(value):
        return f"{got} is the unsigned display; in hex it is written with 0x and four hex digits."
    if got.lower() == format_registers([value - 10], "hex")[0].lower():
        return "addresses start at 0: address 5 is the sixth cell."
    return f"{got!r} is not how the hex display shows address 5."


_12_2_KEYS = ("role", "unit", "function", "address", "length", "interval")


@exercise("12.2", "set up a master tool",
          hint="TestTool('rtu_master', unit=..., function=..., address=..., length=..., interval=...); "
               "input registers are read with function 4.",
          wrong={"role": "rtu_master", "unit": 7, "function": 3, "address": 10, "length": 4, "interval": 0.5})
def _check_12_2(answer: Any) -> str | None:
    from .widgets.testtool import TestTool

    config = answer.config() if isinstance(answer, TestTool) else answer
    if not isinstance(config, dict):
        return "give the TestTool or its config() dict."
    reference = TestTool("rtu_master", unit=7, function=4, address=10, length=4, interval=0.5).config()
    reference_roles = ("rtu_master", "tcp_client")
    for key in _12_2_KEYS:
        if key not in config:
            return f"the configuration has no {key!r}."
    if config["role"] not in reference_roles:
        return f"a {config['role']!r} answers requests; the tool must ask: a master (or a client)."
    for key in _12_2_KEYS[1:]:
        if config[key] != reference[key]:
            if key == "function" and config[key] == 3:
                return "function 3 reads holding registers; input registers are read with function 4."
            return f"{key} is {config[key]!r}, it should be {reference[key]!r}."
    return None


@exercise("12.3", "the transaction id after three polls",
          hint="the transaction id goes up by one per request: 280, 281, 282 are used; the MBAP header "
               "writes it high byte first.",
          wrong=(283, "1B 01"))
def _check_12_3(answer: Any) -> str | None:
    from .framing import parse_hex
    from .widgets.testtool import TestTool

    server = TestTool("tcp_server", unit=1, length=1)
    client = TestTool("tcp_client", partner=server, unit=1, length=1, transaction_id=280)
    client.run_polls(3)
    tid = client.transaction_id.value
    client.run_polls(1)
    first_two = client.traffic.search(direction="tx")[-1].data[:2]
    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair: (transaction_id, 'XX XX')."
    got_tid, got_bytes = answer
    if got_tid != tid:
        if got_tid == tid - 1:
            return "that is the id of the third request; the question asks for the next one."
        return f"the next transaction id is not {got_tid!r}."
    got = parse_hex(got_bytes) if isinstance(got_bytes, str) else bytes(got_bytes)
    if got == first_two[::-1]:
        return "the bytes are swapped: the MBAP header is big-endian, high byte first (000 says otherwise)."
    if got != first_two:
        return f"{got.hex(' ').upper()} is not how {tid} starts the request."
    return None


# --- notebook 13: Troubleshooting lab -----------------------------------------------------------------------

_SILENT_CAUSES = ("wrong unit id", "wrong baud rate or parity", "no slave on the line")
_LAB_SEED = 13


def _silent_wires(seed: int = _LAB_SEED) -> tuple[dict[str, Any], dict[str, str]]:
    """Three wires whose master only gets timeouts, each for another reason; and the reasons."""
    import random

    from .links.loopback import loopback_serial
    from .slave import Slave

    causes = list(_SILENT_CAUSES)
    random.Random(seed).shuffle(causes)
    wires: dict[str, Any] = {}
    truth: dict[str, str] = {}
    for name, cause in zip("ABC", causes):
        slave = Slave(unit=1)
        slave.bank.holding_registers[0] = 1234
        if cause == "wrong unit id":
            slave = Slave(unit=2, bank=slave.bank)       # its address switch says 2, the drawing says 1
            link = loopback_serial(slave, baudrate=9600)
        elif cause == "wrong baud rate or parity":
            # its configuration says 19200 baud, the master's line runs at 9600: the wire honours the
            # slave's own settings, so its receiver samples every bit at the wrong moment
            slave.serial_settings = {"baudrate": 19200, "parity": "N", "stopbits": 1}  # type: ignore[attr-defined]
            link = loopback_serial(slave, baudrate=9600)
        else:
            link = loopback_serial([], baudrate=9600)    # the slave is off, or its cable is not connected
        wires[name] = link
        truth[name] = cause
    return wires, truth


def _word_order_device(seed: int = _LAB_SEED) -> tuple[Any, str, float]:
    """A current sensor sending milliamperes as uint32 in an undisclosed word order."""
    import random

    from .datamodel import DataBank
    from .slave import Slave
    from .values import encode_value

    rng = random.Random(seed)
    order = "CDAB"
    amperes = round(rng.uniform(120.0, 180.0), 3)
    bank = DataBank(sparse=True)
    bank.holding_registers.declare(0, 2, encode_value(round(amperes * 1000), "uint32", order))
    return Slave(unit=1, bank=bank, name="current sensor"), order, amperes


def _slow_board(seed: int = _LAB_SEED) -> Any:
    """An Arduino-style slave whose main loop is slower than the master's 1 s timeout."""
    from .devices.arduino import ArduinoSlave

    return ArduinoSlave(unit=1, loop_time=2.2, jitter=0.1, seed=seed)


def lab(puzzle: str) -> Any:
    """Set up one of notebook 13's troubleshooting puzzles.

    ``lab("silent")``      three loopback wires ``{"A": link, "B": link, "C": link}``; on each, a master
                           asking unit 1 gets only timeouts, each for another reason;
    ``lab("word order")``  a loopback wire to a current sensor (unit 1, holding registers 0-1: a current
                           in mA as an unsigned 32-bit value);
    ``lab("slow slave")``  a loopback wire to an Arduino-style slave (unit 1, input registers 30001-30002)
                           whose main loop is too slow.

    Every call builds a fresh, seeded setup: the same every run.
    """
    from .errors import ConfigError
    from .links.loopback import loopback_serial

    if puzzle == "silent":
        return _silent_wires()[0]
    if puzzle == "word order":
        return loopback_serial(_word_order_device()[0], baudrate=19200)
    if puzzle == "slow slave":
        board = _slow_board()
        return loopback_serial(board, **board.serial_settings)
    raise ConfigError(f"there is no puzzle {puzzle!r}: try 'silent', 'word order' or 'slow slave'")


@exercise("13.1", "three silent slaves",
          hint="poll each wire, then look at what the slave saw: link.slaves[0].counters (other_unit: a "
               "request for another address; checksum_errors: bytes that arrived garbled, as a receiver "
               "at another baud rate assembles them) and its log, link.slaves[0].log. "
               "No slave at all leaves no trace.",
          wrong={"A": "wrong unit id", "B": "wrong unit id", "C": "wrong unit id"})
def _check_13_1(answer: Any) -> str | None:
    truth = _silent_wires()[1]
    if not isinstance(answer, dict) or set(answer) != set(truth):
        return "answer with a dict {'A': cause, 'B': cause, 'C': cause}."
    for name in sorted(truth):
        got = str(answer[name]).strip().lower()
        if got not in _SILENT_CAUSES:
            return f"wire {name}: {answer[name]!r} is not one of {', '.join(map(repr, _SILENT_CAUSES))}."
        if got != truth[name]:
            return f"wire {name} is not silent because of a {got}."
    return None


@exercise("13.2", "a current with an unknown word order",
          hint="read holding registers 0-1 and decode them with mb.decode_value(registers, 'uint32', order) "
               "for the orders 'ABCD' and 'CDAB'; only one gives a current a sensor could measure (in mA).",
          wrong=("ABCD", 292880.386))
def _check_13_2(answer: Any) -> str | None:
    _device, order, amperes = _word_order_device()
    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair: (order, current in amperes), e.g. ('ABCD', 12.5)."
    got_order, got_amperes = answer
    if str(got_order).upper() != order:
        return f"with the order {got_order!r} the current makes no physical sense; try the other one."
    value = _real_answer(got_amperes, "the current")
    if isinstance(value, str):
        return value
    if _close(value, amperes * 1000):
        return "that is in milliamperes; give amperes."
    if not _close(value, amperes, rel=1e-4):
        return f"{value:g} A is not what those registers carry."
    return None


@exercise("13.3", "off by one",
          hint="a reference number counts from 1, the address in the frame from 0: 40001 is address 0. "
               "mb.parse_reference('40021') gives the address.",
          wrong=21)
def _check_13_3(answer: Any) -> str | None:
    from .datamodel import parse_reference

    expected = parse_reference("40021").address
    if isinstance(answer, bool) or not isinstance(answer, int):
        return "answer with the address, an int."
    if answer == expected:
        return None
    if answer == expected + 1:
        return "that is the number after the prefix; the frame carries the address, one less."
    if answer == 40021 or answer == 40020:
        return "the prefix 4 names the table (holding registers); it is not part of the address."
    return f"address {answer} is not where register 40021 is."


@exercise("13.4", "a little-endian transaction id",
          hint="a spec-following server reads the MBAP transaction id high byte first: "
               "mb.TcpFrame.decode(...).transaction_id; a correct client sends 3 as 00 03.",
          wrong=(3, "03 00"))
def _check_13_4(answer: Any) -> str | None:
    from .framing import TcpFrame, parse_hex
    from .pdu import ReadHoldingRegistersRequest

    captured = TcpFrame.decode(parse_hex("03 00 00 00 00 06 01 03 00 00 00 01"), role="request")
    correct = TcpFrame(transaction_id=3, unit=1, pdu=ReadHoldingRegistersRequest(address=0, count=1)).encode()
    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair: (the id the server reads, 'XX XX')."
    seen, first_two = answer
    if seen != captured.transaction_id:
        if seen == 3:
            return "3 is what the client meant; the server reads the two bytes high byte first."
        return f"the server does not read {seen!r} from 03 00."
    got = parse_hex(first_two) if isinstance(first_two, str) else bytes(first_two)
    if got != correct[:2]:
        return f"{got.hex(' ').upper()} is not transaction id 3 written high byte first."
    return None


@exercise("13.5", "a CRC that does not match",
          hint="mb.explain(frame) says what CRC it computed; compare it with the two bytes the frame "
               "carries. The CRC goes low byte first.",
          wrong="01 03 00 00 00 01 0A 84")
def _check_13_5(answer: Any) -> str | None:
    from .framing import RtuFrame
    from .pdu import ReadHoldingRegistersRequest

    expected = RtuFrame(unit=1, pdu=ReadHoldingRegistersRequest(address=0, count=1)).encode()
    return compare_rtu_frame(answer, expected, "your corrected frame", "that is the frame as the faulty "
                             "tool sent it: the CRC bytes are still swapped.")


@exercise("13.6", "estimate a slave's loop time",
          hint="poll 300 times, one request every 5 s, with a 1 s timeout; the fraction answered is about "
               "(timeout - 0.013 s) / loop time, so loop time ~ 0.99 / fraction.",
          wrong=1.0)
def _check_13_6(answer: Any) -> str | None:
    board = _slow_board()
    got = _real_answer(answer, "a loop time in seconds")
    if isinstance(got, str):
        return got
    if abs(got - board.loop_time) <= 0.25 * board.loop_time:
        return None
    if got < board.loop_time:
        return (f"{got:g} s is too short: a loop that fast would answer more requests in time than this "
                "one does.")
    return f"{got:g} s is too long: a loop that slow would answer fewer requests than this one does."
