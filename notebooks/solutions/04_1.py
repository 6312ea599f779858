# Sum: 0x11 + 0x03 + 0x00 + 0x6B + 0x00 + 0x03 = 0x82; two's complement: 0x100 - 0x82 = 0x7E.
import modbus_edu as mb
from modbus_edu.exercises import check

data = mb.parse_hex("11 03 00 6B 00 03")
for step in mb.lrc_trace(data):
    print(f"+ 0x{step.byte:02X} -> 0x{step.after:02X}")
answer = mb.lrc(data)
print(hex(answer))   # 0x7e
check("04.1", answer)
