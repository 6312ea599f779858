"""A frame the learner built byte by byte, read for the one slip that explains every byte it gets wrong.

The slips are the catalogue's (:mod:`.misconceptions`): a value in decimal digits written as hex, a field
low byte first, hex digits read as decimal.  Every checker of a hand-built frame asks :func:`frame_slip`, so
the slip reads the same in every notebook.
"""

from __future__ import annotations

from typing import Any

from .misconceptions import _bytes, detect, name

FRAME_SLIPS = ("decimal-written-as-hex", "field-low-byte-first", "hex-read-as-decimal")
"""The slips :func:`frame_slip` looks for in a frame the learner built byte by byte."""


def _windows(start: int, end: int, limit: int) -> list[list[tuple[int, int]]]:
    """Ways to read the differing bytes ``start..end-1`` as fields of one or two bytes (within ``limit``)."""
    length = end - start
    if length == 1:
        spans = [[(start, start + 1)], [(start - 1, start + 1)], [(start, start + 2)]]
    else:
        spans = [[(i, min(i + 2, end)) for i in range(start, end, 2)]]
    return [span for span in spans if all(0 <= a < b <= limit for a, b in span)]


def frame_slip(got: Any, expected: Any, tail: int = 0, keys: tuple[str, ...] = FRAME_SLIPS) -> str | None:
    """Name the slip that explains every byte where a frame the learner built differs from the right one.

    ``got`` and ``expected`` are frames of the same length; the last ``tail`` bytes (an RTU frame's CRC,
    which follows whatever came before) are left out.  Each run of differing bytes is read as a field of
    one or two bytes, high byte first; a slip of ``keys`` that explains every run is named, with the
    first field's numbers: a value written in decimal digits as hex (500 as ``05 00``), a field low byte
    first (500 as ``F4 01``), hex digits read as decimal (0x1234 as 1234, ``04 D2``).  None when no one
    slip explains them all.
    """
    if not (_bytes(got) and _bytes(expected)) or len(got) != len(expected) or got == expected:
        return None
    limit = len(expected) - tail
    differ = [i for i in range(limit) if got[i] != expected[i]]
    if not differ:
        return None
    runs: list[list[int]] = []
    for i in differ:
        if runs and i == runs[-1][1]:
            runs[-1][1] = i + 1
        else:
            runs.append([i, i + 1])
    for key in keys:
        fields = []
        for start, end in runs:
            for span in _windows(start, end, limit):
                found = [detect(key, int.from_bytes(got[a:b], "big"), int.from_bytes(expected[a:b], "big"))
                         for a, b in span]
                if all(found):
                    fields.append(found[0])
                    break
            else:
                break
        else:
            return name(key, **fields[0])
    return None
