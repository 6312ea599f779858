# A request lands at a random point of the slave's loop; it is answered in time if the loop gets to it
# within timeout - reply seconds.
from modbus_edu.exercises import check


def answered_fraction(loop_time: float, timeout: float, reply: float) -> float:
    if loop_time <= 0:
        return 1.0 if timeout >= reply else 0.0
    return max(0.0, min(1.0, (timeout - reply) / loop_time))


print(round(answered_fraction(1.65, 1.0, 0.0), 2))   # 0.61: the slow sketch of notebook 09
answer = answered_fraction
check("09.4", answer)
