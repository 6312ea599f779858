# FC3's request PDU: the function code, then the starting address and the count, each high byte first.
from modbus_edu.exercises import check


def read_holding_registers_pdu(address: int, count: int) -> bytes:
    if not 1 <= count <= 125:
        raise ValueError(f"count {count}: a read asks for 1 to 125 registers")
    if not 0 <= address or address + count > 65536:
        raise ValueError(f"addresses {address}..{address + count - 1} go past 65535")
    return bytes([3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")


print(read_holding_registers_pdu(107, 3).hex(" ").upper())   # 03 00 6B 00 03
answer = read_holding_registers_pdu
check("02.5", answer)
