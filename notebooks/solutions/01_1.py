# 40108: prefix 4 = holding registers, number 0108 = 108, address = number - 1.
import modbus_edu as mb

reference = mb.parse_reference("40108")
answer = reference.address
print(reference.kind, answer)   # holding_registers 107
