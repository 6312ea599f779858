# Write Multiple Registers: 10 | address 00 04 | quantity 00 02 | byte count 04 | 01 F4 | 03 E8
import modbus_edu as mb
from modbus_edu.exercises import check

answer = mb.WriteMultipleRegistersRequest(address=4, values=[500, 1000]).encode()
print(answer.hex(" ").upper())   # 10 00 04 00 02 04 01 F4 03 E8
check("02.1", answer)
