"""Exercises of notebook 13: Troubleshooting lab."""

from __future__ import annotations

import math
import random
from typing import Any

from ...datamodel import DataBank, parse_reference
from ...devices.arduino import ArduinoSlave, expected_answered_fraction
from ...errors import ConfigError
from ...framing import RtuFrame, TcpFrame, parse_hex
from ...links.loopback import loopback_serial
from ...pdu import ReadHoldingRegistersRequest
from ...slave import Slave
from ...values import ORDERS, decode_value, encode_value
from ..build import build_exercise
from ..core import (
    address_diagnosis,
    as_bytes,
    compare_rtu_frame,
    exercise,
    field_diagnosis,
    int_answer,
    real_answer,
)
from ..diagnosis.misconceptions import ORDER_WORDS, diagnose
from ..diagnosis.misconceptions import name as misconception
from ..diagnosis.procedure import Perturbation, Procedure

_SILENT_CAUSES = ("wrong unit id", "wrong baud rate or parity", "no slave on the line")
_LAB_SEED = 13


def _silent_wires(seed: int = _LAB_SEED) -> tuple[dict[str, Any], dict[str, str]]:
    """Three wires whose master only gets timeouts, each for another reason; and the reasons."""
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
    rng = random.Random(seed)
    order = "CDAB"
    amperes = round(rng.uniform(120.0, 180.0), 3)
    bank = DataBank(sparse=True)
    bank.holding_registers.declare(0, 2, encode_value(round(amperes * 1000), "uint32", order))
    return Slave(unit=1, bank=bank, name="current sensor"), order, amperes


POLL_13_6 = {"timeout": 1.0, "interval": 5.0, "reply": 0.013}
"""Exercise 13.6's poll: the master's timeout and poll interval, and the reply's time on the wire (s)."""


def _slow_board(seed: int = _LAB_SEED) -> Any:
    """An Arduino-style slave whose main loop is slower than the master's 1 s timeout."""
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
          accepts=[{"A": "wrong unit id", "B": "no slave on the line", "C": "wrong baud rate or parity"},
                   {"A": "Wrong unit id", "B": " no slave on the line", "C": "WRONG BAUD RATE OR PARITY"}],
          refuses=[({"A": "wrong unit id", "B": "wrong unit id", "C": "wrong unit id"}, None),
                   ({"A": "no slave on the line", "B": "wrong unit id", "C": "wrong baud rate or parity"},
                    "causes-swapped"),
                   ({"A": "wrong unit id", "B": "wrong baud rate or parity", "C": "no slave on the line"},
                    "causes-swapped")])
def _check_13_1(answer: Any) -> str | None:
    truth = _silent_wires()[1]
    if not isinstance(answer, dict) or set(answer) != set(truth):
        return "answer with a dict {'A': cause, 'B': cause, 'C': cause}."
    given = {name: str(answer[name]).strip().lower() for name in sorted(truth)}
    for name, got in given.items():
        if got not in _SILENT_CAUSES:
            return f"wire {name}: {answer[name]!r} is not one of {', '.join(map(repr, _SILENT_CAUSES))}."
    wrong = [name for name in sorted(truth) if given[name] != truth[name]]
    if not wrong:
        return None
    first = wrong[0]
    against = f"wire {first} cannot be '{given[first]}': {_TRACE_AGAINST[given[first]]}"
    swapped = [(a, b) for a in wrong for b in wrong
               if a < b and given[a] == truth[b] and given[b] == truth[a]]
    if swapped:
        a, b = swapped[0]
        return f"{misconception('causes-swapped')} Here wires {a} and {b} have each other's cause; {against}"
    return against + "."


_TRACE_AGAINST = {
    "no slave on the line": "no slave leaves no trace at all, and this wire's slave has counted or logged "
                            "something",
    "wrong unit id": "a wrong unit id leaves requests for another address in the slave's other_unit "
                     "counter, and this wire's slave has none",
    "wrong baud rate or parity": "a wrong baud rate or parity leaves garbled bytes in the slave's "
                                 "checksum_errors, and this wire's slave has none",
}
"""Why each cause does not fit a wire whose cause is another: the trace that cause would leave."""


@exercise("13.2", "a current of 292 880 amperes",
          hint="read holding registers 0-1 and decode them with mb.decode_value(registers, 'uint32', order) "
               "for the orders 'ABCD' and 'CDAB'; only one gives a current a sensor could measure (in mA).",
          accepts=[("CDAB", 135.541), ("CDAB", 135.5), ("cdab", 135.54), ["CDAB", 135.6]],
          refuses=[(("ABCD", 292880.386), "word-order"), (("CDAB", 135541), "milliamperes-for-amperes"),
                   (("CDAB", 135.4), None), (("CDAB", 136), None)])
def _check_13_2(answer: Any) -> str | None:
    _device, order, amperes = _word_order_device()
    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair: (order, current in amperes), e.g. ('ABCD', 12.5)."
    got_order, got_amperes = answer
    if str(got_order).upper() != order:
        used = str(got_order).upper()
        if used not in ORDER_WORDS:
            return f"{got_order!r} is not a word order: try 'ABCD' and 'CDAB'."
        return misconception("word-order", used=used, used_words=ORDER_WORDS[used], right="another order") + \
            " With this one the current makes no physical sense."
    value = real_answer(got_amperes, "the current")
    if isinstance(value, str):
        return value
    named = diagnose("milliamperes-for-amperes", value, amperes) or diagnose("scale-wrong", value,
                                                                               round(amperes * 1000), amperes)
    if named:
        return named
    if abs(value - amperes) > CURRENT_TOLERANCE:
        return f"{value:g} A is not what those registers carry (to {CURRENT_TOLERANCE:g} A)."
    return None


CURRENT_TOLERANCE = 0.06
"""Exercise 13.2 takes the current to 0.1 A, as a clamp meter shows it: 135.5 for 135.541 A."""


@exercise("13.3", "a value from the register after it",
          hint=("a reference number counts from 1, the address in the frame from 0; the leading 4 only "
                "names the table.",
                "take the number after the 4 and subtract one.",
                "40108 is address 107: mb.parse_reference('40108').address."),
          accepts=[20, 0x14],
          refuses=[(21, "one-based-address"), (40021, "reference-number"), (40020, "reference-number"),
                   (19, "address-one-too-low")])
def _check_13_3(answer: Any) -> str | None:
    expected = parse_reference("40021").address
    got = int_answer(answer, "the address")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    named = address_diagnosis(got, expected) or field_diagnosis(got, expected)
    if named:
        return named
    return f"address {got} is not where register 40021 is."


@exercise("13.4", "the transaction ids that do not match",
          hint=("a spec-following server reads the MBAP transaction id high byte first, whatever order the "
                "client meant.",
                "read the first two bytes as one big-endian number "
                "(mb.TcpFrame.decode(...).transaction_id); a correct client writes its number the same way.",
                "a capture starting 05 00 carries transaction id 0x0500 = 1280; a client meaning 5 sends 00 "
                "05."),
          accepts=[(768, "00 03"), (0x0300, b"\x00\x03"), [768, "0003"]],
          refuses=[((3, "00 03"), "mbap-little-endian"), ((768, "03 00"), "mbap-little-endian"),
                   ((769, "00 03"), None)])
def _check_13_4(answer: Any) -> str | None:
    captured = TcpFrame.decode(parse_hex("03 00 00 00 00 06 01 03 00 00 00 01"), role="request")
    correct = TcpFrame(transaction_id=3, unit=1, pdu=ReadHoldingRegistersRequest(address=0, count=1)).encode()
    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair: (the id the server reads, 'XX XX')."
    seen, first_two = answer
    if seen != captured.transaction_id:
        named = diagnose("mbap-little-endian", seen, captured.transaction_id)
        if named:
            return named + " 3 is what the client meant; the server reads 03 00."
        return (field_diagnosis(seen, captured.transaction_id)
                or f"the server does not read {seen!r} from 03 00.")
    got = as_bytes(first_two)
    if got != correct[:2]:
        return (diagnose("mbap-little-endian", got, correct[:2])
                or f"{got.hex(' ').upper()} is not transaction id 3 written high byte first.")
    return None


@exercise("13.5", "a slave that never answers one tool",
          hint="mb.explain(frame) says what CRC it computed; compare it with the two bytes the frame "
               "carries. The CRC goes low byte first.",
          accepts=["01 03 00 00 00 01 84 0A", "010300000001840a", bytes.fromhex("01 03 00 00 00 01 84 0A")],
          refuses=[("01 03 00 00 00 01 0A 84", "crc-swapped"), ("01 03 00 01 00 01 D5 CA",
                                                                "one-based-address"),
                   ("01 03 00 00 00 01", "crc-forgotten"), ("01 03 00 00 00 02 C4 0B", None),
                   ("84 0A", "part-of-answer"), ("01 03 00 00 00 01 84 11", "crc-initial-zero")])
def _check_13_5(answer: Any) -> str | None:
    expected = RtuFrame(unit=1, pdu=ReadHoldingRegistersRequest(address=0, count=1)).encode()
    return compare_rtu_frame(
        answer, expected, "your corrected frame", "That is the frame as the faulty tool sent it.")


@exercise("13.6", "estimate a slave's loop time",
          hint=("a request is answered only if the slave's loop reaches it within the master's timeout, so "
                "the share answered tells the loop time.",
                "poll many times (300, one every 5 s, 1 s timeout) and take the fraction answered: it is "
                "about (timeout - reply time) / loop time, with a reply of 0.013 s.",
                "60% answered with a 2 s timeout: a loop of about (2 - 0.013) / 0.6 = 3.3 s."),
          accepts=[2.2, 2.0, 2.4, 2],
          refuses=[(2200, "milliseconds-for-seconds"), (1.0, "given-figure"), (5.0, "given-figure"),
                   (3.0, None)])
def _check_13_6(answer: Any) -> str | None:
    board = _slow_board()
    got = real_answer(answer, "a loop time in seconds")
    if isinstance(got, str):
        return got
    if abs(got - board.loop_time) <= 0.25 * board.loop_time:
        return None
    if abs(got / 1000 - board.loop_time) <= 0.25 * board.loop_time:
        return misconception("milliseconds-for-seconds")
    answered = expected_answered_fraction(board.loop_time, POLL_13_6["timeout"], POLL_13_6["reply"])
    named = diagnose("given-figure", got, {"1 s, the master's timeout": POLL_13_6["timeout"],
                                           "5 s, the poll interval": POLL_13_6["interval"],
                                           "the share of requests answered": answered})
    if named:
        return named
    if got < board.loop_time:
        return (f"{got:g} s is too short: a loop that fast would answer more requests in time than this "
                "one does.")
    return f"{got:g} s is too long: a loop that slow would answer fewer requests than this one does."


def _orders_giving(registers: list, expected: float) -> frozenset:
    """Every word order in which ``registers`` decode to ``expected`` (to float32 precision)."""
    return frozenset(order for order in ORDERS
                     if math.isclose(decode_value(registers, "float32", order), expected, rel_tol=1e-6))


def _order_inputs(rng) -> tuple:
    value = round(rng.uniform(-500.0, 500.0), 1)
    registers = list(encode_value(value, "float32", rng.choice(ORDERS)))
    if rng.random() < 0.15:
        value = value + 1000.0  # the registers carry another value: no order fits
    return registers, value


def _order_accepted(expected: frozenset, got) -> bool:
    return (isinstance(got, str) and got in expected) if expected else got is None


def _diagnose_order(args, expected, got) -> str | None:
    registers, value = args
    if not expected:
        named = diagnose("an-order-when-none-fits", got, expected)
        return f"no order gives {value:g} from these registers: return None." + (f" {named}" if named else "")
    if got is None:
        near = [decode_value(registers, "float32", order) for order in sorted(expected)]
        return diagnose("float-compared-exactly", got, near[0]) if near[0] != value else None
    if got in ORDERS:
        return (misconception("word-order", used=got, used_words=ORDER_WORDS[got],
                              right=_orders_in_words(expected))
                + f" In {got} order these registers hold {decode_value(registers, 'float32', got):g}.")
    return f"return one of the names in mb.ORDERS, such as {sorted(expected)[0]!r}."


def _exact_order(registers: list, expected: float) -> str | None:
    """A plausible wrong answer: the first order whose value equals the expected one exactly (==)."""
    return next((order for order in ORDERS if decode_value(registers, "float32", order) == expected), None)


def _close_order(registers: list, expected: float, orders: tuple = ORDERS) -> str | None:
    """The first of ``orders`` in which the registers decode to ``expected`` (math.isclose), or None."""
    return next((order for order in orders
                 if math.isclose(decode_value(registers, "float32", order), expected, rel_tol=1e-6)), None)


ORDER_FOUND = Procedure("the word order the registers carry a value in", _close_order, (
    Perturbation("always-ABCD", "ABCD whatever the registers", "word-order", lambda registers, value: "ABCD"),
    Perturbation("always-CDAB", "CDAB whatever the registers", "word-order", lambda registers, value: "CDAB"),
    Perturbation("exact", "the values compared with ==", "float-compared-exactly", _exact_order,
                 returns_none=True),
    Perturbation("two-orders", "only ABCD and CDAB tried", None,
                 lambda registers, value: _close_order(registers, value, ("ABCD", "CDAB")),
                 returns_none=True),
    Perturbation("larger-register", "the order guessed from which register is larger", "word-order",
                 lambda registers, value: "CDAB" if registers[0] < registers[1] else "ABCD"),
    Perturbation("exact-or-abcd", "the values compared with ==, and ABCD when none is equal",
                 "an-order-when-none-fits", lambda registers, value: _exact_order(registers, value) or "ABCD",
                 also="float-compared-exactly"),
    Perturbation("order-when-none", "an order named even when none fits", "an-order-when-none-fits",
                 lambda registers, value: _close_order(registers, value) or "ABCD"),
), same=lambda mine, got: mine == got and type(mine) is type(got))
"""13.7's procedure: the first order that fits (any fitting order is right; these are the slips' orders)."""


def _orders_in_words(expected: frozenset) -> str:
    """The orders a 13.7 answer may name, in plain words: 'CDAB', 'ABCD or BADC', or None."""
    return " or ".join(repr(order) for order in sorted(expected)) if expected else "None (no order fits)"


build_exercise(
    "13.7", "find a device's word order",
    reference=_orders_giving, inputs=_order_inputs,
    edge_cases=[([0x4396, 0x8000], 301.0), ([0x8000, 0x4396], 301.0), ([0, 0], 0.0), ([0x4396, 0x8000], 7.0)],
    hint=("a device sends its float32 in one of four word orders; the right one is the order in which the "
          "registers decode to the value the display shows.",
          "mb.ORDERS lists the four orders and mb.decode_value(registers, 'float32', order) decodes in one; "
          "compare with math.isclose(..., rel_tol=1e-6), since floats rarely match exactly; None when none "
          "fits.",
          "registers [0x0000, 0x4120] give 10.0 read as CDAB and a tiny number as ABCD: a display showing "
          "10.0 means CDAB."),
    refuses=[(lambda registers, expected: "ABCD", "word-order"),
             (lambda registers, expected: "CDAB", "word-order"), (_exact_order, "float-compared-exactly"),
             (lambda registers, expected: _exact_order(registers, expected) or "ABCD",
              "an-order-when-none-fits")],
    compare=_order_accepted, diagnose=_diagnose_order, show_expected=_orders_in_words, procedure=ORDER_FOUND)
