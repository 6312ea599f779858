# crc16 gives the register value 0x98B2; the low byte 0xB2 goes on the wire first, then 0x98.
import modbus_edu as mb
from modbus_edu.exercises import check

data = mb.parse_hex("11 04 00 08 00 01")
print(hex(mb.crc16(data)))        # 0x98b2
answer = mb.crc_bytes(data)       # wire order
print(answer.hex(" ").upper())    # B2 98
check("03.1", answer)
