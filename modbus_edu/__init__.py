"""modbus_edu: learn Modbus by doing.

The public API is re-exported here; each name lives in the module that owns it (see the README's
architecture section)::

    import modbus_edu as mb
    mb.crc16(b"123456789")                                   # 0x4B37
    mb.RtuFrame(unit=1, pdu=mb.ReadHoldingRegistersRequest(address=0, count=1)).encode()
"""

from . import security  # noqa: F401  (mb.security.make_test_pki, server_context, client_context)
from .capture import read_pcap, write_pcap  # noqa: F401
from .clock import RealClock, VirtualClock  # noqa: F401
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
from .datamodel import (  # noqa: F401
    ADDRESS_SPACE,
    TABLE_KINDS,
    DataBank,
    Reference,
    Table,
    format_reference,
    parse_reference,
    table_kind,
)
from .errors import *  # noqa: F401,F403
from .explain import Dissection, Row, explain, explain_pdu  # noqa: F401
from .framing import (  # noqa: F401
    AsciiFrame,
    AsciiSplitter,
    RtuFrame,
    RtuSplitter,
    TcpFrame,
    TcpSplitter,
    decode_frame,
    detect_mode,
    encode_frame,
    frame_class,
    make_frame,
    parse_hex,
    splitter_for,
)
from .gateway import TcpGateway  # noqa: F401
from .links import (  # noqa: F401
    BusStats,
    Faults,
    Link,
    LoopbackSerialLink,
    LoopbackTcpLink,
    SerialTiming,
    character_time,
    loopback_serial,
    loopback_tcp,
)
from .links.browser_serial import BrowserSerialLink, browser_serial  # noqa: F401
from .links.serial import SerialLink, SerialServer, TcpSerialPort, serial_link  # noqa: F401
from .links.tcp_client import TcpLink, tcp_link  # noqa: F401
from .links.tcp_server import TcpServer  # noqa: F401
from .links.udp import UdpLink, UdpServer, udp_link  # noqa: F401
from .master import Master, MasterStats  # noqa: F401
from .pdu import (  # noqa: F401
    MAX_READ_BITS,
    MAX_READ_REGISTERS,
    MAX_WRITE_COILS,
    MAX_WRITE_REGISTERS,
    DiagnosticsRequest,
    DiagnosticsResponse,
    DiagnosticSubFunction,
    ExceptionCode,
    ExceptionResponse,
    FunctionCode,
    GetCommEventCounterRequest,
    GetCommEventCounterResponse,
    GetCommEventLogRequest,
    GetCommEventLogResponse,
    MaskWriteRegisterRequest,
    MaskWriteRegisterResponse,
    Pdu,
    ReadCoilsRequest,
    ReadCoilsResponse,
    ReadDeviceIdentificationRequest,
    ReadDeviceIdentificationResponse,
    ReadDiscreteInputsRequest,
    ReadDiscreteInputsResponse,
    ReadExceptionStatusRequest,
    ReadExceptionStatusResponse,
    ReadFifoQueueRequest,
    ReadFifoQueueResponse,
    ReadFileRecordRequest,
    ReadFileRecordResponse,
    ReadHoldingRegistersRequest,
    ReadHoldingRegistersResponse,
    ReadInputRegistersRequest,
    ReadInputRegistersResponse,
    ReadWriteMultipleRegistersRequest,
    ReadWriteMultipleRegistersResponse,
    ReportServerIdRequest,
    ReportServerIdResponse,
    WriteFileRecordRequest,
    WriteFileRecordResponse,
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
from .registermap import (  # noqa: F401
    Point,
    Poll,
    RegisterMap,
    RegisterMapError,
    datasheet_to_address,
    load_map,
    plan_polls,
)
from .scan import ScanHit, ScanReport, ascan, scan  # noqa: F401
from .slave import Slave, SlaveCounters  # noqa: F401
from .traffic import Traffic, TrafficLog  # noqa: F401
from .values import (  # noqa: F401
    FORMATS,
    ORDERS,
    TYPES,
    decode_value,
    decode_values,
    encode_value,
    format_registers,
    parse_formatted,
    register_count,
    registers_to_text,
    scale,
    text_to_registers,
    unscale,
)

__version__ = "0.1.0"
