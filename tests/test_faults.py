"""Fault injection: every fault, and what the master's statistics show for it."""

from __future__ import annotations

import pytest

from modbus_edu.errors import (
    ConfigError,
    CrcError,
    FrameLengthError,
    ModbusError,
    ModbusTimeoutError,
    TransactionMismatchError,
)
from modbus_edu.links import Faults, loopback_serial, loopback_tcp
from modbus_edu.master import Master
from modbus_edu.slave import Slave

FC3_TIME = 22 * 10 / 9600  # one FC3 transaction for 1 register at 9600 8N1


def rig(mode="rtu", seed=0, **master_kwargs):
    slave = Slave(unit=1)
    slave.bank.holding_registers[0] = 0x1234
    link = loopback_serial(slave, mode=mode, seed=seed)
    master = Master(link, timeout=master_kwargs.pop("timeout", 0.1), **master_kwargs)
    return slave, link, master


def test_flip_bits_in_the_request_means_a_timeout():
    slave, link, master = rig()
    link.faults.flip_bits(2, target="request")
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)
    assert slave.counters.checksum_errors == 1 and slave.counters.responses == 0
    assert master.stats.timeouts == 1
    assert link.faults.injected["bits_flipped"] == 2
    assert link.monitor[0].note.count("flipped") == 2
    assert master.read_holding_registers(1, 0, 1) == [0x1234]  # one-shot: the next frame is clean


def test_flip_bits_in_the_response_means_a_checksum_error():
    slave, link, master = rig()
    link.faults.flip_bits(1, target="response")
    with pytest.raises(CrcError):
        master.read_holding_registers(1, 0, 1)
    assert master.stats.checksum_errors == 1 and master.stats.timeouts == 0
    assert "checksum error" in master.log[-1].note
    assert link.clock.now == pytest.approx(FC3_TIME)  # no need to wait for the timeout


def test_flip_bits_in_ascii_is_an_lrc_or_format_error():
    slave, link, master = rig(mode="ascii")
    link.faults.flip_bits(1, target="response")
    with pytest.raises(ModbusError):
        master.read_holding_registers(1, 0, 1)
    s = master.stats
    assert s.checksum_errors + s.bad_responses + s.timeouts == 1


def test_drop_bytes_in_the_request_and_in_the_response():
    slave, link, master = rig()
    link.faults.drop_bytes(1, target="request")
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)
    assert slave.counters.checksum_errors + slave.counters.bad_frames == 1
    assert len(link.monitor[0].data) == 7 and "dropped" in link.monitor[0].note
    link.faults.drop_bytes(1, target="response")
    with pytest.raises(FrameLengthError, match="says 2 data bytes, 1 arrived: a byte was lost"):
        master.read_holding_registers(1, 0, 1)
    assert master.stats.timeouts == 1 and master.stats.bad_responses == 1
    # 2 data bytes announced, 0 arrived: one flipped bit in the byte count could do that too
    link.faults.drop_bytes(2, target="response")
    with pytest.raises(CrcError):
        master.read_holding_registers(1, 0, 1)
    assert link.faults.injected["bytes_dropped"] == 4


def test_any_target_hits_the_next_frame_whoever_sends_it():
    slave, link, master = rig()
    link.faults.flip_bits(1)  # target "any": the master's request is next on the wire
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)
    assert slave.counters.checksum_errors == 1


def test_gap_mid_frame_as_a_fault():
    slave, link, master = rig()
    link.faults.insert_gap(at_byte=5, chars=2.0, target="request")
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)
    assert link.stats.broken_frames == 1 and master.stats.timeouts == 1
    assert link.faults.injected["gaps"] == 1


def test_error_rates_are_seeded_and_reproducible():
    def run(seed):
        slave, link, master = rig(seed=seed)
        link.faults.bit_error_rate = 0.01
        link.faults.drop_rate = 0.005
        results = master.poll(interval=0.2, polls=300)
        return master.stats.as_dict(), [type(r).__name__ for r in results], link.clock.now

    first, again, other = run(1), run(1), run(2)
    assert first == again
    assert first != other
    stats = first[0]
    assert stats["valid_responses"] < 300
    assert stats["timeouts"] > 0 and stats["checksum_errors"] > 0
    assert stats["requests"] == (stats["valid_responses"] + stats["timeouts"] + stats["checksum_errors"]
                                 + stats["bad_responses"] + stats["exceptions"])


def test_delay_a_slave():
    slave, link, master = rig(timeout=0.1)
    link.faults.delay(1, 0.05)
    assert master.read_holding_registers(1, 0, 1) == [0x1234]
    assert master.stats.latencies[-1] == pytest.approx(FC3_TIME + 0.05)
    link.faults.delay(1, 0.2)
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)
    assert master.stats.timeouts == 1
    assert link.faults.injected["delayed"] == 2


def test_silence_a_slave_for_some_requests():
    slave, link, master = rig()
    link.faults.silence(1, requests=2)
    results = master.poll(interval=0.5, polls=4)
    assert [type(r).__name__ for r in results] == ["ModbusTimeoutError"] * 2 + ["list"] * 2
    assert slave.counters.requests == 2  # it never heard the first two
    assert master.stats.timeouts == 2 and master.stats.valid_responses == 2
    assert "silenced" in link.monitor[0].note


def test_answer_as_another_unit_is_a_mismatch():
    slave, link, master = rig()
    link.faults.answer_as(1, 9, requests=1)
    with pytest.raises(TransactionMismatchError, match="unit 9, expected 1"):
        master.read_holding_registers(1, 0, 1)
    assert master.stats.mismatches == 1 and master.stats.timeouts == 1
    assert master.read_holding_registers(1, 0, 1) == [0x1234]


def test_answer_as_in_ascii_and_tcp():
    slave, link, master = rig(mode="ascii")
    link.faults.answer_as(1, 3)
    with pytest.raises(TransactionMismatchError):
        master.read_holding_registers(1, 0, 1)
    tcp = loopback_tcp(Slave(unit=1))
    tcp.faults.answer_as(1, 4)
    with pytest.raises(TransactionMismatchError):
        Master(tcp, timeout=0.1).read_coils(1, 0, 1)


def test_tcp_supports_slave_faults_but_not_line_faults():
    link = loopback_tcp(Slave(unit=1), latency=0.01)
    master = Master(link, timeout=0.1)
    link.faults.silence(1, requests=1)
    with pytest.raises(ModbusTimeoutError):
        master.read_coils(1, 0, 1)
    link.faults.delay(1, 0.02, requests=1)
    assert master.read_coils(1, 0, 1) == [False]
    assert master.stats.latencies[-1] == pytest.approx(0.04)
    link.faults.flip_bits(1)
    with pytest.raises(ConfigError, match="serial-line faults"):
        master.read_coils(1, 0, 1)


def test_faults_object_checks_and_clear():
    faults = Faults(seed=3)
    for call in (lambda: faults.flip_bits(0), lambda: faults.drop_bytes(-1), lambda: faults.insert_gap(0, 2),
                 lambda: faults.insert_gap(2, 0), lambda: faults.insert_gap(2, "x"),
                 lambda: faults.flip_bits(1, target="slave"), lambda: faults.delay(1, -1),
                 lambda: faults.answer_as(1, 300)):
        with pytest.raises(ConfigError):
            call()
    with pytest.raises(ConfigError):
        faults.bit_error_rate = 1.5
    with pytest.raises(ConfigError):
        faults.drop_rate = "often"
    faults.bit_error_rate = 0.1
    faults.flip_bits(1, target="response")
    faults.delay(2, 0.5)
    faults.silence(3)
    faults.answer_as(4, 5)
    text = repr(faults)
    parts = ("bit_error_rate=0.1", "next response: flip 1", "delay unit 2", "silence unit 3", "answers as 5")
    for part in parts:
        assert part in text
    faults.clear()
    assert repr(faults) == "<Faults: none>" and not faults.touches_wire
    assert faults.extra_delay(2) == 0.0 and not faults.is_silenced(3) and faults.wrong_unit(4) is None


def test_corrupt_is_deterministic_for_a_seed():
    data = bytes(range(20))
    a, b = Faults(seed=7), Faults(seed=7)
    for f in (a, b):
        f.flip_bits(3)
        f.drop_bytes(2)
        f.insert_gap(at_byte=4, chars=2.5)
    out_a, out_b = a.corrupt(data, "request"), b.corrupt(data, "request")
    assert out_a == out_b
    corrupted, gaps, notes = out_a
    assert len(corrupted) == 18 and gaps == {4: 2.5} and len(notes) == 6
    assert a.pending == []
    # a fault for responses leaves requests alone
    a.flip_bits(1, target="response")
    assert a.corrupt(data, "request")[0] == data and len(a.pending) == 1


def test_silence_counts_only_frames_addressed_to_the_slave_on_a_multidrop_bus():
    slaves = [Slave(unit=u) for u in (1, 2, 3)]
    link = loopback_serial(slaves)
    master = Master(link, timeout=0.1)
    link.faults.silence(2, requests=1)
    assert master.read_coils(1, 0, 1) == [False]  # unit 2 hears nothing of this, uses nothing up
    with pytest.raises(ModbusTimeoutError):
        master.read_coils(2, 0, 1)
    assert master.read_coils(2, 0, 1) == [False]
    assert slaves[1].counters.requests == 1 and slaves[1].counters.other_unit == 0
    assert slaves[0].counters.other_unit == 3  # a request for 2 and two answers heard by unit 1
