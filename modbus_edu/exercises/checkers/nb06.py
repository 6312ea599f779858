"""Exercises of notebook 06: Master and slave over a loopback wire."""

from __future__ import annotations

from typing import Any

from ...crc import crc_bytes
from ...datamodel import DataBank
from ...errors import ChecksumError, CrcError, ModbusError, ModbusExceptionError, ModbusTimeoutError
from ...framing import RtuFrame
from ...links.loopback import loopback_serial
from ...master import Master
from ...slave import Slave
from ..build import build_exercise
from ..core import exercise, int_answer, number_answer, real_answer, right_value_in_another_form
from ..diagnosis.frameslip import frame_slip
from ..diagnosis.misconceptions import diagnose, name
from ..diagnosis.timing import RATE, TRANSACTION_MS


def _one_read_time(baudrate: int, count: int) -> float:
    """Seconds of virtual time one FC3 read of ``count`` registers takes on a loopback line (8N1)."""
    link = loopback_serial(Slave(unit=1), baudrate=baudrate)
    Master(link).read_holding_registers(unit=1, address=0, count=count)
    return link.clock.now


@exercise("06.1", "the time of one transaction",
          hint="request characters + 3.5 characters of silence + response characters + 3.5 characters, "
               "each character 10 bits at 9600 baud; or measure link.clock.now around a read.",
          accepts=[41.67, 41.6667, 41.666666],
          refuses=[(0.04167, "seconds-for-milliseconds"), (34.38, "silences-forgotten"),
                   (22.92, "one-register-response"), (45.0, None),
                   (41666.7, "microseconds-for-milliseconds")])
def _check_06_1(answer: Any) -> str | None:
    expected = _one_read_time(9600, 10) * 1000
    got = real_answer(answer, "a time in milliseconds")
    if isinstance(got, str):
        return got
    named = (TRANSACTION_MS.explain([((9600, "N", 1, 8, 5 + 2 * 10), got)])
             or diagnose("one-register-response", got, _one_read_time(9600, 1) * 1000)
             or diagnose("silences-forgotten", got, (8 + 25) * 10 / 9600 * 1000))
    if named:
        return named
    return number_answer(got, expected, decimals=2, unit="ms", what="the time of that transaction")


@exercise("06.2", "an exception the master reports",
          hint=("a slave that implements a function but lacks the element asked for refuses with an "
                "exception code; mb.ExceptionCode lists the codes.",
                "run it: the master raises mb.ModbusExceptionError, and the error's .code is the slave's "
                "exception code."),
          accepts=[2, 0x02], refuses=[(1, "illegal-function-for-address"), (3, "exception-code-confused"),
                                                   (0x86, None), (0, "refusal-unanswered")])
def _check_06_2(answer: Any) -> str | None:
    bank = DataBank(sparse=True)
    bank.holding_registers.declare(0, 20)
    master = Master(loopback_serial(Slave(unit=1, bank=bank)))
    try:
        master.write_single_coil(unit=1, address=0, value=True)
        return "the checker expected an exception response here and got none; please tell your teacher."
    except ModbusExceptionError as error:
        expected = error.code
    got = int_answer(answer, "an exception code")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == 0:
        return diagnose("refusal-unanswered", "valid", "exception")
    if diagnose("illegal-function-for-address", got, expected):
        return (name("illegal-function-for-address") + " The slave implements function 5, but coil 0 does "
                "not exist in its bank.")
    named = diagnose("exception-function-for-code", got, 5, expected)
    if named:
        return named
    return (diagnose("exception-code-confused", got, expected)
            or f"exception code {got:02X} is not what the slave answers.")


@exercise("06.3", "the most transactions per second",
          hint=("one transaction is request + 3.5 characters of silence + response + 3.5 characters; "
                "transactions follow each other, so the most per second is 1 / the time of one.",
                "FC3 for one register: a request of 8 bytes, a response of 7; 8N1 is 10 bits a character, "
                "and at 19200 baud a bit lasts 1/19200 s.",
                "two registers at 9600 baud: 8 + 3.5 + 9 + 3.5 = 24 characters = 240 bits = 25 ms: 40 "
                "transactions per second."),
          accepts=[87.3, 87.27],
          refuses=[(0.01146, "time-for-rate"), (128.0, "silences-forgotten"), (87.2, "truncated-not-rounded"),
                   (43.6, "another-baud-rate"), (80.0, None)])
def _check_06_3(answer: Any) -> str | None:
    expected = 1 / _one_read_time(19200, 1)
    got = real_answer(answer, "a rate")
    if isinstance(got, str):
        return got
    named = (RATE.explain([((19200, "N", 1, 8, 7), got)])
             or diagnose("another-baud-rate", got, 1 / _one_read_time(9600, 1))
             or diagnose("time-for-rate", got, expected)
             or diagnose("silences-forgotten", got, 19200 / 10 / (8 + 7)))
    if named:
        return named
    return number_answer(got, expected, decimals=1, what="the most transactions per second")


@exercise("06.4", "what a damaged request looks like",
          hint=("a slave checks a request's CRC before anything else; think about what it does with a "
                "request that fails the check, and what the master then gets back.",
                "try it on a loopback line: link.faults.flip_bits(1, target='request') damages the next "
                "request; catch mb.ModbusError as error and look at type(error)."),
          accepts=[ModbusTimeoutError],
          refuses=[(ModbusError, None), (CrcError, "answer-to-damaged-request"),
                   (ChecksumError, "answer-to-damaged-request"), ("timeout", None),
                   (ModbusExceptionError, "answer-to-damaged-request"),
                   (ModbusTimeoutError("x"), "another-form"),
                   ("mb.ModbusTimeoutError", "another-form"),
                   (TimeoutError, "builtin-for-library-exception")])
def _check_06_4(answer: Any) -> str | None:
    link = loopback_serial(Slave(unit=1))
    link.faults.flip_bits(1, target="request")
    try:
        Master(link, timeout=0.5).read_holding_registers(unit=1, address=0, count=1)
        return "the checker expected an error here and got none; please tell your teacher."
    except ModbusError as error:
        expected = type(error)
    if isinstance(answer, BaseException):
        if type(answer) is expected:
            return right_value_in_another_form(
                f"the class itself, {expected.__name__}, not an instance of it "
                f"({expected.__name__}(...) makes one)")
        return f"give an exception class, not an instance ({type(answer).__name__}(...) makes one)."
    got = answer
    if got is expected:
        return None
    if isinstance(got, str) and got.strip().split(".")[-1].lower() == expected.__name__.lower():
        return right_value_in_another_form(
            f"the class itself, mb.{expected.__name__}, not its name as text")
    named = diagnose("builtin-for-library-exception", got)
    if named:
        return named
    if isinstance(got, type) and issubclass(expected, got):
        return f"{got.__name__} is too general: which subclass exactly?"
    if isinstance(got, type) and issubclass(got, ChecksumError):
        return diagnose("answer-to-damaged-request", "checksum error", "timeout")
    if isinstance(got, type) and issubclass(got, ModbusExceptionError):
        return diagnose("answer-to-damaged-request", "exception", "timeout")
    return (f"{getattr(got, '__name__', got)} is not what the master raises: the slave cannot trust the "
            f"damaged request, so what does the master get back?")


def _slave_answer(registers: list, pdu: bytes) -> bytes:
    """What the library's Slave answers to ``pdu`` over a bank of ``len(registers)`` holding registers."""
    bank = DataBank(sparse=True)
    bank.holding_registers.declare(0, len(registers))
    for address, value in enumerate(registers):
        bank.holding_registers[address] = value
    body = bytes([1]) + pdu
    request = body + crc_bytes(body)  # built by hand: a slave must also answer requests it refuses
    answer = RtuFrame.decode(Slave(unit=1, bank=bank).handle(request, mode="rtu"), "response").pdu.encode()
    registers[:] = bank.holding_registers.read(0, len(registers))  # what the slave stored, as a learner would
    return answer


def _read_it_back(args: tuple, state: tuple) -> tuple | None:
    """After a write (FC 6) to a register that exists, the read (FC 3) of that register."""
    registers, pdu = args
    address = int.from_bytes(pdu[1:3], "big")
    if pdu[:1] != b"\x06" or address >= len(registers):
        return None
    return state[0], bytes([3]) + pdu[1:3] + (1).to_bytes(2, "big")


def _register_count(got: bytes, expected: bytes) -> str | None:
    """A read's byte count that holds the number of registers: with the data still two bytes a register,
    the byte count written as the quantity; with one byte a register, a register taken for one byte."""
    if got[2:] == expected[2:]:
        return name("byte-count-for-quantity") if got[1] == expected[1] // 2 else None
    return diagnose("register-one-byte", got[1], expected[1], expected[1] // 2)


def _diagnose_handler(args, expected, got) -> str | None:
    registers, pdu = args
    address = int.from_bytes(pdu[1:3], "big")
    if isinstance(got, bytes) and isinstance(expected, bytes) and len(got) >= 2 and len(expected) >= 2:
        exception = len(got) == 2 and expected[0] & 0x80
        named = (diagnose("exception-bit-missing", got[0], expected[0]) if exception else None) or (
            diagnose(("illegal-function-for-address", "exception-code-confused"), got[1], expected[1])
            if exception and got[0] == expected[0] else None) or (
            _register_count(got, expected) if got[0] == expected[0] == 3 else None)
        if named:
            return named
    if address == 0 and isinstance(got, bytes) and isinstance(expected, bytes):
        named = diagnose("slave-subtracts-one", got, expected)
        if named:
            return named
    if pdu[:1] == b"\x03" and pdu[3:5] == b"\x00\x01" and address < len(registers):
        named = diagnose("write-not-stored", got, bytes([3, 2]) + registers[address].to_bytes(2, "big"),
                         expected)
        if named:
            return named
    if isinstance(got, bytes) and isinstance(expected, bytes):
        return _range_diagnosis(registers, pdu, got, expected) or frame_slip(got, expected)
    return None


def _range_diagnosis(registers: list, pdu: bytes, got: bytes, expected: bytes) -> str | None:
    """A range check off by one, named as 02.5 names it: a request the slave must refuse answered (an invalid
    input accepted), or one it must answer refused; with the boundary the request falls on."""
    if pdu[:1] != b"\x03" or len(pdu) < 5:
        return None
    address, count = int.from_bytes(pdu[1:3], "big"), int.from_bytes(pdu[3:5], "big")
    edge = (f"the count {count} is outside 1..125" if not 1 <= count <= 125 else
            f"registers {address} to {address + count - 1} go past the last one, {len(registers) - 1}"
            if address + count > len(registers) else
            f"the count {count} is within 1..125 and registers {address} to {address + count - 1} all exist")
    answered = got[:1] == b"\x03" and len(got) == 2 + 2 * count and got[1] == 2 * count  # a response to it
    off_by_one = count in (0, 126) or address + count == len(registers) + 1
    if expected[0] & 0x80 and answered and off_by_one:
        return f"Here {edge}: check the range with both of its ends. {name('invalid-input-accepted')}"
    at_an_end = count in (1, 125) or address + count == len(registers)
    if got[:1] == b"\x83" and expected[:1] == b"\x03" and at_an_end:
        return f"a range check off by one: {edge}, so this request must be answered; check both ends."
    return None


def _handler_inputs(rng) -> tuple:
    size = rng.randrange(1, 20)
    registers = [rng.randrange(65536) for _ in range(size)]
    if rng.random() < 0.5:
        count = rng.randrange(1, 8) if rng.random() < 0.9 else rng.choice([0, 126])
        pdu = bytes([3]) + rng.randrange(0, size + 3).to_bytes(2, "big") + count.to_bytes(2, "big")
    else:
        value = rng.randrange(65536)
        pdu = bytes([6]) + rng.randrange(0, size + 3).to_bytes(2, "big") + value.to_bytes(2, "big")
    return registers, pdu


def _echo_without_storing(registers: list, pdu: bytes) -> bytes:
    """A plausible wrong handler: right in every answer, but a write is only echoed, never stored."""
    function, address = pdu[0], int.from_bytes(pdu[1:3], "big")
    if function == 6:
        return bytes(pdu) if address < len(registers) else bytes([0x86, 2])
    count = int.from_bytes(pdu[3:5], "big")
    if not 1 <= count <= 125:
        return bytes([0x83, 3])
    if address + count > len(registers):
        return bytes([0x83, 2])
    data = b"".join(value.to_bytes(2, "big") for value in registers[address:address + count])
    return bytes([3, len(data)]) + data


build_exercise(
    "06.5", "write a slave's request handler",
    reference=_slave_answer, inputs=_handler_inputs,
    edge_cases=[([1234], bytes.fromhex("03 00 00 00 01")), ([1, 2, 3], bytes.fromhex("03 00 01 00 03")),
                ([1, 2, 3], bytes.fromhex("06 00 02 00 2A")), ([1, 2, 3], bytes.fromhex("06 00 03 00 2A")),
                ([0] * 5, bytes.fromhex("03 00 00 00 00")),
                # the boundaries: the largest read, and an address and a count whose high byte counts
                ([7] * 125, bytes.fromhex("03 00 00 00 7D")), ([1, 2, 3], bytes.fromhex("03 01 00 00 01")),
                ([1, 2, 3], bytes.fromhex("03 00 00 01 01"))],
    hint="read the function code; FC3: address and count (2 bytes each, high first), answer 03, byte count, "
         "the registers; FC6: store the value, answer with the request itself. An address outside the list "
         "gets an exception response (the function code with its top bit set, then 02); a count outside "
         "1..125, code 03; any other function, code 01.",
    refuses=[(_echo_without_storing, "write-not-stored"),
             (lambda registers, pdu: bytes([3, 2]) + registers[0].to_bytes(2, "big"), None),
             (lambda registers, pdu: bytes([pdu[0] | 0x80, 2]) if pdu[1:3] == bytes(2) else _slave_answer(
                 registers, pdu), "slave-subtracts-one")],
    read_back=_read_it_back, diagnose=_diagnose_handler)
