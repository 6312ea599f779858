"""What the panels share: colours, the message line, reading numbers typed by people, coloured frames,
and following the typing (:class:`Typing`).

Nothing here knows Modbus.  The panels ask the library for every byte and every field boundary
(:func:`modbus_edu.explain.explain` rows); this module only turns text into numbers and rows into
coloured HTML.
"""

from __future__ import annotations

import asyncio
import html
import traceback
from collections.abc import Callable, Iterable
from pathlib import PurePath
from typing import Any

import ipywidgets as W

from ..errors import ModbusError, ValueFormatError
from ..errors import shown as shown_value

__all__ = [
    "PALETTE",
    "ROLE_COLOURS",
    "esc",
    "hex_text",
    "parse_int",
    "parse_int_list",
    "parse_bit_list",
    "message_html",
    "MessageLine",
    "guarded",
    "MONO",
    "DISSECTION_CSS",
    "dissection_html",
    "field_colours",
    "frame_html",
    "legend_html",
    "text_field",
    "dropdown",
    "shown",
    "is_shown",
    "STALE_STYLE",
    "stale_html",
    "mark_invalid",
    "TYPING_DELAY",
    "running_loop",
    "from_the_page",
    "Typing",
]

#: Soft background colours, one per field of a frame (cycled when a frame has more fields).
PALETTE: tuple[str, ...] = (
    "#ffd8a8",  # orange
    "#b2f2bb",  # green
    "#a5d8ff",  # blue
    "#ffc9c9",  # red
    "#e5dbff",  # violet
    "#fff3bf",  # yellow
    "#c3fae8",  # teal
    "#fcc2d7",  # pink
    "#d0bfff",  # grape
    "#dee2e6",  # grey
    "#ffec99",  # light yellow
    "#99e9f2",  # cyan
)

#: One colour per test-tool role, so that two panels side by side are told apart at a glance
#: (the robot test-tool paper's wish: "background color may be changed for different app modes").
ROLE_COLOURS: dict[str, str] = {
    "rtu_master": "#e7f5ff",
    "rtu_slave": "#ebfbee",
    "tcp_client": "#fff4e6",
    "tcp_server": "#f8f0fc",
}

MONO = "font-family: var(--jp-code-font-family, monospace); white-space: pre-wrap"


def esc(text: object) -> str:
    """HTML-escape anything (after ``str``)."""
    return html.escape(str(text))


def hex_text(data: bytes) -> str:
    """``01 03 00 00 00 01 84 0A``: uppercase hex with spaces, as the course writes frames."""
    return " ".join(f"{b:02X}" for b in data)


# --- numbers typed by people --------------------------------------------------------------------------
def parse_int(text: str | int, name: str) -> int:
    """A whole number typed in a field: ``"107"``, ``"0x6B"``, ``"6Bh"``, ``"0b101"``, ``"1_000"``.

    Raises :class:`~modbus_edu.errors.ValueFormatError` naming the field.  The range is not checked
    here: the library checks it and says what is allowed.
    """
    if isinstance(text, bool):
        raise ValueFormatError(f"{name}: expected a whole number, got {text!r}")
    if isinstance(text, int):
        return text
    s = str(text).strip().replace("_", "")
    if not s:
        raise ValueFormatError(f"{name} is empty: type a whole number (decimal, or hex like 0x6B)")
    sign = 1
    if s[0] in "+-":
        sign, s = (-1 if s[0] == "-" else 1), s[1:]
    try:
        low = s.lower()
        if low.startswith("0x"):
            value = int(s[2:], 16)
        elif low.endswith("h") and len(s) > 1:
            value = int(s[:-1], 16)
        elif low.startswith("0b"):
            value = int(s[2:], 2)
        else:
            if not s.isdigit():
                raise ValueError(s)
            value = int(s, 10)
    except ValueError:
        raise ValueFormatError(
            f"{name}: {str(text).strip()!r} is not a whole number (write 107, or hex as 0x6B)"
        ) from None
    return sign * value


def _items(text: str | Iterable[Any]) -> list[Any]:
    if isinstance(text, str):
        return [t for t in text.replace(";", ",").replace(" ", ",").split(",") if t.strip()]
    return list(text)


def parse_int_list(text: str | Iterable[Any], name: str) -> list[int]:
    """``"10, 0x0102"`` -> ``[10, 258]`` (commas, spaces or semicolons between the numbers)."""
    items = _items(text)
    if not items:
        raise ValueFormatError(f"{name} is empty: type numbers separated by commas, e.g. 10, 0x0102")
    return [parse_int(item, f"{name} #{i}") for i, item in enumerate(items)]


_TRUE = {"1", "on", "true", "t", "yes", "y", "ff00"}
_FALSE = {"0", "off", "false", "f", "no", "n", "0000"}


def parse_bit_list(text: str | Iterable[Any], name: str) -> list[bool]:
    """``"1,0,1,1"``, ``"ON OFF ON"`` or a bit string ``"1011"`` -> ``[True, False, True, True]``.

    A bit string is read left to right: its first character is the first coil.
    """
    if isinstance(text, str):
        compact = text.strip()
        if compact and set(compact) <= {"0", "1"} and len(compact) > 1:
            return [c == "1" for c in compact]
    items = _items(text)
    if not items:
        raise ValueFormatError(f"{name} is empty: type bits separated by commas, e.g. 1, 0, 1 (or ON, OFF)")
    out: list[bool] = []
    for i, item in enumerate(items):
        if isinstance(item, bool):
            out.append(item)
            continue
        if isinstance(item, int) and item in (0, 1):
            out.append(bool(item))
            continue
        word = str(item).strip().lower()
        if word in _TRUE:
            out.append(True)
        elif word in _FALSE:
            out.append(False)
        else:
            raise ValueFormatError(f"{name} #{i}: {str(item).strip()!r} is not a bit (use 1/0 or ON/OFF)")
    return out


# --- the message line -------------------------------------------------------------------------------
_KIND_STYLE = {
    "info": "color: var(--jp-ui-font-color1, #333)",
    "ok": "color: #2b8a3e",
    "warn": "color: #e67700",
    "error": "color: #c92a2a; font-weight: 600",
}


def message_html(text: str, kind: str = "info") -> str:
    """One line of HTML in the colour of its kind: info, ok, warn or error (red)."""
    icon = {"error": "&#9888; ", "warn": "&#9888; ", "ok": "&#10003; "}.get(kind, "")
    return f'<div class="mbe-message mbe-{kind}" style="{_KIND_STYLE.get(kind, "")}">{icon}{esc(text)}</div>'


class MessageLine(W.HTML):
    """The robot test-tool paper's message box: one line that says what happened, instead of a pop-up.

    ``show(text, kind)`` sets it; ``error(exc)`` shows an exception as ``ClassName: message``.
    ``.text`` and ``.kind`` keep the last message for tests and notebooks.
    """

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.text = ""
        self.kind = "info"
        self.add_class("mbe-message-line")

    def show(self, text: str, kind: str = "info") -> None:
        self.text = text
        self.kind = kind
        self.value = message_html(text, kind) if text else ""

    def error(self, exc: BaseException) -> None:
        if isinstance(exc, ModbusError):
            self.show(f"{type(exc).__name__}: {exc}", "error")
        else:  # a bug, not bad input: still never raise into the notebook, but say it is unexpected
            last = traceback.extract_tb(exc.__traceback__)[-1:] if exc.__traceback__ else []
            where = f" (at {PurePath(last[0].filename).name}:{last[0].lineno})" if last else ""
            self.show(f"unexpected {type(exc).__name__}: {exc}{where}", "error")

    def clear(self) -> None:
        self.show("")


def guarded(message: MessageLine, fn: Callable[..., Any]) -> Callable[..., Any]:
    """Wrap a callback so that any exception lands on the message line instead of in the notebook."""

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return fn(*args, **kwargs)
        except Exception as exc:  # noqa: BLE001 - a widget callback must never raise into the page
            message.error(exc)
            return None

    wrapper.__name__ = getattr(fn, "__name__", "callback")
    wrapper.__doc__ = fn.__doc__
    return wrapper


# --- frames as coloured bytes ------------------------------------------------------------------------
def field_colours(rows: Iterable[Any]) -> list[str]:
    """One palette colour per row, in order (a frame's rows are its fields)."""
    return [PALETTE[i % len(PALETTE)] for i, _ in enumerate(rows)]


def frame_html(dissection: Any) -> str:
    """The frame's bytes (ASCII: characters), each field on its own colour, with a tooltip per field.

    Field boundaries come from ``dissection.rows`` (offset, raw bytes, field name, meaning); a row that
    breaks a rule is underlined in red.
    """
    rows = list(dissection.rows)
    colours = field_colours(rows)
    spans = []
    for row, colour in zip(rows, colours):
        border = "border-bottom: 3px solid #c92a2a;" if not getattr(row, "ok", True) else ""
        title = f"{row.field}: {row.meaning}" if row.meaning else row.field
        spans.append(
            f'<span class="mbe-field" title="{esc(title)}" style="background:{colour};{border}'
            f'padding:2px 4px;margin-right:3px;border-radius:4px">{esc(dissection.raw_text(row))}'
            f"</span>"
        )
    return (f'<div class="mbe-frame-bytes" style="{MONO}; font-size: 1.15em; line-height: 2em">'
            f'{"".join(spans)}</div>')


def legend_html(dissection: Any) -> str:
    """A legend: one colour chip and the field's name per row."""
    rows = list(dissection.rows)
    items = []
    for row, colour in zip(rows, field_colours(rows)):
        items.append(
            f'<span style="display:inline-block;margin:0 10px 2px 0;white-space:nowrap">'
            f'<span style="display:inline-block;width:0.9em;height:0.9em;background:{colour};'
            f'border:1px solid #999;vertical-align:middle;margin-right:4px"></span>{esc(row.field)}</span>'
        )
    return f'<div class="mbe-legend" style="font-size:0.9em">{"".join(items)}</div>'


#: Spacing for the dissection table of :meth:`modbus_edu.explain.Dissection._repr_html_` inside a panel.
DISSECTION_CSS = (
    "<style>.mbe-dissection table.modbus-edu-dissection td, .mbe-dissection table.modbus-edu-dissection th"
    " {padding: 1px 8px; text-align: left; vertical-align: top; line-height: 1.35}</style>"
)


def dissection_html(dissection: Any, with_error: bool = False) -> str:
    """The library's HTML table of a dissection, with some room between the columns.

    The library writes the frame's error under the table; a panel that already says it on its message
    line leaves it out (``with_error=False``), so that each error appears once.
    """
    table = dissection._repr_html_()
    if not with_error and dissection.error is not None:
        head, end, _error = table.rpartition("</table>")
        table = head + end
    return DISSECTION_CSS + table


STALE_STYLE = "opacity:0.4;filter:grayscale(1)"


def stale_html(content: str) -> str:
    """The last good content of a view, greyed out while the input it came from does not read."""
    if not content or "mbe-stale" in content:
        return content
    return (f'<div class="mbe-stale" title="the last good result: fix the marked field" '
            f'style="{STALE_STYLE}">{content}</div>')


def mark_invalid(widget: W.DOMWidget, invalid: bool) -> None:
    """Mark an input red (class ``mbe-invalid``) while what it holds does not read, unmark it after."""
    if invalid:
        widget.add_class("mbe-invalid")
    else:
        widget.remove_class("mbe-invalid")
    widget.layout.border = "2px solid #c92a2a" if invalid else None


# --- small widget factories ----------------------------------------------------------------------
def text_field(description: str, value: str = "", css: str | None = None, width: str = "230px",
               placeholder: str = "", tooltip: str = "") -> W.Text:
    """A labelled text box (``css`` adds a class for browser tests, e.g. ``mbe-field-address``).

    It sends its text at every keystroke (``continuous_update``); the panel applies it a moment after
    the last one (:class:`Typing`), so the frame follows the typing without Enter or Tab."""
    box = W.Text(value=value if isinstance(value, str) else shown_value(value), description=description,
                 placeholder=placeholder,
                 style={"description_width": "110px"}, layout=W.Layout(width=width),
                 continuous_update=True)
    if tooltip:
        box.tooltip = tooltip
    if css:
        box.add_class(css)
    return box


def dropdown(description: str, options: Any, value: Any = None, css: str | None = None,
             width: str = "230px") -> W.Dropdown:
    kwargs: dict[str, Any] = {"options": options, "description": description,
                              "style": {"description_width": "110px"}, "layout": W.Layout(width=width)}
    if value is not None:
        kwargs["value"] = value
    box = W.Dropdown(**kwargs)
    if css:
        box.add_class(css)
    return box


def shown(widget: W.DOMWidget, visible: bool) -> None:
    """Show or hide a widget through ``layout.display`` (hidden widgets keep their value)."""
    widget.layout.display = None if visible else "none"


def is_shown(widget: W.DOMWidget) -> bool:
    return widget.layout.display != "none"


# --- following the typing ----------------------------------------------------------------------------
TYPING_DELAY = 0.2
"""Seconds after the last keystroke before a panel applies what was typed (one rebuild per pause, not
one per key; short enough that the frame seems to follow the fingers)."""


def running_loop() -> asyncio.AbstractEventLoop | None:
    """The kernel's asyncio loop when there is one (in Jupyter), else None (a script, a test)."""
    try:
        return asyncio.get_running_loop()
    except RuntimeError:
        return None


def from_the_page(change: dict[str, Any]) -> bool:
    """Whether a value change came from the page (the learner) rather than from code.

    ipywidgets applies a change sent by the browser inside ``set_state``, with the trait named in the
    widget's property lock (the lock that keeps the kernel from echoing the value back); a value set
    from Python is not locked."""
    owner = change.get("owner")
    return change.get("name") in (getattr(owner, "_property_lock", None) or {})


class Typing:
    """Apply a panel's fields a moment (:data:`TYPING_DELAY`) after the learner's last keystroke.

    ``changed`` is the observer of the panel's inputs.  Text typed in the page waits for a pause in the
    typing, on the kernel's asyncio loop; any other change -- a value set from code, a dropdown chosen --
    applies at once, together with anything still waiting.  Without a running loop (a script, a
    headless test) typed text applies at once too.  Deterministic for tests: :meth:`flush` applies what
    waits now, and :attr:`pending` says whether anything does.  ``apply`` holds no protocol logic of its
    own: it is the panel's ``update``.
    """

    def __init__(self, apply: Callable[[], Any], delay: float = TYPING_DELAY) -> None:
        self.apply = apply
        self.delay = delay
        self._timer: asyncio.TimerHandle | None = None

    @property
    def pending(self) -> bool:
        """True while typed text waits for the pause."""
        return self._timer is not None

    def changed(self, change: dict[str, Any]) -> None:
        if from_the_page(change) and isinstance(change.get("owner"), (W.Text, W.Textarea)):
            self.schedule()
        else:
            self.cancel()
            self.apply()

    def schedule(self) -> None:
        """(Re)start the wait: the panel applies ``delay`` seconds from now, unless typing goes on."""
        self.cancel()
        loop = running_loop()
        if loop is None:
            self.apply()
            return
        self._timer = loop.call_later(self.delay, self._fire)

    def _fire(self) -> None:
        self._timer = None
        self.apply()

    def cancel(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None

    def flush(self) -> bool:
        """Apply what waits now; returns whether anything did."""
        if self._timer is None:
            return False
        self.cancel()
        self.apply()
        return True
