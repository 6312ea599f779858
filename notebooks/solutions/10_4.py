import struct
from modbus_edu.exercises import check

# Register 0 holds bytes A B, register 1 holds C D (in ABCD order); the order's name says where each sits.
def decode_float32(registers: list, order: str) -> float:
    raw = registers[0].to_bytes(2, "big") + registers[1].to_bytes(2, "big")
    positions = {letter: index for index, letter in enumerate(order)}   # e.g. CDAB: C at 0, D at 1, ...
    abcd = bytes(raw[positions[letter]] for letter in "ABCD")
    return struct.unpack(">f", abcd)[0]


print(round(decode_float32([0xCCCD, 0x43C9], "CDAB"), 1))   # 403.6
answer = decode_float32
check("10.4", answer)
