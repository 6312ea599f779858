"""Exercises of notebook 14: Beyond the eight functions."""

from __future__ import annotations

from typing import Any

from ..errors import ModbusTimeoutError
from ..links.loopback import loopback_serial
from ..master import Master
from ..pdu import mask_write
from ..slave import Slave
from .build import build_exercise
from .core import exercise, field_diagnosis, int_answer, line_after_tries
from .misconceptions import diagnose


@exercise("14.1", "a register after Mask Write Register",
          hint="keep the bits where the AND mask has 1 (current & and_mask), take the OR mask's bits where "
               "it has 0 (or_mask & ~and_mask), and OR the two.",
          accepts=[0x0135, 309], refuses=[(0x00A5 | 0x0130, "mask-write-or"), (0x0005, None),
                                          (0x00A0, "mask-roles-swapped")])
def _check_14_1(answer: Any) -> str | None:
    expected = mask_write(0x00A5, 0x000F, 0x0130)
    got = int_answer(answer, "a register value")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    named = (diagnose(("mask-write-or", "mask-roles-swapped"), 0x00A5, 0x000F, 0x0130, got)
             or field_diagnosis(got, expected))
    if named:
        return named
    return f"0x{got:04X} is not what the register holds after FC 22."


build_exercise(
    "14.2", "write FC 22's arithmetic",
    reference=mask_write,
    inputs=lambda rng: (rng.randrange(0x10000), rng.randrange(0x10000), rng.randrange(0x10000)),
    edge_cases=[(0x12, 0xF2, 0x25), (0, 0, 0xFFFF), (0xFFFF, 0xFFFF, 0), (0xFFFF, 0, 0)],
    hint="bit by bit: where the AND mask has a 1 the register keeps its bit; where it has a 0 the bit comes "
         "from the OR mask. The result stays a 16-bit value.",
    refuses=[(lambda current, and_mask, or_mask: (current & and_mask) | or_mask, "mask-write-or")],
    diagnose=lambda args, expected, got: diagnose(("mask-write-or", "mask-roles-swapped"), *args, got))
line_after_tries("14.2", "return ((current & and_mask) | (or_mask & ~and_mask)) & 0xFFFF")


def counters_scenario() -> dict[str, int]:
    """Exercise 14.3's bus, run: unit 1's FC 8 counters after the story the exercise tells.

    Units 1 and 2 share a 19200-baud line.  The master clears unit 1's counters, reads unit 1 twice,
    reads unit 2 once, sends unit 1 a read whose request gets one bit flipped on the wire, and then asks
    unit 1 for its bus message count (sub-function 0x0B).  Returns that count, and unit 1's checksum
    error count (0x0C) read after it."""
    link = loopback_serial([Slave(unit=1), Slave(unit=2)], baudrate=19200)
    master = Master(link, timeout=0.1)
    master.diagnostics(unit=1, sub_function=0x0A)
    master.read_holding_registers(unit=1, address=0, count=1)
    master.read_holding_registers(unit=1, address=0, count=1)
    master.read_holding_registers(unit=2, address=0, count=1)
    link.faults.flip_bits(1, target="request")
    try:
        master.read_holding_registers(unit=1, address=0, count=1)
    except ModbusTimeoutError:
        pass
    heard = master.diagnostics(unit=1, sub_function=0x0B)
    errors = master.diagnostics(unit=1, sub_function=0x0C)
    return {"heard": int(heard), "checksum_errors": int(errors)}  # type: ignore[arg-type]


@exercise("14.3", "a bus message count, predicted",
          hint="count every message on the line that unit 1 received with a good CRC since the clear: "
               "requests for it, requests for the other unit, the other unit's responses, and the 0x0B "
               "request itself; a frame with a bad CRC goes to 0x0C instead.",
          accepts=[5, 0x05], refuses=[(6, "damaged-message-counted"), (4, None), (3, "others-not-heard")])
def _check_14_3(answer: Any) -> str | None:
    got = int_answer(answer, "a number of messages")
    if isinstance(got, str):
        return got
    expected = counters_scenario()["heard"]
    if got == expected:
        return None
    if got == expected + 1:
        return diagnose("damaged-message-counted", got, expected) + " Here the damaged request is the one."
    if got == expected - 1:
        return ("one message is missing: unit 1 also hears unit 2's response (every node hears the line), "
                "and the 0x0B request is itself a message, counted before it is answered.")
    named = diagnose("others-not-heard", got, 3)
    if named:
        return named + (" Those are only the requests for unit 1; it also hears the request for unit 2 and "
                        "its response.")
    return f"{got} is not the count unit 1 reports: list every frame on the line after the clear."
