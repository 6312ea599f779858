# Request: 8 bytes.  Response to FC3 for N registers: 5 + 2 x N bytes = 25 for N = 10.
# One transaction = request + 3.5 chars + response + 3.5 chars = 40 characters of 10 bits at 19200 baud.
import modbus_edu as mb
from modbus_edu.exercises import check

timing = mb.SerialTiming(baudrate=19200)
seconds = timing.transaction_time(request_bytes=8, response_bytes=5 + 2 * 10)
answer = 1 / seconds
print(f"{seconds * 1000:.3f} ms per transaction, {answer:.1f} transactions per second")   # 48 per second
check("08.2", answer)
