# A Modbus/TCP frame = 7-byte MBAP header + PDU.  The PDU starts at byte 7 with the function code.
import modbus_edu as mb
from modbus_edu.exercises import check

frame = mb.parse_hex("00 07 00 00 00 06 11 03 00 6B 00 03")
answer = mb.TcpFrame.decode(frame).pdu.encode()   # the same as frame[7:]
print(answer.hex(" ").upper())                     # 03 00 6B 00 03
check("00.2", answer)
