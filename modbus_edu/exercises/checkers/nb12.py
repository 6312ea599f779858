"""Exercises of notebook 12: The test tool."""

from __future__ import annotations

from typing import Any

from ...crc import crc_bytes
from ...datamodel import DataBank
from ...devices.generators import increment_fill
from ...framing import TcpFrame
from ...pdu import ReadHoldingRegistersRequest
from ..build import build_exercise
from ..core import (
    address_diagnosis,
    as_bytes,
    exercise,
    field_diagnosis,
    right_value_in_another_form,
    tcp_frame_diagnosis,
)
from ..diagnosis.misconceptions import diagnose


def _testtool() -> Any:
    """The TestTool widget class."""
    from ...widgets.testtool import TestTool  # the course extra (ipywidgets): imported when a learner checks

    return TestTool


@exercise("12.1", "a grid cell in hex",
          hint=("the fill starts at the first value and adds the increment at each address; the hex display "
                "writes a register as 0x and four hex digits.",
                "address n holds first + n x increment; mb.format_registers([value], 'hex') shows it as the "
                "grid does.",
                "first value 20, increment 4: address 3 holds 32, shown '0x0020'."),
          accepts=["0x0096", "0X0096", " 0x0096 ", "0x96", "0096"],
          refuses=[("0x008C", "one-based-address"), ("150", "another-form"), ("0x0097", None)])
def _check_12_1(answer: Any) -> str | None:
    bank = DataBank(sparse=False)
    increment_fill(bank.holding_registers, 0, 10, 100, 10)
    if not isinstance(answer, str):
        return "answer with the text the grid shows, a string such as '0x0001'."
    got = answer.strip()
    value = bank.holding_registers[5]
    if _hex_value(got) == value:
        return None  # any spelling of the value in hex: 0x0096, 0x96, 0096
    if got == str(value):
        return right_value_in_another_form("the grid's hex display does: 0x and four hex digits")
    if _hex_value(got) == value - 10:
        return address_diagnosis(5, 4) + " Address 5 is the sixth cell."
    named = field_diagnosis(_hex_value(got), value)
    if named:
        return named
    return f"{got!r} is not how the hex display shows address 5."


def _hex_value(text: str) -> int | None:
    """The number ``text`` writes in hex (with or without 0x, in either case), or None."""
    digits = text[2:] if text[:2].lower() == "0x" else text
    if not digits or len(digits) > 8 or any(c not in "0123456789abcdefABCDEF" for c in digits):
        return None
    return int(digits, 16)


_12_2_KEYS = ("role", "unit", "function", "address", "length", "interval")


@exercise("12.2", "set up a master tool",
          hint=("a master tool asks: give it its role, the device (unit), the table (the function that "
                "reads it), the first address, how many (length) and how often (interval, seconds).",
                "input registers are read with function 4; TestTool takes each setting as a keyword: unit=, "
                "function=, address=, length=, interval=.",
                "2 holding registers of unit 3 from address 100 every 2 s: TestTool('rtu_master', unit=3, "
                "function=3, address=100, length=2, interval=2.0)."),
          accepts=[{"role": "rtu_master", "unit": 7, "function": 4, "address": 10, "length": 4,
                    "interval": 0.5},
                   {"role": "tcp_client", "unit": 7, "function": 4, "address": 10, "length": 4,
                    "interval": 0.5}],
          refuses=[({"role": "rtu_master", "unit": 7, "function": 3, "address": 10, "length": 4,
                     "interval": 0.5},
                    "holding-for-input"),
                   ({"role": "rtu_master", "unit": 7, "function": 4, "address": 11, "length": 4,
                     "interval": 0.5},
                    "one-based-address"),
                   ({"role": "rtu_slave", "unit": 7, "function": 4, "address": 10, "length": 4,
                     "interval": 0.5},
                    "slave-for-master")])
def _check_12_2(answer: Any) -> str | None:
    TestTool = _testtool()  # noqa: N806 (a class)
    config = answer.config() if isinstance(answer, TestTool) else answer
    if not isinstance(config, dict):
        return "give the TestTool or its config() dict."
    reference = TestTool("rtu_master", unit=7, function=4, address=10, length=4, interval=0.5).config()
    reference_roles = ("rtu_master", "tcp_client")
    for key in _12_2_KEYS:
        if key not in config:
            return f"the configuration has no {key!r}."
    if config["role"] not in reference_roles:
        return diagnose("slave-for-master", config["role"]) or (
            f"a {config['role']!r} answers requests; the tool must ask: a master (or a client).")
    for key in _12_2_KEYS[1:]:
        if config[key] != reference[key]:
            named = (diagnose("holding-for-input", config[key], reference[key]) if key == "function" else
                     address_diagnosis(config[key], reference[key]) if key == "address" else
                     diagnose("milliseconds-for-seconds", config[key], reference[key]) if key == "interval"
                     else None)
            return named or f"{key} is {config[key]!r}, it should be {reference[key]!r}."
    return None


@exercise("12.3", "the transaction id after three polls",
          hint=("a client gives each new request the next transaction id: count the ids the three polls use.",
                "the first poll carries the starting id, each poll one more; the MBAP header writes the id "
                "in two bytes, high byte first.",
                "a client that starts at 510 and polls twice uses 510 and 511; its next request carries 512 "
                "= 0x0200 and starts 02 00."),
          accepts=[(283, "01 1B"), (283, b"\x01\x1b"), [0x11B, "011b"]],
          refuses=[((283, "1B 01"), "mbap-little-endian"), ((282, "01 1A"), "last-transaction-id"),
                   ((283, "01 1C"), None)])
def _check_12_3(answer: Any) -> str | None:
    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair: (transaction_id, 'XX XX')."
    TestTool = _testtool()  # noqa: N806 (a class)
    server = TestTool("tcp_server", unit=1, length=1)
    client = TestTool("tcp_client", partner=server, unit=1, length=1, transaction_id=280)
    client.run_polls(3)
    tid = client.transaction_id.value
    client.run_polls(1)
    first_two = client.traffic.search(direction="tx")[-1].data[:2]
    got_tid, got_bytes = answer
    if got_tid != tid:
        return (diagnose(("last-transaction-id", "mbap-little-endian"), got_tid, tid)
                or field_diagnosis(got_tid, tid)
                or f"the next transaction id is not {got_tid!r}.")
    got = as_bytes(got_bytes)
    named = diagnose("mbap-little-endian", got, first_two)
    if named:
        return named
    if got != first_two:
        return f"{got.hex(' ').upper()} is not how {tid} starts the request."
    return None


def _read_request(tid: int, unit: int, address: int, count: int) -> bytes:
    return TcpFrame(transaction_id=tid, unit=unit,
                    pdu=ReadHoldingRegistersRequest(address=address, count=count)).encode()


def _request_inputs(rng) -> tuple:
    count = rng.randrange(1, 126)
    return rng.randrange(65536), rng.randrange(256), rng.randrange(0, 65536 - count + 1), count


def _diagnose_request(args, expected, got) -> str | None:
    return tcp_frame_diagnosis(got, expected)


def _with_crc(frame: bytes) -> bytes:
    """A plausible wrong Modbus/TCP frame: a CRC appended, as on a serial line."""
    return frame + crc_bytes(frame[6:])


build_exercise(
    "12.4", "your own master's read request",
    reference=_read_request, inputs=_request_inputs,
    edge_cases=[(280, 1, 0, 1), (1, 1, 0, 10), (65535, 255, 65535, 1),
                # both ends of every field: tid 0, unit 0, the largest count, an address whose bytes differ
                (0, 0, 0, 125), (256, 247, 0x1234, 125)],
    hint="MBAP header (tid, 0, length 6, unit), then the PDU 03, address, count: every 2-byte field high "
         "byte first.",
    refuses=[(lambda tid, unit, address, count: tid.to_bytes(2, "little") + bytes([0, 0, 0, 6, unit, 3])
              + address.to_bytes(2, "big") + count.to_bytes(2, "big"), "mbap-little-endian"),
             (lambda tid, unit, address, count: _with_crc(_read_request(tid, unit, address, count)),
              "crc-on-tcp")],
    diagnose=_diagnose_request)
