# The CRC of 11 03 00 6B 00 03 is 0x8776 (wire: 76 87); the frame carries 76 86, so the slave drops it.
import modbus_edu as mb
from modbus_edu.exercises import check

dissection = mb.explain("11 03 00 6B 00 03 76 86")
print(dissection.error)
answer = dissection.ok   # False: a frame with a bad CRC is never answered
check("03.3", answer)
