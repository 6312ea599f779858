"""FrameDecoder: paste the bytes of a frame, read it field by field."""

from __future__ import annotations

from typing import Any

import ipywidgets as W

from ..errors import ModbusError
from ..explain import Dissection, explain
from ..framing import parse_hex
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
    mark_invalid,
    panel_style,
    stale_html,
)
from .picture import StaticView

__all__ = ["FrameDecoder"]

MODE_OPTIONS = [("auto-detect", "auto"), ("RTU", "rtu"), ("ASCII", "ascii"), ("TCP", "tcp")]
ROLE_OPTIONS = [("auto", "auto"), ("request", "request"), ("response", "response")]
_NAMES = {"rtu": "RTU", "ascii": "ASCII", "tcp": "TCP"}


class FrameDecoder(StaticView, W.VBox):
    """Paste a frame as hex (or an ASCII frame with its ``:``) and see what every byte means.

    Hex may be written the usual ways: ``01 03 00 00 00 01 84 0A``, ``010300000001840A``,
    ``0x01,0x03,...`` or ``:050310000002E6`` (the text goes through
    :func:`modbus_edu.framing.parse_hex`).  The mode is detected (:func:`~modbus_edu.framing.detect_mode`)
    unless you choose it; the role (request or response) is the one that decodes unless you choose it.
    The dissection is :func:`modbus_edu.explain.explain`'s: a wrong CRC or LRC is shown with the value
    it should have had, and any rule the frame breaks is said in red, in place; nothing raises.
    The dissection follows the typing: the text is read a moment after the last keystroke (``typing``,
    a :class:`~modbus_edu.widgets.common.Typing`); a half-typed byte says so under the field.

    Attributes after every change: ``frame`` (the parsed bytes, ``b""`` when the text is not hex),
    ``dissection`` (the :class:`~modbus_edu.explain.Dissection`, or ``None``), ``error`` (the
    :class:`~modbus_edu.errors.ModbusError` shown, or ``None``).

    Example::

        from modbus_edu.widgets import FrameDecoder
        fd = FrameDecoder("01 03 00 00 00 01 84 0B")   # one bit off in the CRC
        fd                                              # red: "CRC mismatch ... expected 84 0A"
        fd.text.value = "01 18 00 00 00 05 01 03 02 04 D2"   # a published TCP response: register = 1234
        fd.dissection.frame.pdu.registers               # (1234,)
    """

    def __init__(self, text: str = "", mode: str = "auto", role: str = "auto", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.add_class("mbe-framedecoder")
        self.frame: bytes = b""
        self.dissection: Dissection | None = None
        self.error: ModbusError | None = None

        self.text = W.Textarea(value=text, placeholder="01 03 00 00 00 01 84 0A   or   :050310000002E6",
                               description="frame", style={"description_width": "60px"},
                               layout=W.Layout(width="640px", max_width="calc(100% - 4px)", height="64px"),
                               continuous_update=True)
        self.text.add_class("mbe-decoder-input")
        self.mode = dropdown("mode", MODE_OPTIONS, mode, css="mbe-field-mode", width="220px")
        self.role = dropdown("role", ROLE_OPTIONS, role, css="mbe-field-role", width="220px")
        for box in (self.mode, self.role):
            box.style = {"description_width": "60px"}
        self.message = MessageLine()
        self.frame_view = W.HTML()
        self.frame_view.add_class("mbe-frame")
        self.dissection_view = W.HTML()
        self.dissection_view.add_class("mbe-dissection")
        self.children = [
            W.HTML("<b>Frame decoder</b> &mdash; paste hex in any common spacing"),
            self.text,
            self.message,  # right under the field: what it says is about the frame typed there
            W.HBox([self.mode, self.role], layout=W.Layout(flex_flow="row wrap")),  # one column when narrow
            self.frame_view,
            self.dissection_view,
            panel_style(),
        ]
        self._update = guarded(self.message, self.update)
        self.typing = Typing(self._update)
        """Applies typed text a moment after the last keystroke; ``typing.flush()`` applies it now."""
        for box in (self.text, self.mode, self.role):
            box.observe(self.typing.changed, names="value")
        self._update()

    def update(self) -> None:
        """Parse and dissect the text (called on every change)."""
        self.frame, self.dissection, self.error = b"", None, None
        if not self.text.value.strip():
            mark_invalid(self.text, False, self.message)
            self.frame_view.value = ""
            self.dissection_view.value = ""
            self.message.show("paste a frame above (hex bytes, or an ASCII frame starting with ':')")
            return
        try:
            data = parse_hex(self.text.value)
        except ModbusError as exc:  # under the field, which is marked; the last good frame greyed out
            self.error = exc
            self.message.error(exc)
            mark_invalid(self.text, True, self.message)
            self.frame_view.value = stale_html(self.frame_view.value)
            self.dissection_view.value = stale_html(self.dissection_view.value)
            return
        self.frame = data
        mode = None if self.mode.value == "auto" else self.mode.value
        role = None if self.role.value == "auto" else self.role.value
        d = explain(data, mode, role)
        self.dissection = d
        self.error = d.error
        how = f"{_NAMES.get(d.mode, d.mode)} ({f'detected: {d.detected}' if mode is None else 'chosen'})"
        if d.error is not None:  # a frame that breaks a rule (a wrong CRC): the field is marked too
            self.message.show(f"{how}: {type(d.error).__name__}: {d.error}", "error")
        else:
            self.message.show(f"{how}: {d.summary}  ({len(data)} bytes)", "ok")
        mark_invalid(self.text, d.error is not None, self.message)
        body = frame_html(d) + legend_html(d) if d.rows else ""
        self.frame_view.value = body + (
            f'<div style="margin-top:4px;font-size:0.9em">bytes: <code class="mbe-frame-hex">'
            f"{esc(hex_text(data))}</code></div>")
        self.dissection_view.value = dissection_html(d)  # the error is on the message line, once

    def static_text(self) -> str:
        return "Frame decoder panel: hex bytes in, every field of the frame explained"

    def __repr__(self) -> str:
        if self.dissection is not None:
            return f"<FrameDecoder {self.dissection.summary}>"
        return f"<FrameDecoder error: {self.error}>" if self.error else "<FrameDecoder (empty)>"
