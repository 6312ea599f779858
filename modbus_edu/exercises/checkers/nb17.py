"""Exercises of notebook 17: Captures and security."""

from __future__ import annotations

from typing import Any

from ... import pdu as p
from ...security import course_roles
from ..build import build_exercise
from ..core import exercise, int_answer, show
from ..diagnosis.misconceptions import diagnose, name
from ..diagnosis.procedures import field_value_procedure

#: The request of exercise 17.1, as a capture shows it.
CAPTURED_WRITE = bytes.fromhex("00 07 00 00 00 06 01 06 00 0a 01 f4")


@exercise("17.1", "the value a captured Modbus/TCP write sets",
          hint="after the 7-byte MBAP header comes the PDU: function code 06, then the register address "
               "(2 bytes) and the value (2 bytes), each high byte first. mb.explain(frame, 'tcp', "
               "'request') shows every field.",
          accepts=[500, 0x01F4],
          refuses=[(10, "another-field"), (0xF401, "field-low-byte-first"), (6, "another-field"),
                   (7, "another-field"), (0x000A, "another-field"), (0x01F5, None)])
def _check_17_1(answer: Any) -> str | None:
    got = int_answer(answer, "a register value")
    if isinstance(got, str):
        return got
    if got == 500:
        return None
    named = field_value_procedure(bytes.fromhex("01 F4"), "value", {
        "register address (00 0A)": 10, "function code": 6, "transaction id": 7, "length field": 6,
        "unit identifier": 1}, register=True).explain([((), got)])
    if named:
        return f"{named} It is not the value: the value is the last two bytes, after the address."
    return f"{show(got)} is not the value: read the last two bytes of the frame, high byte first."


@exercise("17.2", "an operator's write of 3 registers at address 98",
          hint=("a write is allowed only when every address it touches is in the role's range: list the "
                "addresses this request writes.",
                "FC 16 of N registers from address A writes A to A + N - 1: compare the last one with the "
                "operator's range in the course's role table. A refused request gets the code for a "
                "function the server will not carry out for this client.",
                "an operator's FC 15 of 10 coils from address 95 writes 95 to 104: 100 to 104 are outside "
                "0..99, so it is refused; FC 6 at address 99 is allowed (answer 0)."),
          accepts=[1, 0x01],
          refuses=[(0, "first-address-only"), (2, "exception-code-confused"),
                   (0x90, "exception-function-for-code"), (3, "exception-code-confused")])
def _check_17_2(answer: Any) -> str | None:
    got = int_answer(answer, "an exception code (or 0 for allowed)")
    if isinstance(got, str):
        return got
    if got == 1:
        return None
    if got == 0:
        return (diagnose("first-address-only", _request(16, 98, 3), 99, None)
                + " Here the write touches 98, 99 and 100: address 100 is past the operator's 0..99.")
    if got == 2:
        return (name("exception-code-confused") + " Here 02 (illegal data address) is what a slave answers "
                "for an address it does not have; the role check answers before the slave sees the request.")
    named = diagnose("exception-function-for-code", got, 16, 1)
    if named:
        return f"{named} Here the code is the byte after 0x{got:02X}."
    named = diagnose("exception-code-confused", got, 1)
    if named:
        return f"{named} {show(got)} is not the answer: a refused role gets 01."
    return f"{show(got)} is not the answer: 0 if allowed, else the exception code the server sends."


#: The function codes and roles the build exercise 17.3 draws from.
_FUNCTIONS = (1, 2, 3, 4, 5, 6, 15, 16)
_ROLES = ("viewer", "operator", "engineer", "guest")


def _reference(pdu: bytes, role: str) -> bytes | None:
    return course_roles().decide(pdu, role).response


def _request(function: int, address: int, count: int) -> bytes:
    if function in (1, 2, 3, 4):
        cls = {1: p.ReadCoilsRequest, 2: p.ReadDiscreteInputsRequest, 3: p.ReadHoldingRegistersRequest,
               4: p.ReadInputRegistersRequest}[function]
        return cls(address=address, count=count).encode()
    if function == 5:
        return p.WriteSingleCoilRequest(address=address, value=bool(count % 2)).encode()
    if function == 6:
        return p.WriteSingleRegisterRequest(address=address, value=count).encode()
    if function == 15:
        return p.WriteMultipleCoilsRequest(address=address, values=[True] * count).encode()
    return p.WriteMultipleRegistersRequest(address=address, values=list(range(count))).encode()


def _draw(rng: Any) -> tuple[bytes, str]:
    function = rng.choice(_FUNCTIONS)
    address = rng.choice((rng.randrange(0, 100), rng.randrange(90, 110), rng.randrange(0, 60000)))
    count = rng.randrange(1, 11)
    return _request(function, address, count), rng.choice(_ROLES)


def _first_address_only(pdu: bytes, role: str) -> bytes | None:
    """A wrong answer: the operator's writes judged by their first address alone."""
    allowed = {"engineer": True, "viewer": pdu[0] <= 4,
               "operator": pdu[0] <= 4 or int.from_bytes(pdu[1:3], "big") <= 99}.get(role, False)
    return None if allowed else bytes([pdu[0] | 0x80, 0x01])


def _viewer_only(pdu: bytes, role: str) -> bytes | None:
    """A wrong answer: only a viewer's writes are refused."""
    return None if role != "viewer" or pdu[0] <= 4 else bytes([pdu[0] | 0x80, 0x01])


def _common_only(pdu: bytes, role: str) -> bytes | None:
    """A wrong answer: the engineer, too, refused the function codes above the common 1..24."""
    if role == "engineer":
        return None if pdu[0] <= 24 else bytes([pdu[0] | 0x80, 0x01])
    return _reference(pdu, role)


def _diagnose(args: Any, expected: Any, got: Any) -> str | None:
    pdu, role = args
    if isinstance(got, int) and not isinstance(got, bool):
        return "return the whole exception PDU as bytes (function code + 0x80, then 01), not a number."
    if expected is None and got is not None:
        last = int.from_bytes(pdu[1:3], "big") + int.from_bytes(pdu[3:5], "big") - 1
        named = diagnose("range-one-extra", last + 1, last) if role == "operator" and pdu[0] in (15,
                                                                                                 16) else None
        return f"{role} may send this request: return None." + (f" {named}" if named else "")
    if expected is not None and got is None:
        if role == "operator" and pdu[0] in (15, 16):
            return diagnose("first-address-only", pdu, 99, got) or (
                "an operator may write 0..99 only, and a multiple write touches address .. address + "
                "quantity - 1: check the last address too.")
        return f"{role} may not send this request: return bytes([function | 0x80, 0x01])."
    if isinstance(got, (bytes, bytearray)) and len(got) == 2 and got[1] != 1:
        return ("a refused request gets exception 01, illegal function (the role may not use it). "
                + (diagnose("exception-code-confused", got[1], 1) or ""))
    return None


build_exercise(
    "17.3", "decide a request against the course's role table",
    reference=_reference,
    inputs=_draw,
    edge_cases=[(_request(3, 0, 1), "viewer"), (_request(6, 5, 1), "viewer"),
                (_request(6, 99, 1), "operator"), (_request(6, 100, 1), "operator"),
                (_request(16, 98, 2), "operator"), (_request(16, 98, 3), "operator"),
                (_request(15, 0, 100), "operator"), (_request(16, 60000, 10), "engineer"),
                (_request(4, 0, 1), "guest"),
                # multiple coils past 99, and a quantity whose high byte counts (256 coils from 0)
                (_request(15, 98, 3), "operator"), (_request(15, 0, 256), "operator"),
                # an engineer does everything: diagnostics (8), a user-defined code (65), above the 24 of
                # the common functions; anyone else nothing, not even a device identification (43/14)
                (bytes.fromhex("08 00 00 12 34"), "engineer"), (bytes.fromhex("41 00 00"), "engineer"),
                (bytes.fromhex("2B 0E 01 00"), "guest")],
    hint=("pdu[0] is the function code; the address is in bytes 1-2 and, for 15 and 16, the quantity in "
          "bytes 3-4, both high byte first. A viewer reads (1-4); an operator reads, and writes (5, 6, 15, "
          "16) within 0..99; an engineer does everything; anyone else nothing.",
          "a multiple write touches address .. address + quantity - 1: the last address decides. A refusal "
          "is exception 01, the function code with its top bit set and then 01.",
          "an operator's FC 16 from 97 with quantity 3 writes 97, 98, 99: allowed; with quantity 4 it "
          "reaches 100: refused with 90 01."),
    diagnose=_diagnose,
    refuses=[(_first_address_only, "first-address-only"), (_viewer_only, None), (_common_only, None)])
