"""FrameBuilder: pick a mode, a function and its fields, and watch the frame being built byte by byte."""

from __future__ import annotations

import dataclasses
from typing import Any

import ipywidgets as W

from ..errors import ModbusError
from ..explain import Dissection, explain
from ..framing import Frame, make_frame
from ..pdu import ExceptionCode, ExceptionResponse, FunctionCode, Pdu, request_class, response_class
from .common import (
    MessageLine,
    StaticText,
    dissection_html,
    dropdown,
    esc,
    frame_html,
    guarded,
    hex_text,
    legend_html,
    parse_bit_list,
    parse_int,
    parse_int_list,
    shown,
    text_field,
)

__all__ = ["FrameBuilder"]

MODE_OPTIONS = [("RTU", "rtu"), ("ASCII", "ascii"), ("TCP", "tcp")]
ROLE_OPTIONS = [("request", "request"), ("response", "response"), ("exception response", "exception")]
FUNCTION_OPTIONS = [(f"{int(fc):02d} {fc.title}", int(fc)) for fc in FunctionCode]
EXCEPTION_OPTIONS = [(f"{int(c):02X} {c.title}", int(c)) for c in ExceptionCode]


def _text(value: Any) -> str:
    """A field's initial text: lists become ``"1, 2, 3"``, bools ``1``/``0``."""
    if isinstance(value, (list, tuple)):
        return ", ".join(str(int(v)) if isinstance(v, bool) else str(v) for v in value)
    return str(value)


class FrameBuilder(StaticText, W.VBox):
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
    Invalid input (a count of 126 for function 3, a unit of 300 on RTU, ``abc`` as an address) shows
    the library's error message in red, in place, and never raises.

    Attributes after every change:

    ``frame``        the bytes shown (``bytes``); ``b""`` while the input is invalid
    ``adu``          the frame object (``RtuFrame``/``AsciiFrame``/``TcpFrame``) or ``None``
    ``pdu``          the PDU object or ``None``
    ``dissection``   the :class:`~modbus_edu.explain.Dissection` of the frame, or ``None``
    ``error``        the :class:`~modbus_edu.errors.ModbusError` shown, or ``None``

    Example (the request of VECTORS.md ``11 03 00 6B 00 03 76 87``)::

        from modbus_edu.widgets import FrameBuilder
        fb = FrameBuilder(mode="rtu", unit=17, function=3, address=0x6B, count=3)
        fb                      # shows the panel; change any field and the frame follows
        fb.frame.hex(" ")       # '11 03 00 6b 00 03 76 87'
        fb.count.value = "126"  # too many registers: the red line says "quantity ... expected 1 to 125"
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
        self.transaction_id = text_field("transaction id", transaction_id, css="mbe-field-transaction-id")
        self.address = text_field("address", address, css="mbe-field-address",
                                  tooltip="0-based address, as in the frame (register 40001 is address 0)")
        self.count = text_field("count", count, css="mbe-field-count")
        self.value = text_field("value", value, css="mbe-field-value", tooltip="register value 0..65535")
        self.coil = dropdown("coil", [("ON (FF 00)", True), ("OFF (00 00)", False)], bool(coil),
                             css="mbe-field-coil")
        self.values = text_field("values", "", css="mbe-field-values", width="420px")
        # FC15 takes coil values, FC16 register values: the field remembers the text of each kind
        self._values_text = {"bits": "1, 0, 1, 1", "registers": "10, 258"}
        self._values_kind: str | None = None
        self._quiet = False
        self.bits = text_field("bits", _text(bits), css="mbe-field-bits", width="420px",
                               placeholder="1, 0, 1, 1  (first bit first)")
        self.registers = text_field("registers", _text(registers), css="mbe-field-registers", width="420px",
                                    placeholder="1234, 0x04D2")
        self.exception_code = dropdown("exception code", EXCEPTION_OPTIONS, int(exception_code),
                                       css="mbe-field-exception-code", width="420px")
        self._field_inputs = [self.address, self.count, self.value, self.coil, self.values, self.bits,
                              self.registers, self.exception_code]

        self.message = MessageLine()
        self.frame_view = W.HTML()
        self.frame_view.add_class("mbe-frame")
        self.dissection_view = W.HTML()
        self.dissection_view.add_class("mbe-dissection")

        left = W.VBox([self.mode, self.role, self.function, self.unit, self.transaction_id])
        right = W.VBox(self._field_inputs)
        self.children = [
            W.HTML("<b>Frame builder</b> &mdash; every byte below comes from the library"),
            W.HBox([left, right]),
            self.message,
            self.frame_view,
            self.dissection_view,
        ]
        self._update = guarded(self.message, self.update)
        kind = self._values_kind_now() or "registers"
        if values is not None:
            self._values_text[kind] = _text(values)
        self.values.value = self._values_text[kind]
        self._values_kind = kind
        for box in [self.mode, self.role, self.function, self.unit, self.transaction_id,
                    *self._field_inputs]:
            box.observe(lambda _change: None if self._quiet else self._update(), names="value")
        self._update()

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
            elif f.name == "value":
                out[f.name] = self.coil if "bool" in str(f.type) else self.value
            else:
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
        return {"address": self.address, "count": self.count, "value": self.value, "coil": self.coil,
                "values": self.values, "bits": self.bits, "registers": self.registers,
                "exception_code": self.exception_code}

    def _show_fields(self, needed: dict[str, W.DOMWidget]) -> None:
        wanted = set(map(id, needed.values()))
        for box in self._field_inputs:
            shown(box, id(box) in wanted)
        shown(self.transaction_id, self.mode.value == "tcp")
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
    def _arguments(self, needed: dict[str, W.DOMWidget]) -> dict[str, Any]:
        kwargs: dict[str, Any] = {}
        for name, box in needed.items():
            if box is self.coil or box is self.exception_code:
                kwargs[name] = box.value
            elif name in ("values", "bits"):
                kwargs[name] = (parse_bit_list(box.value, name) if self._is_bits(name)
                                else parse_int_list(box.value, name))
            elif name == "registers":
                kwargs[name] = parse_int_list(box.value, name)
            else:
                kwargs[name] = parse_int(box.value, name)
        if self.role.value == "exception":
            kwargs["function"] = self.function.value
        return kwargs

    def update(self) -> None:
        """Rebuild the frame from the fields (called on every change; errors go to the message line)."""
        needed = self._inputs()
        self._show_fields(needed)
        self.frame, self.adu, self.pdu, self.dissection, self.error = b"", None, None, None, None
        try:
            unit = parse_int(self.unit.value, "unit")
            tid = parse_int(self.transaction_id.value, "transaction id") if self.mode.value == "tcp" else 0
            pdu = self.pdu_class()(**self._arguments(needed))
            adu = make_frame(self.mode.value, unit, pdu, tid)
            data = adu.encode()
        except ModbusError as exc:
            self.error = exc
            self.message.error(exc)
            self.frame_view.value = (
                '<div class="mbe-frame-bytes" style="color:#868e96;font-style:italic">'
                "no frame: fix the field named in red</div>")
            self.dissection_view.value = ""
            return
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

    def static_text(self) -> str:
        return "Frame builder panel: fields in, a Modbus frame out, each byte coloured by its field"

    def __repr__(self) -> str:
        shown = self.dissection.summary if self.dissection is not None else f"error: {self.error}"
        return f"<FrameBuilder {self.frame.hex(' ').upper() or '(no frame)'} | {shown}>"
