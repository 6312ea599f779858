"""The CRC's steps, each changed as a learner's slip changes it: shared by the CRC procedures
(:data:`.procedures.CRC`, :data:`.procedures.CRC_WIRE`), the gateway's CRC check (:mod:`.gateway`) and the
CRC of every RTU frame built by hand (:mod:`.frames`), so that one CRC slip reads the same in each."""

from __future__ import annotations

from ...crc import crc16
from .misconceptions import crc16_reflected, crc16_unreflected, crc_bit_loop


def _swap16(value: int) -> int:
    return (value & 0xFF) << 8 | value >> 8


def hex_as_decimal(value: int) -> int | None:
    """``value``'s hex digits read as a decimal number (0x1234 as 1234), where they are all decimal."""
    text = f"{value:X}"
    return int(text) if text.isdecimal() and int(text) != value else None


CRC_STEPS = (
    (
        "initial-zero",
        "the register started at 0 instead of 0xFFFF",
        "crc-initial-zero",
        lambda data: crc16_reflected(data, initial=0),
    ),
    ("unreflected", "the polynomial unreflected (0x8005, shifting left)", "crc-msb-first", crc16_unreflected),
    (
        "unreflected-right-shift",
        "0x8005 XORed while shifting right",
        "crc-msb-first",
        lambda data: crc16_reflected(data, poly=0x8005),
    ),
    ("high-first", "the register's bytes swapped", "crc-swapped", lambda data: _swap16(crc16(data))),
    ("final-xor", "a final XOR with 0xFFFF", None, lambda data: crc16(data) ^ 0xFFFF),
    ("seven-shifts", "7 shifts a byte instead of 8", "crc-bit-loop",
     lambda data: crc_bit_loop(data, shifts=7)),
    ("nine-shifts", "9 shifts a byte instead of 8", "crc-bit-loop",
     lambda data: crc_bit_loop(data, shifts=9)),
    ("test-after-shift", "the bit tested after the shift instead of before", "crc-bit-loop",
     lambda data: crc_bit_loop(data, test_after=True)),
    ("last-byte-left-out", "the last byte left out", "crc-not-every-byte",
     lambda data: crc16(data[:-1]) if data else None),
    ("first-255", "only the first 255 bytes", "crc-not-every-byte",
     lambda data: crc16(data[:255]) if len(data) > 255 else None),
    ("first-256", "only the first 256 bytes", "crc-not-every-byte",
     lambda data: crc16(data[:256]) if len(data) > 256 else None),
    ("low-byte-only", "only the low byte", "crc-one-byte", lambda data: crc16(data) & 0xFF),
    ("high-byte-only", "only the high byte", "crc-one-byte", lambda data: crc16(data) >> 8),
    (
        "address-left-out",
        "the first byte (the address) left out",
        "checksum-without-address",
        lambda data: crc16(data[1:]) if data else None,
    ),
    (
        "hex-as-decimal",
        "the CRC's hex digits read as decimal",
        "hex-read-as-decimal",
        lambda data: hex_as_decimal(crc16(data)),
    ),
    (
        "as-bytes",
        "the CRC's two bytes returned instead of the register",
        "crc-as-bytes",
        lambda data: crc16(data).to_bytes(2, "little"),
    ),
    (
        "as-bytes-high-first",
        "the register's two bytes, high first, returned instead of the register",
        "crc-as-bytes",
        lambda data: crc16(data).to_bytes(2, "big"),
    ),
)
"""The CRC's perturbations: key, the change in words, its misconception, the changed procedure."""


REGISTER_SLIPS = ("initial-zero", "unreflected", "unreflected-right-shift", "final-xor", "hex-as-decimal",
                  "seven-shifts", "test-after-shift")
"""The steps that change the register's value itself (not its bytes' order or number): an RTU frame built
by hand carries any of them in its CRC field."""
