# Function code 4 reads input registers: measurements the device makes; a master may only read them.
from modbus_edu.datamodel import DataBank, table_kind

kind = table_kind(4)
answer = (kind, DataBank().table(kind).writable)
print(answer)   # ('input_registers', False)
