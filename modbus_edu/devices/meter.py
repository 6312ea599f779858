"""The power meter of the power-meter paper: a three-phase meter read over RS-485 with function 03.

The paper: H. M. K. K. M. B. Herath, S. V. A. S. H. Ariyathunge, H. D. N. S. Priyankara, "Development of a
Data Acquisition and Monitoring System Based on MODBUS RTU Communication Protocol", IJISRT 5(6), 2020.

Source 003 reads a power measuring device on the soft-starter panel of a milling machine.  Its
settings (Table 2): **device id 1, 19200 baud, 8 data bits, no parity, 1 stop bit** (8N1), Modbus RTU.
It reads **holding registers with function code 03** (Table 4), and Table 5 gives the register map:
every quantity sits in a *pair* of registers, at these (0-based, on-the-wire) addresses:

=============  ============  ==========  =====================  ======================
quantity       addresses     reference   what the registers     engineering value
                                         carry (Table 5)
=============  ============  ==========  =====================  ======================
VL1, VL2, VL3  0x00, 0x0A,   40001, ...  volts x 10             raw / 10  -> V
               0x14
AL1, AL2, AL3  0x02, 0x0C,               milliamperes           raw / 1000 -> A
               0x16
PF1, PF2, PF3  0x08, 0x12,               power factor x 100     raw / 100
               0x1C
THD VL1..AL3   0x30 .. 0x3A              % THD x 10             raw / 10  -> %
active energy  0x3C                      kWh                    raw       -> kWh
=============  ============  ==========  =====================  ======================

**Word order (our choice; the paper does not say).**  Each quantity is an *unsigned 32-bit* integer
spread over its register pair with the **high word at the lower address** (the "ABCD", big-endian
word order of :mod:`modbus_edu.values`): the current AL1 = 304.9 A = 304 900 mA = 0x0004_A704 is
register 0x02 = 0x0004 and register 0x03 = 0xA704.  Many meters do this; others swap the words
("CDAB"), which is why a real meter's manual must be read before trusting a 32-bit value.  A single
register cannot hold 304 900: this is why the map needs pairs.

Only the registers of Table 5 exist (a sparse :class:`~modbus_edu.datamodel.DataBank`): a read that
touches any other address -- 0x04 between AL1 and PF1, say -- is answered with **exception 02,
illegal data address**, as the specification asks of a real device.  So a master cannot read the
whole map in one request; :func:`read_meter` reads it in the five contiguous blocks of
:func:`meter_blocks`.  The meter is read-only: like the paper's, it is read with function 03, and
any other function is answered with **exception 01, illegal function**.

``PowerMeter(trial=1)`` and ``PowerMeter(trial=2)`` hold exactly the values of the power-meter paper's Table 6
(the two trials: VL1 403.6 V then 412.6 V, AL1 304.9 A then 288.9 A, PF1 0.66 then 0.60, ...).  Table 6 prints
no energy reading, so the two energy values here (:data:`TRIAL_ENERGY_KWH`) are the course's own, marked as
such.  ``live=True`` makes the values drift around the trial's values, with seeded noise, as a function of the
time of the clock the meter is attached to (a loopback link sets it): reading the meter every second for ten
minutes gives trends to plot, the same on every run.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from importlib import resources
from typing import Any

from ..datamodel import DataBank, format_reference
from ..errors import ConfigError, shown
from ..pdu import ExceptionCode, ExceptionResponse, FunctionCode, Pdu
from ..registermap import load_map
from ..slave import Slave
from ..values import decode_value, encode_value, scale, unscale
from .generators import Noise, Sine

__all__ = [
    "MeterRegister",
    "METER_MAP",
    "power_meter_map",
    "METER_BY_NAME",
    "TRIALS",
    "TRIAL_ENERGY_KWH",
    "PowerMeter",
    "meter_blocks",
    "decode_meter",
    "read_meter",
    "meter_table",
]

UINT32_MAX = 0xFFFF_FFFF


@dataclass(frozen=True)
class MeterRegister:
    """One entry of the power-meter paper's Table 5: a quantity and the register pair that carries it.

    ``name``         short name used as a key: ``"VL1"``, ``"AL1"``, ``"THD_VL1"``, ``"PF1"``, ``"kWh"``
    ``label``        the paper's parameter name: ``"Phase voltage - VL1"``
    ``address``      the first (lower) address of the pair, 0-based as in the frame (0x00 for VL1)
    ``unit``         the engineering unit after scaling: ``"V"``, ``"A"``, ``"%"``, ``""``, ``"kWh"``
    ``scale``        what the meter multiplied the value by: 10 for "V x 10", 1000 for "mA"
                     (value = raw / scale, see :func:`modbus_edu.values.scale`)
    ``description``  a sentence for people (tables, tooltips)
    ``raw_unit``     the unit column of Table 5 as printed: ``"V x 10"``, ``"mA"``, ``"% x 10"``, ...
    ``count``        registers it takes: 2 (an unsigned 32-bit value, high word first)
    """

    name: str
    label: str
    address: int
    unit: str
    scale: int
    description: str
    raw_unit: str
    count: int = 2

    @property
    def addresses(self) -> range:
        """The addresses of the pair: ``range(address, address + 2)``."""
        return range(self.address, self.address + self.count)

    @property
    def reference(self) -> str:
        """The holding-register reference number of the first register (address 0x00 -> ``"40001"``)."""
        return format_reference("holding_registers", self.address)

    @property
    def decimals(self) -> int:
        """Decimal places the scale gives (x10 -> 1, x100 -> 2, mA -> A: 3)."""
        return max(0, round(math.log10(self.scale)))

    @property
    def shown_decimals(self) -> int:
        """Decimal places the power-meter paper's Table 6 prints (currents: 1, "304.9 A", although the meter
        sends mA)."""
        return 1 if self.unit == "A" else self.decimals

    def registers(self, value: float) -> list[int]:
        """The two registers that carry the engineering ``value`` (high word first)."""
        return encode_value(unscale(value, self.scale), "uint32", "ABCD")

    def value(self, registers: Sequence[int]) -> float:
        """The engineering value carried by the register pair (high word first)."""
        return scale(decode_value(registers, "uint32", "ABCD"), self.scale)

    def format(self, value: float, decimals: int | None = None) -> str:
        """``403.6 V``, ``304.9 A``, ``0.66``: the value with its unit, as Table 6 prints it
        (``decimals`` overrides: ``decimals=self.decimals`` shows the full resolution, ``304.900 A``)."""
        text = f"{value:.{self.shown_decimals if decimals is None else decimals}f}"
        return f"{text} {self.unit}".rstrip()


def _entry(
    name: str, label: str, address: int, unit: str, factor: int, raw_unit: str, text: str
) -> MeterRegister:
    return MeterRegister(name, label, address, unit, factor, text, raw_unit)


#: The power-meter paper's Table 5, in the paper's order.  Addresses are 0-based frame addresses (hexadecimal
#: in the paper).
METER_MAP: tuple[MeterRegister, ...] = (
    _entry("VL1", "Phase voltage - VL1", 0x00, "V", 10, "V x 10", "voltage of phase L1, in tenths of a volt"),
    _entry("VL2", "Phase voltage - VL2", 0x0A, "V", 10, "V x 10", "voltage of phase L2, in tenths of a volt"),
    _entry("VL3", "Phase voltage - VL3", 0x14, "V", 10, "V x 10", "voltage of phase L3, in tenths of a volt"),
    _entry("AL1", "Current - AL1", 0x02, "A", 1000, "mA", "current of phase L1, in milliamperes"),
    _entry("AL2", "Current - AL2", 0x0C, "A", 1000, "mA", "current of phase L2, in milliamperes"),
    _entry("AL3", "Current - AL3", 0x16, "A", 1000, "mA", "current of phase L3, in milliamperes"),
    _entry("THD_VL1", "%THD VL1", 0x30, "%", 10, "% x 10",
           "total harmonic distortion of the L1 voltage, in tenths of a percent"),
    _entry("THD_VL2", "%THD VL2", 0x32, "%", 10, "% x 10",
           "total harmonic distortion of the L2 voltage, in tenths of a percent"),
    _entry("THD_VL3", "%THD VL3", 0x34, "%", 10, "% x 10",
           "total harmonic distortion of the L3 voltage, in tenths of a percent"),
    _entry("THD_AL1", "%THD AL1", 0x36, "%", 10, "% x 10",
           "total harmonic distortion of the L1 current, in tenths of a percent"),
    _entry("THD_AL2", "%THD AL2", 0x38, "%", 10, "% x 10",
           "total harmonic distortion of the L2 current, in tenths of a percent"),
    _entry("THD_AL3", "%THD AL3", 0x3A, "%", 10, "% x 10",
           "total harmonic distortion of the L3 current, in tenths of a percent"),
    _entry("kWh", "Active energy", 0x3C, "kWh", 1, "kWh", "active energy counted so far, in kilowatt-hours"),
    _entry("PF1", "Power factor - PF1", 0x08, "", 100, "P.F. x 100",
           "power factor of phase L1, in hundredths"),
    _entry("PF2", "Power factor - PF2", 0x12, "", 100, "P.F. x 100",
           "power factor of phase L2, in hundredths"),
    _entry("PF3", "Power factor - PF3", 0x1C, "", 100, "P.F. x 100",
           "power factor of phase L3, in hundredths"),
)

def power_meter_map() -> Any:
    """The same map as a register map file, ``devices/maps/power_meter.csv``, loaded into a
    :class:`~modbus_edu.registermap.RegisterMap` (uint32 ABCD points, scale = 1 / the meter's factor):
    ``power_meter_map().read(master, unit=1)`` gives what :func:`read_meter` gives."""
    return load_map(resources.files("modbus_edu.devices") / "maps" / "power_meter.csv")


#: The entries of :data:`METER_MAP` by name.
METER_BY_NAME: dict[str, MeterRegister] = {e.name: e for e in METER_MAP}

#: The power-meter paper's Table 6: the values the GUI showed in the two trials (engineering units; no energy
#: in the paper).
TRIALS: dict[int, dict[str, float]] = {
    1: {
        "VL1": 403.6, "VL2": 399.9, "VL3": 399.3,
        "AL1": 304.9, "AL2": 319.6, "AL3": 302.0,
        "THD_VL1": 1.6, "THD_VL2": 1.0, "THD_VL3": 0.7,
        "THD_AL1": 4.2, "THD_AL2": 4.7, "THD_AL3": 4.4,
        "PF1": 0.66, "PF2": 0.70, "PF3": 0.72,
    },
    2: {
        "VL1": 412.6, "VL2": 410.5, "VL3": 411.7,
        "AL1": 288.9, "AL2": 300.1, "AL3": 284.1,
        "THD_VL1": 1.8, "THD_VL2": 1.0, "THD_VL3": 1.0,
        "THD_AL1": 4.3, "THD_AL2": 4.1, "THD_AL3": 4.4,
        "PF1": 0.60, "PF2": 0.64, "PF3": 0.68,
    },
}

#: Active energy of each trial, in kWh.  NOT from the paper (Table 6 prints none): the course's own values.
TRIAL_ENERGY_KWH: dict[int, int] = {1: 48_215, 2: 48_263}


def meter_blocks(entries: Iterable[MeterRegister] = METER_MAP) -> list[tuple[int, int, list[MeterRegister]]]:
    """Group register pairs into contiguous blocks, one read request each: ``[(address, count, entries)]``.

    For Table 5 there are five blocks: 0x00-0x03 (VL1, AL1), 0x08-0x0D (PF1, VL2, AL2), 0x12-0x17 (PF2,
    VL3, AL3), 0x1C-0x1D (PF3) and 0x30-0x3D (the six THD values and the energy).  Reading across a gap
    (0x04..0x07 hold nothing) would be answered with exception 02.
    """
    blocks: list[tuple[int, int, list[MeterRegister]]] = []
    for e in sorted(entries, key=lambda e: e.address):
        if blocks and blocks[-1][0] + blocks[-1][1] == e.address and blocks[-1][1] + e.count <= 125:
            start, count, members = blocks[-1]
            blocks[-1] = (start, count + e.count, members + [e])
        else:
            blocks.append((e.address, e.count, [e]))
    return blocks


def decode_meter(
    registers: Mapping[int, int], entries: Iterable[MeterRegister] = METER_MAP
) -> dict[str, float]:
    """Engineering values from ``{address: register value}``: ``{"VL1": 403.6, ...}`` in map order."""
    out: dict[str, float] = {}
    for e in entries:
        try:
            pair = [registers[a] for a in e.addresses]
        except KeyError as exc:
            raise ConfigError(f"{e.name}: register 0x{exc.args[0]:02X} of its pair was not read") from None
        out[e.name] = e.value(pair)
    return out


def read_meter(master: Any, unit: int = 1, entries: Iterable[MeterRegister] = METER_MAP) -> dict[str, float]:
    """Read the whole map through ``master`` (any :class:`~modbus_edu.master.Master`) with function 03.

    One request per block of :func:`meter_blocks`; returns ``{name: engineering value}`` in the order of
    :data:`METER_MAP` (VL1 in V, AL1 in A, THD in %, PF as a fraction, energy in kWh).  Errors of the
    master (timeout, exception response) propagate.
    """
    entries = list(entries)
    registers: dict[int, int] = {}
    for address, count, _members in meter_blocks(entries):
        values = master.read_holding_registers(unit=unit, address=address, count=count)
        registers.update(zip(range(address, address + count), values))
    return decode_meter(registers, entries)


def meter_table(*trials: Mapping[str, float], titles: Sequence[str] | None = None) -> str:
    """A plain-text table in the layout of the power-meter paper's Table 6: one row per quantity, one column
    per reading.

    ``meter_table(read_meter(m1), read_meter(m2))`` prints the two trials side by side.  Quantities
    missing from a reading show ``-``.
    """
    if titles is None:
        titles = [f"Trial {i + 1}" for i in range(len(trials))]
    titles = list(titles)
    if len(titles) != len(trials):
        raise ConfigError(f"{len(titles)} titles for {len(trials)} readings")
    rows = [["Parameter", *titles]]
    for e in METER_MAP:
        rows.append([e.label, *(e.format(t[e.name]) if e.name in t else "-" for t in trials)])
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines = []
    for r in rows:
        cells = [r[0].ljust(widths[0])] + [c.rjust(w) for c, w in zip(r[1:], widths[1:])]
        lines.append("  ".join(cells).rstrip())
    return "\n".join(lines)


def _trial_values(trial: int) -> dict[str, float]:
    values = dict(TRIALS[trial])
    values["kWh"] = TRIAL_ENERGY_KWH[trial]
    return values


def _active_power_kw(values: Mapping[str, float]) -> float:
    """Total active power in kW, P = sum of V x I x PF / sqrt(3) (the paper's voltages are line to line)."""
    watts = sum(values[f"VL{i}"] * values[f"AL{i}"] * values[f"PF{i}"] for i in (1, 2, 3)) / math.sqrt(3)
    return watts / 1000


class PowerMeter(Slave):
    """The power meter of the power-meter paper, as a slave: ``PowerMeter(unit=1, trial=1 | 2, live=False,
    seed=0)``.

    It serves the power-meter paper's Table 5 (:data:`METER_MAP`) as holding registers, read with function 03;
    each quantity is an **unsigned 32-bit value in its register pair, high word at the lower address** (the
    paper leaves the word order open; this is the course's choice).  Addresses outside the map answer
    exception 02; functions other than 03 answer exception 01.

    ``trial`` selects the values of the power-meter paper's Table 6 (1 or 2).  With ``live=True`` every value
    drifts around the trial's value: a slow sine (a few tenths of a percent; each quantity its own period and
    phase) plus seeded Gaussian noise, computed from the time of the clock the meter is attached to
    (``meter.clock``, set by a loopback link; 0 when there is none), and the energy counter grows with the
    active power.  The same ``seed`` gives the same readings at the same times.

    The serial settings of 003 are class attributes, so a wire reads naturally::

        link = loopback_serial(meter, baudrate=PowerMeter.BAUDRATE, parity=PowerMeter.PARITY,
                               stopbits=PowerMeter.STOPBITS)
    """

    UNIT = 1
    BAUDRATE = 19200
    DATABITS = 8
    PARITY = "N"
    STOPBITS = 1
    FUNCTIONS = frozenset({int(FunctionCode.READ_HOLDING_REGISTERS)})
    """The function codes the meter answers; anything else gets exception 01."""

    def __init__(
        self, unit: int = 1, trial: int = 1, live: bool = False, seed: int = 0, **kwargs: Any
    ) -> None:
        if trial not in TRIALS or isinstance(trial, bool):
            raise ConfigError(f"trial must be 1 or 2 (the two trials of the meter's readings), got "
                              f"{shown(trial)}")
        if isinstance(seed, bool) or not isinstance(seed, int):
            raise ConfigError(f"seed must be an int, got {shown(seed)}")
        kwargs.setdefault("name", f"power meter {unit}")
        super().__init__(unit, DataBank(sparse=True), **kwargs)
        self.trial = trial
        self.live = bool(live)
        self.seed = seed
        self.base: dict[str, float] = _trial_values(trial)
        """The values of the trial (Table 6, plus the course's energy reading), in engineering units."""
        self._signals = {e.name: self._signal(i, e) for i, e in enumerate(METER_MAP) if e.name != "kWh"}
        for e in METER_MAP:
            self.bank.holding_registers.declare(e.address, e.count, e.registers(self.base[e.name]))
        self.updated_at: float | None = None

    def __repr__(self) -> str:
        live = " live" if self.live else ""
        return f"<PowerMeter unit={self.unit} trial={self.trial}{live} {self.counters.as_dict()}>"

    @property
    def serial_settings(self) -> dict[str, Any]:
        """The power-meter paper's line settings, ``{"baudrate": 19200, "parity": "N", "stopbits": 1,
        "bytesize": 8}``.

        A loopback wire reads them: on a line with other settings the meter hears garbage and never
        answers.  ``loopback_serial(meter, **meter.serial_settings)`` gives a wire that matches.
        """
        return {"baudrate": self.BAUDRATE, "parity": self.PARITY, "stopbits": self.STOPBITS,
                "bytesize": self.DATABITS}

    # -- values -----------------------------------------------------------------------------------
    def _signal(self, index: int, e: MeterRegister) -> Noise:
        """Seeded drift of one quantity, in raw register units (raw = value x scale)."""
        raw = unscale(self.base[e.name], e.scale)
        kind = e.name.rstrip("123")
        swing, sigma = {"VL": (0.004, 0.0008), "AL": (0.03, 0.004), "THD_VL": (0.08, 0.03),
                        "THD_AL": (0.06, 0.03), "PF": (0.02, 0.004)}[kind]
        period = 60.0 + 17.0 * index
        phase = 2 * math.pi * ((self.seed * 0.618 + index * 0.377) % 1.0)
        drift = Sine(raw, raw * swing, period, phase)
        return Noise(drift, sigma=max(raw * sigma, 0.3), seed=self.seed * 101 + index)

    def values_at(self, t: float) -> dict[str, float]:
        """The engineering values the meter shows at time ``t`` (seconds): the trial's when not live."""
        if not self.live:
            return dict(self.base)
        out: dict[str, float] = {}
        for e in METER_MAP:
            if e.name == "kWh":
                continue
            raw = min(max(round(self._signals[e.name].raw(t)), 0), UINT32_MAX)
            out[e.name] = scale(raw, e.scale)
        out["kWh"] = float(self.base["kWh"] + math.floor(max(t, 0.0) * _active_power_kw(self.base) / 3600.0))
        return out

    def update(self, t: float | None = None) -> dict[str, float]:
        """Write the values at time ``t`` (default: the clock's now) into the registers; return them."""
        if t is None:
            t = self._now()
        values = self.values_at(t)
        table = self.bank.holding_registers
        for e in METER_MAP:
            table.write(e.address, e.registers(values[e.name]))
        self.updated_at = t
        return values

    def read_values(self) -> dict[str, float]:
        """The values in the registers now, decoded (no request involved: the device's own view)."""
        table = self.bank.holding_registers
        return {e.name: e.value(table.read(e.address, e.count)) for e in METER_MAP}

    # -- the slave --------------------------------------------------------------------------------
    def before_read(self, table_kind: str, address: int, count: int) -> None:
        """A live meter measures when asked: refresh the registers for the clock's time first."""
        if self.live:
            now = self._now()
            if now != self.updated_at:
                self.update(now)
        super().before_read(table_kind, address, count)

    def process(self, request: Pdu) -> Pdu:
        """Function 03 goes to the bank (unmapped addresses: exception 02); anything else: exception 01."""
        function = getattr(request, "function_code", 0)
        if getattr(request, "role", None) == "request" and function not in self.FUNCTIONS:
            return ExceptionResponse(function, int(ExceptionCode.ILLEGAL_FUNCTION))
        return super().process(request)
