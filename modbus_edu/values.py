"""Numbers and text across 16-bit registers.

A Modbus register holds 16 bits and nothing else: the protocol says neither how to put a negative
number, a 32-bit counter or a floating-point value into registers, nor in which order.  Each device
maker chooses, and the device's manual says (or should).  This module does the conversions.

Types
-----
=========  =========  ===============================================
type       registers  values
=========  =========  ===============================================
uint16     1          0 .. 65535
int16      1          -32768 .. 32767 (two's complement)
uint32     2          0 .. 4294967295
int32      2          -2147483648 .. 2147483647
float32    2          IEEE 754 single precision (about 7 digits)
float64    4          IEEE 754 double precision (about 16 digits)
=========  =========  ===============================================

Orders
------
Write the value's bytes big-endian (most significant first) and call them A B C D (E F G H for 64
bits).  A register travels high byte first; the *order* says which bytes each register carries:

=====  ==========================  ==================================  ==================================
order  meaning                     32 bits: registers                  64 bits: registers
=====  ==========================  ==================================  ==================================
ABCD   big-endian words and bytes  ``[AB] [CD]``                       ``[AB] [CD] [EF] [GH]``
CDAB   word-swapped                ``[CD] [AB]``                       ``[GH] [EF] [CD] [AB]``
BADC   byte-swapped                ``[BA] [DC]``                       ``[BA] [DC] [FE] [HG]``
DCBA   little-endian               ``[DC] [BA]``                       ``[HG] [FE] [DC] [BA]``
=====  ==========================  ==================================  ==================================

So the four orders are two independent choices: the **word order** (ABCD, BADC: most significant
register first; CDAB, DCBA: least significant register first) and the **byte order inside each
register** (ABCD, CDAB: as the value; BADC, DCBA: swapped).  For 64-bit values "word-swapped" means
the whole word order is reversed, as in Modbus Poll's "little-endian byte swap".  For the 16-bit types
only the byte order counts: ABCD = CDAB, BADC = DCBA.

Example, the float32 123.456 = bytes ``42 F6 E9 79``::

    ABCD -> 0x42F6 0xE979      CDAB -> 0xE979 0x42F6
    BADC -> 0xF642 0x79E9      DCBA -> 0x79E9 0xF642

Also here: scaling (a meter sends 403.6 V as 4036, "x10"), ASCII text two characters per register, and
the display formats of a test tool's data grid (:func:`format_registers`).
"""

from __future__ import annotations

import math
import operator
import struct
from collections.abc import Sequence
from dataclasses import dataclass
from decimal import ROUND_HALF_UP, Decimal, InvalidOperation

from .errors import ValueFormatError, guard_numbers, shown

__all__ = [
    "TYPES",
    "ORDERS",
    "FORMATS",
    "TypeInfo",
    "register_count",
    "encode_value",
    "decode_value",
    "decode_values",
    "scale",
    "unscale",
    "text_to_registers",
    "registers_to_text",
    "format_registers",
    "parse_formatted",
]


@dataclass(frozen=True)
class TypeInfo:
    """What a value type is made of: ``registers`` 16-bit registers, packed with ``struct`` code ``code``."""

    name: str
    registers: int
    code: str
    is_float: bool
    minimum: int | None
    maximum: int | None


#: The value types, by name.
TYPES: dict[str, TypeInfo] = {
    "int16": TypeInfo("int16", 1, "h", False, -(2**15), 2**15 - 1),
    "uint16": TypeInfo("uint16", 1, "H", False, 0, 2**16 - 1),
    "int32": TypeInfo("int32", 2, "i", False, -(2**31), 2**31 - 1),
    "uint32": TypeInfo("uint32", 2, "I", False, 0, 2**32 - 1),
    "float32": TypeInfo("float32", 2, "f", True, None, None),
    "float64": TypeInfo("float64", 4, "d", True, None, None),
}

#: The word/byte orders (see the module docstring).
ORDERS: tuple[str, ...] = ("ABCD", "CDAB", "BADC", "DCBA")

_WORD_SWAP = {"ABCD": False, "CDAB": True, "BADC": False, "DCBA": True}
_BYTE_SWAP = {"ABCD": False, "CDAB": False, "BADC": True, "DCBA": True}

_WIDE_TYPES = ("int32", "uint32", "float32", "float64")

#: Display formats of :func:`format_registers`.
FORMATS: tuple[str, ...] = (
    "hex",
    "binary",
    "unsigned",
    "signed",
    "ascii_char",
    "ascii_value",
) + tuple(f"{t}_{o}" for t in _WIDE_TYPES for o in ORDERS)


# --- checks -------------------------------------------------------------------------------------------
def _type_info(type: str) -> TypeInfo:
    if isinstance(type, str):
        info = TYPES.get(type.strip().lower())
        if info is not None:
            return info
    raise ValueFormatError(f"unknown value type {shown(type)}: expected one of {', '.join(TYPES)}")


def _order(order: str) -> str:
    if isinstance(order, str) and order.strip().upper() in ORDERS:
        return order.strip().upper()
    raise ValueFormatError(
        f"unknown order {shown(order)}: expected one of {', '.join(ORDERS)} "
        f"(ABCD big-endian, CDAB word-swapped, BADC byte-swapped, DCBA little-endian)"
    )


def _type_name(value: object) -> str:
    return type(value).__name__


def _check_registers(registers: Sequence[int], what: str = "registers") -> list[int]:
    """The registers as a list of ints 0..65535, or a ValueFormatError naming the bad one."""
    if isinstance(registers, (int, str, bytes, bytearray)) or not hasattr(registers, "__iter__"):
        raise ValueFormatError(
            f"{what} must be a list of 16-bit values, got {_type_name(registers)} {shown(registers)}"
        )
    out = []
    for i, r in enumerate(registers):
        try:
            if isinstance(r, (bool, float)):
                raise TypeError
            v = operator.index(r)
        except TypeError:
            raise ValueFormatError(
                f"{what}[{i}] is {type(r).__name__} {shown(r)}: a register holds a whole number 0..65535"
            ) from None
        if not 0 <= v <= 0xFFFF:
            raise ValueFormatError(f"{what}[{i}] = {shown(v)} is outside 0..65535: a register holds 16 bits")
        out.append(v)
    return out


def register_count(type: str) -> int:
    """How many registers a value of ``type`` takes: 1 (16-bit), 2 (32-bit) or 4 (float64)."""
    return _type_info(type).registers


# --- bytes <-> registers --------------------------------------------------------------------------------
def _bytes_to_registers(data: bytes, order: str) -> list[int]:
    """Big-endian value bytes -> registers in ``order``."""
    if _BYTE_SWAP[order]:
        words = [data[i] | (data[i + 1] << 8) for i in range(0, len(data), 2)]
    else:
        words = [(data[i] << 8) | data[i + 1] for i in range(0, len(data), 2)]
    if _WORD_SWAP[order]:
        words.reverse()
    return words


def _registers_to_bytes(registers: list[int], order: str) -> bytes:
    """Registers in ``order`` -> big-endian value bytes."""
    words = list(reversed(registers)) if _WORD_SWAP[order] else registers
    out = bytearray()
    for w in words:
        if _BYTE_SWAP[order]:
            out += bytes((w & 0xFF, w >> 8))
        else:
            out += bytes((w >> 8, w & 0xFF))
    return bytes(out)


@guard_numbers
def encode_value(value: int | float, type: str = "uint16", order: str = "ABCD") -> list[int]:
    """The registers that carry ``value`` as ``type`` in ``order``.

    >>> encode_value(-2, "int16")
    [65534]
    >>> [hex(r) for r in encode_value(123.456, "float32", "CDAB")]
    ['0xe979', '0x42f6']

    A value that does not fit the type (``70000`` as uint16, ``1.5`` as an integer type, ``1e39`` as
    float32) raises :class:`~modbus_edu.errors.ValueFormatError`.
    """
    info = _type_info(type)
    order = _order(order)
    if info.is_float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            try:
                if isinstance(value, (str, bytes, bytearray)):
                    raise TypeError  # text is not a number, even "1.5": parse it first
                value = float(value)  # e.g. numpy floats, Decimal
            except (TypeError, ValueError, OverflowError):
                raise ValueFormatError(
                    f"{info.name} holds a number, got {_type_name(value)} {shown(value)}"
                ) from None
        try:
            data = struct.pack(">" + info.code, value)
        except (OverflowError, struct.error):
            raise ValueFormatError(
                f"{shown(value)} is too large for {info.name} (largest finite value about 3.4e38); "
                f"use float64"
            ) from None
    else:
        try:
            if isinstance(value, (float, bool)):
                raise TypeError
            number = operator.index(value)
        except TypeError:
            hint = " (round it first, or use float32)" if isinstance(value, float) else ""
            raise ValueFormatError(
                f"{info.name} holds a whole number, got {_type_name(value)} {shown(value)}{hint}"
            ) from None
        assert info.minimum is not None and info.maximum is not None
        if not info.minimum <= number <= info.maximum:
            raise ValueFormatError(
                f"{number} does not fit {info.name}: its range is {info.minimum}..{info.maximum}"
            )
        data = struct.pack(">" + info.code, number)
    return _bytes_to_registers(data, order)


@guard_numbers
def decode_value(registers: Sequence[int], type: str = "uint16", order: str = "ABCD") -> int | float:
    """The value that ``registers`` carry as ``type`` in ``order`` (the inverse of :func:`encode_value`).

    >>> decode_value([0x42F6, 0xE979], "float32")
    123.45600128173828

    (float32 keeps about 7 significant digits: 123.456 comes back as the nearest float32.)
    The number of registers must be exactly :func:`register_count` of the type.
    """
    info = _type_info(type)
    order = _order(order)
    regs = _check_registers(registers)
    if len(regs) != info.registers:
        raise ValueFormatError(
            f"{info.name} takes {info.registers} register{'s' if info.registers > 1 else ''}, "
            f"got {len(regs)}"
        )
    return struct.unpack(">" + info.code, _registers_to_bytes(regs, order))[0]


def decode_values(registers: Sequence[int], type: str = "uint16", order: str = "ABCD") -> list[int | float]:
    """Consecutive values of ``type``: 4 registers -> two int32, ...

    The number of registers must be a multiple of :func:`register_count` of the type.
    """
    info = _type_info(type)
    order = _order(order)
    regs = _check_registers(registers)
    n = info.registers
    if len(regs) % n:
        left = len(regs) % n
        raise ValueFormatError(
            f"{len(regs)} registers do not make whole {info.name} values ({n} registers each): "
            f"{left} register{'s' if left > 1 else ''} left over from index {len(regs) - left}"
        )
    fmt = ">" + info.code
    return [
        struct.unpack(fmt, _registers_to_bytes(regs[i : i + n], order))[0] for i in range(0, len(regs), n)
    ]


# --- scaling ----------------------------------------------------------------------------------------------
def _decimal(x: int | float | Decimal | str, what: str) -> Decimal:
    if isinstance(x, bool):
        raise ValueFormatError(f"{what} must be a number, got {shown(x)}")
    try:
        d = x if isinstance(x, Decimal) else Decimal(str(x)) if isinstance(x, float) else Decimal(x)
    except (InvalidOperation, TypeError, ValueError):
        raise ValueFormatError(f"{what} must be a number, got {shown(x)}") from None
    if not d.is_finite():
        raise ValueFormatError(f"{what} must be a finite number, got {shown(x)}")
    return d


@guard_numbers
def scale(raw: int | float, factor: int | float = 10) -> float:
    """The engineering value of a raw register value the device multiplied by ``factor``.

    A meter that sends volts "x10" sends 403.6 V as 4036: ``scale(4036, 10)`` -> ``403.6``; a power
    factor "x100" of 0.66 arrives as 66.  The division is done in decimal, so the result is the float
    nearest the exact decimal quotient and prints as you expect (403.6, not 403.59999999999997).
    A factor below 1 works too: ``scale(4036, 0.1)`` -> ``40360.0``.
    """
    f = _decimal(factor, "factor")
    if f == 0:
        raise ValueFormatError("factor must not be 0 (it is what the device multiplied the value by)")
    result = float(_decimal(raw, "raw value") / f)
    if not math.isfinite(result):
        raise ValueFormatError(f"scale({shown(raw)}, {shown(factor)}) is too large for a float: no register "
                               "carries such a value")
    return result


@guard_numbers
def unscale(value: int | float, factor: int | float = 10) -> int:
    """The raw integer to send for ``value`` on a device that scales by ``factor``: ``unscale(403.6, 10)``
    -> ``4036``.  Rounds half away from zero (``unscale(0.665, 100)`` -> 67), working in decimal on the
    number as written (``str(value)``), so binary float noise does not creep in.
    """
    f = _decimal(factor, "factor")
    if f == 0:
        raise ValueFormatError("factor must not be 0 (it is what the device multiplied the value by)")
    try:
        return int((_decimal(value, "value") * f).quantize(Decimal(1), rounding=ROUND_HALF_UP))
    except InvalidOperation:
        raise ValueFormatError(f"unscale({shown(value)}, {shown(factor)}): the raw value has more digits "
                               "than any register pair can carry") from None


# --- text ---------------------------------------------------------------------------------------------------
def text_to_registers(
    text: str, length: int | None = None, pad: str = "\x00", order: str = "AB"
) -> list[int]:
    """Pack ASCII ``text`` two characters per register, the first character in the high byte.

    >>> [hex(r) for r in text_to_registers("ABC")]
    ['0x4142', '0x4300']

    An odd length is completed with ``pad`` (NUL by default; some devices pad with spaces: ``pad=" "``).
    ``length`` is a number of registers (0..65536): shorter text is padded up to it, longer text raises
    :class:`~modbus_edu.errors.ValueFormatError`.  ``order="BA"`` puts the first character in the low
    byte, as some devices do.  Characters outside ASCII (0..127) raise ValueFormatError.
    """
    if not isinstance(text, str):
        raise ValueFormatError(f"text must be a str, got {_type_name(text)} {shown(text)}")
    if not isinstance(pad, str) or len(pad) != 1 or not pad.isascii():
        raise ValueFormatError(f"pad must be one ASCII character, got {shown(pad)}")
    if order not in ("AB", "BA"):
        raise ValueFormatError(f"text order must be 'AB' (first character high) or 'BA', got {shown(order)}")
    for i, ch in enumerate(text):
        if not ch.isascii():
            raise ValueFormatError(
                f"character {i} of the text, {ch!r} (U+{ord(ch):04X}), is not ASCII: a register byte holds "
                f"one ASCII character 0..127"
            )
    needed = (len(text) + 1) // 2
    if length is not None:
        if isinstance(length, bool) or not isinstance(length, int) or not 0 <= length <= 0x10000:
            raise ValueFormatError(f"length is a number of registers, 0..65536 (a table holds 65536), "
                                   f"got {shown(length)}")
        if needed > length:
            raise ValueFormatError(
                f"{len(text)} characters need {needed} registers (2 per register), only {length} allowed"
            )
        needed = length
    data = text.encode("ascii").ljust(2 * needed, pad.encode("ascii"))
    if order == "AB":
        return [(data[i] << 8) | data[i + 1] for i in range(0, len(data), 2)]
    return [data[i] | (data[i + 1] << 8) for i in range(0, len(data), 2)]


def registers_to_text(registers: Sequence[int], order: str = "AB", strip: str = "\x00") -> str:
    """The ASCII text in ``registers``, two characters each, the high byte first (``order="AB"``).

    Trailing characters in ``strip`` (NUL by default; pass ``"\\x00 "`` to drop space padding too, or
    ``""`` to keep everything) are removed.  A byte above 127 raises
    :class:`~modbus_edu.errors.ValueFormatError` naming the register and the byte.
    """
    if order not in ("AB", "BA"):
        raise ValueFormatError(f"text order must be 'AB' (first character high) or 'BA', got {shown(order)}")
    regs = _check_registers(registers)
    chars = []
    for i, r in enumerate(regs):
        pair = (r >> 8, r & 0xFF) if order == "AB" else (r & 0xFF, r >> 8)
        for j, b in enumerate(pair):
            if b > 0x7F:
                raise ValueFormatError(
                    f"register {i} (0x{r:04X}) byte {j} is 0x{b:02X}, not ASCII (0..127): this is not "
                    f"text, or not in this byte order"
                )
            chars.append(chr(b))
    return "".join(chars).rstrip(strip) if strip else "".join(chars)


# --- display formats ----------------------------------------------------------------------------------------
def _printable(b: int) -> str:
    return chr(b) if 0x20 <= b <= 0x7E else "."


def _format_float(x: float, bits: int) -> str:
    if math.isnan(x) or math.isinf(x):
        return repr(x)
    if bits == 32:
        # the shortest decimal that gives back the same float32 (float32 0.1 shows as 0.1)
        for digits in range(6, 10):
            text = f"{x:.{digits}g}"
            if struct.pack(">f", float(text)) == struct.pack(">f", x):
                break
        return repr(float(text))  # printed like any Python float: 1.0, 0.1, 3.4028235e+38
    return repr(x)


def _format_one(r: int, fmt: str) -> str:
    if fmt == "hex":
        return f"0x{r:04X}"
    if fmt == "binary":
        b = f"{r:016b}"
        return " ".join(b[i : i + 4] for i in range(0, 16, 4))
    if fmt == "unsigned":
        return str(r)
    if fmt == "signed":
        return str(r - 0x10000 if r & 0x8000 else r)
    if fmt == "ascii_char":
        return _printable(r >> 8) + _printable(r & 0xFF)
    if fmt == "ascii_value":
        return f"{r >> 8} {r & 0xFF}"
    raise AssertionError(fmt)  # pragma: no cover


def _check_format(fmt: str) -> str:
    if isinstance(fmt, str):
        f = fmt.strip()
        low = f.lower()
        if low in FORMATS:
            return low
        if "_" in f:
            t, _, o = f.rpartition("_")
            name = f"{t.lower()}_{o.upper()}"
            if name in FORMATS:
                return name
    raise ValueFormatError(f"unknown display format {shown(fmt)}: expected one of {', '.join(FORMATS)}")


@guard_numbers
def format_registers(registers: Sequence[int], fmt: str = "unsigned") -> list[str]:
    """One display string per register, as a test tool's data grid shows them.

    Formats (:data:`FORMATS`):

    * ``hex`` ``"0x04D2"``, ``binary`` ``"0000 0100 1101 0010"``, ``unsigned`` ``"1234"``,
      ``signed`` (int16) ``"-1"`` for 0xFFFF;
    * ``ascii_char``: the two bytes as characters, high byte first, non-printables as ``.``
      (0x4142 -> ``"AB"``); ``ascii_value``: the two bytes in decimal (0x04D2 -> ``"4 210"``);
    * wide types ``<type>_<order>`` such as ``int32_ABCD``, ``uint32_CDAB``, ``float32_BADC``,
      ``float64_ABCD``: a value spans 2 or 4 registers; its text goes on the first register of its
      group and ``""`` on the others.  Registers left over at the end that cannot make a whole value
      show ``"—"``.
    """
    fmt = _check_format(fmt)
    regs = _check_registers(registers)
    if fmt in FORMATS[:6]:
        return [_format_one(r, fmt) for r in regs]
    type_, _, order = fmt.rpartition("_")
    info = TYPES[type_]
    n = info.registers
    whole = len(regs) - len(regs) % n
    out: list[str] = []
    for i in range(0, whole, n):
        v = decode_value(regs[i : i + n], type_, order)
        if info.is_float:
            text = _format_float(v, 32 if n == 2 else 64)
        else:
            text = str(v)
        out.append(text)
        out.extend([""] * (n - 1))
    out.extend(["—"] * (len(regs) - whole))
    return out


@guard_numbers
def parse_formatted(text: str, fmt: str = "unsigned") -> list[int]:
    """The registers a grid cell's ``text`` stands for in display format ``fmt`` (the inverse of
    :func:`format_registers` for one value): ``parse_formatted("0x04D2", "hex")`` -> ``[1234]``,
    ``parse_formatted("-1", "signed")`` -> ``[65535]``, ``parse_formatted("1.5", "float32_CDAB")`` ->
    two registers.  Bad text raises :class:`~modbus_edu.errors.ValueFormatError`.
    """
    fmt = _check_format(fmt)
    if not isinstance(text, str):
        raise ValueFormatError(f"cell text must be a str, got {_type_name(text)} {shown(text)}")
    s = text.strip()

    def bad(expected: str) -> ValueFormatError:
        return ValueFormatError(f"{shown(text)} is not a {fmt} value: expected {expected}")

    try:
        if fmt == "hex":
            digits = s[2:] if s.lower().startswith("0x") else s
            if not digits or any(c not in "0123456789abcdefABCDEF" for c in digits):
                raise bad("hex digits such as 0x04D2")
            return encode_value(int(digits, 16), "uint16")
        if fmt == "binary":
            digits = s.replace(" ", "").replace("_", "")
            digits = digits[2:] if digits.lower().startswith("0b") else digits
            if not digits or any(c not in "01" for c in digits):
                raise bad("binary digits such as 0000 0100 1101 0010")
            return encode_value(int(digits, 2), "uint16")
        if fmt == "unsigned":
            return encode_value(_parse_int(s, bad("a whole number 0..65535")), "uint16")
        if fmt == "signed":
            return encode_value(_parse_int(s, bad("a whole number -32768..32767")), "int16")
        if fmt == "ascii_char":
            if len(text) > 2:
                raise bad("at most two characters")
            return text_to_registers(text, length=1)
        if fmt == "ascii_value":
            parts = s.split()
            if len(parts) != 2:
                raise bad("two byte values such as '4 210'")
            hi, lo = (_parse_int(p, bad("two byte values 0..255 such as '4 210'")) for p in parts)
            if not (0 <= hi <= 255 and 0 <= lo <= 255):
                raise bad("two byte values 0..255 such as '4 210'")
            return [(hi << 8) | lo]
        type_, _, order = fmt.rpartition("_")
        if TYPES[type_].is_float:
            try:
                number: int | float = float(s)
            except ValueError:
                raise bad("a number such as 1.5") from None
        else:
            number = _parse_int(s, bad("a whole number"))
        return encode_value(number, type_, order)
    except ValueFormatError as exc:
        if str(exc).startswith(repr(text)):
            raise
        raise ValueFormatError(f"{shown(text)} as {fmt}: {exc}") from None


def _parse_int(s: str, error: ValueFormatError) -> int:
    t = s.replace("_", "")
    if t[:1] in "+-":
        body = t[1:]
    else:
        body = t
    if not body or not body.isascii() or not body.isdigit():
        raise error
    return int(t)
