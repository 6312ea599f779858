# Slave 17 (= 0x11) answers function 1 with 0x81 and exception code 02, illegal data address.
import modbus_edu as mb
from modbus_edu.exercises import check

answer = mb.RtuFrame(unit=17, pdu=mb.ExceptionResponse(function=1, code=2)).encode()
print(answer.hex(" ").upper())       # 11 81 02 C0 54
check("07.2", answer)
