"""FC 12's event bytes in words, checked against the slave's own event log."""

from __future__ import annotations

import doctest

import pytest

import modbus_edu as mb
from modbus_edu import comm_events
from modbus_edu.comm_events import describe_event


@pytest.mark.parametrize("event, words", [
    (0x80, "message received"),
    (0xA0, "message received: in listen-only mode"),
    (0xC2, "message received: communication error, broadcast received"),
    (0x40, "response sent"),
    (0x41, "response sent: read exception sent (exception 01-03)"),
    (0x42, "response sent: server abort exception sent (exception 04)"),
    (0x44, "response sent: server busy exception sent (exception 05-06)"),
    (0x48, "response sent: program NAK exception sent (exception 07)"),
    (0x04, "entered listen-only mode"),
    (0x00, "communications restarted"),
    (0x13, "not an event"),
])
def test_each_kind_of_event_byte_is_named(event, words):
    assert describe_event(event).startswith(words) or words in describe_event(event)


def test_a_value_that_is_not_a_byte_is_refused():
    for bad in (-1, 256, "80", True):
        with pytest.raises(mb.ModbusError):
            describe_event(bad)


def test_the_slaves_log_reads_as_the_story_that_happened():
    slave = mb.Slave(unit=1)
    slave.bank.files.sparse = True  # a device with no files: a file record read is exception 02
    master = mb.Master(mb.loopback_serial(slave))
    master.read_holding_registers(unit=1, address=0, count=1)
    with pytest.raises(mb.ModbusExceptionError):
        master.read_file_record(unit=1, file=9, record=0, count=1)   # exception 02
    events = master.get_comm_event_log(unit=1).events
    # newest first: the FC 12 request itself, the exception sent, its request, the normal answer, its request
    assert [describe_event(e) for e in events[:5]] == [
        "message received", "response sent: read exception sent (exception 01-03)", "message received",
        "response sent", "message received"]
    assert doctest.testmod(comm_events).failed == 0
