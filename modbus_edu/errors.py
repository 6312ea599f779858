"""Every error the library raises on bad input.

All of them derive from :class:`ModbusError`, so ``except mb.ModbusError`` catches anything a malformed
frame, a wrong setting or a misbehaving device can cause.  The messages are meant to be read by a learner:
they say *what* was wrong, *where* (the byte offset, when there is one) and *what was expected*.
"""

from __future__ import annotations

import functools
import importlib
from collections.abc import Callable
from typing import Any, TypeVar

from .codes import exception_meaning

__all__ = [
    "ModbusError",
    "MissingDependencyError",
    "SecurityError",
    "CaptureError",
    "FrameError",
    "ChecksumError",
    "CrcError",
    "LrcError",
    "AsciiFormatError",
    "MbapError",
    "UnitError",
    "ReservedUnitWarning",
    "FrameLengthError",
    "PduError",
    "UnknownFunctionError",
    "QuantityError",
    "AddressRangeError",
    "ByteCountError",
    "ValueRangeError",
    "TruncatedError",
    "TrailingBytesError",
    "DataModelError",
    "IllegalAddressError",
    "ReferenceNumberError",
    "ValueFormatError",
    "ModbusExceptionError",
    "ModbusTimeoutError",
    "TransactionMismatchError",
    "LinkError",
    "ConfigError",
    "NumberError",
    "BrowserError",
    "ReferenceUnavailable",
    "shown",
    "guard_numbers",
]

T = TypeVar("T")


class ModbusError(Exception):
    """Base class of every error modbus_edu raises on bad input."""


# --- framing: the application data unit (RTU, ASCII, TCP) --------------------------------------
class FrameError(ModbusError):
    """A frame (ADU) is malformed: wrong length, bad delimiter, bad header."""


class ChecksumError(FrameError):
    """A frame's error check does not match the bytes it protects.

    ``received`` is the value the frame carries, ``computed`` the one calculated over its bytes.
    """

    def __init__(self, message: str, *, received: int, computed: int) -> None:
        super().__init__(message)
        self.received = received
        self.computed = computed


class CrcError(ChecksumError):
    """An RTU frame's CRC-16 does not match its bytes."""


class LrcError(ChecksumError):
    """An ASCII frame's LRC does not match its bytes."""


class AsciiFormatError(FrameError):
    """An ASCII frame lacks its ':' start, its CR LF end, or holds something other than hex digits."""


class MbapError(FrameError):
    """A Modbus/TCP MBAP header is wrong: protocol identifier not 0, or a length that does not fit."""


class UnitError(FrameError):
    """A unit identifier (slave address) is outside the range the mode allows."""


class ReservedUnitWarning(ModbusError, UserWarning):
    """A frame is built for a reserved serial address (248..255): allowed, but not a standard slave."""


class FrameLengthError(FrameError):
    """A frame is too short or too long to be a Modbus frame of this mode."""


# --- the protocol data unit ----------------------------------------------------------------------
class PduError(ModbusError):
    """A PDU (function code and data) breaks a rule of the Modbus application protocol."""


class UnknownFunctionError(PduError):
    """The function code (or FC 8's sub-function, FC 43's MEI type) is not one this library implements."""

    def __init__(self, message: str, *, function: int | None = None) -> None:
        super().__init__(message)
        self.function = function


class QuantityError(PduError):
    """A quantity of coils or registers is outside the limits of its function."""


class AddressRangeError(PduError):
    """Starting address plus quantity runs past the last address, 65535."""


class ByteCountError(PduError):
    """A byte count field disagrees with the quantity or with the bytes that follow."""


class ValueRangeError(PduError):
    """A value does not fit its field (a register outside 0..65535, a coil not FF00/0000, ...)."""


class TruncatedError(PduError):
    """The bytes end before the PDU does."""


class TrailingBytesError(PduError):
    """Bytes remain after the end of a complete PDU."""


# --- the data model and values -------------------------------------------------------------------
class DataModelError(ModbusError):
    """A data-model problem: an address that is not in the bank, a reference number that is wrong."""


class IllegalAddressError(DataModelError):
    """An address is outside 0..65535 or, in a sparse bank, was never declared."""


class ReferenceNumberError(DataModelError):
    """A reference number such as 40001 or 4x0001 is malformed or out of range."""


class ValueFormatError(ModbusError):
    """A value cannot be converted to or from registers with the given type and word order."""


# --- roles: what a master sees -------------------------------------------------------------------
class ModbusExceptionError(ModbusError):
    """The slave answered with an exception response.

    ``function`` is the function code of the request, ``code`` the exception code (1 = illegal function,
    2 = illegal data address, 3 = illegal data value, 4 = server device failure, ...), ``meaning`` the
    specification's explanation of the code.
    """

    def __init__(self, function: int, code: int, meaning: str | None = None) -> None:
        if meaning is None:
            meaning = exception_meaning(code)
        self.function = function
        self.code = code
        self.meaning = meaning
        super().__init__(
            f"exception response to function {function} (0x{function:02X}): "
            f"code {code:02X} {meaning}"
        )


class ModbusTimeoutError(ModbusError):
    """No valid response arrived before the timeout."""


class TransactionMismatchError(ModbusError):
    """A response does not belong to the request: another transaction id, unit or function."""


class LinkError(ModbusError):
    """A link cannot carry traffic: port not open, connection refused or closed."""


class ConfigError(ModbusError):
    """A setting is not valid (baud rate, parity, mode, role name, ...)."""


class NumberError(ModbusError):
    """A number that no Modbus setting or field can hold: thousands of digits, or too large for a float."""


class OneLineError(ModbusError):
    """An error that says everything in its message: in a notebook (IPython, JupyterLite) it shows as that
    one line, without a traceback, so a learner reads what to do instead of where the library stopped."""

    def _render_traceback_(self) -> list[str]:
        return [f"{type(self).__name__}: {self}"]


class MissingDependencyError(OneLineError, ImportError):
    """A part of the library needs a package that is not installed: the widgets and plots need the
    ``course`` extra (JupyterLab, ipywidgets, matplotlib); the message says what to install."""


REPOSITORY = "git+https://github.com/modbus-edu/modbus_edu"
"""Where pip installs the library from until a release is published."""


def require(module: str, user: str, extra: str = "course") -> Any:
    """Import ``module`` for ``user`` (a part of the library), or raise :class:`MissingDependencyError`
    saying how to install it (from the repository until a release is on PyPI):
    ``pip install "modbus-edu[course] @ git+https://github.com/modbus-edu/modbus_edu"``."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise MissingDependencyError(
            f"{user} needs {module.split('.')[0]}, which is not installed here ({exc}); it comes with the "
            f"course's extra: pip install \"modbus-edu[{extra}] @ {REPOSITORY}\" (or `make lab` in a clone "
            "of the course)"
        ) from None


def shown(value: object, limit: int = 60) -> str:
    """``repr(value)`` for a message, safe for any value: huge ints by size, long reprs cut.

    Every message that shows a value a learner gave goes through this: Python refuses to write an int
    of more than 4300 digits (a ValueError of its own, not the mistake the learner made), and a message
    that printed a smaller one whole would still be pages long.  An int beyond 64 bits is described by
    its size instead (``an int of 16610 bits (about 5001 digits)``); a list or object whose repr cannot
    be written (it holds such an int) by its type."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 64:
        bits = value.bit_length()
        sign = "a negative" if value < 0 else "an"
        return f"{sign} int of {bits} bits (about {int(bits * 0.30103) + 1} digits)"
    try:
        text = repr(value)
    except Exception:  # an object whose __repr__ fails: say what it is
        return f"a {type(value).__name__}"
    return text if len(text) <= limit else text[: limit - 1] + "…"


def guard_numbers(function: Callable[..., T]) -> Callable[..., T]:
    """Let no ValueError or OverflowError out of ``function``: they become :class:`NumberError`.

    Python refuses to print an int of more than 4300 digits (ValueError) and to turn a huge int into a
    float (OverflowError); a setting or value like that, checked by ``function``, gets a message
    instead."""

    @functools.wraps(function)
    def guarded(*args: Any, **kwargs: Any) -> T:
        try:
            return function(*args, **kwargs)
        except (ValueError, OverflowError) as exc:
            if isinstance(exc, ModbusError):
                raise
            name = getattr(function, "__qualname__", "this call").replace(".__init__", "")
            raise NumberError(f"{name}: a number far too large for any Modbus setting or field "
                              f"({type(exc).__name__}: {str(exc)[:70]})") from None

    return guarded


class CaptureError(ModbusError):
    """A capture file (pcap, pcapng) cannot be written or read: not a capture, damaged, cut short."""


class SecurityError(ModbusError):
    """Modbus/TCP Security cannot go on: a certificate, a key or a role that is missing or not valid."""


class BrowserError(OneLineError):
    """Asked for a socket in a browser (JupyterLite, Pyodide), where no socket can be opened.

    A web page cannot listen on a port, and it cannot open a TCP or UDP connection to a device: servers,
    gateways and links to real devices need a local Python or Binder.
    """


class ReferenceUnavailable(ModbusError):
    """The library's own answer to a build exercise, called where the grader judges that exercise.

    The grader runs a learner's function in a clean room whose copy of the library has, in place of the
    code that answers the exercise (``mb.crc16`` for the CRC exercise), a body that raises this error;
    so a function that only calls the library, however wrapped, is told so instead of being credited.
    ``name`` is how the learner would write what was called (``"mb.crc16"``)."""

    def __init__(self, name: str) -> None:
        self.name = str(name)
        super().__init__(f"calls {self.name}, the library's own answer to this exercise; write your own")
