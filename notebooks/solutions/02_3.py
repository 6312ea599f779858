# Function 4 (read input registers) + 0x80 = 0x84, exception code 02 = illegal data address.
import modbus_edu as mb
from modbus_edu.exercises import check

answer = mb.ExceptionResponse(function=4, code=mb.ExceptionCode.ILLEGAL_DATA_ADDRESS).encode()
print(answer.hex(" ").upper())   # 84 02
check("02.3", answer)
