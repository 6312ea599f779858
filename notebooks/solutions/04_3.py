# High register first (ABCD): 0x0001 x 65536 + 0xE240 = 65536 + 57920 = 123456.
import modbus_edu as mb

answer = mb.decode_value([0x0001, 0xE240], "uint32", "ABCD")
print(answer)   # 123456
