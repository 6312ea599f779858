# The MBAP header: transaction id, protocol id 0, length (unit + PDU), unit; every field high byte first.
from modbus_edu.exercises import check


def mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return tid.to_bytes(2, "big") + (0).to_bytes(2, "big") + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit])


print(mbap_header(280, 1, bytes.fromhex("03 00 00 00 01")).hex(" ").upper())   # 01 18 00 00 00 06 01
answer = mbap_header
check("05.5", answer)
