"""The encapsulated interface transport (specification sections 6.19, 6.21): Read Device Identification
(FC 43, MEI type 14)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ..codes import (
    MAX_PDU_SIZE,
    _printable,
)
from ..errors import (
    TrailingBytesError,
    TruncatedError,
    UnknownFunctionError,
    ValueRangeError,
    shown,
)
from .base import (
    Field,
    Pdu,
    _check_int,
    _expect_length,
    _expect_minimum,
)

MEI_READ_DEVICE_ID = 0x0E
"""FC 43's MEI type for Read Device Identification (the only MEI type this library speaks)."""


DEVICE_ID_OBJECTS = {0x00: "VendorName", 0x01: "ProductCode", 0x02: "MajorMinorRevision",
                     0x03: "VendorUrl", 0x04: "ProductName", 0x05: "ModelName", 0x06: "UserApplicationName"}
"""The specification's standard objects: 0-2 basic (mandatory), 3-6 regular; 0x80-0xFF are extended."""


READ_DEVICE_ID_CODES = {1: "basic (stream)", 2: "regular (stream)", 3: "extended (stream)", 4: "one object"}

_STREAM_LAST = {1: 0x02, 2: 0x7F, 3: 0xFF}
"""The last object id of each stream's category: basic 0x00-0x02, regular 0x03-0x7F, extended 0x80-0xFF."""


@dataclass(frozen=True, slots=True)
class ReadDeviceIdentificationRequest(Pdu):
    """Read Device Identification (FC 43, 0x2B, MEI type 0x0E) request::

        offset  size  field
        0       1     function code 0x2B
        1       1     MEI type 0x0E
        2       1     read device ID code: 1 basic, 2 regular, 3 extended (stream access), 4 one object
        3       1     object id: where the stream starts, or the one object wanted
    """

    read_code: int = 1
    object_id: int = 0

    function_code: ClassVar[int] = 0x2B
    fixed_size: ClassVar[int | None] = 4
    role: ClassVar[str] = "request"

    def __post_init__(self) -> None:
        if _check_int(self.read_code, "read_code") not in READ_DEVICE_ID_CODES:
            raise ValueRangeError(f"read device ID code {self.read_code}: expected 1 (basic), 2 (regular), "
                                  "3 (extended) or 4 (one object)")
        if not 0 <= _check_int(self.object_id, "object_id") <= 0xFF:
            raise ValueRangeError(f"object id {self.object_id} does not fit its one byte: expected 0..255")

    def encode(self) -> bytes:
        return bytes([0x2B, MEI_READ_DEVICE_ID, self.read_code, self.object_id])

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_length(data, 4, "Read Device Identification request", offset)
        if data[1] != MEI_READ_DEVICE_ID:
            raise UnknownFunctionError(f"at byte {offset + 1}: MEI type 0x{data[1]:02X}; this library reads "
                                       "device identification only (MEI type 0x0E)", function=0x2B)
        if data[2] not in READ_DEVICE_ID_CODES:
            raise ValueRangeError(f"at byte {offset + 2}: read device ID code {data[2]}, expected 1 to 4")
        return cls(data[2], data[3])

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [self._function_field(raw),
                Field(1, raw[1:2], "MEI type", 0x0E, "Read Device Identification"),
                Field(2, raw[2:3], "read device ID code", self.read_code,
                      READ_DEVICE_ID_CODES[self.read_code]),
                Field(3, raw[3:4], "object id", self.object_id,
                      DEVICE_ID_OBJECTS.get(self.object_id, "extended object" if self.object_id >= 0x80
                                            else "reserved object id"))]

    def misfit(self, response: Pdu) -> str:
        """The same read device ID code; one object (code 4) is the object asked for; a stream holds
        objects of its category only (basic 0x00-0x02, regular up to 0x7F)."""
        if response.read_code != self.read_code:
            return f"read device ID code {response.read_code}, expected {self.read_code}"
        ids = [object_id for object_id, _ in response.objects]
        if self.read_code == 4:
            if ids != [self.object_id]:
                got = ", ".join(f"0x{i:02X}" for i in ids) or "none"
                return f"object id(s) {got}, expected the one object asked for, 0x{self.object_id:02X}"
            return ""
        last = _STREAM_LAST[self.read_code]
        outside = [i for i in ids if i > last]
        if outside:
            return (f"object 0x{outside[0]:02X} in a {READ_DEVICE_ID_CODES[self.read_code]} stream, whose "
                    f"objects end at 0x{last:02X}")
        return ""

    def _summary_items(self):
        return [("read_code", self.read_code), ("object_id", self.object_id)]


@dataclass(frozen=True, slots=True)
class ReadDeviceIdentificationResponse(Pdu):
    """Read Device Identification (FC 43, 0x2B, MEI type 0x0E) response::

        offset  size  field
        0       1     function code 0x2B
        1       1     MEI type 0x0E
        2       1     read device ID code (as in the request)
        3       1     conformity level (0x01-0x03, +0x80 if objects can be read one by one)
        4       1     more follows: 0xFF if the objects go on in another response, else 0x00
        5       1     next object id (where the next request starts when more follows)
        6       1     number of objects N
        7...          N objects, each: object id (1), length L (1), value (L bytes)
    """

    read_code: int
    conformity: int
    more_follows: bool
    next_object_id: int
    objects: tuple[tuple[int, bytes], ...]

    function_code: ClassVar[int] = 0x2B
    role: ClassVar[str] = "response"

    @classmethod
    def length_from(cls, data: bytes) -> int | None:
        """Its objects say how long it is: walk their headers (None: need more bytes; past a PDU: refused)."""
        if len(data) < 7:
            return None
        at = 7
        for _ in range(data[6]):
            if at + 2 > len(data):  # the next object's header has not come yet (or cannot, past a PDU)
                return None if len(data) < MAX_PDU_SIZE else MAX_PDU_SIZE + 1
            at += 2 + data[at + 1]
            if at > MAX_PDU_SIZE:
                return at  # longer than a PDU: the caller refuses it
        return at

    @classmethod
    def length_prefix(cls) -> int:
        return MAX_PDU_SIZE

    def __post_init__(self) -> None:
        objects = []
        for item in self.objects:
            object_id, value = item
            value = value.encode() if isinstance(value, str) else value
            object_id = _check_int(object_id, "object id")
            if not isinstance(value, (bytes, bytearray)) or not 0 <= object_id <= 0xFF:
                raise ValueRangeError(f"an object is (id 0..255, bytes or text), got {shown(item)}")
            objects.append((object_id, bytes(value)))
        object.__setattr__(self, "objects", tuple(objects))
        if 7 + sum(2 + len(value) for _, value in objects) > MAX_PDU_SIZE:
            raise ValueRangeError("the objects do not fit one response (253 bytes): split them with "
                                  "more_follows")
        for name in ("read_code", "conformity", "next_object_id"):
            if not 0 <= _check_int(getattr(self, name), name) <= 0xFF:
                raise ValueRangeError(f"{name} does not fit its one byte: expected 0..255")

    def encode(self) -> bytes:
        head = bytes([0x2B, MEI_READ_DEVICE_ID, self.read_code, self.conformity,
                      0xFF if self.more_follows else 0x00, self.next_object_id, len(self.objects)])
        return head + b"".join(bytes([object_id, len(value)]) + value for object_id, value in self.objects)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = "Read Device Identification response"
        _expect_minimum(data, 7, name, offset)
        if data[1] != MEI_READ_DEVICE_ID:
            raise UnknownFunctionError(f"at byte {offset + 1}: MEI type 0x{data[1]:02X}, expected 0x0E",
                                       function=0x2B)
        if data[4] not in (0x00, 0xFF):
            raise ValueRangeError(f"at byte {offset + 4}: more follows is 0x{data[4]:02X}, expected 0x00 or "
                                  "0xFF")
        objects, at, size = [], 7, len(data)
        for _ in range(data[6]):
            end = at + 2 + data[at + 1] if at + 2 <= size else size + 1
            if end > size:
                raise TruncatedError(f"{name} is truncated: object {len(objects) + 1} of {data[6]} runs past "
                                     f"its {size} bytes (from byte {offset + at})")
            objects.append((data[at], data[at + 2:end]))
            at = end
        if at != size:
            raise TrailingBytesError(f"{name} has {size - at} trailing byte(s) from byte {offset + at}")
        # every field was checked above: build without checking again
        return cls._from_wire(data[2], data[3], data[4] == 0xFF, data[5], tuple(objects))

    def fields(self) -> list[Field]:
        raw = self.encode()
        rows = [self._function_field(raw),
                Field(1, raw[1:2], "MEI type", 0x0E, "Read Device Identification"),
                Field(2, raw[2:3], "read device ID code", self.read_code,
                      READ_DEVICE_ID_CODES.get(self.read_code, "unknown")),
                Field(3, raw[3:4], "conformity level", self.conformity, f"0x{self.conformity:02X}"),
                Field(4, raw[4:5], "more follows", self.more_follows,
                      "0xFF: ask again from the next object id" if self.more_follows
                      else "0x00: the last part"),
                Field(5, raw[5:6], "next object id", self.next_object_id, "where the next request starts"),
                Field(6, raw[6:7], "number of objects", len(self.objects), "")]
        at = 7
        for object_id, value in self.objects:
            label = DEVICE_ID_OBJECTS.get(object_id, f"object 0x{object_id:02X}")
            text = _printable(value.decode("ascii", "replace"))  # never a control character
            rows.append(Field(at, raw[at:at + 2 + len(value)], label, text,
                              f"object id {object_id}, {len(value)} bytes"))
            at += 2 + len(value)
        return rows

    def _summary_items(self):
        objects = {object_id: value.decode("ascii", "replace") for object_id, value in self.objects}
        return [("objects", objects),
                ("more_follows", self.more_follows)]
