# FC 22's arithmetic: bits kept where the AND mask has 1, the OR mask's bits where it has 0.
from modbus_edu.exercises import check


def mask_write(current: int, and_mask: int, or_mask: int) -> int:
    return (current & and_mask) | (or_mask & ~and_mask & 0xFFFF)


print(hex(mask_write(0x12, 0xF2, 0x25)))   # 0x17, the specification's example
answer = mask_write
check("14.2", answer)
