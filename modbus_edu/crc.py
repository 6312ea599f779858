"""Error checks of the serial modes: CRC-16/MODBUS (RTU) and LRC (ASCII).

CRC-16/MODBUS
-------------
The 16-bit register starts at 0xFFFF.  For every byte of the message:

1. XOR the byte into the low half of the register;
2. eight times: look at the lowest bit (the LSB), shift the register one place right, and if the bit
   that fell out was 1, XOR the register with 0xA001.

0xA001 is the generator polynomial 0x8005 written backwards (bit-reflected), because Modbus works
through each byte least significant bit first, as a UART sends it.  What is left in the register is the
CRC.  On the wire its **low byte goes first**, then the high byte: ``crc16(b"123456789") == 0x4B37``
is sent as ``37 4B``.

The table method does the eight shift/XOR steps of a byte in one look-up: the entry for index *i* is
what eight steps do to the value *i*.  256 entries of 16 bits (512 bytes of memory) buy roughly eight
times fewer operations per byte, the trade-off that the robot test-tool paper describes.

LRC
---
The longitudinal redundancy check of ASCII mode: add the bytes (not the hex characters) of address and
PDU, keep the low 8 bits, and take the two's complement.  Adding the LRC to that sum gives 0 mod 256.
"""

from __future__ import annotations

import sys
from collections.abc import Iterator
from dataclasses import dataclass

from .errors import ValueRangeError, shown

POLYNOMIAL = 0xA001
"""The CRC-16/MODBUS polynomial 0x8005, bit-reflected."""

INITIAL = 0xFFFF
"""The CRC register's starting value."""


def build_crc_table(polynomial: int = POLYNOMIAL) -> tuple[int, ...]:
    """Build the 256-entry look-up table: entry *i* is eight shift/XOR steps applied to *i*."""
    table = []
    for index in range(256):
        register = index
        for _ in range(8):
            if register & 1:
                register = (register >> 1) ^ polynomial
            else:
                register >>= 1
        table.append(register)
    return tuple(table)


CRC_TABLE: tuple[int, ...] = build_crc_table()
"""The 256 precomputed values; ``CRC_TABLE[1] == 0xC0C1``."""


def _as_bytes(data: bytes | bytearray | memoryview | list[int]) -> bytes:
    if isinstance(data, (bytes, bytearray, memoryview)):
        return bytes(data)
    if isinstance(data, (int, str)):  # bytes(5) would be five zero bytes, and a str has no byte values
        raise ValueRangeError(f"a checksum is computed over bytes, not {type(data).__name__} {shown(data)}: "
                              "give bytes (b'\\x01\\x03', bytes.fromhex('01 03')) or a list of ints 0..255")
    try:
        return bytes(data)
    except (TypeError, ValueError):
        raise ValueRangeError(f"cannot read {shown(data)} as bytes: each item must be an int 0..255"
                              ) from None


def crc16_bitwise(data: bytes) -> int:
    """CRC-16/MODBUS computed bit by bit, exactly as the specification describes it."""
    register = INITIAL
    for byte in _as_bytes(data):
        register ^= byte
        for _ in range(8):
            if register & 1:
                register = (register >> 1) ^ POLYNOMIAL
            else:
                register >>= 1
    return register


_WORD_TABLE: list[int] | None = None


def _word_table() -> list[int]:
    """65536 entries: what two table steps with zero data bytes do to a 16-bit register value.

    XORing two message bytes into the 16-bit register and then doing 16 shift/XOR steps leaves a value
    that depends on the register alone, so one look-up can stand for two bytes.  Built once, on first
    use, from CRC_TABLE (about 30 ms and 0.5 MiB); it changes nothing but the speed on long inputs.
    """
    global _WORD_TABLE
    if _WORD_TABLE is None:
        table = CRC_TABLE
        entries = []
        for register in range(65536):
            register = (register >> 8) ^ table[register & 0xFF]
            register = (register >> 8) ^ table[register & 0xFF]
            entries.append(register)
        _WORD_TABLE = entries
    return _WORD_TABLE


def crc16(data: bytes) -> int:
    """CRC-16/MODBUS of ``data`` by the table method (the register value; low byte goes first on the wire).

    >>> hex(crc16(b"123456789"))
    '0x4b37'

    Inputs of 256 bytes or more are taken two bytes per look-up (see ``_word_table``); the result is the
    same as ``crc16_bitwise``.
    """
    if not isinstance(data, (bytes, bytearray)):
        data = _as_bytes(data)
    register = INITIAL
    table = CRC_TABLE
    length = len(data)
    if length >= 256 and sys.byteorder == "little":
        words = _word_table()
        even = length & ~1
        for word in memoryview(data)[:even].cast("H"):
            register = words[register ^ word]
        data = data[even:]
    for byte in data:
        register = (register >> 8) ^ table[(register ^ byte) & 0xFF]
    return register


def crc_bytes(data: bytes) -> bytes:
    """The two CRC bytes in wire order (low byte first), ready to append to an RTU frame."""
    return crc16(data).to_bytes(2, "little")


@dataclass(frozen=True)
class CrcStep:
    """One step of the bitwise CRC.

    ``action`` is ``"xor_byte"`` (the message byte XORed into the register), ``"shift"`` (the LSB was 0:
    shift right only) or ``"shift_xor"`` (the LSB was 1: shift right, then XOR with 0xA001).
    ``bit`` is None for the XOR-in step and 0..7 for the eight shifts.  ``shifted`` is the register
    right after the shift, before any XOR with the polynomial (for the XOR-in step: ``after``).
    """

    byte_index: int
    byte: int
    bit: int | None
    action: str
    before: int
    after: int
    lsb: int | None
    shifted: int = 0

    def describe(self) -> str:
        """One line for a learner: what happened to the register in this step."""
        if self.action == "xor_byte":
            return (f"byte {self.byte_index} (0x{self.byte:02X}): 0x{self.before:04X} XOR 0x{self.byte:02X}"
                    f" = 0x{self.after:04X}")
        if self.action == "shift":
            return f"bit {self.bit}: LSB 0, shift right: 0x{self.before:04X} -> 0x{self.after:04X}"
        return (f"bit {self.bit}: LSB 1, shift right and XOR 0xA001: 0x{self.before:04X} -> "
                f"0x{self.after:04X}")


def crc16_trace(data: bytes) -> Iterator[CrcStep]:
    """Yield every step of the bitwise CRC: per byte one XOR step, then eight shift steps.

    The ``after`` of the last step is ``crc16(data)``.
    """
    register = INITIAL
    for index, byte in enumerate(_as_bytes(data)):
        before = register
        register ^= byte
        yield CrcStep(index, byte, None, "xor_byte", before, register, None, register)
        for bit in range(8):
            before = register
            lsb = register & 1
            register >>= 1
            shifted = register
            if lsb:
                register ^= POLYNOMIAL
            yield CrcStep(index, byte, bit, "shift_xor" if lsb else "shift", before, register, lsb, shifted)


@dataclass(frozen=True)
class TableStep:
    """One byte of the table method: ``after = (before >> 8) XOR CRC_TABLE[index]``,
    where ``index = (before XOR byte) & 0xFF``."""

    byte_index: int
    byte: int
    index: int
    table_value: int
    before: int
    after: int

    def describe(self) -> str:
        return (f"byte {self.byte_index} (0x{self.byte:02X}): "
                f"index = (0x{self.before:04X} ^ 0x{self.byte:02X}) & 0xFF = 0x{self.index:02X}; "
                f"0x{self.before >> 8:04X} ^ table[0x{self.index:02X}]"
                f" (0x{self.table_value:04X}) = 0x{self.after:04X}")


def crc16_table_trace(data: bytes) -> Iterator[TableStep]:
    """Yield one step per byte of the table method, with the table entry it used."""
    register = INITIAL
    for position, byte in enumerate(_as_bytes(data)):
        index = (register ^ byte) & 0xFF
        value = CRC_TABLE[index]
        after = (register >> 8) ^ value
        yield TableStep(position, byte, index, value, register, after)
        register = after


def lrc(data: bytes) -> int:
    """LRC of ASCII mode: two's complement of the 8-bit sum of the bytes.

    >>> hex(lrc(bytes.fromhex("050610010200")))
    '0xe2'
    """
    return (-sum(_as_bytes(data))) & 0xFF


@dataclass(frozen=True)
class LrcStep:
    """One byte added into the LRC's running 8-bit sum."""

    byte_index: int
    byte: int
    before: int
    after: int


def lrc_trace(data: bytes) -> list[LrcStep]:
    """The running sum byte by byte; the LRC is ``(-steps[-1].after) & 0xFF`` (0 for no bytes)."""
    steps = []
    total = 0
    for index, byte in enumerate(_as_bytes(data)):
        steps.append(LrcStep(index, byte, total, (total + byte) & 0xFF))
        total = (total + byte) & 0xFF
    return steps
