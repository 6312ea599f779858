"""VirtualClock and RealClock."""

from __future__ import annotations

import pytest

from modbus_edu.clock import Clock, RealClock, VirtualClock
from modbus_edu.errors import ConfigError


def test_events_run_in_time_order_then_schedule_order():
    clock = VirtualClock()
    seen = []
    clock.call_at(0.3, seen.append, "c")
    clock.call_at(0.1, seen.append, "a1")
    clock.call_at(0.1, seen.append, "a2")
    clock.call_later(0.2, seen.append, "b")
    assert clock.pending == 4 and clock.next_time == 0.1
    assert clock.run_until(0.25) is False
    assert seen == ["a1", "a2", "b"] and clock.now == 0.25
    clock.run_until_idle()
    assert seen == ["a1", "a2", "b", "c"] and clock.now == 0.3
    assert clock.next_time is None and clock.step() is False


def test_cancel_and_past_times():
    clock = VirtualClock(start=5.0)
    seen = []
    timer = clock.call_later(1.0, seen.append, "never")
    clock.cancel(timer)
    clock.cancel(None)
    clock.call_at(1.0, seen.append, "late")  # in the past: runs now
    assert clock.pending == 1
    clock.run_until(5.5)
    assert seen == ["late"] and clock.now == 5.5
    clock.run_until(2.0)  # never backwards
    assert clock.now == 5.5


def test_schedule_is_call_at_without_a_timer():
    clock = VirtualClock(start=1.0)
    seen = []
    clock.call_at(2.0, seen.append, "timer")
    assert clock.schedule(2.0, seen.append, "scheduled") is None
    clock.schedule(0.5, seen.append, "late")  # in the past: runs now, after what is due now
    timer = clock.call_at(1.5, seen.append, "cancelled")
    timer.cancel()
    assert clock.pending == 3 and clock.next_time == 1.0
    assert clock.step() and seen == ["late"] and clock.now == 1.0
    clock.run_until(3.0)
    assert seen == ["late", "timer", "scheduled"] and clock.events_run == 3
    with pytest.raises(ConfigError):
        clock.schedule(float("nan"), seen.append, "never")


def test_callbacks_may_schedule_more_and_step_moves_time():
    clock = VirtualClock()
    seen = []

    def tick(n):
        seen.append((round(clock.now, 9), n))
        if n < 3:
            clock.call_later(0.5, tick, n + 1)

    clock.call_later(0.5, tick, 1)
    assert clock.step() and clock.now == 0.5
    assert clock.run_until_idle() == 2
    assert seen == [(0.5, 1), (1.0, 2), (1.5, 3)]
    assert clock.events_run == 3


def test_run_until_with_stop_predicate():
    clock = VirtualClock()
    box = []
    clock.call_at(1.0, box.append, 1)
    clock.call_at(2.0, box.append, 2)
    assert clock.run_until(10.0, stop=lambda: bool(box)) is True
    assert clock.now == 1.0 and box == [1]
    assert clock.run_until(10.0, stop=lambda: bool(box)) is True  # already true: returns at once
    assert clock.now == 1.0


def test_run_until_idle_limit_and_runaway_guard():
    clock = VirtualClock()
    clock.call_at(1.0, lambda: None)
    clock.call_at(3.0, lambda: None)
    assert clock.run_until_idle(limit=2.0) == 1 and clock.now == 1.0

    def forever():
        clock.call_later(1.0, forever)

    clock.call_later(0, forever)
    with pytest.raises(ConfigError):
        clock.run_until_idle(max_events=50)


def test_advance_and_sleep_are_instant_and_exact():
    clock = VirtualClock()
    clock.advance(600.0)
    clock.sleep(0.25)
    clock.sleep(0)
    assert clock.now == 600.25
    with pytest.raises(ConfigError):
        clock.advance(-1)
    with pytest.raises(ConfigError):
        clock.call_later(-0.1, lambda: None)
    with pytest.raises(ConfigError):
        clock.call_at(float("nan"), lambda: None)
    assert "VirtualClock" in repr(clock)


def test_real_clock_has_the_same_interface():
    clock = RealClock()
    assert isinstance(clock, Clock) and isinstance(VirtualClock(), Clock)
    t0 = clock.now
    clock.sleep(0)
    assert clock.now >= t0 >= 0
    assert "RealClock" in repr(clock)
