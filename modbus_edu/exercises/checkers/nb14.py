"""Exercises of notebook 14: Beyond the eight functions."""

from __future__ import annotations

from typing import Any

from ...errors import ModbusTimeoutError
from ...links.loopback import loopback_serial
from ...master import Master
from ...pdu import mask_write
from ...slave import Slave
from ..build import build_exercise
from ..core import exercise, field_diagnosis, int_answer, line_after_tries
from ..diagnosis.misconceptions import diagnose
from ..diagnosis.procedure import say
from ..diagnosis.procedures import message_count_procedure

MASK_SLIPS = ("or-mask-forgotten", "mask-write-or", "mask-roles-swapped")
"""The catalogue's slips of FC 22's two masks, tried on every mask exercise."""


@exercise("14.1", "a register after Mask Write Register",
          hint=("FC 22 works bit by bit: where the AND mask has a 1 the register keeps its bit; where it "
                "has a 0 the bit comes from the OR mask.",
                "write the three values in binary, one under the other, and go through the bit positions: "
                "AND-mask bit 1, copy the register's bit; 0, copy the OR mask's bit.",
                "the specification's example: register 0x12 = 0001 0010, AND 0xF2 = 1111 0010, OR 0x25 = "
                "0010 0101: bits 7-4 and 1 kept, bits 3, 2 and 0 from the OR mask: 0001 0111 = 0x17."),
          accepts=[0x0135, 309], refuses=[(0x00A5 | 0x0130, "mask-write-or"), (0x0005, "or-mask-forgotten"),
                                          (0x00A0, "mask-roles-swapped")])
def _check_14_1(answer: Any) -> str | None:
    expected = mask_write(0x00A5, 0x000F, 0x0130)
    got = int_answer(answer, "a register value")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    named = (diagnose(MASK_SLIPS, 0x00A5, 0x000F, 0x0130, got)
             or field_diagnosis(got, expected))
    if named:
        return named
    return f"0x{got:04X} is not what the register holds after FC 22."


build_exercise(
    "14.2", "write FC 22's arithmetic",
    reference=mask_write,
    inputs=lambda rng: (rng.randrange(0x10000), rng.randrange(0x10000), rng.randrange(0x10000)),
    edge_cases=[(0x12, 0xF2, 0x25), (0, 0, 0xFFFF), (0xFFFF, 0xFFFF, 0), (0xFFFF, 0, 0),
                # masks that separate each slip: alternate bits, and an OR mask with bits the AND mask keeps
                (0x5555, 0xAAAA, 0xFFFF), (0x0F0F, 0xFF00, 0x00FF)],
    hint="bit by bit: where the AND mask has a 1 the register keeps its bit; where it has a 0 the bit comes "
         "from the OR mask. The result stays a 16-bit value.",
    refuses=[(lambda current, and_mask, or_mask: (current & and_mask) | or_mask, "mask-write-or"),
             (lambda current, and_mask, or_mask: current & and_mask, "or-mask-forgotten")],
    diagnose=lambda args, expected, got: diagnose(MASK_SLIPS, *args, got))
line_after_tries("14.2", "build it from two parts and OR them: the bits kept from the register (AND it with "
                 "the AND mask) and the bits taken from the OR mask where the AND mask has 0 (the OR mask "
                 "ANDed with the AND mask's inverse, ~, kept to 16 bits).",
                 "8 bits for short: register 0x5A, AND 0xF0, OR 0x33: kept 0x5A & 0xF0 = 0x50; inverse "
                 "0x0F; taken 0x33 & 0x0F = 0x03; result 0x50 | 0x03 = 0x53.")


UNIT1_READS_14_3 = 2
"""How many sound reads of unit 1 exercise 14.3's story makes: unit 1 sends a response to each."""


def counters_scenario() -> dict[str, int]:
    """Exercise 14.3's bus, run: unit 1's FC 8 counters after the story the exercise tells.

    Units 1 and 2 share a 19200-baud line.  The master clears unit 1's counters, reads unit 1 twice,
    reads unit 2 once, sends unit 1 a read whose request gets one bit flipped on the wire, and then asks
    unit 1 for its bus message count (sub-function 0x0B).  Returns that count, and unit 1's checksum
    error count (0x0C) read after it."""
    link = loopback_serial([Slave(unit=1), Slave(unit=2)], baudrate=19200)
    master = Master(link, timeout=0.1)
    master.diagnostics(unit=1, sub_function=0x0A)
    for _ in range(UNIT1_READS_14_3):
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
          hint=("apply the rule of the exercise frame by frame: which frames does unit 1 receive after the "
                "clear, and which of them have a good CRC?",
                "write the line's frames after the clear in order, each request and each response; unit 1 "
                "receives all of them but its own responses (it sends those); a frame with a bad CRC goes "
                "to 0x0C, not here.",
                "after a clear, one read of unit 3 and one of unit 4, then 0x0B to unit 3: unit 3 counts "
                "the request for it, the request for unit 4, unit 4's response and the 0x0B request: 4."),
          accepts=[5, 0x05], refuses=[(6, None), (4, None),
                                      (3, "others-not-heard"), (7, "own-frames-counted")])
def _check_14_3(answer: Any) -> str | None:
    got = int_answer(answer, "a number of messages")
    if isinstance(got, str):
        return got
    expected = counters_scenario()["heard"]
    if got == expected:
        return None
    procedure = message_count_procedure(expected, own_responses=UNIT1_READS_14_3,
                                        own_requests=UNIT1_READS_14_3)
    found = procedure.reproducing([((), got)])
    if found:
        extra = {-1: "one message too few", 1: "one message too many"}.get(got - expected)
        if extra and len({item.misconception for item in found}) > 1:
            return (f"{got} counts {extra}: " + " or ".join(item.step for item in found)
                    + "? The number alone cannot say which; list the frames after the clear, one by one.")
        return say(found)
    return f"{got} is not the count unit 1 reports: list every frame on the line after the clear."
