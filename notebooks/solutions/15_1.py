# FC 3 for two registers: request 8 bytes, response 3 + 2 x 2 + 2 = 9 bytes, and 3.5 characters of silence after
# each. At 19200 baud 8E1 a character is 11 bits (start, 8 data, parity, stop).
from modbus_edu.exercises import check

answer = (8 + 3.5 + 9 + 3.5) * 11 / 19200 * 1000
print(f"{answer:.2f} ms")   # 13.75 ms
check("15.1", answer)
