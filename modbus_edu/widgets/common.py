"""What the panels share: colours, the message line, reading numbers typed by people, coloured frames,
and following the typing (:class:`Typing`).

Nothing here knows Modbus.  The panels ask the library for every byte and every field boundary
(:func:`modbus_edu.explain.explain` rows); this module only turns text into numbers and rows into
coloured HTML.
"""

from __future__ import annotations

import asyncio
import base64
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
    "PANEL_CLASSES",
    "PANEL_CSS",
    "panel_style",
    "PANEL_SCRIPT",
    "scroll_box",
    "live",
    "focus_after_click",
    "PlotImage",
    "FIELD_NUMBER_STYLE",
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
        raise ValueFormatError(f"{name}: expected a whole number, got {shown_value(text)}")
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
    "ok": "color: #2b6e35",
    "warn": "color: #9c4a00",
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
        live(self)

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


#: The field number in front of a field's bytes and in its legend chip: dark on every palette colour.
FIELD_NUMBER_STYLE = "font-size:0.7em;color:#343a40;margin-right:2px"


def frame_html(dissection: Any) -> str:
    """The frame's bytes (ASCII: characters), each field on its own colour, with a tooltip per field.

    Colour is never the only sign: each field's bytes start with the field's number, which its legend
    chip carries too (:func:`legend_html`), and the tooltip names the field.  Field boundaries come from
    ``dissection.rows`` (offset, raw bytes, field name, meaning); a row that breaks a rule is underlined
    in red (and its rule is said in words in the dissection).
    """
    rows = list(dissection.rows)
    colours = field_colours(rows)
    spans = []
    for number, (row, colour) in enumerate(zip(rows, colours), 1):
        border = "border-bottom: 3px solid #c92a2a;" if not getattr(row, "ok", True) else ""
        title = f"{row.field}: {row.meaning}" if row.meaning else row.field
        spans.append(
            f'<span class="mbe-field" title="{esc(title)}" style="background:{colour};{border}'
            f'padding:2px 4px;margin-right:3px;border-radius:4px"><sup class="mbe-field-number" '
            f'style="{FIELD_NUMBER_STYLE}">{number}</sup>{esc(dissection.raw_text(row))}</span>'
        )
    return (f'<div class="mbe-frame-bytes" style="{MONO}; font-size: 1.15em; line-height: 2em">'
            f'{"".join(spans)}</div>')


def legend_html(dissection: Any) -> str:
    """A legend: per row, a chip in the field's colour holding the field's number, and the field's name
    (the number ties the name to the bytes in :func:`frame_html` without relying on colour)."""
    rows = list(dissection.rows)
    items = []
    for number, (row, colour) in enumerate(zip(rows, field_colours(rows)), 1):
        items.append(
            f'<span class="mbe-legend-item" style="display:inline-block;margin:0 10px 2px 0;'
            f'white-space:nowrap"><span style="display:inline-block;min-width:0.9em;padding:0 3px;'
            f'background:{colour};border:1px solid #999;border-radius:3px;text-align:center;'
            f'vertical-align:middle;margin-right:4px;{FIELD_NUMBER_STYLE.split(";margin")[0]}">{number}</span>'
            f'{esc(row.field)}</span>'
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


#: Greyed, yet still readable (WCAG AA contrast): the colours go, a dashed frame goes round it.  No
#: opacity: it would lighten the panels' grey text (#5c636a, 6:1 on white) below 4.5:1.
STALE_STYLE = "filter:grayscale(1);outline:1px dashed #5c636a;outline-offset:2px"


def stale_html(content: str) -> str:
    """The last good content of a view, greyed out while the input it came from does not read."""
    if not content or "mbe-stale" in content:
        return content
    return (f'<div class="mbe-stale" title="the last good result: fix the marked field" '
            f'style="{STALE_STYLE}">{content}</div>')


def mark_invalid(widget: W.DOMWidget, invalid: bool, message: W.DOMWidget | None = None) -> None:
    """Mark an input red (class ``mbe-invalid``) while what it holds does not read, unmark it after.

    In the page the input is then ``aria-invalid``, and ``message`` (the view that says what is wrong)
    is its ``aria-describedby``: a screen reader says "invalid" and the reason, not only a red border
    (:data:`PANEL_SCRIPT` sets the attributes, which ipywidgets cannot set from Python)."""
    if invalid:
        widget.add_class("mbe-invalid")
    else:
        widget.remove_class("mbe-invalid")
    described = f"mbe-described-{message.model_id}" if message is not None else None
    if message is not None and described not in widget._dom_classes:  # once: no message to the page after
        message.add_class(f"mbe-says-{message.model_id}")
        widget._dom_classes = tuple(c for c in widget._dom_classes if not c.startswith("mbe-described-")) + (
            described,)
    widget.layout.border = "2px solid #c92a2a" if invalid else None


# --- what every panel needs to be usable by everyone ---------------------------------------------------
#: The panels' classes (each panel's outermost box carries its own).
PANEL_CLASSES = ("mbe-framebuilder", "mbe-framedecoder", "mbe-crcexplorer", "mbe-testtool",
                 "mbe-meterdashboard")


def _in_panels(selector: str) -> str:
    return ", ".join(f".{panel} {part.strip()}" for panel in PANEL_CLASSES for part in selector.split(","))


#: The stylesheet of the live panels: a focus ring anyone can see on every control reached with the
#: keyboard (JupyterLab's own is a 1 px light-blue border), and tab titles dark enough to read (WCAG AA).
PANEL_CSS = (
    "<style>"
    + _in_panels(":focus-visible, input:focus, select:focus, textarea:focus")
    + " {outline: 2px solid #1864ab !important; outline-offset: 1px}"
    # ... never cut off: ipywidgets' boxes clip what overflows them (overflow: auto), and a control at a
    # box's edge lost the ring's top and bottom; the boxes made to scroll say so in their own layout
    + ", ".join(f".{panel}" for panel in PANEL_CLASSES) + ", " + _in_panels(".widget-box")
    + " {overflow: visible}"
    + _in_panels(".widget-checkbox .widget-label-basic") + " {padding-left: 4px}"
    + _in_panels(".lm-TabBar-tab") + " {color: var(--jp-ui-font-color1, #212529) !important}"
    # ipywidgets' coloured buttons carry white text on light colours: darker ones, the same hues
    + _in_panels(".jupyter-button.mod-primary, .jupyter-button.mod-info") + " {background-color: #1864ab}"
    + _in_panels(".jupyter-button.mod-success") + " {background-color: #2b6e35}"
    + _in_panels(".jupyter-button.mod-warning") + " {background-color: #9c4a00}"
    + _in_panels(".jupyter-button.mod-danger") + " {background-color: #b02525}"
    # a number field typed out of its range (PANEL_SCRIPT): red, and the reason on a line under it
    + _in_panels(".mbe-number-invalid") + " {flex-wrap: wrap; height: auto}"
    + _in_panels(".mbe-number-invalid > input") + " {border: 2px solid #c92a2a !important}"
    + _in_panels(".mbe-number-error") + " {flex: 0 0 100%; color: #c92a2a; font-weight: 600;"
    " font-size: 0.9em; line-height: 1.3; white-space: normal; margin: 2px 0}"
    + "</style>"
)


#: What a panel needs in the page that ipywidgets 8.1 cannot say from Python (its controls carry no ARIA
#: attribute, and a widget sets no attribute of its own on its element).  It runs once per view of the
#: panel, on the panel's outermost element, and again whenever the panel's DOM changes:
#:
#: * the panel keeps its keys: a key pressed in it goes no further than the panel, with or without Ctrl,
#:   Alt, Shift or Meta, so JupyterLab's shortcuts (Lumino's keymap listens on the document, in the
#:   bubbling phase) never see it: ↓ changes a dropdown and scrolls a log instead of moving to the next
#:   cell, "m" on a button does not turn the panel's cell into Markdown, Ctrl+Backspace does not merge
#:   the cell into the one above, Ctrl+Enter and Alt+Enter do not run it again, Ctrl+Shift+↓ does not move
#:   it.  The control's own handling and the browser's default action still happen (Ctrl+C, Ctrl+V and
#:   Ctrl+A in a text field), except that Ctrl+A outside a text field selects nothing (not the whole
#:   page).  Two keys go on: Ctrl+S (Cmd+S, with or without Shift) saves the notebook, and Escape leaves
#:   the panel: the focus goes back to the panel's cell, in command mode, where every shortcut works.
#:   (Lumino's ``data-lm-suppress-shortcuts`` would have to sit on every focused control itself -- the
#:   keymap matches the notebook's ``... :focus`` selector on the control before it reaches an ancestor --
#:   and it would silence Ctrl+S too.);
#: * a number field typed out of its range (a unit of 300 where 0 to 255 are allowed) is refused, not
#:   clamped: the change does not reach ipywidgets (which would silently make it 255), and the field is
#:   ``aria-invalid``, described by a line under it that says what it takes and which value is still
#:   used.  A field back in range is sent and unmarked;
#: * ``aria-hidden`` on the FontAwesome ``<i>`` of a button (its glyph, U+F0xx, is not a word: without
#:   it a button is named "\uf019 read once");
#: * ``aria-pressed`` on each button of a ToggleButtons (from its ``mod-active`` class), and the group
#:   ``role=group`` named by its description;
#: * ``role=region`` and a name (the tooltip) on each :func:`scroll_box`;
#: * ``role=status`` (``aria-live=polite``) on each :func:`live` view, so that a result or an error
#:   that appears is read out;
#: * ``aria-invalid`` and ``aria-describedby`` on the input of a field :func:`mark_invalid` marks.
#:
#: It rides on an ``<img>`` that never loads (its ``onerror``): ipywidgets writes an HTML widget's value
#: as ``innerHTML``, where a ``<script>`` does not run but an event attribute does.
PANEL_SCRIPT = r"""
(function (img) {
  var sel = '__PANELS__', tries = 0;
  function ids(el) {
    if (!el.id) { window.mbeIds = (window.mbeIds || 0) + 1; el.id = 'mbe-a11y-' + window.mbeIds; }
    return el.id;
  }
  function set(el, name, value) {
    if (value === null) { if (el.hasAttribute(name)) el.removeAttribute(name); }
    else if (el.getAttribute(name) !== value) el.setAttribute(name, value);
  }
  function each(root, css, fn) { root.querySelectorAll(css).forEach(fn); }
  function label(panel) {
    each(panel, 'i.fa', function (i) { set(i, 'aria-hidden', 'true'); });
    each(panel, '.widget-toggle-buttons', function (g) {
      set(g, 'role', 'group');
      var l = g.querySelector(':scope > .widget-label');
      if (l && l.textContent.trim()) set(g, 'aria-labelledby', ids(l));
    });
    each(panel, '.widget-toggle-button', function (b) {
      set(b, 'aria-pressed', String(b.classList.contains('mod-active')));
    });
    each(panel, '.mbe-scroll', function (w) {  // the widget's element scrolls and takes the focus
      var l = w.querySelector(':scope > .widget-label');
      set(w, 'role', 'region');
      set(w, 'aria-label', l && l.title ? l.title : null);
    });
    each(panel, '.mbe-live > .widget-html-content', function (c) {
      if (!c.parentElement.classList.contains('mbe-scroll')) set(c, 'role', 'status');  // else a region
      set(c, 'aria-live', 'polite'); set(c, 'aria-atomic', 'true');
    });
    each(panel, '[class*="mbe-described-"]', function (w) {
      var input = w.querySelector('input, textarea, select');
      if (!input) return;
      var bad = w.classList.contains('mbe-invalid'), token = null;
      w.classList.forEach(function (c) { if (c.indexOf('mbe-described-') === 0) token = c.slice(14); });
      var says = token && panel.querySelector('.mbe-says-' + token + ' > .widget-html-content');
      set(input, 'aria-invalid', bad ? 'true' : null);
      set(input, 'aria-describedby', bad && says ? ids(says) : null);
    });
    each(panel, '.mbe-number-invalid > input', number);
  }
  function editable(el) {
    return el.isContentEditable || el.tagName === 'TEXTAREA' || (el.tagName === 'INPUT'
      && ['button', 'checkbox', 'radio', 'range', 'color', 'file', 'submit', 'reset'].indexOf(el.type) < 0);
  }
  function number(el) {  // a number field out of its range, or holding no number: say why, under it
    var v = el.validity, w = el.parentElement, note = w.querySelector(':scope > .mbe-number-error');
    var bad = v.rangeOverflow || v.rangeUnderflow || v.stepMismatch || v.badInput || v.valueMissing;
    if (!bad) {
      if (note) { note.remove(); w.classList.remove('mbe-number-invalid'); }
      set(el, 'aria-invalid', null); set(el, 'aria-describedby', null);
      return false;
    }
    if (!note) {
      note = document.createElement('div'); note.className = 'mbe-number-error';
      set(note, 'role', 'status'); set(note, 'aria-live', 'polite');
      w.appendChild(note); w.classList.add('mbe-number-invalid');
    }
    var range = el.min !== '' && el.max !== '' ? el.min + ' to ' + el.max
      : el.min !== '' ? el.min + ' or more' : el.max !== '' ? el.max + ' or less' : 'a number';
    var kept = el.dataset.mbeKept ? '; still ' + el.dataset.mbeKept : '';
    var text = '\u26a0 ' + (v.rangeOverflow ? range + ' only: ' + el.value + ' is too large' + kept
      : v.rangeUnderflow ? range + ' only: ' + el.value + ' is too small' + kept
      : v.stepMismatch ? 'steps of ' + el.step + ' from ' + (el.min || 0) + ': '
                         + el.value + ' is between two'
      : 'type a number, ' + range);
    if (note.textContent !== text) note.textContent = text;
    set(el, 'aria-invalid', 'true'); set(el, 'aria-describedby', ids(note));
    return true;
  }
  function leave(panel, e) {  // Escape: back to the panel's cell, in command mode
    var cell = panel.closest('.jp-Cell');
    if (!cell) return;
    e.preventDefault(); e.stopPropagation();
    if (document.activeElement && document.activeElement.blur) document.activeElement.blur();
    cell.focus();
  }
  function keep() {
    var panel = img.closest(sel);
    if (!panel) { if (tries++ < 200) setTimeout(keep, 50); return; }
    label(panel);
    if (panel.mbeObserver) return;
    panel.addEventListener('keydown', function (e) {
      var accel = e.ctrlKey || e.metaKey, letter = (e.key || '').toLowerCase();
      if (accel && !e.altKey && letter === 's') return;  // save: JupyterLab's, as everywhere
      e.stopPropagation();
      if (accel && !e.altKey && letter === 'a' && !editable(e.target)) e.preventDefault();
    });
    panel.addEventListener('keydown', function (e) {  // first: ipywidgets' text fields stop their keys
      if (e.key === 'Escape') leave(panel, e);
    }, true);
    panel.addEventListener('focusin', function (e) {
      var t = e.target;
      if (t.type === 'number' && t.checkValidity()) t.dataset.mbeKept = t.value;
    });
    panel.addEventListener('input', function (e) { if (e.target.type === 'number') number(e.target); }, true);
    panel.addEventListener('change', function (e) {  // before ipywidgets' own handler, which clamps
      var t = e.target;
      if (t.type !== 'number') return;
      var v = t.validity;
      if (v.rangeOverflow || v.rangeUnderflow) { e.stopPropagation(); number(t); return; }
      if (!number(t)) t.dataset.mbeKept = t.value;
    }, true);
    panel.mbeObserver = new MutationObserver(function () { label(panel); });
    panel.mbeObserver.observe(panel, {subtree: true, childList: true, attributes: true,
                                      attributeFilter: ['class', 'title', 'min', 'max', 'step']});
  }
  keep();
})(this)
"""


def panel_style() -> W.HTML:
    """The panels' stylesheet and :data:`PANEL_SCRIPT`, as a hidden child of a panel (hidden: the
    picture leaves it out)."""
    script = PANEL_SCRIPT.replace("__PANELS__", ", ".join(f".{c}" for c in PANEL_CLASSES))
    hook = f'<img class="mbe-panel-script" alt="" src="data:," onerror="{html.escape(script.strip())}">'
    style = W.HTML(PANEL_CSS + hook, layout=W.Layout(display="none"))
    style.add_class("mbe-panel-style")
    return style


def scroll_box(widget: W.DOMWidget, name: str) -> W.DOMWidget:
    """Make a view that scrolls reachable with the keyboard (Tab to it, then the arrow keys scroll it:
    the panel keeps its keys from the notebook, see :data:`PANEL_SCRIPT`); ``name`` is its tooltip,
    what it holds, which the page also gives it as its name (a region a screen reader announces).
    An HTML view, not a Box: ipywidgets 8.1 makes no Box tabbable and draws none with a tooltip."""
    widget.tabbable = True
    widget.tooltip = name
    widget.add_class("mbe-scroll")
    return widget


def live(widget: W.DOMWidget) -> W.DOMWidget:
    """Make an HTML view a polite live region (``role=status``, set in the page by
    :data:`PANEL_SCRIPT`): a screen reader reads what it comes to say -- a result, an error -- without
    the learner moving there.  For short views whose change is news; not for logs or tables."""
    widget.add_class("mbe-live")
    return widget


def focus_after_click(button: W.Button, then: W.DOMWidget) -> None:
    """When a click from the page leaves ``button`` disabled ("run to end" at the end, "start" while
    running), move the keyboard focus to ``then`` (the control that comes next, say "stop"): a disabled
    button drops the focus to the page's body and a keyboard user loses their place.  A click made from
    code (``button.click()``) moves no focus: the learner may be typing in another cell."""

    def moved(_widget: W.Widget, content: dict[str, Any], _buffers: Any) -> None:
        if content.get("event") == "click" and button.disabled and not getattr(then, "disabled", False):
            then.focus()

    button.on_msg(moved)  # after the Button's own handler, which ran the click


class PlotImage(W.HTML):
    """A PNG picture with a text alternative (``alt``), which ipywidgets' Image cannot carry (and it
    draws no Image with a tooltip).  ``show(png, alt)`` puts a new picture in; ``.png`` is its bytes.
    ``css`` is the class of the <img> itself."""

    def __init__(self, alt: str, css: str, width: str = "900px", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.png = b""
        self.alt = alt
        self.css = css
        self.width = width

    def show(self, png: bytes, alt: str | None = None) -> None:
        self.png = png
        if alt is not None:
            self.alt = alt
        data = base64.b64encode(png).decode("ascii")
        self.value = (f'<img class="{esc(self.css)}" alt="{esc(self.alt)}" '
                      f'src="data:image/png;base64,{data}" '
                      f'style="width:{esc(self.width)};max-width:100%;height:auto;object-fit:contain">')


# --- small widget factories ----------------------------------------------------------------------
#: A field's widest: its box, less ipywidgets' margins (2 px a side), so that at 200% zoom it shrinks with
#: the panel instead of running past it (WCAG 1.4.10).
NARROW = "calc(100% - 4px)"


def text_field(description: str, value: str = "", css: str | None = None, width: str = "230px",
               placeholder: str = "", tooltip: str = "") -> W.Text:
    """A labelled text box (``css`` adds a class for browser tests, e.g. ``mbe-field-address``).

    It sends its text at every keystroke (``continuous_update``); the panel applies it a moment after
    the last one (:class:`Typing`), so the frame follows the typing without Enter or Tab."""
    box = W.Text(value=value if isinstance(value, str) else shown_value(value), description=description,
                 placeholder=placeholder,
                 style={"description_width": "110px"}, layout=W.Layout(width=width, max_width=NARROW),
                 continuous_update=True)
    if tooltip:
        box.tooltip = tooltip
    if css:
        box.add_class(css)
    return box


def dropdown(description: str, options: Any, value: Any = None, css: str | None = None,
             width: str = "230px") -> W.Dropdown:
    kwargs: dict[str, Any] = {"options": options, "description": description,
                              "style": {"description_width": "110px"},
                              "layout": W.Layout(width=width, max_width=NARROW)}
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
