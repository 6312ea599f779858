"""What a gateway does to an RTU request (15.2), as a procedure: check the CRC, drop it, put an MBAP header
in front.  Its CRC check is the CRC's own procedure (:data:`.procedures.CRC`): a gateway whose CRC starts
its register at 0, or reads the carried CRC high byte first, refuses the frames whose CRC is right and
forwards some that are damaged; which frames it refuses tells which CRC slip it makes.  The header's slips
are the MBAP's (the transaction id low byte first, a length that counts the PDU alone, the CRC kept).

An answer here is the Modbus/TCP frame, or :data:`REFUSED` where the function raises: the evidence is every
frame the learner's function was given, refused or not.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ...crc import crc16
from .crcsteps import CRC_STEPS
from .procedure import REFUSED, Perturbation, Procedure


def _tcp(body: bytes, tid: int, *, tid_order: str = "big", more: int = 0) -> bytes:
    return tid.to_bytes(2, tid_order) + bytes(2) + (len(body) + more).to_bytes(2, "big") + body


def _gateway(check: Callable[[bytes], bool] | None,
             build: Callable[[bytes, int], bytes] = lambda frame, tid: _tcp(frame[:-2], tid)):
    """A gateway that refuses a frame unless ``check(frame)`` (None: forwards every frame), and builds its
    Modbus/TCP frame with ``build(frame, tid)``; None (no evidence) for a frame too short to hold a
    unit, a function and a CRC."""

    def forward(frame: bytes, tid: int) -> Any:
        if len(frame) < 4:
            return None
        if check is not None and not check(frame):
            return REFUSED
        return build(frame, tid)

    return forward


def _carried(frame: bytes, order: str = "little") -> int:
    return int.from_bytes(frame[-2:], order)


def _crc_check(compute: Callable[[bytes], Any], order: str = "little") -> Callable[[bytes], bool]:
    return lambda frame: compute(frame[:-2]) == _carried(frame, order)


_RIGHT_CHECK = _crc_check(crc16)

CHECKS = ("initial-zero", "unreflected", "unreflected-right-shift", "final-xor", "address-left-out")
"""The CRC's slips (:data:`.crcsteps.CRC_STEPS`) a gateway's CRC check may make."""


def separating_frames(body: bytes) -> list[bytes]:
    """``body`` (a unit and a PDU) with the CRC each slip of the CRC check computes, and with the right CRC
    high byte first: frames the library refuses, each forwarded by one wrong check alone, so that which
    ones a learner's gateway forwards tells its slip."""
    frames = [body + compute(body).to_bytes(2, "little") for key, _step, _misconception, compute in CRC_STEPS
              if key in CHECKS]
    return [*frames, body + crc16(body).to_bytes(2, "big")]

_BUILDS = (
    ("crc-kept", "the CRC kept after the PDU", "crc-on-tcp",
     lambda frame, tid: _tcp(frame[:-2], tid, more=2) + frame[-2:]),
    ("crc-kept-length-without", "the CRC kept after the PDU, the length without it", "crc-on-tcp",
     lambda frame, tid: _tcp(frame[:-2], tid) + frame[-2:]),
    ("tid-little-endian", "the transaction id low byte first", "mbap-little-endian",
     lambda frame, tid: _tcp(frame[:-2], tid, tid_order="little")),
    ("length-pdu-only", "a length that counts the PDU alone", "mbap-length",
     lambda frame, tid: _tcp(frame[:-2], tid, more=-1)),
    ("length-whole", "a length that counts the whole frame", "mbap-length",
     lambda frame, tid: _tcp(frame[:-2], tid, more=6)),
    ("unit-left-out", "the unit identifier left out", "unit-missing",
     lambda frame, tid: _tcp(frame[1:-2], tid)),
    ("unit-left-out-length-kept", "the unit identifier left out, the length still counting it",
     "unit-missing",
     lambda frame, tid: _tcp(frame[1:-2], tid, more=1)),
    ("length-missing", "the length field left out", "mbap-length-missing",
     lambda frame, tid: tid.to_bytes(2, "big") + bytes(2) + frame[:-2]),
)
"""The slips of the Modbus/TCP frame a gateway builds: key, step, misconception, build(RTU frame, tid)."""

GATEWAY = Procedure(
    "what a gateway does to an RTU request",
    _gateway(_RIGHT_CHECK),
    tuple(
        [Perturbation(f"crc-{key}", f"a CRC check with {step}", misconception, _gateway(_crc_check(compute)))
         for key, step, misconception, compute in CRC_STEPS if key in CHECKS]
        + [
            Perturbation("crc-read-high-first", "a CRC check that reads the carried CRC high byte first",
                         "crc-swapped", _gateway(_crc_check(crc16, "big"))),
            Perturbation("crc-unchecked", "every frame forwarded, its CRC never checked",
                         "invalid-input-accepted", _gateway(None)),
        ]
        + [Perturbation(key, step, misconception, _gateway(_RIGHT_CHECK, build))
           for key, step, misconception, build in _BUILDS]
        + [Perturbation(f"{key}+unchecked", f"{step}, and every frame forwarded unchecked", misconception,
                        _gateway(None, build), also="invalid-input-accepted")
           for key, step, misconception, build in _BUILDS]),
    same=lambda mine, got: (mine == got if isinstance(mine, str) else
                            isinstance(got, (bytes, bytearray)) and bytes(got) == mine),
    refusals=True,
)
"""The gateway of 15.2: (an RTU request frame, a transaction id) -> its Modbus/TCP frame, or REFUSED."""

