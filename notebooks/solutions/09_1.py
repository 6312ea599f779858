# 3xxxx = input registers, read with function 4; number 10 is address 9.
import modbus_edu as mb
from modbus_edu.exercises import check

ref = mb.parse_reference("30010")
print(repr(ref))                    # Reference(kind='input_registers', address=9)
answer = (4, ref.address)
check("09.1", answer)
