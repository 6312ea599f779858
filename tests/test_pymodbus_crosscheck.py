"""Interoperability with pymodbus 3.16: every function, both roles, both directions, RTU, ASCII and TCP.

For each PDU class, hypothesis draws valid fields, a unit and a transaction id.  Then, in each mode:

* ours -> pymodbus: the frame we encode is decoded by pymodbus's framer (``FramerRTU``, ``FramerAscii``,
  ``FramerSocket`` with ``DecodePDU(is_server=<request role>)``) to a pymodbus PDU with the same fields;
* pymodbus -> ours: the frame pymodbus builds from the same fields (``buildFrame``) is byte for byte the
  frame we build, and our strict decoder turns it back into the same PDU, unit and transaction id.
"""

from __future__ import annotations

import logging

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pymodbus.framer import FramerAscii, FramerRTU, FramerSocket
from pymodbus.pdu import DecodePDU
from pymodbus.pdu import bit_message as pm_bits
from pymodbus.pdu import register_message as pm_regs
from pymodbus.pdu.exceptionresponse import ExceptionResponse as PmExceptionResponse

from modbus_edu import pdu as ours
from modbus_edu.framing import AsciiFrame, RtuFrame, TcpFrame

logging.getLogger("pymodbus").setLevel(logging.CRITICAL)

SETTINGS = settings(max_examples=100, deadline=None)

PM_FRAMERS = {"rtu": FramerRTU, "ascii": FramerAscii, "tcp": FramerSocket}


# --- strategies for our PDUs ---------------------------------------------------------------------------
def bits_of(data: bytes) -> list[bool]:
    return [bool(byte >> bit & 1) for byte in data for bit in range(8)]


def bit_lists(n: int) -> st.SearchStrategy[list[bool]]:
    return st.binary(min_size=(n + 7) // 8, max_size=(n + 7) // 8).map(lambda b: bits_of(b)[:n])


def span(limit: int) -> st.SearchStrategy[tuple[int, int]]:
    return st.integers(1, limit).flatmap(lambda n: st.tuples(st.integers(0, 65536 - n), st.just(n)))


ADDRESS = st.integers(0, 0xFFFF)
REGISTER = st.integers(0, 0xFFFF)


def read_request(cls, limit):
    return span(limit).map(lambda ac: cls(address=ac[0], count=ac[1]))


def write_response(cls, limit):
    return span(limit).map(lambda ac: cls(address=ac[0], count=ac[1]))


def single(cls, values):
    return st.builds(cls, address=ADDRESS, value=values)


STRATEGIES = {
    ours.ReadCoilsRequest: read_request(ours.ReadCoilsRequest, 2000),
    ours.ReadDiscreteInputsRequest: read_request(ours.ReadDiscreteInputsRequest, 2000),
    ours.ReadHoldingRegistersRequest: read_request(ours.ReadHoldingRegistersRequest, 125),
    ours.ReadInputRegistersRequest: read_request(ours.ReadInputRegistersRequest, 125),
    ours.ReadCoilsResponse: st.integers(1, 2000).flatmap(bit_lists).map(
        lambda b: ours.ReadCoilsResponse(bits=b)),
    ours.ReadDiscreteInputsResponse: st.integers(1, 2000).flatmap(bit_lists).map(
        lambda b: ours.ReadDiscreteInputsResponse(bits=b)),
    ours.ReadHoldingRegistersResponse: st.lists(REGISTER, min_size=1, max_size=125).map(
        lambda r: ours.ReadHoldingRegistersResponse(registers=r)),
    ours.ReadInputRegistersResponse: st.lists(REGISTER, min_size=1, max_size=125).map(
        lambda r: ours.ReadInputRegistersResponse(registers=r)),
    ours.WriteSingleCoilRequest: single(ours.WriteSingleCoilRequest, st.booleans()),
    ours.WriteSingleCoilResponse: single(ours.WriteSingleCoilResponse, st.booleans()),
    ours.WriteSingleRegisterRequest: single(ours.WriteSingleRegisterRequest, REGISTER),
    ours.WriteSingleRegisterResponse: single(ours.WriteSingleRegisterResponse, REGISTER),
    ours.WriteMultipleCoilsRequest: st.integers(1, 1968).flatmap(
        lambda n: st.tuples(st.integers(0, 65536 - n), bit_lists(n))).map(
        lambda av: ours.WriteMultipleCoilsRequest(address=av[0], values=av[1])),
    ours.WriteMultipleRegistersRequest: st.integers(1, 123).flatmap(
        lambda n: st.tuples(st.integers(0, 65536 - n), st.lists(REGISTER, min_size=n, max_size=n))).map(
        lambda av: ours.WriteMultipleRegistersRequest(address=av[0], values=av[1])),
    ours.WriteMultipleCoilsResponse: write_response(ours.WriteMultipleCoilsResponse, 1968),
    ours.WriteMultipleRegistersResponse: write_response(ours.WriteMultipleRegistersResponse, 123),
    ours.ExceptionResponse: st.builds(
        ours.ExceptionResponse, function=st.sampled_from([1, 2, 3, 4, 5, 6, 15, 16, 7, 0x2B, 0x7F]),
        code=st.integers(1, 255)),
}


# --- the same PDU in pymodbus's objects --------------------------------------------------------------
def padded(bits) -> list[bool]:
    bits = list(bits)
    return bits + [False] * (-len(bits) % 8)


def to_pymodbus(pdu: ours.Pdu, unit: int, tid: int):
    """Build pymodbus's PDU object for the same fields."""
    ids = {"dev_id": unit, "transaction_id": tid}
    name = type(pdu).__name__
    if isinstance(pdu, ours.ExceptionResponse):
        return PmExceptionResponse(pdu.function, pdu.code, device_id=unit, transaction=tid)
    cls = getattr(pm_bits, name, None) or getattr(pm_regs, name)
    if isinstance(pdu, (ours.ReadCoilsRequest, ours.ReadDiscreteInputsRequest,
                        ours.ReadHoldingRegistersRequest, ours.ReadInputRegistersRequest,
                        ours.WriteMultipleCoilsResponse, ours.WriteMultipleRegistersResponse)):
        return cls(address=pdu.address, count=pdu.count, **ids)
    if isinstance(pdu, (ours.ReadCoilsResponse, ours.ReadDiscreteInputsResponse)):
        return cls(bits=list(pdu.bits), **ids)
    if isinstance(pdu, (ours.ReadHoldingRegistersResponse, ours.ReadInputRegistersResponse)):
        return cls(registers=list(pdu.registers), **ids)
    if isinstance(pdu, (ours.WriteSingleCoilRequest, ours.WriteSingleCoilResponse)):
        return cls(address=pdu.address, bits=[pdu.value], **ids)
    if isinstance(pdu, (ours.WriteSingleRegisterRequest, ours.WriteSingleRegisterResponse)):
        return cls(address=pdu.address, registers=[pdu.value], **ids)
    if isinstance(pdu, ours.WriteMultipleCoilsRequest):
        return cls(address=pdu.address, bits=list(pdu.values), **ids)
    if isinstance(pdu, ours.WriteMultipleRegistersRequest):
        return cls(address=pdu.address, registers=list(pdu.values), **ids)
    raise AssertionError(f"no pymodbus counterpart for {name}")


def assert_same_fields(pm, pdu: ours.Pdu) -> None:
    """A PDU pymodbus decoded carries the fields of ours."""
    assert type(pm).__name__ == type(pdu).__name__
    assert pm.function_code == pdu.function_code
    if isinstance(pdu, ours.ExceptionResponse):
        assert pm.exception_code == pdu.code
    elif isinstance(pdu, (ours.ReadCoilsResponse, ours.ReadDiscreteInputsResponse)):
        assert list(pm.bits) == padded(pdu.bits)
    elif isinstance(pdu, (ours.ReadHoldingRegistersResponse, ours.ReadInputRegistersResponse)):
        assert list(pm.registers) == list(pdu.registers)
    elif isinstance(pdu, (ours.WriteSingleCoilRequest, ours.WriteSingleCoilResponse)):
        assert (pm.address, list(pm.bits)) == (pdu.address, [pdu.value])
    elif isinstance(pdu, (ours.WriteSingleRegisterRequest, ours.WriteSingleRegisterResponse)):
        assert (pm.address, list(pm.registers)) == (pdu.address, [pdu.value])
    elif isinstance(pdu, ours.WriteMultipleCoilsRequest):
        assert (pm.address, pm.count, list(pm.bits)) == (pdu.address, len(pdu.values), list(pdu.values))
    elif isinstance(pdu, ours.WriteMultipleRegistersRequest):
        assert (pm.address, pm.count, list(pm.registers)) == (pdu.address, len(pdu.values), list(pdu.values))
    else:  # read requests, write-multiple responses
        assert (pm.address, pm.count) == (pdu.address, pdu.count)


def our_frame(mode: str, unit: int, tid: int, pdu: ours.Pdu):
    if mode == "rtu":
        return RtuFrame(unit=unit, pdu=pdu)
    if mode == "ascii":
        return AsciiFrame(unit=unit, pdu=pdu)
    return TcpFrame(transaction_id=tid, unit=unit, pdu=pdu)


def decode_ours(mode: str, data: bytes, role: str):
    return {"rtu": RtuFrame, "ascii": AsciiFrame, "tcp": TcpFrame}[mode].decode(data, role=role)


def expected_after_decoding(pdu: ours.Pdu) -> ours.Pdu:
    """What our decoder gives back for the bytes of ``pdu``: read-bits responses hold their padding."""
    if isinstance(pdu, (ours.ReadCoilsResponse, ours.ReadDiscreteInputsResponse)):
        return type(pdu)(bits=padded(pdu.bits))
    return pdu


# --- the cross-check ---------------------------------------------------------------------------------
CLASSES = list(STRATEGIES)


def test_every_function_and_role_is_checked() -> None:
    assert {(c.function_code, c.role) for c in CLASSES if c is not ours.ExceptionResponse} == {
        (fc, role) for fc in (1, 2, 3, 4, 5, 6, 15, 16) for role in ("request", "response")}


def crosscheck(pdu: ours.Pdu, serial_unit: int, tcp_unit: int, tid: int) -> None:
    role = pdu.role
    for mode in ("rtu", "ascii", "tcp"):
        unit = tcp_unit if mode == "tcp" else serial_unit
        frame_tid = tid if mode == "tcp" else 0
        framer = PM_FRAMERS[mode](DecodePDU(is_server=role == "request"))

        # ours -> pymodbus
        data = our_frame(mode, unit, tid, pdu).encode()
        used, pm = framer.handleFrame(data, 0, 0)
        assert pm is not None, f"pymodbus could not decode our {mode} frame {data.hex(' ')}"
        assert used == len(data)
        assert pm.dev_id == unit
        assert pm.transaction_id == frame_tid
        assert_same_fields(pm, pdu)

        # pymodbus -> ours
        built = framer.buildFrame(to_pymodbus(pdu, unit, frame_tid))
        assert built == data, f"{mode}: pymodbus built {built.hex(' ')}, we built {data.hex(' ')}"
        frame = decode_ours(mode, built, role)
        assert frame.unit == unit
        if mode == "tcp":
            assert frame.transaction_id == tid
            assert frame.protocol_id == 0
        assert frame.pdu == expected_after_decoding(pdu)
        assert type(frame.pdu) is type(pdu)


@pytest.mark.parametrize("cls", CLASSES, ids=lambda c: c.__name__)
@SETTINGS
@given(data=st.data())
def test_crosscheck(cls, data) -> None:
    pdu = data.draw(STRATEGIES[cls], label="pdu")
    serial_unit = data.draw(st.integers(0, 247), label="serial unit")
    tcp_unit = data.draw(st.integers(0, 255), label="tcp unit")
    tid = data.draw(st.integers(0, 0xFFFF), label="transaction id")
    crosscheck(pdu, serial_unit, tcp_unit, tid)


@pytest.mark.parametrize(
    ("pdu", "unit"),
    [
        (ours.ReadHoldingRegistersRequest(address=0, count=1), 1),
        (ours.ReadHoldingRegistersRequest(address=65535, count=1), 247),
        (ours.ReadCoilsRequest(address=65536 - 2000, count=2000), 0),
        (ours.ReadCoilsResponse(bits=[True] * 2000), 1),
        (ours.ReadHoldingRegistersResponse(registers=[0xFFFF] * 125), 1),
        (ours.WriteMultipleCoilsRequest(address=0, values=[True] * 1968), 17),
        (ours.WriteMultipleRegistersRequest(address=65536 - 123, values=list(range(123))), 17),
        (ours.WriteSingleCoilRequest(address=0xFFFF, value=False), 1),
        (ours.ExceptionResponse(function=0x7F, code=0xFF), 1),
    ],
    ids=lambda x: type(x).__name__ if isinstance(x, ours.Pdu) else str(x),
)
def test_crosscheck_edges(pdu: ours.Pdu, unit: int) -> None:
    crosscheck(pdu, unit, 255, 0xFFFF)
    crosscheck(pdu, unit, 0, 0)


def test_pymodbus_accepts_our_vectors_and_we_accept_pymodbus_frames() -> None:
    # the RTU frame of VECTORS.md both ways, spelled out once
    data = bytes.fromhex("0103000000018 40A".replace(" ", ""))
    used, pm = FramerRTU(DecodePDU(is_server=True)).handleFrame(data, 0, 0)
    assert (pm.dev_id, pm.address, pm.count) == (1, 0, 1)
    built = FramerRTU(DecodePDU(is_server=True)).buildFrame(
        pm_regs.ReadHoldingRegistersRequest(address=0, count=1, dev_id=1))
    assert built == data
    assert RtuFrame.decode(built, role="request").pdu == ours.ReadHoldingRegistersRequest(address=0, count=1)
