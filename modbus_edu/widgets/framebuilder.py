"""FrameBuilder: pick a mode, a function and its fields, and watch the frame being built byte by byte."""

from __future__ import annotations

import dataclasses
import warnings
from typing import Any

import ipywidgets as W

from ..errors import ModbusError, ValueFormatError
from ..explain import Dissection, explain
from ..framing import Frame, make_frame, parse_hex
from ..pdu import ExceptionCode, ExceptionResponse, FunctionCode, Pdu, request_class, response_class
from .common import (
    MessageLine,
    Typing,
    dissection_html,
    dropdown,
    esc,
    frame_html,
    guarded,
    hex_text,
    legend_html,
    live,
    mark_invalid,
    panel_style,
    parse_bit_list,
    parse_int,
    parse_int_list,
    shown,
    stale_html,
    text_field,
)
from .picture import StaticView

__all__ = ["FrameBuilder"]

MODE_OPTIONS = [("RTU", "rtu"), ("ASCII", "ascii"), ("TCP", "tcp")]
ROLE_OPTIONS = [("request", "request"), ("response", "response"), ("exception response", "exception")]
FUNCTION_OPTIONS = [(f"{int(fc):02d} {fc.title}", int(fc)) for fc in FunctionCode]
EXCEPTION_OPTIONS = [(f"{int(c):02X} {c.title}", int(c)) for c in ExceptionCode]


@dataclasses.dataclass(frozen=True)
class FieldSpec:
    """How the panel asks for one field of a PDU class (a dataclass field of :mod:`modbus_edu.pdu`).

    ``label`` is the field's name on screen, in the spec's words; its errors use the same words.
    ``kind``: ``"int"`` (a number), ``"ints"`` (a list of numbers), ``"bits"`` (a list of bits),
    ``"bool"`` (ON/OFF), ``"exception"`` (an exception code) or ``"list"`` (bits or numbers, as the PDU
    class's type says).
    """

    label: str
    kind: str = "int"
    tooltip: str = ""
    width: str = "230px"


#: The one place that says how each PDU field is asked for.  The functions and which fields each takes
#: come from the library (:class:`~modbus_edu.pdu.FunctionCode`, ``request_class``/``response_class``
#: and their dataclass fields): a function added there appears here, and a field not listed below gets
#: a number box named after it.
FIELDS: dict[str, FieldSpec] = {
    "address": FieldSpec("address", tooltip="0-based address, as in the frame (register 40001 is address 0)"),
    "count": FieldSpec("quantity", tooltip="the spec's Quantity of Coils / Inputs / Registers: how many"),
    "value": FieldSpec("value", tooltip="register value 0..65535"),
    "coil": FieldSpec("coil", "bool", "FF 00 switches the coil ON, 00 00 OFF"),
    "values": FieldSpec("values", "list", width="420px"),
    "bits": FieldSpec("bits", "bits", "1, 0, 1, 1  (first bit first)", width="420px"),
    "registers": FieldSpec("registers", "ints", "1234, 0x04D2", width="420px"),
    "exception_code": FieldSpec("exception code", "exception", width="420px"),
    "and_mask": FieldSpec("AND mask", tooltip="FC 22: the bits of the register that are kept"),
    "or_mask": FieldSpec("OR mask", tooltip="FC 22: the bits set where the AND mask has 0"),
    "read_address": FieldSpec("read address", tooltip="FC 23: first register read (after the write)"),
    "read_count": FieldSpec("read quantity", tooltip="FC 23: 1..125 registers read"),
    "write_address": FieldSpec("write address", tooltip="FC 23: first register written"),
    "status": FieldSpec("status", tooltip="FC 7: eight status bits 0..255; FC 11/12: 0 ready, 0xFFFF busy"),
    "sub_function": FieldSpec("sub-function", tooltip="FC 8: 0 return query data, 0x0B-0x12 counters, ..."),
    "data": FieldSpec("data", "hex", "FC 8: bytes in hex, e.g. 00 00", width="420px"),
    "event_count": FieldSpec("event count", tooltip="FC 11/12: messages completed normally"),
    "message_count": FieldSpec("message count", tooltip="FC 12: messages seen on the bus"),
    "events": FieldSpec("events", "hex", "FC 12: event bytes in hex, newest first", width="420px"),
    "records": FieldSpec("records", "records", "FC 20: file, record, length; FC 20 response: values; "
                         "FC 21: file, record, values (groups split by ;)", width="420px"),
    "server_id": FieldSpec("server ID", "hex", "bytes in hex, e.g. 4D 45 54 45 52", width="420px"),
    "run_indicator": FieldSpec("run indicator", "run", "FF: the device runs, 00: it does not"),
    "additional_data": FieldSpec("additional data", "hex", "FC 17: device-specific bytes after the run "
                                 "indicator, in hex (may be empty)", width="420px"),
    "read_code": FieldSpec("read device ID code",
                           tooltip="FC 43/14: 1 basic, 2 regular, 3 extended, 4 one object"),
    "object_id": FieldSpec("object id", tooltip="FC 43/14: where the stream starts, or the one object"),
    "conformity": FieldSpec("conformity level", tooltip="0x81 basic, 0x82 regular, 0x83 extended"),
    "more_follows": FieldSpec("more follows", "more", "FF: another response continues the objects"),
    "next_object_id": FieldSpec("next object id", tooltip="where the next request starts"),
    "objects": FieldSpec("objects", "objects", "0=ACME; 1=PM-9; 2=1.0  (id=text; ...)", width="420px"),
}

#: When the library's message names no field shown, the field its error class is about.
ERROR_FIELDS: dict[str, tuple[str, ...]] = {
    "QuantityError": ("count", "values", "bits", "registers"),
    "AddressRangeError": ("address", "count", "values"),
    "ValueRangeError": ("value", "values", "registers", "address"),
    "ByteCountError": ("bits", "registers", "values"),
    "UnitError": ("unit",),
    "MbapError": ("transaction_id",),
}


def _parse_objects(text: str, label: str) -> tuple[tuple[int, bytes], ...]:
    """``"0=ACME; 1=PM-9"`` as FC 43/14 objects: ((0, b"ACME"), (1, b"PM-9"))."""
    objects = []
    for part in (p.strip() for p in text.split(";")):
        if not part:
            continue
        key, sep, value = part.partition("=")
        if not sep:
            raise ValueFormatError(f"{label}: {part!r} is not id=text (e.g. 0=ACME)")
        objects.append((parse_int(key.strip(), label), value.strip().encode()))
    return tuple(objects)


def _parse_records(text: str, label: str, cls: type) -> tuple:
    """File records (FC 20/21) from groups of numbers split by ';': ``"4, 1, 2; 3, 9, 1"``.

    FC 20 request: (file, record, length) per group; FC 20 response: the registers of each record;
    FC 21: (file, record, values...) per group."""
    groups = [parse_int_list(part, label) for part in text.split(";") if part.strip()]
    if cls.function_code == 0x14 and cls.role == "response":
        return tuple(tuple(group) for group in groups)
    read = cls.function_code == 0x14
    if not groups or not all(len(group) == 3 if read else len(group) >= 3 for group in groups):
        rest = "the length" if read else "one or more values"
        raise ValueFormatError(f"{label}: each group is file, record, then {rest}")
    if read:
        return tuple(tuple(group) for group in groups)
    return tuple((group[0], group[1], tuple(group[2:])) for group in groups)


def _text(value: Any) -> str:
    """A field's initial text: lists become ``"1, 2, 3"``, bools ``1``/``0``."""
    if isinstance(value, (list, tuple)):
        return ", ".join(str(int(v)) if isinstance(v, bool) else str(v) for v in value)
    return str(value)


class FrameBuilder(StaticView, W.VBox):
    """Build a Modbus frame from its fields and see every byte, coloured by the field it belongs to.

    Choose the mode (RTU, ASCII, TCP), the role (request, response, or an exception response), the
    function (all eight everyday functions) and the unit; only the fields that this function and role
    carry are shown (address, count, a register value, a coil ON/OFF, a list of values, the bits or
    registers of a read response, an exception code; the transaction id for TCP).  Numbers may be
    typed in decimal or hex (``107`` or ``0x6B``); lists are separated by commas (``10, 0x0102``; bits
    as ``1, 0, 1`` or ``ON, OFF`` or ``101``).

    Every byte comes from the library: the widget builds the PDU object
    (:mod:`modbus_edu.pdu`), wraps it with :func:`modbus_edu.framing.make_frame` and shows
    ``.encode()``; the colours and the table below are :func:`modbus_edu.explain.explain`'s rows.
    Invalid input (a quantity of 126 for function 3, a unit of 300 on RTU, ``abc`` as an address) shows
    the library's error message in red beside that field (marked red), once, and never raises; the
    frame and the table keep their place with the last good frame greyed out.  The frame follows the
    typing: a field applies a moment after the last keystroke (``typing``, a
    :class:`~modbus_edu.widgets.common.Typing`), no Enter needed; a value set from code applies at once.

    Attributes after every change:

    ``frame``        the bytes shown (``bytes``); ``b""`` while the input is invalid
    ``adu``          the frame object (``RtuFrame``/``AsciiFrame``/``TcpFrame``) or ``None``
    ``pdu``          the PDU object or ``None``
    ``dissection``   the :class:`~modbus_edu.explain.Dissection` of the frame, or ``None``
    ``error``        the :class:`~modbus_edu.errors.ModbusError` shown, or ``None``

    Example (the specification's Read Holding Registers example, section 6.3, sent to unit 0x11)::

        from modbus_edu.widgets import FrameBuilder
        fb = FrameBuilder(mode="rtu", unit=17, function=3, address=0x6B, count=3)
        fb                      # shows the panel; change any field and the frame follows
        fb.frame.hex(" ")       # '11 03 00 6b 00 03 76 87'
        fb.count.value = "126"  # too many: beside the quantity field, "quantity ... expected 1 to 125"
    """

    def __init__(
        self,
        mode: str = "rtu",
        unit: int | str = 1,
        function: int = 3,
        role: str = "request",
        *,
        transaction_id: int | str = 1,
        address: int | str = 0,
        count: int | str = 1,
        value: int | str = 0,
        coil: bool = True,
        values: Any = None,
        bits: Any = "1, 0, 1, 1",
        registers: Any = "1234",
        exception_code: int = 2,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.add_class("mbe-framebuilder")
        self.frame: bytes = b""
        self.adu: Frame | None = None
        self.pdu: Pdu | None = None
        self.dissection: Dissection | None = None
        self.error: ModbusError | None = None

        self.mode = dropdown("mode", MODE_OPTIONS, mode, css="mbe-field-mode")
        self.role = dropdown("role", ROLE_OPTIONS, role, css="mbe-field-role")
        self.function = dropdown("function", FUNCTION_OPTIONS, int(function), css="mbe-field-function",
                                 width="320px")
        self.unit = text_field("unit (slave id)", unit, css="mbe-field-unit",
                               tooltip="slave address on a serial line, unit identifier on TCP")
        self.transaction_id = text_field("transaction id", transaction_id, css="mbe-field-transaction-id",
                                         tooltip="MBAP transaction identifier (TCP only), 0..65535")
        initial = {"address": address, "count": count, "value": value, "coil": bool(coil), "bits": bits,
                   "registers": registers, "exception_code": int(exception_code), "values": "",
                   "read_count": 1, "read_code": 1, "conformity": 0x81, "objects": "0=ACME; 1=PM-9; 2=1.0",
                   "data": "00 00", "events": "", "records": "4, 1, 2", "server_id": "4D 45 54 45 52"}
        self._field_inputs: list[W.DOMWidget] = []
        self._error_labels: dict[str, W.HTML] = {}
        self._rows: dict[str, W.HBox] = {}
        self.field_errors: dict[str, str] = {}
        """The error shown beside each field now (field name -> message); empty when all is well."""
        self.field_notes: dict[str, str] = {}
        """A warning shown beside a field whose frame still builds (a reserved unit, say)."""
        for name in FIELDS:
            default = "" if FIELDS[name].kind == "hex" else True if FIELDS[name].kind == "run" else 0
            setattr(self, name, self._make_input(name, initial.get(name, default)))
        # FC15 takes coil values, FC16 register values: the field remembers the text of each kind
        self._values_text = {"bits": "1, 0, 1, 1", "registers": "10, 258"}
        self._values_kind: str | None = None
        self._quiet = False

        self.message = MessageLine()
        self.frame_view = W.HTML()
        self.frame_view.add_class("mbe-frame")
        self.dissection_view = W.HTML()
        self.dissection_view.add_class("mbe-dissection")
        self._last_good: tuple[str, str] | None = None

        wrap = W.Layout(flex_flow="row wrap", align_items="center")
        self.left = W.VBox([W.HBox([self._row("mode", self.mode), self._row("role", self.role),
                                    self._row("function", self.function)], layout=wrap),
                            W.HBox([self._row("unit", self.unit),
                                    self._row("transaction_id", self.transaction_id)], layout=wrap)])
        self.right = W.VBox([self._rows[name] for name in FIELDS])
        self.fields_box = W.VBox([self.left, self.right])  # each error has room beside its field
        self.children = [
            W.HTML("<b>Frame builder</b> &mdash; every byte below comes from the library"),
            self.fields_box,
            self.message,
            self.frame_view,
            self.dissection_view,
            panel_style(),
        ]
        self._update = guarded(self.message, self.update)
        self.typing = Typing(self._update)
        """Applies typed text a moment after the last keystroke; ``typing.flush()`` applies it now."""
        kind = self._values_kind_now() or "registers"
        if values is not None:
            self._values_text[kind] = _text(values)
        self.values.value = self._values_text[kind]
        self._values_kind = kind
        for box in [self.mode, self.role, self.function, self.unit, self.transaction_id,
                    *self._field_inputs]:
            box.observe(self._changed, names="value")
        self._update()

    def _changed(self, change: dict[str, Any]) -> None:
        """Any input changed: typed text waits for a pause in the typing, the rest applies at once."""
        if not self._quiet:
            self.typing.changed(change)

    # -- the inputs, each with its error beside it ------------------------------------------------------
    def _make_input(self, name: str, initial: Any) -> W.DOMWidget:
        """The input of one PDU field, as :data:`FIELDS` describes it (a number box when not listed)."""
        spec = FIELDS.get(name, FieldSpec(name.replace("_", " ")))
        css = f"mbe-field-{name.replace('_', '-')}"
        if spec.kind == "bool":
            box: W.DOMWidget = dropdown(spec.label, [("ON (FF 00)", True), ("OFF (00 00)", False)],
                                        bool(initial), css=css)
        elif spec.kind == "run":
            box = dropdown(spec.label, [("ON (FF)", True), ("OFF (00)", False)], True, css=css)
        elif spec.kind == "more":
            box = dropdown(spec.label, [("00: the last part", False), ("FF: more follows", True)], False,
                           css=css)
        elif spec.kind == "exception":
            box = dropdown(spec.label, EXCEPTION_OPTIONS, int(initial), css=css, width=spec.width)
        else:
            placeholder = spec.tooltip if spec.kind in ("bits", "ints") else ""
            box = text_field(spec.label, _text(initial), css=css, width=spec.width, placeholder=placeholder,
                             tooltip=spec.tooltip)
        self._field_inputs.append(box)
        self._row(name, box)
        return box

    def _row(self, name: str, box: W.DOMWidget) -> W.HBox:
        label = live(W.HTML(layout=W.Layout(margin="0 0 0 8px")))
        label.add_class("mbe-field-error")
        label.add_class(f"mbe-field-error-{name.replace('_', '-')}")
        self._error_labels[name] = label
        self._rows[name] = W.HBox([box, label], layout=W.Layout(align_items="center", max_width="100%"))
        return self._rows[name]

    def _spec_label(self, name: str) -> str:
        if name in ("unit", "transaction_id", "mode", "role", "function"):
            return {"unit": "unit", "transaction_id": "transaction id"}.get(name, name)
        return FIELDS.get(name, FieldSpec(name.replace("_", " "))).label

    def _mark(self, errors: dict[str, str], notes: dict[str, str] | None = None) -> None:
        """Show each error beside its field (once), mark the field red, clear the others.  ``notes``:
        warnings of the library about a field whose frame still builds (amber, the field not marked)."""
        self.field_errors = dict(errors)
        self.field_notes = dict(notes or {})
        for name, label in self._error_labels.items():
            box = self._rows[name].children[0]
            text = errors.get(name)
            note = self.field_notes.get(name)
            if text:
                label.value = (f'<span style="color:#c92a2a;font-weight:600;white-space:normal">&#9888; '
                               f"{esc(text)}</span>")
            elif note:
                label.value = f'<span style="color:#9c4a00;white-space:normal">&#9888; {esc(note)}</span>'
            else:
                label.value = ""
            shown(label, bool(text or note))
            mark_invalid(box, bool(text), label)

    def _field_of(self, exc: ModbusError, needed: dict[str, W.DOMWidget]) -> str | None:
        """The field an error of the library is about: the first shown field its message names (in
        the field's words), else the field its error class is about."""
        visible = ["unit", *(["transaction_id"] if self.mode.value == "tcp" else []),
                   *[n for n, box in self._field_map().items() if box in needed.values()]]
        text = str(exc).lower()
        for name in visible:
            if self._spec_label(name).lower() in text:
                return name
        for name in ERROR_FIELDS.get(type(exc).__name__, ()):
            if name in visible:
                return name
        return None

    # -- which fields ----------------------------------------------------------------------------
    def pdu_class(self) -> type[Pdu]:
        """The PDU class of the chosen function and role (from the library's tables)."""
        if self.role.value == "exception":
            return ExceptionResponse
        if self.role.value == "response":
            return response_class(self.function.value)
        return request_class(self.function.value)

    def _inputs(self) -> dict[str, W.DOMWidget]:
        """The input behind each constructor field of the PDU class (read from its dataclass fields)."""
        out: dict[str, W.DOMWidget] = {}
        for f in dataclasses.fields(self.pdu_class()):
            if f.name == "function":  # ExceptionResponse: the function dropdown says which
                continue
            if f.name == "code":
                out[f.name] = self.exception_code
            elif f.name == "value" and "bool" in str(f.type):
                out[f.name] = self.coil
            else:
                if not hasattr(self, f.name):  # a field FIELDS does not list: a box named after it
                    kind = FIELDS.get(f.name, FieldSpec("")).kind
                    setattr(self, f.name, self._make_input(f.name, "" if kind == "hex" else 0))
                    self.right.children = [*self.right.children, self._rows[f.name]]
                    self._quiet = True
                    getattr(self, f.name).observe(self._changed, names="value")
                    self._quiet = False
                out[f.name] = getattr(self, f.name)
        return out

    def _values_kind_now(self) -> str | None:
        """``"bits"`` or ``"registers"``: what the ``values`` field of the chosen PDU class holds."""
        if "values" not in {f.name for f in dataclasses.fields(self.pdu_class())}:
            return None
        return "bits" if self._is_bits("values") else "registers"

    def _is_bits(self, name: str) -> bool:
        field = {f.name: f for f in dataclasses.fields(self.pdu_class())}[name]
        return "bool" in str(field.type)

    def visible_fields(self) -> list[str]:
        """The names of the inputs shown now (``["unit", "address", "count"]`` for an FC3 request)."""
        names = ["unit"]
        if self.mode.value == "tcp":
            names.append("transaction_id")
        names += [name for name, box in self._field_map().items() if box in self._inputs().values()]
        return names

    def _field_map(self) -> dict[str, W.DOMWidget]:
        return {name: self._rows[name].children[0] for name in self._rows
                if name not in ("mode", "role", "function", "unit", "transaction_id")}

    def _show_fields(self, needed: dict[str, W.DOMWidget]) -> None:
        wanted = set(map(id, needed.values()))
        for name, box in self._field_map().items():
            shown(self._rows[name], id(box) in wanted)
        shown(self._rows["transaction_id"], self.mode.value == "tcp")
        if "values" in needed:
            kind = self._values_kind_now()
            if kind is not None and kind != self._values_kind:
                if self._values_kind is not None:
                    self._values_text[self._values_kind] = self.values.value
                self._quiet = True
                try:
                    self.values.value = self._values_text[kind]
                finally:
                    self._quiet = False
                self._values_kind = kind
            bits = kind == "bits"
            self.values.description = "coil values" if bits else "register values"
            self.values.placeholder = "1, 0, 1, 1  (first coil first)" if bits else "10, 0x0102"

    # -- building ----------------------------------------------------------------------------------
    def _arguments(self, needed: dict[str, W.DOMWidget], errors: dict[str, str]) -> dict[str, Any]:
        """Read every needed field; a field that does not read gets its error (in its own words)."""
        kwargs: dict[str, Any] = {}
        for name, box in needed.items():
            key = next(n for n, b in self._field_map().items() if b is box)
            label = box.description if hasattr(box, "description") else key
            try:
                if isinstance(box, W.Dropdown):
                    kwargs[name] = box.value
                elif FIELDS.get(key, FieldSpec("")).kind == "hex":
                    kwargs[name] = parse_hex(box.value)
                elif FIELDS.get(key, FieldSpec("")).kind == "objects":
                    kwargs[name] = _parse_objects(box.value, label)
                elif FIELDS.get(key, FieldSpec("")).kind == "records":
                    kwargs[name] = _parse_records(box.value, label, self.pdu_class())
                elif name in ("values", "bits") or FIELDS.get(key, FieldSpec("")).kind in ("bits", "ints"):
                    kwargs[name] = (parse_bit_list(box.value, label) if self._is_bits(name)
                                    else parse_int_list(box.value, label))
                else:
                    kwargs[name] = parse_int(box.value, label)
            except ModbusError as exc:
                errors[key] = f"{type(exc).__name__}: {exc}"
        if self.role.value == "exception":
            kwargs["function"] = self.function.value
        return kwargs

    def update(self) -> None:
        """Rebuild the frame from the fields (called on every change).

        An error goes beside the field it is about, once, in that field's words, and the field is
        marked; the frame and the table keep their place, showing the last good frame greyed out.
        """
        needed = self._inputs()
        self._show_fields(needed)
        self.frame, self.adu, self.pdu, self.dissection, self.error = b"", None, None, None, None
        errors: dict[str, str] = {}
        try:
            unit = tid = 0
            for name, read in (("unit", lambda: parse_int(self.unit.value, "unit")),
                               ("transaction_id", lambda: parse_int(self.transaction_id.value,
                                                                    "transaction id"))):
                if name == "transaction_id" and self.mode.value != "tcp":
                    continue
                try:
                    value = read()
                except ModbusError as exc:
                    errors[name] = f"{type(exc).__name__}: {exc}"
                    self.error = exc
                else:
                    unit, tid = (value, tid) if name == "unit" else (unit, value)
            arguments = self._arguments(needed, errors)
            if errors:
                raise ValueFormatError("; ".join(errors.values()))
            pdu = self.pdu_class()(**arguments)
            with warnings.catch_warnings(record=True) as caught:  # e.g. a reserved unit: built, with a note
                warnings.simplefilter("always")
                adu = make_frame(self.mode.value, unit, pdu, tid)
                data = adu.encode()
        except ModbusError as exc:
            self._failed(exc, errors, needed)
            return
        notes = {}
        for w in caught:
            field = self._field_of(ModbusError(str(w.message)), needed) or "unit"
            notes[field] = f"{w.category.__name__}: {w.message}"
        self._mark({}, notes)
        role = "response" if self.role.value == "exception" else self.role.value
        self.pdu, self.adu, self.frame = pdu, adu, data
        self.dissection = explain(data, self.mode.value, role)
        self.message.show(f"{self.dissection.summary}  ({len(data)} bytes)", "ok")
        chars = ""
        if self.mode.value == "ascii":  # what a terminal shows, then the byte values of the characters
            text = data.decode("ascii").replace("\r", " CR").replace("\n", " LF")
            chars = (f'<div style="margin-top:4px;font-size:0.9em">characters: '
                     f'<code class="mbe-frame-chars">{esc(text)}</code></div>')
        self.frame_view.value = (
            frame_html(self.dissection) + legend_html(self.dissection) + chars
            + f'<div style="margin-top:4px;font-size:0.9em">{"bytes" if chars else "hex"}: '
            f'<code class="mbe-frame-hex">{esc(hex_text(data))}</code></div>'
        )
        self.dissection_view.value = dissection_html(self.dissection)
        self._last_good = (self.frame_view.value, self.dissection_view.value)

    def _failed(self, exc: ModbusError, errors: dict[str, str], needed: dict[str, W.DOMWidget]) -> None:
        """No frame now: the error beside its field, the last good frame greyed out in its place."""
        if not errors:
            field = self._field_of(exc, needed)
            if field is not None:
                errors[field] = f"{type(exc).__name__}: {exc}"
        self.error = exc
        self._mark(errors)
        if errors:
            names = ", ".join(self._spec_label(n) for n in errors)
            self.message.show(f"no frame: fix the field marked in red ({names})", "error")
        else:  # an error no field owns: it goes on the message line (once)
            self.message.error(exc)
        if self._last_good is not None:
            self.frame_view.value = stale_html(self._last_good[0])
            self.dissection_view.value = stale_html(self._last_good[1])
        else:
            self.frame_view.value = ('<div class="mbe-frame-bytes" style="color:#5c636a;font-style:italic">'
                                     "no frame yet: fix the field marked in red</div>")
            self.dissection_view.value = ""

    def static_text(self) -> str:
        return "Frame builder panel: fields in, a Modbus frame out, each byte coloured by its field"

    def __repr__(self) -> str:
        shown = self.dissection.summary if self.dissection is not None else f"error: {self.error}"
        return f"<FrameBuilder {self.frame.hex(' ').upper() or '(no frame)'} | {shown}>"
