# The echo must be the request, byte for byte; what follows it is the answer.
from modbus_edu.exercises import check


def strip_echo(sent: bytes, received: bytes) -> bytes:
    if received[:len(sent)] != sent:
        raise ValueError("the bytes read back do not start with the request: no echo, or a damaged one")
    return received[len(sent):]


request = bytes.fromhex("01 04 00 00 00 02 71 CB")
print(strip_echo(request, request + bytes.fromhex("01 04 04 99 9A 43 65 04 2C")).hex(" "))
answer = strip_echo
check("16.4", answer)
