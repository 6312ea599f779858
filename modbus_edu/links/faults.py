"""Fault injection for the loopback links: scripted and seeded, so every run breaks the same way.

Real lines lose bytes, flip bits and stall; real slaves answer late, not at all, or with the wrong
address.  A :class:`Faults` object (``link.faults``) makes the virtual wire do the same, on purpose, so a
learner can see what each fault does to the master's statistics.

Line faults (serial links only; TCP carries its own checksums and retransmissions):

* ``bit_error_rate`` -- each byte on the wire has this probability of one flipped data bit;
* ``drop_rate`` -- each byte has this probability of never reaching the line;
* :meth:`flip_bits` -- the next frame gets ``bits`` flipped bits (at seeded-random places);
* :meth:`drop_bytes` -- the next frame loses ``count`` bytes;
* :meth:`insert_gap` -- the next frame falls silent for ``chars`` character times before byte ``at_byte``
  (more than 1.5 breaks an RTU frame, 3.5 or more cuts it in two).

"The next frame" is the next one of the kind given by ``target``: ``"request"`` (sent by the master),
``"response"`` (sent by a slave) or ``"any"``.

Slave faults (every loopback link):

* :meth:`delay` -- a slave answers ``seconds`` later than it would;
* :meth:`silence` -- a slave is cut off the bus: it hears nothing and answers nothing;
* :meth:`answer_as` -- a slave answers with another unit id in its response;
* :meth:`swap_ab` -- a slave's A and B wires are swapped (serial links): its transceiver sees every
  level inverted, so its receiver assembles garbage (:func:`~modbus_edu.links.wire.uart_receive` with
  ``inverted=True``), the CRC fails and it never answers.

Adapter fault (serial links):

* :attr:`echo` -- the master's USB-RS485 adapter keeps its receiver on while it transmits, so every
  request comes back to the master as a frame of its own, before any answer.

Each of them is counted in :attr:`injected` and noted on the link's monitor.  All randomness comes from
``random.Random(seed)``.
"""

from __future__ import annotations

import random
from collections import Counter
from dataclasses import dataclass

from ..errors import ConfigError, shown

__all__ = ["Faults", "WireFault"]

TARGETS = ("request", "response", "any")


def _check_target(target: str) -> str:
    if target not in TARGETS:
        raise ConfigError(f"target must be 'request', 'response' or 'any', got {shown(target)}")
    return target


def _check_rate(name: str, value: float) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"{name} must be a probability between 0 and 1, got {shown(value)}") from None
    if not 0.0 <= value <= 1.0:
        raise ConfigError(f"{name} must be a probability between 0 and 1, got {shown(value)}")
    return value


@dataclass
class WireFault:
    """A one-shot fault waiting for the next frame of its ``target`` kind."""

    kind: str  # "flip" | "drop" | "gap"
    target: str
    amount: float  # bits to flip, bytes to drop, or character times of silence
    at_byte: int | None = None


@dataclass
class _SlaveFault:
    value: float | int | None
    remaining: int | None  # how many more requests it applies to (None: until cleared)

    def use(self) -> bool:
        """Consume one use; False once exhausted."""
        if self.remaining is None:
            return True
        if self.remaining <= 0:
            return False
        self.remaining -= 1
        return True


class Faults:
    """The faults a loopback link injects (``link.faults``); see the module's documentation."""

    def __init__(self, seed: int | None = 0) -> None:
        self.seed = seed
        self.rng = random.Random(seed)
        self._bit_error_rate = 0.0
        self._drop_rate = 0.0
        self.pending: list[WireFault] = []
        """One-shot line faults not yet applied, oldest first."""
        self._delays: dict[int, _SlaveFault] = {}
        self._silenced: dict[int, _SlaveFault] = {}
        self._answer_as: dict[int, _SlaveFault] = {}
        self._swapped: set[int] = set()
        self._echo = False
        self.injected: Counter[str] = Counter()
        """How many faults of each kind were injected: ``bits_flipped``, ``bytes_dropped``, ``gaps``,
        ``delayed``, ``silenced``, ``wrong_unit``, ``inverted`` (frames a slave heard through swapped
        A/B wires), ``echoed`` (requests the adapter echoed)."""

    def __repr__(self) -> str:
        active = []
        if self._bit_error_rate:
            active.append(f"bit_error_rate={self._bit_error_rate}")
        if self._drop_rate:
            active.append(f"drop_rate={self._drop_rate}")
        active += [f"next {f.target}: {f.kind} {f.amount:g}" for f in self.pending]
        active += [f"delay unit {u}: +{f.value} s" for u, f in self._delays.items()]
        active += [f"silence unit {u}" for u in self._silenced]
        active += [f"unit {u} answers as {f.value}" for u, f in self._answer_as.items()]
        active += [f"unit {u}: A/B swapped" for u in sorted(self._swapped)]
        active += ["the adapter echoes requests"] if self._echo else []
        return f"<Faults: {', '.join(active) if active else 'none'}>"

    # -- rates ------------------------------------------------------------------------------------
    @property
    def bit_error_rate(self) -> float:
        """Probability (0..1) that a byte on the wire gets one of its data bits flipped."""
        return self._bit_error_rate

    @bit_error_rate.setter
    def bit_error_rate(self, value: float) -> None:
        self._bit_error_rate = _check_rate("bit_error_rate", value)

    @property
    def drop_rate(self) -> float:
        """Probability (0..1) that a byte never reaches the line."""
        return self._drop_rate

    @drop_rate.setter
    def drop_rate(self, value: float) -> None:
        self._drop_rate = _check_rate("drop_rate", value)

    # -- one-shot line faults ---------------------------------------------------------------------
    def flip_bits(self, bits: int = 1, *, target: str = "any") -> None:
        """Flip ``bits`` data bits (different ones, seeded-random places) in the next ``target`` frame."""
        if not isinstance(bits, int) or bits < 1:
            raise ConfigError(f"flip_bits: bits must be a positive integer, got {shown(bits)}")
        self.pending.append(WireFault("flip", _check_target(target), bits))

    def drop_bytes(self, count: int = 1, *, target: str = "any") -> None:
        """Remove ``count`` bytes (seeded-random places) from the next ``target`` frame."""
        if not isinstance(count, int) or count < 1:
            raise ConfigError(f"drop_bytes: count must be a positive integer, got {shown(count)}")
        self.pending.append(WireFault("drop", _check_target(target), count))

    def insert_gap(self, at_byte: int, chars: float, *, target: str = "any") -> None:
        """Make the next ``target`` frame pause ``chars`` character times before its byte ``at_byte``."""
        if not isinstance(at_byte, int) or at_byte < 1:
            raise ConfigError(
                f"insert_gap: at_byte must be 1 or more (a gap inside a frame), got {shown(at_byte)}"
            )
        try:
            chars = float(chars)
        except (TypeError, ValueError):
            raise ConfigError(
                f"insert_gap: chars must be a number of character times, got {shown(chars)}"
            ) from None
        if not chars > 0:
            raise ConfigError(f"insert_gap: chars must be > 0, got {shown(chars)}")
        self.pending.append(WireFault("gap", _check_target(target), chars, at_byte))

    # -- slave faults -----------------------------------------------------------------------------
    def delay(self, unit: int, seconds: float, *, requests: int | None = None) -> None:
        """Slave ``unit`` answers ``seconds`` later (for the next ``requests`` requests, or until cleared)."""
        if not seconds >= 0:
            raise ConfigError(f"delay: seconds must be >= 0, got {shown(seconds)}")
        self._delays[unit] = _SlaveFault(float(seconds), requests)

    def silence(self, unit: int, *, requests: int | None = None) -> None:
        """Cut slave ``unit`` off the bus (for the next ``requests`` frames it hears, or until cleared)."""
        self._silenced[unit] = _SlaveFault(None, requests)

    def answer_as(self, unit: int, other_unit: int, *, requests: int | None = None) -> None:
        """Slave ``unit`` puts ``other_unit`` in the address field of its responses."""
        if not isinstance(other_unit, int) or not 0 <= other_unit <= 255:
            raise ConfigError(f"answer_as: other_unit must be 0..255, got {shown(other_unit)}")
        self._answer_as[unit] = _SlaveFault(other_unit, requests)

    def swap_ab(self, unit: int, swapped: bool = True) -> None:
        """Connect slave ``unit`` with its A and B wires swapped (``swapped=False`` puts them right).

        The pair carries a voltage difference; swapped, its sign flips, and the slave's receiver sees
        the idle line as 0 and every bit inverted.  Nothing is damaged, nothing answers.
        """
        if isinstance(unit, bool) or not isinstance(unit, int) or not 0 <= unit <= 255:
            raise ConfigError(f"swap_ab: unit must be 0..255, got {shown(unit)}")
        if swapped:
            self._swapped.add(unit)
        else:
            self._swapped.discard(unit)

    def swapped(self, unit: int | None) -> bool:
        """True if slave ``unit`` is wired with A and B swapped."""
        return unit in self._swapped

    @property
    def echo(self) -> bool:
        """True if the master's adapter echoes each request back to the master (local echo)."""
        return self._echo

    @echo.setter
    def echo(self, value: bool) -> None:
        if not isinstance(value, bool):
            raise ConfigError(f"echo must be True or False, got {shown(value)}")
        self._echo = value

    def clear(self) -> None:
        """Remove every fault (rates back to 0).  The :attr:`injected` counts stay."""
        self._bit_error_rate = self._drop_rate = 0.0
        self._swapped.clear()
        self._echo = False
        self.pending.clear()
        self._delays.clear()
        self._silenced.clear()
        self._answer_as.clear()

    # -- used by the links ------------------------------------------------------------------------
    def _take(self, table: dict[int, _SlaveFault], unit: int | None) -> _SlaveFault | None:
        if unit is None:
            return None
        fault = table.get(unit)
        if fault is None:
            return None
        if not fault.use():
            del table[unit]
            return None
        if fault.remaining == 0:
            del table[unit]
        return fault

    def silences(self, unit: int | None) -> bool:
        """True if slave ``unit`` is cut off the bus now (without using up one of its ``requests``)."""
        if not self._silenced:
            return False
        fault = self._silenced.get(unit) if unit is not None else None
        return fault is not None and (fault.remaining is None or fault.remaining > 0)

    def is_silenced(self, unit: int | None) -> bool:
        """True (and one use consumed) if slave ``unit`` is cut off for this frame."""
        if not self._silenced or self._take(self._silenced, unit) is None:
            return False
        self.injected["silenced"] += 1
        return True

    def extra_delay(self, unit: int | None) -> float:
        """Extra seconds slave ``unit`` waits before this answer (one use consumed)."""
        if not self._delays:
            return 0.0
        fault = self._take(self._delays, unit)
        if fault is None:
            return 0.0
        self.injected["delayed"] += 1
        return float(fault.value or 0.0)

    def wrong_unit(self, unit: int | None) -> int | None:
        """The unit slave ``unit`` answers as this time, or None to answer normally."""
        if not self._answer_as:
            return None
        fault = self._take(self._answer_as, unit)
        if fault is None:
            return None
        self.injected["wrong_unit"] += 1
        return int(fault.value)  # type: ignore[arg-type]

    @property
    def touches_wire(self) -> bool:
        """True if some line fault may apply to the next frame (a quick test for the common case)."""
        return bool(self.pending or self._bit_error_rate or self._drop_rate)

    def corrupt(
        self, data: bytes, role: str, data_bits: int = 8
    ) -> tuple[bytes, dict[int, float], list[str]]:
        """Apply the line faults to one frame about to go on the wire.

        Returns the bytes as transmitted, the gaps (``{byte index: character times of silence before
        it}``) and notes describing what was done.
        """
        rng = self.rng
        out = bytearray(data)
        gaps: dict[int, float] = {}
        notes: list[str] = []
        mine = [f for f in self.pending if f.target in (role, "any")]
        for fault in mine:
            self.pending.remove(fault)
        for fault in mine:
            if fault.kind == "flip" and out:
                places = rng.sample(range(len(out) * data_bits), min(int(fault.amount), len(out) * data_bits))
                for place in sorted(places):
                    index, bit = divmod(place, data_bits)
                    out[index] ^= 1 << bit
                    notes.append(f"bit {bit} of byte {index} flipped")
                self.injected["bits_flipped"] += len(places)
        for fault in mine:
            if fault.kind == "drop" and out:
                count = min(int(fault.amount), len(out))
                for index in sorted(rng.sample(range(len(out)), count), reverse=True):
                    notes.append(f"byte {index} (0x{out[index]:02X}) dropped")
                    del out[index]
                self.injected["bytes_dropped"] += count
        if self._bit_error_rate or self._drop_rate:
            index = 0
            while index < len(out):
                if self._drop_rate and rng.random() < self._drop_rate:
                    notes.append(f"byte {index} (0x{out[index]:02X}) dropped")
                    del out[index]
                    self.injected["bytes_dropped"] += 1
                    continue
                if self._bit_error_rate and rng.random() < self._bit_error_rate:
                    bit = rng.randrange(data_bits)
                    out[index] ^= 1 << bit
                    notes.append(f"bit {bit} of byte {index} flipped")
                    self.injected["bits_flipped"] += 1
                index += 1
        for fault in mine:
            if fault.kind == "gap" and 0 < (fault.at_byte or 0) < len(out):
                gaps[int(fault.at_byte)] = gaps.get(int(fault.at_byte), 0.0) + fault.amount
                notes.append(f"{fault.amount:g} character times of silence before byte {fault.at_byte}")
                self.injected["gaps"] += 1
        return bytes(out), gaps, notes
