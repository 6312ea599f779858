"""CrcExplorer: the CRC-16/MODBUS bit by bit or by table, and the LRC, one step at a time."""

from __future__ import annotations

from typing import Any

import ipywidgets as W

from ..crc import (
    CRC_TABLE,
    INITIAL,
    POLYNOMIAL,
    crc16,
    crc16_table_trace,
    crc16_trace,
    crc_bytes,
    lrc,
    lrc_trace,
)
from ..errors import ModbusError
from ..framing import parse_hex
from .common import (
    MONO,
    MessageLine,
    Typing,
    esc,
    focus_after_click,
    guarded,
    hex_text,
    live,
    mark_invalid,
    panel_style,
    scroll_box,
    stale_html,
)
from .picture import StaticView

__all__ = ["CrcExplorer"]

MAX_BITWISE_BYTES = 2048
"""The most bytes the explorer follows bit by bit (18 432 steps); a frame has at most 256."""

MAX_BYTES = 65536
"""The most bytes the explorer follows by table or LRC, one step a byte."""

METHODS = [("CRC-16 bit by bit", "bitwise"), ("CRC-16 by table", "table"), ("LRC (ASCII mode)", "lrc")]
METHOD_TIPS = ["RTU's CRC-16: each byte, then eight shifts, XOR 0xA001 when a 1 falls out",
               "the same CRC-16, one look-up in a 256-entry table per byte",
               "ASCII mode's LRC: add the bytes, keep 8 bits, take the two's complement"]


def _bin16(value: int) -> str:
    b = f"{value:016b}"
    return " ".join(b[i:i + 4] for i in range(0, 16, 4))


def _bin8(value: int) -> str:
    b = f"{value:08b}"
    return f"{b[:4]} {b[4:]}"


#: The width of the label column of a step ("start running sum" is the longest label).
LABEL_WIDTH = 19


class CrcExplorer(StaticView, W.VBox):
    """Step through the error check of a frame: the CRC-16 of RTU (bit by bit, or by table) and the LRC.

    Type the bytes (hex, any common spacing); the steps follow the typing, a moment after the last
    keystroke (``typing``, a :class:`~modbus_edu.widgets.common.Typing`).  **Bit by bit** follows the
    specification's algorithm, from :func:`modbus_edu.crc.crc16_trace`: the register starts at 0xFFFF;
    each byte is XORed into its
    low half, then eight times the register shifts right and, when the bit that fell out (the LSB) was
    1, is XORed with 0xA001.  Each step shows the register in binary and hex, the shift and the XOR.
    **By table** (:func:`~modbus_edu.crc.crc16_table_trace`) does a byte per step and shows the table
    index and the entry used.  **LRC** (:func:`~modbus_edu.crc.lrc_trace`) adds the bytes and takes the
    two's complement.  At the end: the value, and the bytes in wire order (CRC: low byte first).

    Buttons: *next bit* (one step), *next byte*, *back*, *reset*, *run to end*.  State for notebooks and
    tests: ``steps`` (the trace), ``position`` (steps done), ``register`` (the value now), ``result``
    (the final value: ``crc16(data)`` or ``lrc(data)``), ``wire`` (the check bytes as sent), ``data``.

    Example::

        from modbus_edu.widgets import CrcExplorer
        cx = CrcExplorer("01 03 00 00 00 01")
        cx                       # press "next bit" and watch the register
        cx.next_byte.click()     # the first byte done: 9 steps (XOR in, 8 shifts)
        cx.run_to_end.click()
        hex(cx.register), cx.wire.hex(" ")     # ('0xa84', '84 0a')
        cx.method.value = "table"              # the same CRC, one table look-up per byte
    """

    def __init__(self, data: str | bytes = "01 03 00 00 00 01", method: str = "bitwise",
                 **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.add_class("mbe-crcexplorer")
        self.data: bytes = b""
        self.steps: list[Any] = []
        self.position = 0
        text = data if isinstance(data, str) else hex_text(bytes(data))
        self.text = W.Text(value=text, description="bytes (hex)", style={"description_width": "90px"},
                           layout=W.Layout(width="560px", max_width="calc(100% - 4px)"),
                           continuous_update=True)
        self.text.add_class("mbe-crc-input")
        self.method = W.ToggleButtons(options=METHODS, value=method, tooltips=METHOD_TIPS,
                                      description="method", style={"description_width": "90px"})
        self.method.add_class("mbe-crc-method")

        def button(label: str, icon: str, tip: str) -> W.Button:
            b = W.Button(description=label, icon=icon, tooltip=tip,
                         layout=W.Layout(width="auto", flex="0 0 auto"))
            b.add_class("mbe-crc-" + label.replace(" ", "-"))
            return b

        self.next_bit = button("next bit", "step-forward", "one step (bitwise: one shift; else one byte)")
        self.next_byte = button("next byte", "forward", "finish the current byte")
        self.back = button("back", "step-backward", "undo one step")
        self.reset = button("reset", "undo", "back to the start value")
        self.run_to_end = button("run to end", "fast-forward", "do every step")
        self.message = MessageLine()
        self.bytes_view = W.HTML()
        self.bytes_view.add_class("mbe-crc-bytes")
        self.step_view = W.HTML(layout=W.Layout(overflow="auto"))  # long lines scroll, never clip
        live(scroll_box(self.step_view, "the current step (scrolls)"))
        self.step_view.add_class("mbe-crc-step")
        self.result_view = live(W.HTML())
        self.result_view.add_class("mbe-crc-result")
        self.history_view = W.HTML()
        self.children = [
            W.HTML("<b>CRC explorer</b> &mdash; the error check, one step at a time"),
            self.text,
            self.message,  # right under the field: what it says is about the bytes typed there
            self.method,
            W.HBox([self.reset, self.back, self.next_bit, self.next_byte, self.run_to_end],
                   layout=W.Layout(flex_flow="row wrap")),  # buttons on two lines rather than squeezed
            self.bytes_view,
            self.step_view,
            self.result_view,
            self.history_view,
            panel_style(),
        ]
        self._load = guarded(self.message, self.load)
        self.typing = Typing(self._load)
        """Applies typed bytes a moment after the last keystroke; ``typing.flush()`` applies them now."""
        self.text.observe(self.typing.changed, names="value")
        self.method.observe(self.typing.changed, names="value")
        self.next_bit.on_click(guarded(self.message, lambda _b: self.step(1)))
        self.next_byte.on_click(guarded(self.message, lambda _b: self.finish_byte()))
        self.back.on_click(guarded(self.message, lambda _b: self.step(-1)))
        self.reset.on_click(guarded(self.message, lambda _b: self.goto(0)))
        self.run_to_end.on_click(guarded(self.message, lambda _b: self.goto(len(self.steps))))
        for forward in (self.next_bit, self.next_byte, self.run_to_end):
            focus_after_click(forward, self.back)  # at the end these three go grey: step back from there
        for backward in (self.back, self.reset):
            focus_after_click(backward, self.next_bit)  # at the start these two go grey: step on
        self._load()

    # -- state ---------------------------------------------------------------------------------------
    @property
    def initial(self) -> int:
        """The start value: 0xFFFF for the CRC, 0 for the LRC's running sum."""
        return 0 if self.method.value == "lrc" else INITIAL

    @property
    def register(self) -> int:
        """The CRC register (LRC: the running 8-bit sum) after the steps done so far."""
        return self.steps[self.position - 1].after if self.position else self.initial

    @property
    def done(self) -> bool:
        return self.position >= len(self.steps)

    @property
    def result(self) -> int:
        """The final check value of the data: CRC-16 register, or the LRC byte."""
        return lrc(self.data) if self.method.value == "lrc" else crc16(self.data)

    @property
    def wire(self) -> bytes:
        """The check bytes as they go on the wire: CRC low byte first; LRC one byte (two hex chars)."""
        return bytes([lrc(self.data)]) if self.method.value == "lrc" else crc_bytes(self.data)

    def load(self) -> None:
        """Read the bytes and compute the trace of the chosen method; back to step 0."""
        self.steps, self.position, self.data = [], 0, b""
        try:
            data = parse_hex(self.text.value) if self.text.value.strip() else b""
        except ModbusError as exc:
            self.message.error(exc)  # right under the bytes field, which is marked red
            mark_invalid(self.text, True, self.message)
            self._render(stale=True)
            return
        method = self.method.value
        limit = MAX_BITWISE_BYTES if method == "bitwise" else MAX_BYTES
        if len(data) > limit:
            how = "bit by bit (9 steps a byte)" if method == "bitwise" else "step by step"
            self.message.show(f"{len(data):,} bytes are too many to follow {how}: at most {limit:,}. "
                              "Shorten them" + (", or choose 'by table'." if method == "bitwise" else "."),
                              "error")
            mark_invalid(self.text, True, self.message)
            self._render(stale=True)
            return
        mark_invalid(self.text, False, self.message)
        self.data = data
        if method == "bitwise":
            self.steps = list(crc16_trace(data))
        elif method == "table":
            self.steps = list(crc16_table_trace(data))
        else:
            self.steps = list(lrc_trace(data))
        self.message.show(f"{len(data)} bytes, {len(self.steps)} steps" if data else "type some bytes")
        self.next_bit.description = "next bit" if method == "bitwise" else "next step"
        self._render()

    def goto(self, position: int) -> None:
        self.position = max(0, min(len(self.steps), position))
        self._render()

    def step(self, delta: int = 1) -> None:
        self.goto(self.position + delta)

    def finish_byte(self) -> None:
        """Advance to the end of the current byte (if at a byte boundary: through the next byte)."""
        if self.done:
            return
        index = self.steps[self.position].byte_index
        target = self.position
        while target < len(self.steps) and self.steps[target].byte_index == index:
            target += 1
        self.goto(target)

    # -- views ---------------------------------------------------------------------------------------
    def _current_byte(self) -> int | None:
        if self.done:
            return None
        return self.steps[self.position].byte_index

    def _render(self, stale: bool = False) -> None:
        """Draw the views; ``stale`` (the bytes do not read): keep the last good views, greyed out."""
        for b in (self.next_bit, self.next_byte, self.run_to_end):
            b.disabled = self.done
        for b in (self.back, self.reset):
            b.disabled = self.position == 0
        views = (self.bytes_view, self.step_view, self.result_view, self.history_view)
        if stale:
            for view in views:
                view.value = stale_html(view.value)
            return
        self.bytes_view.value = self._bytes_html()
        self.step_view.value = self._step_html()
        self.result_view.value = self._result_html()
        self.history_view.value = self._history_html()

    def _bytes_html(self) -> str:
        if not self.data:
            return ""
        current = self._current_byte()
        last = self.steps[self.position - 1].byte_index if self.position else -1
        parts = []
        for i, b in enumerate(self.data):
            if i == current:
                style = "background:#ffd43b;font-weight:bold"
            elif i <= last and (current is None or i < current):
                style = "background:#d3f9d8"
            else:
                style = "color:#5c636a"
            parts.append(f'<span style="{style};padding:1px 3px;border-radius:3px">{b:02X}</span>')
        return f'<div style="{MONO}">bytes: {" ".join(parts)}</div>'

    def _reg_line(self, label: str, value: int, note: str = "", width: int = 16) -> str:
        """``label`` in a column of its own (at least one space after it), the value in binary and hex."""
        bits = _bin16(value) if width == 16 else _bin8(value)
        hexv = f"0x{value:04X}" if width == 16 else f"0x{value:02X}"
        return f"{label:<{LABEL_WIDTH - 1}} {bits}   {hexv}{('   ' + note) if note else ''}"

    def _step_html(self) -> str:
        method = self.method.value
        lines: list[str] = []
        if not self.steps:
            return ""
        if self.position == 0:
            start = self.initial
            width = 8 if method == "lrc" else 16
            what = "running sum" if method == "lrc" else "register"
            lines.append(self._reg_line(f"start {what}", start, "", width))
            nxt = self.steps[0]
            lines.append(f"next: byte 0 = 0x{nxt.byte:02X}")
        else:
            s = self.steps[self.position - 1]
            title = f"step {self.position} of {len(self.steps)}"
            if method == "bitwise":
                lines.append(f"{title}: {s.describe()}")
                if s.action == "xor_byte":
                    lines.append(self._reg_line("register", s.before))
                    lines.append(self._reg_line("XOR byte", s.byte, f"(0x{s.byte:02X} into the low half)"))
                    lines.append(self._reg_line("=", s.after))
                else:
                    shifted = s.shifted
                    lines.append(self._reg_line("register", s.before, f"LSB = {s.lsb}"))
                    lines.append(self._reg_line(">> 1", shifted, "shift right, a 0 comes in on the left"))
                    if s.action == "shift_xor":
                        lines.append(self._reg_line("XOR 0xA001", POLYNOMIAL, "because the LSB was 1"))
                        lines.append(self._reg_line("=", s.after))
                    else:
                        lines.append(" " * LABEL_WIDTH + "(LSB was 0: no XOR)")
            elif method == "table":
                lines.append(f"{title}: {s.describe()}")
                lines.append(self._reg_line("register", s.before))
                lines.append(f"{'index':<{LABEL_WIDTH - 1}} (0x{s.before & 0xFF:02X} XOR byte 0x{s.byte:02X})"
                             f" = 0x{s.index:02X} = {s.index}")
                lines.append(self._reg_line(">> 8", s.before >> 8, "the high byte moves down"))
                lines.append(self._reg_line(f"table[0x{s.index:02X}]", s.table_value,
                                            "eight shift/XOR steps, done in advance"))
                lines.append(self._reg_line("=", s.after))
            else:
                lines.append(f"{title}: add byte {s.byte_index} = 0x{s.byte:02X}")
                lines.append(self._reg_line("sum", s.before, "", 8))
                lines.append(self._reg_line("+ byte", s.byte, "", 8))
                lines.append(self._reg_line("= (mod 256)", s.after, "", 8))
        html = "\n".join(esc(line) for line in lines)
        extra = self._table_html() if method == "table" and self.position else ""
        return f'<pre style="{MONO};margin:4px 0">{html}</pre>{extra}'

    def _table_html(self) -> str:
        """The row of the 256-entry table around the entry used, that entry highlighted."""
        s = self.steps[self.position - 1]
        row = s.index - s.index % 8
        cells = []
        for i in range(row, row + 8):
            style = "background:#ffd43b;font-weight:bold" if i == s.index else ""
            cells.append(f'<td style="{style};padding:0 6px">[{i:02X}] {CRC_TABLE[i]:04X}</td>')
        return (f'<table style="{MONO};font-size:0.9em"><tr><td>table row:</td>{"".join(cells)}</tr></table>')

    def _result_html(self) -> str:
        if not self.done or not self.steps:
            if not self.data and not self.steps:
                return ""
            return '<div style="color:#5c636a">the result appears after the last step</div>'
        if self.method.value == "lrc":
            total, value = self.register, lrc(self.data)
            text = (f"LRC = two's complement of 0x{total:02X} = 0x{value:02X}; in the frame it is written "
                    f"as the two characters '{value:02X}' before CR LF")
        else:
            value = self.register
            wire = crc_bytes(self.data)
            text = (f"CRC = 0x{value:04X}; on the wire low byte first: {hex_text(wire)}  "
                    f"(frame: {hex_text(self.data + wire)})")
        return f'<div style="{MONO};color:#2b6e35;font-weight:bold">{esc(text)}</div>'

    def _history_html(self, last: int = 12) -> str:
        if not self.position or self.method.value == "lrc":
            return ""
        done = self.steps[max(0, self.position - last):self.position]
        rows = "".join(f"<li>{esc(s.describe())}</li>" for s in done)
        return f'<details><summary>last steps</summary><ol start="{self.position - len(done) + 1}" ' \
               f'style="{MONO};font-size:0.85em">{rows}</ol></details>'

    # -- optional plot -------------------------------------------------------------------------------
    def plot(self, ax: Any = None) -> Any:
        """Plot the register after every step (matplotlib, the course's :mod:`~modbus_edu.plotstyle`);
        returns the Axes."""
        if ax is None:
            from ..plotstyle import figure  # deferred: matplotlib, needed only to plot

            _fig, ax = figure()
        values = [self.initial] + [s.after for s in self.steps]
        ax.step(range(len(values)), values, where="post")
        ax.set_xlabel("step")
        ax.set_ylabel("register")
        ax.set_title(f"{dict((v, k) for k, v in METHODS)[self.method.value]}: {hex_text(self.data)}")
        return ax

    def static_text(self) -> str:
        return "CRC explorer panel: the CRC-16 (or the LRC) of your bytes, step by step"

    def __repr__(self) -> str:
        return (f"<CrcExplorer {self.method.value}: {len(self.data)} bytes, step {self.position} of "
                f"{len(self.steps)}, result 0x{self.result:0{2 if self.method.value == 'lrc' else 4}X}, "
                f"on the wire {self.wire.hex(' ').upper()}>")
