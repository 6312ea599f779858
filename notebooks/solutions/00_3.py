# Slave 2, Read Holding Registers (function 3), address 0, 2 registers; RtuFrame adds the CRC.
import modbus_edu as mb
from modbus_edu.exercises import check

answer = mb.RtuFrame(unit=2, pdu=mb.ReadHoldingRegistersRequest(address=0, count=2)).encode()
print(answer.hex(" ").upper())   # 02 03 00 00 00 02 C4 38
check("00.3", answer)
