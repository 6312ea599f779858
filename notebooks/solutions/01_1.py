# 40250: prefix 4 = holding registers, number 0250 = 250, address = number - 1.
import modbus_edu as mb
from modbus_edu.exercises import check

reference = mb.parse_reference("40250")
answer = reference.address
print(reference.kind, answer)   # holding_registers 249
check("01.1", answer)
