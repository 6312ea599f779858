# Silence gives a timeout: a slave ignores requests for other units and requests it cannot trust.
# A damaged response is a checksum (CRC) error, a refusal an exception, another unit's answer a mismatch.
from modbus_edu.exercises import check

answer = {
    "request for a unit nobody has": "timeout",
    "one bit flipped in the request": "timeout",
    "one bit flipped in the response": "checksum error",
    "read of an address the slave does not have": "exception",
    "response carries another unit id": "mismatch",
}
check("07.3", answer)
