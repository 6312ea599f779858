# The first byte of an RTU frame is the slave address.  0x11 is hexadecimal: 1 x 16 + 1 = 17.
import modbus_edu as mb
from modbus_edu.exercises import check

frame = mb.parse_hex("11 03 00 6B 00 03 76 87")
answer = mb.RtuFrame.decode(frame).unit   # the library reads the byte for us
print(answer)                              # 17, the same as int("11", 16)
check("00.1", answer)
