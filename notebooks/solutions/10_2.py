# 288.9 A = 288 900 mA = 0x00046884: high word 0x0004 first, then 0x6884.
import modbus_edu as mb
from modbus_edu.exercises import check

answer = mb.encode_value(288900, "uint32", "ABCD")
print([f"0x{r:04X}" for r in answer])              # ['0x0004', '0x6884']
check("10.2", answer)
