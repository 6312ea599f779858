"""The protocol data unit (PDU): a function code and its data.

A PDU is the part of a Modbus message that is the same in every mode (RTU, ASCII, TCP)::

    +---------------+-----------------------------+
    | function code | data (0 to 252 bytes)       |
    |   1 byte      | layout depends on function  |
    +---------------+-----------------------------+

The first byte says what to do; for a response with its top bit set (function code + 0x80) it says
"this is an exception response" instead.  Every field wider than one byte is big-endian (high byte
first).  This module has one request class and one response class per function code, each documenting
its byte layout, plus :class:`ExceptionResponse`.  Constructors check every rule of the specification
(quantity limits, address range, value ranges) and ``decode`` checks the bytes (byte counts, truncated
and trailing data); a broken rule raises a :class:`~modbus_edu.errors.PduError` subclass whose message
says what was wrong, at which byte, and what was expected.

Byte offsets in error messages count from the first byte of the PDU (the function code) unless the
caller passes ``offset`` to :func:`decode_pdu` so that they count from the start of the whole frame.

The classes live in modules that follow the specification's sections: :mod:`.bits` (FC 1, 2, 5, 15),
:mod:`.registers` (FC 3, 4, 6, 16, 22, 23, 24), :mod:`.diagnostics` (FC 7, 8, 11, 12, 17), :mod:`.files`
(FC 20, 21), :mod:`.mei` (FC 43/14) and :mod:`.exceptions`; :mod:`.base` holds what they share (the
:class:`Pdu` class, the field checks, the registry, :func:`decode_pdu` and :func:`pdu_length`).  Every name
is importable from ``modbus_edu.pdu``.
"""

from ..codes import (
    MAX_PDU_SIZE,
    ROLES,
    SERIAL_LINE_ONLY,
    ExceptionCode,
    FunctionCode,
    exception_meaning,
    function_title,
)
from .base import (
    MAX_READ_BITS,
    MAX_READ_REGISTERS,
    MAX_READ_WRITE_REGISTERS,
    MAX_WRITE_COILS,
    MAX_WRITE_REGISTERS,
    OPEN_LENGTH,
    REQUEST_CLASSES,
    RESPONSE_CLASSES,
    Field,
    Pdu,
    decode_pdu,
    pack_bits,
    pdu_class,
    pdu_length,
    request_class,
    response_class,
    unpack_bits,
)
from .base import (
    _check_role as _check_role,
)
from .bits import (
    COIL_OFF,
    COIL_ON,
    ReadCoilsRequest,
    ReadCoilsResponse,
    ReadDiscreteInputsRequest,
    ReadDiscreteInputsResponse,
    WriteMultipleCoilsRequest,
    WriteMultipleCoilsResponse,
    WriteSingleCoilRequest,
    WriteSingleCoilResponse,
)
from .diagnostics import (
    DiagnosticsRequest,
    DiagnosticsResponse,
    DiagnosticSubFunction,
    GetCommEventCounterRequest,
    GetCommEventCounterResponse,
    GetCommEventLogRequest,
    GetCommEventLogResponse,
    ReadExceptionStatusRequest,
    ReadExceptionStatusResponse,
    ReportServerIdRequest,
    ReportServerIdResponse,
)
from .exceptions import (
    ExceptionResponse,
)
from .files import (
    MAX_RECORD_NUMBER,
    ReadFileRecordRequest,
    ReadFileRecordResponse,
    WriteFileRecordRequest,
    WriteFileRecordResponse,
)
from .mei import (
    DEVICE_ID_OBJECTS,
    MEI_READ_DEVICE_ID,
    READ_DEVICE_ID_CODES,
    ReadDeviceIdentificationRequest,
    ReadDeviceIdentificationResponse,
)
from .registers import (
    MAX_FIFO_COUNT,
    MaskWriteRegisterRequest,
    MaskWriteRegisterResponse,
    ReadFifoQueueRequest,
    ReadFifoQueueResponse,
    ReadHoldingRegistersRequest,
    ReadHoldingRegistersResponse,
    ReadInputRegistersRequest,
    ReadInputRegistersResponse,
    ReadWriteMultipleRegistersRequest,
    ReadWriteMultipleRegistersResponse,
    WriteMultipleRegistersRequest,
    WriteMultipleRegistersResponse,
    WriteSingleRegisterRequest,
    WriteSingleRegisterResponse,
    mask_write,
)

__all__ = [
    "MAX_PDU_SIZE",
    "OPEN_LENGTH",
    "ROLES",
    "SERIAL_LINE_ONLY",
    "ExceptionCode",
    "FunctionCode",
    "exception_meaning",
    "function_title",
    "MAX_READ_BITS",
    "MAX_READ_REGISTERS",
    "MAX_WRITE_COILS",
    "MAX_WRITE_REGISTERS",
    "MAX_READ_WRITE_REGISTERS",
    "COIL_ON",
    "COIL_OFF",
    "Field",
    "pack_bits",
    "unpack_bits",
    "Pdu",
    "ReadCoilsRequest",
    "ReadCoilsResponse",
    "ReadDiscreteInputsRequest",
    "ReadDiscreteInputsResponse",
    "ReadHoldingRegistersRequest",
    "ReadHoldingRegistersResponse",
    "ReadInputRegistersRequest",
    "ReadInputRegistersResponse",
    "WriteSingleCoilRequest",
    "WriteSingleCoilResponse",
    "WriteSingleRegisterRequest",
    "WriteSingleRegisterResponse",
    "WriteMultipleCoilsRequest",
    "WriteMultipleCoilsResponse",
    "WriteMultipleRegistersRequest",
    "WriteMultipleRegistersResponse",
    "ExceptionResponse",
    "ReadExceptionStatusRequest",
    "ReadExceptionStatusResponse",
    "ReportServerIdRequest",
    "ReportServerIdResponse",
    "mask_write",
    "MaskWriteRegisterRequest",
    "MaskWriteRegisterResponse",
    "ReadWriteMultipleRegistersRequest",
    "ReadWriteMultipleRegistersResponse",
    "MAX_FIFO_COUNT",
    "ReadFifoQueueRequest",
    "ReadFifoQueueResponse",
    "MEI_READ_DEVICE_ID",
    "DEVICE_ID_OBJECTS",
    "READ_DEVICE_ID_CODES",
    "ReadDeviceIdentificationRequest",
    "ReadDeviceIdentificationResponse",
    "DiagnosticSubFunction",
    "DiagnosticsRequest",
    "DiagnosticsResponse",
    "GetCommEventCounterRequest",
    "GetCommEventCounterResponse",
    "GetCommEventLogRequest",
    "GetCommEventLogResponse",
    "MAX_RECORD_NUMBER",
    "ReadFileRecordRequest",
    "ReadFileRecordResponse",
    "WriteFileRecordRequest",
    "WriteFileRecordResponse",
    "REQUEST_CLASSES",
    "RESPONSE_CLASSES",
    "request_class",
    "response_class",
    "decode_pdu",
    "pdu_class",
    "pdu_length",
]
