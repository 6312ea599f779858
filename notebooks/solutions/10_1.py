# Registers 0x0000 and 0x1009, high word first: 0x00001009 = 4105 tenths of a volt = 410.5 V.
import modbus_edu as mb
from modbus_edu.devices import METER_BY_NAME
from modbus_edu.exercises import check

frame = mb.RtuFrame.decode(mb.parse_hex("01 03 04 00 00 10 09 37 F5"), role="response")
registers = frame.pdu.registers
answer = METER_BY_NAME["VL2"].value(registers)      # = mb.scale(mb.decode_value(registers, "uint32"), 10)
print(registers, answer)                           # (0, 4105) 410.5
check("10.1", answer)
