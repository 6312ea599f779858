"""modbus_edu: learn Modbus by doing.

The public API is re-exported here; each name lives in the module that owns it (see the README's
architecture section)::

    import modbus_edu as mb
    mb.crc16(b"123456789")                                   # 0x4B37
    mb.RtuFrame(unit=1, pdu=mb.ReadHoldingRegistersRequest(address=0, count=1)).encode()
"""

from __future__ import annotations

from .crc import (  # noqa: F401
    CRC_TABLE,
    POLYNOMIAL,
    build_crc_table,
    crc16,
    crc16_bitwise,
    crc16_table_trace,
    crc16_trace,
    crc_bytes,
    lrc,
    lrc_trace,
)
from .errors import *  # noqa: F401,F403
from .pdu import (  # noqa: F401
    MAX_READ_BITS,
    MAX_READ_REGISTERS,
    MAX_WRITE_COILS,
    MAX_WRITE_REGISTERS,
    ExceptionCode,
    ExceptionResponse,
    FunctionCode,
    Pdu,
    ReadCoilsRequest,
    ReadCoilsResponse,
    ReadDiscreteInputsRequest,
    ReadDiscreteInputsResponse,
    ReadHoldingRegistersRequest,
    ReadHoldingRegistersResponse,
    ReadInputRegistersRequest,
    ReadInputRegistersResponse,
    WriteMultipleCoilsRequest,
    WriteMultipleCoilsResponse,
    WriteMultipleRegistersRequest,
    WriteMultipleRegistersResponse,
    WriteSingleCoilRequest,
    WriteSingleCoilResponse,
    WriteSingleRegisterRequest,
    WriteSingleRegisterResponse,
    decode_pdu,
    pdu_length,
)

__version__ = "0.1.0"
