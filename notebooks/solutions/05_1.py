# Bytes 0-1, big-endian: 0x002A = 42.
import modbus_edu as mb
from modbus_edu.exercises import check

frame = mb.parse_hex("00 2A 00 00 00 06 11 03 00 6B 00 03")
answer = mb.TcpFrame.decode(frame).transaction_id
print(answer)   # 42
check("05.1", answer)
