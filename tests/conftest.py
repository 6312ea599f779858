"""Shared by every test file: at the end of a run, where the time went, by file (setup, call and teardown
of its tests, module fixtures included), so that a run that grows slow says which file made it slow."""

from __future__ import annotations

from collections import Counter

SLOWEST_FILES = 10


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    seconds: Counter[str] = Counter()
    for reports in terminalreporter.stats.values():
        for report in reports:
            nodeid = getattr(report, "nodeid", "")
            duration = getattr(report, "duration", None)
            if nodeid and isinstance(duration, float):
                seconds[nodeid.split("::", 1)[0]] += duration
    if not seconds:
        return
    total = sum(seconds.values())
    slowest = ", ".join(f"{path} {spent:.0f}" for path, spent in seconds.most_common(SLOWEST_FILES))
    terminalreporter.write_line(f"seconds by file ({total:.0f} in all), the slowest: {slowest}")
