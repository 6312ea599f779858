# One 8E1 character is start + 8 data + parity + stop = 11 bits; at 4800 baud it lasts 11 / 4800 s.
# The silence that ends an RTU frame is 3.5 of them (the fixed 1.750 ms only applies above 19200 baud).
import modbus_edu as mb
from modbus_edu.exercises import check

timing = mb.SerialTiming(baudrate=4800, parity="E", stopbits=1)
answer = timing.t35
print(f"{answer * 1000:.3f} ms")          # 3.5 x 11 / 4800 s = 8.021 ms
check("08.1", answer)
