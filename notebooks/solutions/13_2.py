# High word first gives about 293 000 A; low word first (CDAB) gives a current a machine can draw.
import modbus_edu as mb
from modbus_edu.exercises import lab
from modbus_edu.exercises import check

registers = mb.Master(lab("word order")).read_holding_registers(unit=1, address=0, count=2)
for order in ("ABCD", "CDAB"):
    print(order, mb.decode_value(registers, "uint32", order) / 1000, "A")
answer = ("CDAB", mb.decode_value(registers, "uint32", "CDAB") / 1000)
check("13.2", answer)
