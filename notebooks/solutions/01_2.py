# Input registers have the prefix 3; address 9 is element number 10, written with four digits.
import modbus_edu as mb
from modbus_edu.exercises import check

answer = mb.format_reference("input_registers", 9)
print(answer)   # 30010
check("01.2", answer)
