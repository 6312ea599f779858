# One RTU transaction: request, t3.5, response, t3.5 (fixed at 1.75 ms above 19200 baud).
from modbus_edu.exercises import check


def transaction_time(baudrate: int, parity: str, stopbits: int, request_bytes: int, response_bytes: int) -> float:
    bits = 1 + 8 + (0 if parity == "N" else 1) + stopbits
    character = bits / baudrate
    t35 = 3.5 * character if baudrate <= 19200 else 0.00175
    return request_bytes * character + t35 + response_bytes * character + t35


print(round(transaction_time(9600, "N", 1, 8, 7) * 1000, 2), "ms")   # 22.92 ms
answer = transaction_time
check("08.4", answer)
