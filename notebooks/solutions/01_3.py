# Function code 4 reads input registers: measurements the device makes; a master may only read them.
import modbus_edu as mb
from modbus_edu.exercises import check

kind = mb.table_kind(4)
answer = (kind, mb.DataBank().table(kind).writable)
print(answer)   # ('input_registers', False)
check("01.3", answer)
