# A slave's request handler for FC3 and FC6 over a list of holding registers.
from modbus_edu.exercises import check


def handle(registers: list, pdu: bytes) -> bytes:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    if function == 3:
        count = int.from_bytes(pdu[3:5], "big")
        if not 1 <= count <= 125:
            return bytes([0x83, 3])                       # illegal data value
        if address + count > len(registers):
            return bytes([0x83, 2])                       # illegal data address
        data = b"".join(value.to_bytes(2, "big") for value in registers[address:address + count])
        return bytes([3, len(data)]) + data
    if function == 6:
        if address >= len(registers):
            return bytes([0x86, 2])
        registers[address] = int.from_bytes(pdu[3:5], "big")
        return bytes(pdu)                                 # the echo of the request
    return bytes([function | 0x80, 1])                    # illegal function


print(handle([1234, 42], bytes.fromhex("03 00 00 00 02")).hex(" ").upper())   # 03 04 04 D2 00 2A
answer = handle
check("06.5", answer)
