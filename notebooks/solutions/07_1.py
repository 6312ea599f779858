# 0x83 = 0x80 + 0x03: an exception response to function 3 (read holding registers); then code 02.
import modbus_edu as mb
from modbus_edu.exercises import check

frame = mb.RtuFrame.decode(mb.parse_hex("11 83 02 C1 34"), role="response")
answer = (frame.pdu.function, frame.pdu.code)
print(answer, frame.pdu)             # (3, 2): illegal data address
check("07.1", answer)
