"""The exception response (specification section 7): the request's function code + 0x80 and an exception
code."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ..codes import (
    exception_meaning,
    function_title,
)
from ..errors import (
    UnknownFunctionError,
    ValueRangeError,
)
from .base import (
    Field,
    Pdu,
    _check_int,
    _expect_length,
    _pdu_bytes,
)


@dataclass(frozen=True, slots=True)
class ExceptionResponse(Pdu):
    """Exception response: the server could not carry out the request::

        offset  size  field
        0       1     function code of the request + 0x80 (its most significant bit set)
        1       1     exception code (01 illegal function, 02 illegal data address,
                      03 illegal data value, 04 server device failure, ...)

    ``function`` is the request's function code (1-127); ``function_code`` is the byte on the wire.
    Example: ``83 02`` answers a Read Holding Registers request whose addresses do not exist.
    """

    function: int
    code: int

    role: ClassVar[str] = "response"
    fixed_size: ClassVar[int | None] = 2
    is_exception: ClassVar[bool] = True

    def __post_init__(self) -> None:
        function = _check_int(self.function, "function")
        if function & 0x80 and 0x81 <= function <= 0xFF:
            function &= 0x7F
        if not 1 <= function <= 0x7F:
            raise ValueRangeError(f"exception response for function {function}: expected a code 1 to 127")
        code = _check_int(self.code, "exception code")
        if not 1 <= code <= 0xFF:
            raise ValueRangeError(f"exception code {code} is outside 1..255")
        object.__setattr__(self, "function", function)
        object.__setattr__(self, "code", code)

    @property
    def function_code(self) -> int:  # type: ignore[override]
        return self.function | 0x80

    @property
    def title(self) -> str:
        return f"Exception ({function_title(self.function)})"

    @property
    def meaning(self) -> str:
        return exception_meaning(self.code)

    def encode(self) -> bytes:
        return bytes((self.function | 0x80, self.code))

    @classmethod
    def decode(cls, data: bytes, offset: int = 0):
        data = _pdu_bytes(data, offset)
        _expect_length(data, 2, "exception response", offset)
        if not data[0] & 0x80:
            raise UnknownFunctionError(
                f"at byte {offset}: 0x{data[0]:02X} is not an exception function code (expected 0x81-0xFF)",
                function=data[0])
        if data[0] == 0x80:
            raise UnknownFunctionError(
                f"at byte {offset}: function code 0x80 would be an exception response to function 0, "
                f"which does not exist (expected 0x81-0xFF)", function=0x80)
        if data[1] == 0:
            raise ValueRangeError(f"at byte {offset + 1}: exception code 0x00, expected 0x01-0xFF")
        return cls(data[0] & 0x7F, data[1])

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [Field(0, raw[:1], "function code", raw[0],
                      f"0x{self.function:02X} + 0x80: exception response to {function_title(self.function)}"),
                Field(1, raw[1:2], "exception code", self.code, self.meaning)]

    def summary(self) -> str:
        return f"Exception response to {function_title(self.function)}: code {self.code:02X}, {self.meaning}"
