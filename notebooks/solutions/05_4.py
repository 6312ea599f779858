# The length 00 06 was written low byte first (06 00 = 1536): the MBAP length field is wrong.
import modbus_edu as mb
from modbus_edu.exercises import check

dissection = mb.explain("01 18 00 00 06 00 01 03 00 00 00 01", mode="tcp")
print(dissection.error)
answer = next(row.field for row in dissection.rows if not row.ok)
print(answer)   # length
check("05.4", answer)
