"""Exercises of notebook 08: Serial timing."""

from __future__ import annotations

from typing import Any

from ...errors import ModbusError as _Error
from ...links.loopback import loopback_serial
from ...links.wire import SerialTiming
from ...master import Master
from ...slave import Slave
from ..build import build_exercise
from ..core import Written, exercise, number_answer, real_answer
from ..diagnosis.misconceptions import diagnose
from ..diagnosis.procedures import TRANSACTION_TIME
from ..diagnosis.timing import RATE, T35


@exercise("08.1", "the silence that ends a frame at 4800 baud 8E1",
          hint=("t3.5 is 3.5 character times (the fixed 1.75 ms applies only above 19200 baud); with even "
                "parity a character is 11 bits (start, 8 data, parity, stop).",
                "one character lasts bits / baud rate seconds; multiply by 3.5. "
                "mb.SerialTiming(baudrate=..., parity=...).t35 checks it.",
                "at 9600 baud 8N1 a character is 10 bits, 1.042 ms, and t3.5 is 0.003646 s."),
          accepts=[0.008021, 0.00802083, 0.0080208],
          refuses=[(0.007292, "parity-bit-forgotten"), (0.002292, "one-character-for-t35"),
                   (8.021, "milliseconds-for-seconds"), (0.009, None)])
def _check_08_1(answer: Any) -> str | None:
    timing = SerialTiming(baudrate=4800, parity="E", stopbits=1)
    expected = timing.t35
    got = real_answer(answer, "a silence in seconds")
    if isinstance(got, str):
        return got
    named = (T35.explain([((4800, "E", 1), got)])
             or diagnose("parity-bit-forgotten", got, 3.5 * SerialTiming(baudrate=4800).char_time)
             or diagnose("one-character-for-t35", got, timing.char_time))
    if named:
        return named
    return number_answer(got, expected, decimals=6, unit="s", what="3.5 characters of 8E1 at 4800 baud")


@exercise("08.2", "transactions per second reading 10 registers at 19200 baud",
          hint=("one transaction is request + 3.5 characters of silence + response + 3.5 characters; the "
                "line carries one transaction after the other.",
                "request 8 bytes, response 5 + 2 x 10 bytes; 8N1 is 10 bits a character, each bit 1/19200 "
                "s; transactions per second = 1 / the time of one.",
                "one register at 9600 baud: 8 + 3.5 + 7 + 3.5 = 22 characters = 220 bits = 22.9 ms, about "
                "43.6 transactions per second."),
          accepts=[48.0, 48, 47.99],
          refuses=[(58.18, "silences-forgotten"), (0.02083, "time-for-rate"), (87.3, "one-register-response"),
                   (50.0, None)])
def _check_08_2(answer: Any) -> str | None:
    timing = SerialTiming(baudrate=19200)
    expected = 1 / timing.transaction_time(8, 5 + 2 * 10)
    got = real_answer(answer, "a number of transactions per second")
    if isinstance(got, str):
        return got
    named = RATE.explain([((19200, "N", 1, 8, 5 + 2 * 10), got)]) or diagnose(
        "silences-forgotten", got, 1 / timing.frame_time(8 + 25)) or diagnose("time-for-rate",
                                                                                           got,
                                                                                            expected)
    if named:
        return named
    named = diagnose("one-register-response", got, 1 / timing.transaction_time(8, 7))
    if named:
        return named
    return number_answer(got, expected, decimals=1, what="the most transactions per second")


@exercise("08.3", "which pauses inside a frame leave it unanswered",
          hint="a pause of more than 1.5 character times breaks an RTU frame, and one of 3.5 or more cuts "
               "it in two; either way the slave gets no valid request.",
          accepts=[[2.0, 3.0, 5.0], (5, 3, 2), {2.0, 3.0, 5.0}],
          refuses=[([5.0], "t15-forgotten"), ([3.0, 5.0], "pause-threshold"),
                   ([1.4, 2.0, 3.0, 5.0], "pause-threshold"), ([1.0, 5.0], None)])
def _check_08_3(answer: Any) -> str | None:
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
    except (TypeError, ValueError, OverflowError):
        return "the list should hold numbers of character times taken from [1.0, 1.4, 2.0, 3.0, 5.0]."
    if got == expected:
        return None
    named = diagnose("t15-forgotten", got, expected) or diagnose("pause-threshold", got, expected, pauses)
    if named:
        return named
    missing = [p for p in expected if p not in got]
    extra = [p for p in got if p not in expected]
    if extra:
        return (f"a pause of {extra[0]:g} characters is not more than 1.5: the frame stays whole and is "
                "answered.")
    return (f"a pause of {missing[0]:g} characters also leaves the request unanswered "
            "(more than 1.5 breaks the frame).")


def _transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int,
                      response_bytes: int) -> float:
    return SerialTiming(baudrate=baudrate, parity=parity, stopbits=stopbits).transaction_time(
        request_bytes, response_bytes)


def _timing_inputs(rng) -> tuple:
    return _decimal(rng.choice([1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200]), rng.choice("NEO"),
                    rng.choice([1, 2]), rng.randrange(8, 256), rng.randrange(5, 256))


def _decimal(*args) -> tuple:
    """08.4's inputs with every number written in decimal in messages (38400 baud, never 0x9600)."""
    return tuple(Written(arg) if isinstance(arg, int) else arg for arg in args)


def _close_enough(expected: float, got) -> bool:
    if isinstance(got, bool) or not isinstance(got, (int, float)):
        return False
    return abs(got - expected) <= 1e-9 + 1e-9 * expected


def _timing_boundary(args) -> str | None:
    """The boundary of 08.4's range a failing input falls on: the rate where the fixed silences start."""
    baudrate = args[0]
    if baudrate == 19200:
        return "At 19200 baud the silences are still 3.5 characters; the fixed 1.75 ms start above it."
    if 19200 < baudrate <= 19201:
        return "Just above 19200 baud the fixed 1.75 ms already apply."
    return None


def _diagnose_timing(args, expected, got) -> str | None:
    if not isinstance(got, (int, float)):
        return None
    baudrate, parity, stopbits, request, response = args
    char = (1 + 8 + (parity != "N") + stopbits) / baudrate
    t35 = 0.00175 if baudrate > 19200 else 3.5 * char
    named = (diagnose("silences-forgotten", got, (request + response) * char)
             or diagnose("silences-forgotten", got, (request + response) * char + t35))
    if not named and baudrate > 19200:
        named = diagnose("fixed-silence-ignored", got, (request + 3.5 + response + 3.5) * char)
    if not named and (parity, stopbits) != ("N", 1):
        named = diagnose("parity-bit-forgotten", got, _transaction_time(baudrate, "N", 1, request, response))
    eight_bits = (request + response + (0 if baudrate > 19200 else 7)) * 8 / baudrate + (
        2 * 0.00175 if baudrate > 19200 else 0)
    return (named or diagnose("milliseconds-for-seconds", got, expected)
            or diagnose("start-stop-forgotten", got, eight_bits)
            or diagnose("three-characters-for-t35", got, (request + response + 6) * char))


build_exercise(
    "08.4", "write the transaction time yourself",
    reference=_transaction_time, inputs=_timing_inputs,
    edge_cases=[_decimal(9600, "N", 1, 8, 7), _decimal(19200, "E", 1, 8, 255), _decimal(38400, "N", 2, 8, 7),
                _decimal(115200, "N", 1, 8, 7), _decimal(19201, "N", 1, 8, 7),   # just above 19200: 1.75 ms
                _decimal(1200, "O", 2, 256, 256)],  # the other ends of the ranges
    hint="bits per character = 1 start + 8 data + 1 if parity + stop bits; a character takes bits / baudrate "
         "seconds; t3.5 is 3.5 characters up to 19200 baud and 0.00175 s above; the time is request + t3.5 + "
         "response + t3.5.",
    refuses=[(lambda baudrate, parity, stopbits, request, response: (request + response + 7) * 10 / baudrate,
              "parity-bit-forgotten"),
             (lambda baudrate, parity, stopbits, request, response:
              (request + response) * (1 + 8 + (parity != "N") + stopbits) / baudrate, "silences-forgotten"),
             (lambda baudrate, parity, stopbits, request, response:
              (request + response + 7) * (1 + 8 + (parity != "N") + stopbits) / baudrate,
              "fixed-silence-ignored"),
             (lambda *args: 1000 * _transaction_time(*args), "milliseconds-for-seconds"),
             (lambda baudrate, parity, stopbits, request, response:
              (request + response + 7) * 8 / baudrate if baudrate <= 19200 else
              (request + response) * 8 / baudrate + 0.0035, "start-stop-forgotten"),
             (lambda baudrate, parity, stopbits, request, response:
              (request + response + 6) * (1 + 8 + (parity != "N") + stopbits) / baudrate,
              "three-characters-for-t35"),
             (lambda baudrate, parity, stopbits, request, response:
              (request + response) * (1 + 8 + (parity != "N") + stopbits) / baudrate + 0.0035
              if baudrate >= 19200 else _transaction_time(baudrate, parity, stopbits, request, response),
              "fixed-silence-at-19200")],
    diagnose=_diagnose_timing, compare=_close_enough, procedure=TRANSACTION_TIME, boundary=_timing_boundary)
