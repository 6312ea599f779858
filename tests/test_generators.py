"""Dummy data: seeded fills and time-driven generators, all within 0..65535."""

from __future__ import annotations

import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from modbus_edu.datamodel import DataBank
from modbus_edu.devices.generators import (
    AutoFill,
    Constant,
    Generator,
    Noise,
    Ramp,
    Sine,
    Uniform,
    clamp_register,
    increment_fill,
    random_fill,
)
from modbus_edu.errors import ConfigError, IllegalAddressError


# --- random fill -----------------------------------------------------------------------------------
def test_random_fill_is_reproducible():
    a, b = DataBank(), DataBank()
    va = random_fill(a.holding_registers, 0, 50, seed=42)
    vb = random_fill(b.holding_registers, 0, 50, seed=42)
    assert va == vb == a.holding_registers.read(0, 50) == b.holding_registers.read(0, 50)
    assert random_fill(DataBank().holding_registers, 0, 50, seed=43) != va
    assert len(set(va)) > 40  # really random-looking


def test_random_fill_bounds_and_bits():
    bank = DataBank()
    vals = random_fill(bank.input_registers, 100, 500, seed=1, low=10, high=20)
    assert all(10 <= v <= 20 for v in vals) and set(vals) == set(range(10, 21))
    assert random_fill(bank.holding_registers, 0, 5, seed=1, low=7, high=7) == [7] * 5
    bits = random_fill(bank.coils, 0, 200, seed=3)
    assert all(type(b) is bool for b in bits) and True in bits and False in bits
    assert bank.coils.read(0, 200) == bits


def test_random_fill_accepts_a_random_instance():
    rng = random.Random(5)
    first = random_fill(DataBank().holding_registers, 0, 3, rng)
    second = random_fill(DataBank().holding_registers, 0, 3, rng)
    assert first != second  # the sequence continues
    assert random_fill(DataBank().holding_registers, 0, 3, random.Random(5)) == first


def test_random_fill_edges_and_errors():
    bank = DataBank()
    random_fill(bank.holding_registers, 65535, 1, seed=0)
    with pytest.raises(IllegalAddressError):
        random_fill(bank.holding_registers, 65535, 2, seed=0)
    sparse = DataBank(sparse=True)
    sparse.holding_registers.declare(0, 2)
    with pytest.raises(IllegalAddressError, match="address 2 "):
        random_fill(sparse.holding_registers, 0, 3, seed=0)
    assert sparse.holding_registers.read(0, 2) == [0, 0]
    for kwargs in ({"low": -1}, {"high": 65536}, {"low": 5, "high": 4}, {"low": 1.5}):
        with pytest.raises(ConfigError):
            random_fill(bank.holding_registers, 0, 1, seed=0, **kwargs)
    for seed in (None, 1.5, [1]):
        with pytest.raises(ConfigError, match="seed"):
            random_fill(bank.holding_registers, 0, 1, seed)
    with pytest.raises(ConfigError, match="table"):
        random_fill(bank, 0, 1, seed=0)
    with pytest.raises(ConfigError, match="count"):
        random_fill(bank.coils, 0, -1, seed=0)


# --- increment fill -----------------------------------------------------------------------------------
def test_increment_fill():
    t = DataBank().holding_registers
    assert increment_fill(t, 0, 4, start=100, step=10) == [100, 110, 120, 130]
    assert t.read(0, 4) == [100, 110, 120, 130]
    assert increment_fill(t, 0, 4, start=65534, step=1) == [65534, 65535, 0, 1]  # wraps like a counter
    assert increment_fill(t, 0, 3, start=-1, step=-1) == [65535, 65534, 65533]
    assert increment_fill(t, 65535, 1, start=9) == [9]
    assert increment_fill(DataBank().coils, 0, 4, start=0, step=1) == [False, True, False, True]
    with pytest.raises(ConfigError):
        increment_fill(t, 0, 2, start=1.5)
    with pytest.raises(IllegalAddressError):
        increment_fill(t, 65535, 2)


@settings(max_examples=200, deadline=None)
@given(st.integers(-10**6, 10**6), st.integers(-10**5, 10**5), st.integers(0, 40))
def test_increment_fill_stays_in_range(start, step, count):
    vals = increment_fill(DataBank().holding_registers, 0, count, start, step)
    assert len(vals) == count
    assert all(0 <= v <= 65535 for v in vals)
    assert all((vals[i + 1] - vals[i]) % 65536 == step % 65536 for i in range(count - 1))


# --- generators ---------------------------------------------------------------------------------------------
def test_clamp_register():
    assert [clamp_register(x) for x in (-5, 0, 1.4, 1.6, 65535.4, 1e9, float("-inf"), float("nan"))] == [
        0,
        0,
        1,
        2,
        65535,
        65535,
        0,
        0,
    ]


def test_ramp():
    r = Ramp(start=100, step=10, period=1.0)
    assert [r.value(t) for t in (0, 0.5, 1, 1.99, 2, 10)] == [100, 100, 110, 110, 120, 200]
    assert r.value(0.1 * 30) == 130  # 3.0000000000000004 counts as 3 periods, and 2.9999999999999996 too
    assert r(sum([0.1] * 30)) == 130
    assert Ramp(0, 1, period=0.5).value(2) == 4
    down = Ramp(start=5, step=-2)
    assert [down.value(t) for t in range(5)] == [5, 3, 1, 0, 0]  # clamped at 0
    assert Ramp(65530, 3).value(10) == 65535  # clamped at the top
    wrap = Ramp(65530, 3, wrap=True)
    assert [wrap.value(t) for t in range(5)] == [65530, 65533, 0, 3, 6]
    saw = Ramp(10, 1, low=10, high=12, wrap=True)
    assert [saw.value(t) for t in range(6)] == [10, 11, 12, 10, 11, 12]
    assert Ramp(0, 1, low=10, high=12).value(100) == 12


def test_sine():
    s = Sine(base=2300, amplitude=50, period=60)
    assert [s.value(t) for t in (0, 15, 30, 45, 60)] == [2300, 2350, 2300, 2250, 2300]
    assert Sine(base=0, amplitude=100, period=4).value(3) == 0  # -100 clamped
    assert Sine(base=65535, amplitude=100, period=4).value(1) == 65535


def test_noise_depends_only_on_seed_channel_and_time():
    n = Noise(base=1000, sigma=10, seed=7)
    forward = [n.value(t) for t in range(20)]
    backward = [n.value(t) for t in reversed(range(20))]
    assert forward == backward[::-1]
    assert forward == [Noise(base=1000, sigma=10, seed=7).value(t) for t in range(20)]
    assert forward != [Noise(base=1000, sigma=10, seed=8).value(t) for t in range(20)]
    assert n.value(3) == n.value(3.0)
    assert [n.value(t, channel=1) for t in range(20)] != forward
    assert 950 < sum(forward) / 20 < 1050
    assert Noise(base=1000, sigma=0, seed=1).value(5) == 1000


def test_noise_on_a_signal():
    clean = Sine(2300, 50, 60)
    noisy = Noise(clean, sigma=3, seed=1)
    diffs = [noisy.value(t) - clean.value(t) for t in range(100)]
    assert any(diffs) and all(abs(d) < 20 for d in diffs)


def test_uniform_holds_for_a_period():
    u = Uniform(low=0, high=65535, seed=3, period=2.0)
    assert u.values(0, 5) == u.values(1.9, 5)
    assert u.values(2.0, 5) == u.values(3.9, 5) != u.values(0, 5)
    assert u.values(0, 3) == [u.value(0, 0), u.value(0, 1), u.value(0, 2)]
    assert len(set(u.values(0, 20))) > 15
    assert Uniform(5, 5, seed=0).values(1, 3) == [5, 5, 5]


def test_constant():
    assert Constant(7).value(123) == 7
    assert Constant(-3).value(0) == 0


@pytest.mark.parametrize(
    "make",
    [
        lambda: Ramp(period=0),
        lambda: Ramp(step="1"),
        lambda: Ramp(low=3, high=2),
        lambda: Sine(period=-1),
        lambda: Sine(base=float("nan")),
        lambda: Noise(sigma=-1),
        lambda: Noise(seed=None),
        lambda: Uniform(high=70000),
        lambda: Uniform(period=0),
        lambda: Constant("x"),
    ],
)
def test_generator_settings_checked(make):
    with pytest.raises(ConfigError):
        make()


generators = st.one_of(
    st.builds(
        Ramp,
        start=st.integers(-(10**6), 10**6),
        step=st.integers(-(10**4), 10**4),
        period=st.floats(0.01, 100),
        wrap=st.booleans(),
    ),
    st.builds(
        Sine,
        base=st.floats(-1e5, 1e5),
        amplitude=st.floats(0, 1e5),
        period=st.floats(0.01, 1000),
        phase=st.floats(-10, 10),
    ),
    st.builds(Noise, base=st.floats(-1e5, 1e5), sigma=st.floats(0, 1e5), seed=st.integers(0, 2**32)),
    st.builds(Uniform, seed=st.integers(0, 2**32), period=st.floats(0.01, 100)),
)


@settings(max_examples=300, deadline=None)
@given(generators, st.floats(-1e6, 1e6), st.integers(0, 10))
def test_generators_deterministic_and_in_range(gen, t, channel):
    v = gen.value(t, channel)
    assert type(v) is int and 0 <= v <= 65535
    assert gen.value(t, channel) == v
    assert isinstance(gen, Generator)


# --- auto fill --------------------------------------------------------------------------------
def test_autofill_ticks_on_the_clock():
    bank = DataBank()
    fill = AutoFill(bank.input_registers, 10, 3, Ramp(0, 1), interval=1.0)
    assert fill.update(0.0) == [0, 0, 0]
    assert fill.update(0.5) is None
    assert fill.next_tick() == 1.0
    assert fill.update(1.0) == [1, 1, 1]
    assert bank.input_registers.read(10, 3) == [1, 1, 1]
    assert fill.update(4.7) == [4, 4, 4]  # ticks 2 and 3 were skipped: the latest one is written
    assert fill.last_tick == 4.0 and fill.ticks == 3
    assert fill.update(4.9) is None
    assert fill.update(5.0) == [5, 5, 5]


def test_autofill_values_do_not_depend_on_polling():
    def run(times):
        bank = DataBank()
        fill = AutoFill(bank.holding_registers, 0, 4, Uniform(seed=9), interval=0.5)
        for now in times:
            fill.update(now)
        return bank.holding_registers.read(0, 4)

    fine = [i * 0.01 for i in range(301)]
    coarse = [0.0, 1.3, 2.2, 3.0]
    assert run(fine) == run(coarse) == Uniform(seed=9).values(3.0, 4)


def test_autofill_start_stop_and_first():
    bank = DataBank()
    fill = AutoFill(bank.holding_registers, 0, 1, Ramp(0, 1), interval=2.0, first=10.0)
    assert fill.update(9.99) is None
    assert fill.update(10.0) == [10 // 1]
    fill.stop()
    assert fill.update(12.0) is None
    assert bank.holding_registers[0] == 10
    fill.start()
    assert fill.update(12.5) == [12]
    fill.start(now=20.3)
    assert fill.update(20.3) == [20]
    assert fill.update(22.2) is None
    assert fill.update(22.3) == [22]


def test_autofill_bits_and_generator_lists():
    bank = DataBank()
    fill = AutoFill(bank.coils, 0, 2, [Constant(1), Constant(2)], interval=1)
    assert fill.update(0) == [True, False]
    assert bank.coils.read(0, 2) == [True, False]
    gens = [Ramp(0, 1), Sine(100, 0, 10)]
    fill2 = AutoFill(bank.holding_registers, 0, 2, gens)
    assert fill2.update(3) == [3, 100]


def test_autofill_checks():
    bank = DataBank()
    sparse = DataBank(sparse=True)
    with pytest.raises(IllegalAddressError):
        AutoFill(sparse.holding_registers, 0, 2, Ramp())
    with pytest.raises(IllegalAddressError):
        AutoFill(bank.holding_registers, 65535, 2, Ramp())
    with pytest.raises(ConfigError, match="2 generators for 3 elements"):
        AutoFill(bank.holding_registers, 0, 3, [Ramp(), Ramp()])
    with pytest.raises(ConfigError):
        AutoFill(bank.holding_registers, 0, 1, lambda t: 5)
    with pytest.raises(ConfigError):
        AutoFill(bank.holding_registers, 0, 1, Ramp(), interval=0)
    with pytest.raises(ConfigError):
        AutoFill(bank.holding_registers, 0, 0, Ramp())
    with pytest.raises(ConfigError):
        AutoFill(bank, 0, 1, Ramp())
    fill = AutoFill(bank.holding_registers, 0, 1, Ramp())
    with pytest.raises(ConfigError):
        fill.update("now")


def test_autofill_with_a_virtual_clock_if_present():
    clock_mod = pytest.importorskip("modbus_edu.clock")
    clock = clock_mod.VirtualClock()
    bank = DataBank()
    fill = AutoFill(bank.input_registers, 0, 1, Ramp(0, 5), interval=1.0)
    seen = []
    for _ in range(4):
        fill.update(clock.now)
        seen.append(bank.input_registers[0])
        clock.advance(1.0)
    assert seen == [0, 5, 10, 15]


@pytest.mark.parametrize("t", [float("nan"), float("inf"), "x", None])
def test_a_generator_refuses_a_time_that_is_not_a_finite_number(t) -> None:
    with pytest.raises(ConfigError, match="finite number of seconds"):
        Sine(100, 10, 5).value(t)
