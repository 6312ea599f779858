# Write Multiple Registers: 10 | address 00 01 | quantity 00 02 | byte count 04 | 00 0A | 01 02
import modbus_edu as mb

answer = mb.WriteMultipleRegistersRequest(address=1, values=[10, 258]).encode()
print(answer.hex(" ").upper())   # 10 00 01 00 02 04 00 0A 01 02
