import math

import modbus_edu as mb
from modbus_edu.exercises import check


# Try the four word orders; the one whose float32 is the value the device should show is the device's.
def find_order(registers: list, expected: float):
    for order in mb.ORDERS:
        if math.isclose(mb.decode_value(registers, "float32", order), expected, rel_tol=1e-6):
            return order
    return None


print(find_order([0x8000, 0x4396], 301.0))   # CDAB
answer = find_order
check("13.7", answer)
