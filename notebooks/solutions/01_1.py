# 40108: prefix 4 = holding registers, number 0108 = 108, address = number - 1.
from modbus_edu.datamodel import parse_reference

reference = parse_reference("40108")
answer = reference.address
print(reference.kind, answer)   # holding_registers 107
