# Slave 1, Write Single Register (function 6), address 2, value 0x1234; RtuFrame appends the CRC low byte first.
import modbus_edu as mb
from modbus_edu.exercises import check

answer = mb.RtuFrame(unit=1, pdu=mb.WriteSingleRegisterRequest(address=2, value=0x1234)).encode()
print(answer.hex(" ").upper())   # 01 06 00 02 12 34 25 7D
check("03.2", answer)
