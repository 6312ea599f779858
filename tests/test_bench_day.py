"""The bench day (notebook 16): a meter that misbehaves as real ones do, and the tools to find out why.

Wrong parity and A/B swapped give silence, an echoing adapter hands the master its own request, the
first answer after power-up comes late; the flowchart, the echo helper and the worksheet exercises.
"""

from __future__ import annotations

import doctest

import pytest

import modbus_edu as mb
from modbus_edu import exercises
from modbus_edu.devices import BenchMeter, bench_map
from modbus_edu.devices import bench as bench_module
from modbus_edu.errors import ConfigError
from modbus_edu.exercises import nb16
from modbus_edu.links import echo as echo_module
from modbus_edu.links.echo import EchoError, strip_echo
from modbus_edu.links.wire import SerialTiming, uart_receive

FREQUENCY = 70  # the bench meter's frequency: 30071, address 70, a float32 (two registers, CDAB)


def _read_frequency(link, timeout: float = 1.5):
    master = mb.Master(link, timeout=timeout)
    registers = master.read_input_registers(unit=1, address=FREQUENCY, count=2)
    return mb.decode_value(registers, "float32", "CDAB"), master


# --- the wire: A and B swapped ---------------------------------------------------------------------------
def test_an_inverted_line_gives_garbage_and_a_straight_one_the_bytes():
    line = SerialTiming(9600, "E")
    request = bytes.fromhex("01 04 00 46 00 02 90 1E")
    assert uart_receive(request, line, line).data == request
    inverted = uart_receive(request, line, line, inverted=True)
    assert inverted.data != request and inverted.framing_errors + inverted.parity_errors > 0
    # the idle line reads 0 and every level is flipped: no character survives as it was sent
    assert request[0] not in inverted.data[:1]


def test_a_meter_with_a_and_b_swapped_stays_silent_until_the_wires_are_swapped_back():
    meter = BenchMeter()
    link = mb.loopback_serial(meter, baudrate=9600, parity="E")
    link.faults.swap_ab(1)
    with pytest.raises(mb.ModbusTimeoutError):
        _read_frequency(link, timeout=0.2)
    assert meter.counters.requests == 0 and link.faults.injected["inverted"] == 1
    assert "A and B swapped" in str(link.monitor)
    link.faults.swap_ab(1, swapped=False)
    link.run(1.0)
    value, _ = _read_frequency(link)
    assert value == 50.0


def test_swap_ab_refuses_a_unit_that_is_not_one():
    with pytest.raises(ConfigError):
        mb.loopback_serial().faults.swap_ab("1")


# --- the adapter: echo -----------------------------------------------------------------------------------
def test_an_echoing_adapter_hands_the_master_its_own_request_first():
    link = mb.loopback_serial(BenchMeter(wake_time=0), baudrate=9600, parity="E")
    link.faults.echo = True
    master = mb.Master(link, timeout=0.5)
    with pytest.raises(mb.ModbusError, match="byte count 0"):
        master.read_input_registers(unit=1, address=FREQUENCY, count=2)
    sent, echoed = [entry.data for entry in master.log][:2]
    assert sent == echoed and master.stats.bad_responses == 1
    assert link.faults.injected["echoed"] == 1
    link.faults.echo = False
    link.run(0.5)
    assert mb.decode_value(master.read_input_registers(unit=1, address=FREQUENCY, count=2), "float32",
                           "CDAB") == 50.0


def test_echo_is_a_bool_and_clear_turns_it_off():
    faults = mb.loopback_serial().faults
    with pytest.raises(ConfigError):
        faults.echo = "yes"
    faults.echo = True
    faults.swap_ab(3)
    assert "echoes" in repr(faults) and "A/B swapped" in repr(faults)
    faults.clear()
    assert faults.echo is False and not faults.swapped(3)


def test_strip_echo_returns_the_answer_and_refuses_a_missing_or_damaged_echo():
    request = bytes.fromhex("01 04 00 00 00 02 71 CB")
    answer = mb.RtuFrame(unit=1, pdu=mb.ReadInputRegistersResponse(registers=[0x999A, 0x4365])).encode()
    assert strip_echo(request, request + answer) == answer
    assert strip_echo(request, request) == b""
    for received in (answer, request[:5], request[:-1] + b"\x00" + answer):
        with pytest.raises(EchoError):
            strip_echo(request, received)
    with pytest.raises(mb.ModbusError):
        strip_echo(b"", answer)
    assert doctest.testmod(echo_module).failed == 0


# --- the meter: its menu, its slow first answer, its map ----------------------------------------------
def test_the_wrong_parity_gives_silence_and_the_menus_parity_an_answer():
    meter = BenchMeter(wake_time=0)
    with pytest.raises(mb.ModbusTimeoutError):
        _read_frequency(mb.loopback_serial(meter, baudrate=9600, parity="N"), timeout=0.2)
    assert meter.counters.requests == 0 and meter.counters.checksum_errors == 1
    value, _ = _read_frequency(mb.loopback_serial(meter, **meter.serial_settings))
    assert value == 50.0 and meter.serial_settings == {"baudrate": 9600, "parity": "E", "stopbits": 1}


def test_the_menu_moves_the_meter_and_refuses_what_it_does_not_offer():
    meter = BenchMeter(wake_time=0)
    meter.set_menu(address=7, baudrate=19200, parity="none")
    assert (meter.unit, meter.baudrate, meter.parity) == (7, 19200, "N")
    master = mb.Master(mb.loopback_serial(meter, baudrate=19200, parity="N"))
    assert len(master.read_input_registers(unit=7, address=0, count=2)) == 2
    for bad in ({"address": 0}, {"address": 248}, {"baudrate": 115200}, {"parity": "M"}):
        with pytest.raises(ConfigError):
            meter.set_menu(**bad)
    with pytest.raises(ConfigError):
        BenchMeter(wake_time=-1)


def test_the_first_answer_after_power_up_is_late_then_the_meter_is_quick():
    meter = BenchMeter(wake_time=0.8)
    link = mb.loopback_serial(meter, **meter.serial_settings)
    master = mb.Master(link, timeout=0.5)
    with pytest.raises(mb.ModbusTimeoutError):
        master.read_input_registers(unit=1, address=FREQUENCY, count=2)
    link.run(1.0)  # the late answer arrives and is thrown away as stale before the next request
    master.read_input_registers(unit=1, address=FREQUENCY, count=2)
    assert master.stats.latencies[-1] < 0.05
    meter.power_cycle()
    patient = mb.Master(link, timeout=1.5)
    patient.read_input_registers(unit=1, address=FREQUENCY, count=2)
    assert 0.8 < patient.stats.latencies[-1] < 0.85


def test_the_meter_has_only_its_datasheet_registers_and_only_function_04():
    meter = BenchMeter(wake_time=0)
    master = mb.Master(mb.loopback_serial(meter, **meter.serial_settings))
    with pytest.raises(mb.ModbusExceptionError) as error:
        master.read_input_registers(unit=1, address=1, count=2)   # counted from 1: address 2 is no register
    assert error.value.code == 2
    with pytest.raises(mb.ModbusExceptionError) as error:
        master.read_holding_registers(unit=1, address=0, count=2)
    assert error.value.code == 1
    values = bench_map().read(master, unit=1)
    assert values == pytest.approx(bench_module.BENCH_VALUES, rel=1e-6)
    # read with the wrong word order, the frequency is absurd
    registers = master.read_input_registers(unit=1, address=FREQUENCY, count=2)
    assert abs(mb.decode_value(registers, "float32", "ABCD")) < 1e-3


def test_the_datasheet_and_the_map_file_agree():
    for point in bench_map():
        assert f"{30001 + point.address}" in bench_module.DATASHEET
    assert "low word first" in bench_module.DATASHEET and "function code 04" in bench_module.DATASHEET


def test_the_flowchart_draws_every_symptom_and_every_check():
    import matplotlib.pyplot as plt

    figure = bench_module.troubleshooting_figure()
    texts = [text.get_text() for text in figure.axes[0].texts]
    for symptom, checks in bench_module.TROUBLESHOOTING.items():
        assert symptom in texts
        for name, hint in checks:
            assert f"{name}\n{hint}" in texts
    assert {"A/B", "settings", "first answer", "numbering", "word order", "parity", "echo"} <= {
        name for checks in bench_module.TROUBLESHOOTING.values() for name, _ in checks}
    plt.close(figure)


# --- the exercises ---------------------------------------------------------------------------------------
MAP_HEADER = "name,table,address,type,order,scale,unit\n"
RIGHT_ROWS = ["voltage,input,30001,float32,CDAB,1,V", "current,input,30007,float32,CDAB,1,A",
              "active_power,input,30013,float32,CDAB,1,W", "frequency,input,30071,float32,CDAB,1,Hz",
              "import_energy,input,30073,float32,CDAB,1,kWh"]


def _map(rows):
    return MAP_HEADER + "\n".join(rows) + "\n"


@pytest.mark.parametrize("answer", [
    _map(RIGHT_ROWS),
    _map(reversed(RIGHT_ROWS)),                                               # any row order
    "name,table,address,type,order\n" + "\n".join(r.rsplit(",", 2)[0] for r in RIGHT_ROWS),  # no scale/unit
    _map(r.replace("voltage", "u_l1") for r in RIGHT_ROWS),                   # names are the learner's
])
def test_16_1_accepts_the_map_in_any_reasonable_spelling(answer):
    assert exercises.evaluate("16.1", answer).ok is True


@pytest.mark.parametrize("answer, words", [
    (_map(r.replace("CDAB", "ABCD") for r in RIGHT_ROWS), "low word first"),
    (_map(r.replace("input", "holding") for r in RIGHT_ROWS), "input registers"),
    (_map(r.replace(",300", ",300").replace("30001", "30002") for r in RIGHT_ROWS), "one too high"),
    (_map(r.replace("float32", "uint32") for r in RIGHT_ROWS), "float32"),
    (_map(r.replace("CDAB,1", "CDAB,0.1") for r in RIGHT_ROWS), "scale is 1"),
    (_map(RIGHT_ROWS[:4]), "one row each"),
    (_map(r.replace("3000", "").replace("300", "") for r in RIGHT_ROWS), "counted from 1"),
    (_map(RIGHT_ROWS).replace("30001", "0").replace("30007", "6").replace("30013", "12")
     .replace("30071", "70").replace("30073", "72"), "protocol addresses"),
    ("voltage 30001", "cannot read it"),
    (42, "as a str"),
])
def test_16_1_names_the_mistake(answer, words):
    result = exercises.evaluate("16.1", answer)
    assert result.ok is False and words in result.message, result.message


def test_16_2_accepts_the_planners_frames_as_bytes_or_hex():
    frames = nb16.expected_frames()
    assert len(frames) == 4
    assert exercises.evaluate("16.2", frames).ok is True
    assert exercises.evaluate("16.2", [frame.hex(" ") for frame in frames]).ok is True
    assert frames == [bytes(mb.RtuFrame(unit=1, pdu=mb.ReadInputRegistersRequest(address=poll.address,
                                                                                 count=poll.count)).encode())
                      for poll in BenchMeter().map.plan()]


def _with_crc(body: bytes) -> bytes:
    return body + mb.crc16(body).to_bytes(2, "little")


@pytest.mark.parametrize("change, words", [
    (lambda f: f[:-2] + f[-2:][::-1], "swapped CRC bytes"),
    (lambda f: _with_crc(f[:1] + b"\x03" + f[2:-2]), "holding and input registers confused"),
    (lambda f: _with_crc(f[:2] + (int.from_bytes(f[2:4], "big") + 1).to_bytes(2, "big") + f[4:-2]),
     "a 1-based address"),
    (lambda f: _with_crc(f[:2] + (int.from_bytes(f[2:4], "big") + 30001).to_bytes(2, "big") + f[4:-2]),
     "reference number"),
    (lambda f: _with_crc(b"\x02" + f[1:-2]), "unit 2"),
])
def test_16_2_names_the_slip_in_a_frame(change, words):
    frames = nb16.expected_frames()
    frames[0] = change(frames[0])
    result = exercises.evaluate("16.2", frames)
    assert result.ok is False and words in result.message, result.message


def test_16_2_refuses_one_request_per_value_and_frames_out_of_order():
    assert "one request per value" in exercises.evaluate("16.2", exercises.EXERCISES["16.2"].wrong).message
    frames = nb16.expected_frames()
    assert "out of place" in exercises.evaluate("16.2", frames[::-1]).message
    assert "list of frames" in exercises.evaluate("16.2", frames[0]).message


@pytest.mark.parametrize("answer", ["A/B", "swap A and B", "Swap the wires.", "polarity", "A and B swapped",
                                    "reverse A and B", "b/a", "D0/D1"])
def test_16_3_accepts_a_b_in_its_spellings(answer):
    assert exercises.evaluate("16.3", answer).ok is True


@pytest.mark.parametrize("answer", sorted(nb16.REFUSED_16_3))
def test_16_3_refuses_the_other_checks_with_a_reason(answer):
    result = exercises.evaluate("16.3", answer)
    assert result.ok is False and nb16.REFUSED_16_3[answer] in result.message


def test_16_4_refuses_a_function_that_never_checks_the_echo():
    result = exercises.evaluate("16.4", lambda sent, received: received[len(sent):])
    assert result.ok is False and "should raise" in result.message
