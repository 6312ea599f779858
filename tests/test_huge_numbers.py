"""A huge int given anywhere raises the library's own error, with a message of a few lines.

Python refuses to write an int of more than 4300 digits (``ValueError: Exceeds the limit``) and to turn
one into a float (``OverflowError``).  A message that showed such a number whole would raise that error
instead of the library's; each message here names the number by its size
(:func:`modbus_edu.errors.shown`).  Every call below leaked Python's error before.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import modbus_edu as mb
from modbus_edu.errors import shown


def _master() -> mb.Master:
    return mb.Master(mb.loopback_serial(mb.Slave(unit=1)), timeout=0.1)


def _log() -> mb.TrafficLog:
    log = mb.TrafficLog()
    log.add(0.0, "tx", "rtu", b"\x01\x03\x00\x00\x00\x01\x84\x0a")
    return log


CALLS = {
    "text_to_registers length": lambda n: mb.text_to_registers("\x00", n),
    "Master.read_once function": lambda n: _master().read_once(n, 1, 0, 1),
    "Master.poll function": lambda n: _master().poll(function=n),
    "Master.poll interval": lambda n: _master().poll(n, 1),
    "Master retries": lambda n: mb.Master(mb.loopback_serial(mb.Slave()), retries=-n if n > 0 else n),
    "Master transaction_id": lambda n: mb.Master(mb.loopback_serial(mb.Slave()), transaction_id=n),
    "SerialTiming parity": lambda n: mb.SerialTiming(parity=n),
    "SerialTiming stopbits": lambda n: mb.SerialTiming(stopbits=n),
    "SerialTiming bytesize": lambda n: mb.SerialTiming(bytesize=n),
    "character_time parity": lambda n: mb.character_time(9600, parity=n),
    "TcpFrame protocol_id": lambda n: mb.TcpFrame(1, 1, mb.ReadHoldingRegistersRequest(0, 1), protocol_id=n),
    "WriteSingleCoilRequest value": lambda n: mb.WriteSingleCoilRequest(0, n),
    "ReadHoldingRegistersResponse registers": lambda n: mb.ReadHoldingRegistersResponse(registers=[n]),
    "WriteMultipleRegistersRequest values": lambda n: mb.WriteMultipleRegistersRequest(0, [1, n]),
    "Reference address": lambda n: mb.Reference("holding_registers", n),
    "datasheet_to_address number": lambda n: mb.datasheet_to_address(n),
    "table_kind": lambda n: mb.table_kind(n),
    "DataBank.table": lambda n: mb.DataBank().table(n),
    "Table.write values": lambda n: mb.DataBank().holding_registers.write(0, [n]),
    "decode_frame mode": lambda n: mb.decode_frame(b"\x01\x03\x00\x00\x00\x01\x84\x0a", mode=n),
    "decode_values type": lambda n: mb.decode_values([1], n),
    "TrafficLog.explain index": lambda n: _log().explain(n),
    "TrafficLog maxlen": lambda n: mb.TrafficLog(maxlen=n),
    "VirtualClock start": lambda n: mb.VirtualClock(n),
    "loopback_tcp latency": lambda n: mb.LoopbackTcpLink(latency=n),
}


def test_shown_names_a_huge_int_by_its_size():
    assert shown(10**5000) == "an int of 16610 bits (about 5001 digits)"
    assert shown(2**64 - 1) == str(2**64 - 1)  # up to 64 bits a number is written as it is
    assert shown(-(10**5000)) == "a negative int of 16610 bits (about 5001 digits)"  # the sign is kept
    assert shown([1, 10**5000]) == "a list"  # a list whose repr Python refuses to write


@pytest.mark.parametrize("call", CALLS.values(), ids=CALLS.keys())
def test_a_number_of_5000_digits_raises_the_library_error(call):
    with pytest.raises(mb.ModbusError) as caught:
        call(10**5000)
    assert len(str(caught.value)) < 600


@settings(max_examples=40, deadline=None)
@given(st.integers(4300, 12_000), st.sampled_from([1, -1]), st.integers(0, 99), st.sampled_from(list(CALLS)))
def test_any_huge_int_anywhere_gets_a_short_message(digits, sign, tail, name):
    with pytest.raises(mb.ModbusError) as caught:
        CALLS[name](sign * (10**digits + tail))
    assert len(str(caught.value)) < 600
