# A datasheet that numbers registers from 1: register 1 is address 0, register 65536 address 65535.
def to_address(number: int) -> int:
    if not 1 <= number <= 65536:
        raise ValueError(f"register {number} is outside 1..65536")
    return number - 1


answer = to_address
