"""Exercises of notebook 08: Serial timing."""

from __future__ import annotations

from typing import Any

from .build import build_exercise
from .core import close, exercise, number_answer, real_answer


@exercise("08.1", "the silence that ends a frame at 4800 baud 8E1",
          hint="t3.5 is 3.5 character times; with even parity a character is 11 bits (start, 8 data, "
               "parity, stop). mb.SerialTiming(baudrate=..., parity=...).t35 gives it in seconds.",
          wrong=3.5 * 10 / 4800)
def _check_08_1(answer: Any) -> str | None:
    from ..links.wire import SerialTiming

    timing = SerialTiming(baudrate=4800, parity="E", stopbits=1)
    expected = timing.t35
    got = real_answer(answer, "a silence in seconds")
    if isinstance(got, str):
        return got
    if close(got, 3.5 * SerialTiming(baudrate=4800).char_time):
        return "you counted 10 bits per character; even parity adds a bit: 11."
    if close(got, timing.char_time):
        return "that is one character time; the silence that ends a frame is 3.5 of them."
    return number_answer(got, expected, decimals=6, unit="s", what="3.5 characters of 8E1 at 4800 baud")


@exercise("08.2", "transactions per second reading 10 registers at 19200 baud",
          hint="request 8 bytes, response 5 + 2 x 10 bytes, plus two silences of 3.5 characters; "
               "1 / mb.SerialTiming(19200).transaction_time(request_bytes, response_bytes).",
          wrong=19200 / 10 / (8 + 25))
def _check_08_2(answer: Any) -> str | None:
    from ..links.wire import SerialTiming

    timing = SerialTiming(baudrate=19200)
    expected = 1 / timing.transaction_time(8, 5 + 2 * 10)
    got = real_answer(answer, "a number of transactions per second")
    if isinstance(got, str):
        return got
    if close(got, 1 / timing.frame_time(8 + 25)):
        return "you left out the two silences of 3.5 characters (after the request and after the response)."
    if close(got, 1 / timing.transaction_time(8, 7)):
        return "that is for one register; the response to a read of 10 registers has 5 + 2 x 10 bytes."
    if close(got, 1 / expected):
        return "that is the time of one transaction in seconds; the question asks how many fit in a second."
    return number_answer(got, expected, decimals=1, what="the most transactions per second")


@exercise("08.3", "which pauses inside a frame leave it unanswered",
          hint="a pause of more than 1.5 character times breaks an RTU frame, and one of 3.5 or more cuts "
               "it in two; either way the slave gets no valid request.",
          wrong=[5.0])
def _check_08_3(answer: Any) -> str | None:
    from ..errors import ModbusError as _Error
    from ..links.loopback import loopback_serial
    from ..master import Master
    from ..slave import Slave

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


def _transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int,
                      response_bytes: int) -> float:
    from ..links.wire import SerialTiming

    return SerialTiming(baudrate=baudrate, parity=parity, stopbits=stopbits).transaction_time(
        request_bytes, response_bytes)


def _timing_inputs(rng) -> tuple:
    return (rng.choice([1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200]), rng.choice("NEO"),
            rng.choice([1, 2]), rng.randrange(8, 256), rng.randrange(5, 256))


def _close_enough(expected: float, got) -> bool:
    if isinstance(got, bool) or not isinstance(got, (int, float)):
        return False
    return abs(got - expected) <= 1e-9 + 1e-9 * expected


def _diagnose_timing(args, expected, got) -> str | None:
    if not isinstance(got, (int, float)):
        return None
    baudrate, parity, stopbits, request, response = args
    bits = 1 + 8 + (parity != "N") + stopbits
    char = bits / baudrate
    if abs(got - (request + response) * char) < 1e-9:
        return "you left out the two 3.5-character silences."
    if baudrate > 19200 and abs(got - (request + 3.5 + response + 3.5) * char) < 1e-9:
        return "above 19200 baud the silence is fixed at 1.75 ms, not 3.5 character times."
    if abs(got * 1000 - expected) < 1e-6 or abs(got - expected * 1000) < 1e-3:
        return "give seconds, not milliseconds."
    if abs(got - (request + 3.5 + response + 3.5) * (10 / baudrate)) < 1e-9 and bits != 10:
        return f"a character of {parity} parity and {stopbits} stop bit(s) has {bits} bits, not 10."
    return None


build_exercise(
    "08.4", "write the transaction time yourself",
    reference=_transaction_time, inputs=_timing_inputs,
    edge_cases=[(9600, "N", 1, 8, 7), (19200, "E", 1, 8, 255), (38400, "N", 2, 8, 7), (115200, "N", 1, 8, 7)],
    hint="bits per character = 1 start + 8 data + 1 if parity + stop bits; a character takes bits / baudrate "
         "seconds; t3.5 is 3.5 characters up to 19200 baud and 0.00175 s above; the time is request + t3.5 + "
         "response + t3.5.",
    wrong=lambda baudrate, parity, stopbits, request, response: (request + response + 7) * 10 / baudrate,
    diagnose=_diagnose_timing, compare=_close_enough)
