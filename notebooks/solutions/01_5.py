# A reference number is the table's digit, then a 4-digit number counted from 1: the address is one less.
from modbus_edu.exercises import check

TABLES = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}


def parse_reference(text: str) -> tuple:
    table = TABLES[text[0]]              # an unknown first digit raises KeyError
    number = int(text[1:])
    if not 1 <= number <= 9999:
        raise ValueError(f"{text}: the number after the table digit counts from 1")
    return table, number - 1


print(parse_reference("40108"))          # ('holding_registers', 107)
answer = parse_reference
check("01.5", answer)
