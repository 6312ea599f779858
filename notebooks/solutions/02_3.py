# Function 3 + 0x80 = 0x83, exception code 02 = illegal data address.
import modbus_edu as mb

answer = mb.ExceptionResponse(function=3, code=mb.ExceptionCode.ILLEGAL_DATA_ADDRESS).encode()
print(answer.hex(" ").upper())   # 83 02
