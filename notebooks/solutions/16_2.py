# Five digits: 3xxxx / 4xxxx; six digits: 3xxxxx / 4xxxxx. The rest after the table digit, minus one.
def to_address(number: int) -> int:
    if 30001 <= number <= 39999 or 40001 <= number <= 49999:
        return number % 10000 - 1
    if 300001 <= number <= 365536 or 400001 <= number <= 465536:
        return number % 100000 - 1
    raise ValueError(f"{number} is not a 3x/4x reference number")


answer = to_address
