# 3xxxx = input registers, read with function 4; number 10 is address 9.
import modbus_edu as mb

ref = mb.parse_reference("30010")
print(repr(ref))                    # Reference(kind='input_registers', address=9)
answer = (4, ref.address)
