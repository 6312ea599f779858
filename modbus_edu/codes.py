"""The codes of the Modbus application protocol and the constants every layer shares.

This module imports nothing from the library, so any module can import it: the function codes and their
titles, the exception codes and their meanings, the two roles a message can play, the sizes of a PDU and
of the Modbus/TCP MBAP header, and the hex notation messages and dissections use.
"""

from __future__ import annotations

import functools
import struct
from enum import IntEnum

__all__ = [
    "FunctionCode",
    "ExceptionCode",
    "SERIAL_LINE_ONLY",
    "WRITE_FUNCTIONS",
    "BROADCAST_FUNCTIONS",
    "exception_meaning",
    "function_title",
    "ROLES",
    "MAX_PDU_SIZE",
    "MBAP_HEADER_SIZE",
    "MIN_MBAP_LENGTH",
    "MAX_MBAP_LENGTH",
    "MBAP",
]

MAX_PDU_SIZE = 253
"""A serial ADU is at most 256 bytes: 1 address + 253 PDU + 2 CRC."""

MBAP_HEADER_SIZE = 7
"""The MBAP header: transaction id (2) + protocol id (2) + length (2) + unit id (1)."""
MIN_MBAP_LENGTH = 2
"""Smallest legal MBAP length field: the unit id and a function code."""
MAX_MBAP_LENGTH = 1 + MAX_PDU_SIZE
"""Largest legal MBAP length field: the unit id and the largest PDU (254)."""
MBAP = struct.Struct(">HHHB")
"""The MBAP header's layout: transaction id, protocol id, length, unit id, all big-endian."""

ROLES: tuple[str, ...] = ("request", "response")
"""Which way a message travels: master to slave (request) or slave to master (response)."""


class FunctionCode(IntEnum):
    """The public function codes this library implements: the eight everyday ones, 7, 17, 22, 23, 24, 43."""

    READ_COILS = 0x01
    READ_DISCRETE_INPUTS = 0x02
    READ_HOLDING_REGISTERS = 0x03
    READ_INPUT_REGISTERS = 0x04
    WRITE_SINGLE_COIL = 0x05
    WRITE_SINGLE_REGISTER = 0x06
    READ_EXCEPTION_STATUS = 0x07
    DIAGNOSTICS = 0x08
    GET_COMM_EVENT_COUNTER = 0x0B
    GET_COMM_EVENT_LOG = 0x0C
    WRITE_MULTIPLE_COILS = 0x0F
    WRITE_MULTIPLE_REGISTERS = 0x10
    REPORT_SERVER_ID = 0x11
    READ_FILE_RECORD = 0x14
    WRITE_FILE_RECORD = 0x15
    MASK_WRITE_REGISTER = 0x16
    READ_WRITE_MULTIPLE_REGISTERS = 0x17
    READ_FIFO_QUEUE = 0x18
    READ_DEVICE_IDENTIFICATION = 0x2B

    @property
    def title(self) -> str:
        """The specification's name, e.g. ``"Read Holding Registers"``."""
        return _TITLES.get(self.value) or self.name.replace("_", " ").title()


SERIAL_LINE_ONLY = frozenset({0x07, 0x08, 0x0B, 0x0C, 0x11})
"""Functions the specification defines for serial lines only (a gateway may still pass them on)."""

WRITE_FUNCTIONS = frozenset({0x05, 0x06, 0x0F, 0x10, 0x15, 0x16, 0x17})
"""Functions that write to the data model (FC 23 reads as well): the ones a role's write grant covers."""

BROADCAST_FUNCTIONS = frozenset({0x05, 0x06, 0x0F, 0x10, 0x15, 0x16})
"""The functions a broadcast (unit 0 on a serial line) may carry: the writes that answer nothing but an
echo or an acknowledgement (FC 5, 6, 15, 16, 21 and 22).

The *Modbus over Serial Line* guide (V1.02, section 2.1) says broadcast requests are necessarily writing
commands, and no slave answers one.  So a read (FC 1, 2, 3, 4, 7, 11, 12, 17, 20, 24, 43) has no meaning
as a broadcast: what it asks for could never come back.  FC 23, Read/Write Multiple Registers, is
left out by this library's choice, not by the guide (which does not name it): its point is the registers
it reads back in the same transaction, which a broadcast can never return, so the course's slave does not
carry out its write half either; another device may.  FC 8, Diagnostics, is a
conversation with one device (an echo, a counter, a mode) and is not a broadcast either.

The master refuses to send a broadcast of any other function (:class:`~modbus_edu.errors.ConfigError`),
and a slave that hears one neither acts on it nor answers.  The older Modicon guide (PI-MBUS-300)
allows a broadcast of FC 5, 6, 15 and 16 only: a device built to it ignores a broadcast FC 21 or 22."""

_TITLES = {0x11: "Report Server ID", 0x17: "Read/Write Multiple Registers", 0x18: "Read FIFO Queue"}


class ExceptionCode(IntEnum):
    """Exception codes a server puts in an exception response."""

    ILLEGAL_FUNCTION = 0x01
    ILLEGAL_DATA_ADDRESS = 0x02
    ILLEGAL_DATA_VALUE = 0x03
    SERVER_DEVICE_FAILURE = 0x04
    ACKNOWLEDGE = 0x05
    SERVER_DEVICE_BUSY = 0x06
    NEGATIVE_ACKNOWLEDGE = 0x07
    MEMORY_PARITY_ERROR = 0x08
    GATEWAY_PATH_UNAVAILABLE = 0x0A
    GATEWAY_TARGET_DEVICE_FAILED_TO_RESPOND = 0x0B

    @property
    def meaning(self) -> str:
        """The specification's explanation, in one sentence."""
        return _EXCEPTION_MEANINGS[self]

    @property
    def title(self) -> str:
        return self.name.replace("_", " ").lower()


_EXCEPTION_MEANINGS = {
    ExceptionCode.ILLEGAL_FUNCTION: "illegal function: the server does not support this function code",
    ExceptionCode.ILLEGAL_DATA_ADDRESS: (
        "illegal data address: the address, or address plus quantity, is not in the server's data"),
    ExceptionCode.ILLEGAL_DATA_VALUE: (
        "illegal data value: a value in the request (a quantity, a coil value) is not allowed"),
    ExceptionCode.SERVER_DEVICE_FAILURE: (
        "server device failure: an unrecoverable error occurred while the server performed the action"),
    ExceptionCode.ACKNOWLEDGE: "acknowledge: the request was accepted but will take a long time",
    ExceptionCode.SERVER_DEVICE_BUSY: (
        "server device busy: the server is busy with a long command, retry later"),
    ExceptionCode.NEGATIVE_ACKNOWLEDGE: (
        "negative acknowledge: the server cannot perform the program function (from the older Modicon "
        "guide; the current specification no longer lists code 07)"),
    ExceptionCode.MEMORY_PARITY_ERROR: (
        "memory parity error: reading a file record (FC 20 or 21, reference type 6), the server found its "
        "extended file memory failed a consistency check"),
    ExceptionCode.GATEWAY_PATH_UNAVAILABLE: (
        "gateway path unavailable: the gateway could not set up a path to the target"),
    ExceptionCode.GATEWAY_TARGET_DEVICE_FAILED_TO_RESPOND: (
        "gateway target device failed to respond: no response came from the target device"),
}


def exception_meaning(code: int) -> str:
    """The meaning of an exception code, also for codes the specification does not define."""
    try:
        return ExceptionCode(code).meaning
    except ValueError:
        return f"code 0x{code:02X} is not defined by the specification (vendor specific?)"


@functools.lru_cache(maxsize=512)
def function_title(function: int) -> str:
    """``"Read Holding Registers"`` for 3; a neutral name for codes this library does not implement.
    Remembered: every summary and dissection asks it."""
    try:
        return FunctionCode(function).title
    except ValueError:
        return f"function 0x{function:02X}"


def _hex(data: bytes | bytearray | memoryview) -> str:
    """``01 03 00`` style hex of some bytes: upper case, a space between bytes."""
    return bytes(data).hex(" ").upper()


def _printable(text: str) -> str:
    """A device's text for a reader: printable characters as they are, every other one (a control
    character, an escape sequence's ESC, a line break, a bidirectional override) and the backslash
    escaped as Python writes them (``\\x1b``, ``\\n``, ``\\u202e``), so a device can neither clear a
    terminal nor forge a line of output."""
    return "".join(char if char.isprintable() and char != "\\" else repr(char)[1:-1] for char in text)
