"""Traffic logs: every frame a master, a slave or a wire monitor saw, with its time and direction.

A :class:`TrafficLog` is a list of :class:`Traffic` entries.  The master logs what it sends (``"tx"``)
and receives (``"rx"``); a loopback wire's monitor logs everything on the line, marking what the master
sent ``"tx"`` and what a slave sent ``"rx"``.  Times are on the clock of the link (virtual seconds on
a loopback wire), so a log replays identically every time.

The master, the slave and the wire monitor log every frame with :meth:`TrafficLog.record`, which keeps the
entry as a plain tuple and makes the :class:`Traffic` object only when someone looks at it.  A ten-minute
poll logs tens of thousands of frames: tuples of strings and numbers are invisible to Python's garbage
collector, while as many objects would be scanned by it over and over (on a long simulated poll, a third
of the time).  A slave's fast path (a Modbus/TCP read answered from bytes) records its answer's note as
the request's and the answer's PDU bytes; the note is written when the log is read.

>>> log = TrafficLog()
>>> log.append(Traffic(0.0, "tx", "rtu", bytes.fromhex("010300000001840A"), source="master", dest="unit 1"))
>>> print(log.to_text())
      time  dir  mode  bytes                    note
  0.000000  tx   rtu   01 03 00 00 00 01 84 0A  master -> unit 1
"""

from __future__ import annotations

import dataclasses
import html
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass, replace
from typing import Any

from . import pdu as _pdu
from .codes import _hex
from .errors import ConfigError, ModbusError, guard_numbers, shown
from .explain import explain

__all__ = ["Traffic", "TrafficLog", "pdu_note"]

DIRECTIONS = ("tx", "rx")


@dataclass(frozen=True, init=False)
class Traffic:
    """One frame seen by a master, a slave or a monitor.

    ``time``       seconds on the link's clock when the frame was sent or completely received
                   (on a wire monitor: when its first bit went on the line; ``duration`` is how long
                   the line was busy with it)
    ``direction``  ``"tx"`` sent by the logging party (by the master, on a monitor) or ``"rx"``
                   received by it (sent by a slave, on a monitor)
    ``mode``       ``"rtu"``, ``"ascii"`` or ``"tcp"``
    ``data``       the raw bytes, exactly as on the wire
    ``source``, ``dest``   who sent it, and to whom (labels such as ``"master"``, ``"unit 3"``)
    ``note``       what happened to it: ``"CRC error"``, ``"2 bits flipped"``, ``"ignored: unit 2"``
    ``role``       ``"request"`` or ``"response"`` when known (``None``: guess from ``direction``)
    """

    time: float
    direction: str
    mode: str
    data: bytes
    source: str = ""
    dest: str = ""
    note: str = ""
    role: str | None = None
    duration: float = 0.0

    def __init__(
        self,
        time: float,
        direction: str,
        mode: str,
        data: bytes,
        source: str = "",
        dest: str = "",
        note: str = "",
        role: str | None = None,
        duration: float = 0.0,
    ) -> None:
        if direction not in DIRECTIONS:
            raise ConfigError(f"Traffic direction must be 'tx' or 'rx', got {shown(direction)}")
        # The entry is frozen (assigning to a field raises): its fields are written once, here, directly.
        self.__dict__.update(
            time=time, direction=direction, mode=mode, data=data if data.__class__ is bytes else bytes(data),
            source=source, dest=dest, note=note, role=role, duration=duration,
        )

    @property
    def hex(self) -> str:
        """The bytes as spaced uppercase hex (an ASCII frame too: its characters' codes)."""
        return _hex(self.data)

    @property
    def text(self) -> str:
        """The bytes as people read them: an ASCII frame as its characters, anything else as hex."""
        if self.mode == "ascii" and self.data[:1] == b":":
            return self.data.decode("ascii", "replace").replace("\r", "\\r").replace("\n", "\\n")
        return self.hex

    @property
    def unit(self) -> int | None:
        """The unit id the frame carries (``None`` if the frame is too short to have one)."""
        data = self.data
        try:
            if self.mode == "tcp":
                return data[6] if len(data) > 6 else None
            if self.mode == "ascii":
                return int(data[1:3], 16) if len(data) >= 3 and data[:1] == b":" else None
            return data[0] if data else None
        except ValueError:
            return None

    @property
    def function(self) -> int | None:
        """The function code byte (128+ for an exception response), or ``None``."""
        data = self.data
        try:
            if self.mode == "tcp":
                return data[7] if len(data) > 7 else None
            if self.mode == "ascii":
                return int(data[3:5], 16) if len(data) >= 5 and data[:1] == b":" else None
            return data[1] if len(data) > 1 else None
        except ValueError:
            return None

    @property
    def guessed_role(self) -> str:
        """``role`` if known, else ``"request"`` for ``tx`` and ``"response"`` for ``rx``."""
        if self.role:
            return self.role
        return "request" if self.direction == "tx" else "response"

    def label(self) -> str:
        """``"master -> unit 1"``, or just the note's parties that are known."""
        if self.source or self.dest:
            return f"{self.source or '?'} -> {self.dest or '?'}"
        return ""

    def __str__(self) -> str:
        parts = [f"{self.time:10.6f}", f"{self.direction:<3}", f"{self.mode:<4}", self.text]
        extra = "; ".join(p for p in (self.label(), self.note) if p)
        return "  ".join(parts) + (f"  {extra}" if extra else "")


_Row = tuple  # (time, direction, mode, data, source, dest, note, role, duration): a recorded entry

# --- notes for PDUs ----------------------------------------------------------------------------------
_NOTES: dict[tuple, str] = {}
_NOTES_MAX = 512
_FIELD_NAMES: dict[type, tuple[str, ...] | None] = {}
_INT_OR_BOOL = (int, bool)


def _field_names(cls: type) -> tuple[str, ...] | None:
    """The fields of one of the library's PDU classes (None for any other class: its notes are not kept)."""
    try:
        return _FIELD_NAMES[cls]
    except KeyError:
        names = None
        if cls.__module__.startswith("modbus_edu.pdu") and dataclasses.is_dataclass(cls):
            names = tuple(f.name for f in dataclasses.fields(cls))
        _FIELD_NAMES[cls] = names
        return names


def pdu_note(pdu: Any) -> str:
    """``pdu.summary()``, the note the master and the slave log with a frame, remembered.

    A master polling a meter sends the same request thousands of times and often gets the same answer;
    writing its summary costs more than the rest of the log entry, so each distinct PDU's text is written
    once and looked up afterwards.  A summary depends only on the PDU's class and field values (PDUs are
    frozen), so it is remembered under exactly those: the class, each field's value *and its exact type*
    (a register holding an ``IntEnum`` prints differently from one holding the same plain ``int``).
    PDUs with values of other types, and classes from outside the library, are simply summarised again.
    """
    cls = pdu.__class__
    names = _field_names(cls)
    if names is None:
        return pdu.summary()
    key: list[Any] = [cls]
    for name in names:
        value = getattr(pdu, name)
        kind = value.__class__
        if kind is tuple:
            kinds = set(map(type, value))
            if len(kinds) > 1:
                return pdu.summary()
            kind = kinds.pop() if kinds else None
            if kind is not None and kind not in _INT_OR_BOOL:
                return pdu.summary()
        elif kind not in _INT_OR_BOOL:
            return pdu.summary()
        key.append(kind)
        key.append(value)
    frozen = tuple(key)
    note = _NOTES.get(frozen)
    if note is None:
        note = pdu.summary()
        if len(_NOTES) >= _NOTES_MAX:
            _NOTES.clear()
        _NOTES[frozen] = note
    return note


_REPLY_NOTES: dict[tuple[bytes, bytes], str] = {}


def _note_text(note: str | tuple[bytes, bytes]) -> str:
    """A recorded note as text.  A note may be recorded as ``(request PDU, response PDU)``, the bytes of a
    request a slave answered on its fast path (:meth:`~modbus_edu.pdu.Pdu.answer_from_bytes`) and of its
    answer: the class of the request's function writes it now (:meth:`~modbus_edu.pdu.Pdu.reply_note`),
    remembered for the last 512 different pairs (a polled device answers the same few)."""
    if note.__class__ is not tuple:
        return note  # type: ignore[return-value]
    text = _REPLY_NOTES.get(note)  # type: ignore[arg-type]
    if text is None:
        request, reply = note
        text = _pdu.request_class(request[0]).reply_note(request, reply)
        if len(_REPLY_NOTES) >= _NOTES_MAX:
            _REPLY_NOTES.clear()
        _REPLY_NOTES[note] = text  # type: ignore[index]
    return text


def _entry(item: Traffic | _Row) -> Traffic:
    """The :class:`Traffic` of a stored item (a recorded row becomes one now, its note written)."""
    if item.__class__ is not tuple:
        return item  # type: ignore[return-value]
    note = item[6]
    if note.__class__ is tuple:
        return Traffic(*item[:6], _note_text(note), *item[7:])
    return Traffic(*item)


class TrafficLog:
    """A list of :class:`Traffic` entries, with search, text and HTML views.

    ``maxlen`` keeps only the newest entries (``None``: keep all).  Index it like a list: ``log[-1]`` is
    the newest entry.
    """

    @guard_numbers
    def __init__(self, entries: list[Traffic] | None = None, maxlen: int | None = None) -> None:
        self._entries: deque[Traffic | _Row] = deque(entries or (), maxlen=maxlen)
        # record() keeps rows only when add() and append() are this class's own: a subclass that
        # overrides them (the command line's log that prints every entry) still sees every entry.
        cls = type(self)
        self._rows = cls.add is TrafficLog.add and cls.append is TrafficLog.append

    @property
    def maxlen(self) -> int | None:
        return self._entries.maxlen

    def append(self, entry: Traffic) -> None:
        """Add an entry at the end (the oldest one goes if the log is full)."""
        self._entries.append(entry)

    def add(self, time: float, direction: str, mode: str, data: bytes, **kwargs: Any) -> Traffic:
        """Build a :class:`Traffic` from its fields, append it and return it."""
        entry = Traffic(time, direction, mode, data, **kwargs)
        self._entries.append(entry)
        return entry

    def record(
        self,
        time: float,
        direction: str,
        mode: str,
        data: bytes,
        source: str = "",
        dest: str = "",
        note: str = "",
        role: str | None = None,
        duration: float = 0.0,
    ) -> None:
        """Log a frame like :meth:`add`, but keep it as a plain tuple until someone looks at it.

        What the master, the slaves and the wire monitor use: reading the log (``log[i]``, iterating,
        :meth:`search`, :meth:`to_text`) gives the same :class:`Traffic` entries as :meth:`add` would.
        ``note`` may be ``(request PDU, response PDU)``, bytes a slave's fast path answered: the log
        writes that note when it is read (:func:`_note_text`).
        """
        if not self._rows:
            self.add(time, direction, mode, data, source=source, dest=dest, note=_note_text(note), role=role,
                     duration=duration)
            return
        if direction not in DIRECTIONS:
            raise ConfigError(f"Traffic direction must be 'tx' or 'rx', got {shown(direction)}")
        if data.__class__ is not bytes:
            data = bytes(data)
        self._entries.append((time, direction, mode, data, source, dest, note, role, duration))

    def annotate(self, text: str, index: int = -1) -> None:
        """Add ``text`` to the note of entry ``index`` (default: the newest; no-op on an empty log)."""
        entries = self._entries
        if not entries:
            return
        old = entries[index]
        if old.__class__ is tuple:
            note = _note_text(old[6])
            entries[index] = (*old[:6], f"{note}; {text}" if note else text, *old[7:])
            return
        entries[index] = replace(old, note=f"{old.note}; {text}" if old.note else text)  # type: ignore[arg-type]

    def clear(self) -> None:
        """Forget every entry."""
        self._entries.clear()

    def __iter__(self) -> Iterator[Traffic]:
        return iter(list(map(_entry, self._entries)))

    def __len__(self) -> int:
        return len(self._entries)

    def __getitem__(self, index: int) -> Traffic:
        try:
            return _entry(self._entries[index])
        except IndexError:
            raise ModbusError(
                f"traffic log index {shown(index)} is out of range: the log holds "
                f"{len(self._entries)} entries"
            ) from None

    def __repr__(self) -> str:
        return f"<TrafficLog: {len(self)} entries>"

    # -- finding --------------------------------------------------------------------------------
    def search(
        self,
        unit: int | None = None,
        function: int | None = None,
        text: str | None = None,
        direction: str | None = None,
    ) -> TrafficLog:
        """The entries that match every criterion given, as a new log.

        ``unit``: the unit id in the frame; ``function``: the function code (an exception response to
        function 3 matches both 3 and 0x83); ``text``: case-insensitive, in the hex (``"84 0a"``), in
        the ASCII text of an ASCII frame, in the note or the source/destination labels;
        ``direction``: ``"tx"`` or ``"rx"``.
        """
        needle = text.strip().lower() if text else None
        found = []
        for entry in map(_entry, self._entries):
            if unit is not None and entry.unit != unit:
                continue
            if function is not None:
                fc = entry.function
                if fc is None or (fc != function and (fc & 0x7F) != function):
                    continue
            if direction is not None and entry.direction != direction:
                continue
            if needle:
                haystack = " ".join(
                    (entry.hex, entry.data.hex(), entry.text, entry.note, entry.source, entry.dest)
                ).lower()
                if needle not in haystack:
                    continue
            found.append(entry)
        return TrafficLog(found)

    def explain(self, index: int) -> Any:
        """The field-by-field dissection of entry ``index`` (see :func:`modbus_edu.explain.explain`)."""
        entry = self[index]
        return explain(entry.data, entry.mode, entry.guessed_role)

    # -- showing --------------------------------------------------------------------------------
    def to_text(self, newest_first: bool = False) -> str:
        """An aligned table: time, direction, mode, bytes, and who/what."""
        entries = list(map(_entry, self._entries))
        if newest_first:
            entries.reverse()
        texts = [e.text for e in entries]
        width = max([len(text) for text in texts] + [5])
        lines = [f"{'time':>10}  dir  mode  {'bytes':<{width}}  note"]
        for e, text in zip(entries, texts):
            extra = "; ".join(p for p in (e.label(), e.note) if p)
            line = f"{e.time:10.6f}  {e.direction:<3}  {e.mode:<4}  {text:<{width}}  {extra}"
            lines.append(line.rstrip())
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.to_text()

    def _repr_html_(self) -> str:
        rows = []
        for i, e in enumerate(map(_entry, self._entries)):
            colour = "#e8f0fe" if e.direction == "tx" else "#e6f4ea"
            rows.append(
                f'<tr style="background:{colour}"><td>{i}</td><td>{e.time:.6f}</td><td>{e.direction}</td>'
                f"<td>{e.mode}</td><td>{html.escape(e.label())}</td>"
                f'<td style="font-family:monospace">{html.escape(e.text)}</td>'
                f"<td>{html.escape(e.note)}</td></tr>"
            )
        head = (
            "<tr><th>#</th><th>time (s)</th><th>dir</th><th>mode</th><th>from &rarr; to</th>"
            "<th>bytes</th><th>note</th></tr>"
        )
        return f'<table class="modbus-traffic">{head}{"".join(rows)}</table>'
