# FC 22: keep the bits of 0x00A5 where the AND mask is 1 (0x0005), take the OR mask's bits elsewhere (0x0130).
from modbus_edu.exercises import check

answer = (0x00A5 & 0x000F) | (0x0130 & ~0x000F & 0xFFFF)
print(hex(answer))   # 0x135
check("14.1", answer)
