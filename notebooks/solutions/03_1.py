# crc16 gives the register value 0x8776; the low byte 0x76 goes on the wire first, then 0x87.
import modbus_edu as mb

data = mb.parse_hex("11 03 00 6B 00 03")
print(hex(mb.crc16(data)))        # 0x8776
answer = mb.crc_bytes(data)       # wire order
print(answer.hex(" ").upper())    # 76 87
