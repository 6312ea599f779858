# An exception response: the function code with its top bit set, then the exception code.
from modbus_edu.exercises import check


def exception_response(function: int, code: int) -> bytes:
    return bytes([function | 0x80, code])


print(exception_response(3, 2).hex(" ").upper())   # 83 02
answer = exception_response
check("07.4", answer)
