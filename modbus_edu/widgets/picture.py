"""The picture of a panel: static HTML of what it shows, for a notebook read without running it.

A saved notebook keeps no widget state (:func:`modbus_edu.course.strip_widget_state`), so on GitHub, on
nbviewer, or in JupyterLab before Run All, a panel's output falls back from the live widget to the next
representation of its mimebundle.  :func:`picture` draws that representation: the panel's own widget
tree walked once -- its fields with the text they hold, its buttons, its tabs, and the HTML views
(frame, dissection, CRC steps) exactly as the library wrote them -- as inert HTML: no scripts, no
inputs, nothing that pretends to respond.  A label above it says "run this cell to use it".

Nothing here knows Modbus: it only turns widgets into HTML.  The picture is of the panel as its cell left
it, so a re-executed notebook stores the same picture every time (strict nbval compares it).
"""

from __future__ import annotations

from typing import Any

import ipywidgets as W

from .common import PlotImage, esc

__all__ = ["RUN_TO_USE", "StaticView", "picture", "panel_picture"]

#: What a panel's picture and its text say: it is not live yet.
RUN_TO_USE = "run this cell to use it"

_FIELD = ("display:inline-block;min-width:3em;padding:2px 6px;border:1px solid #adb5bd;border-radius:2px;"
          "background:#f8f9fa;color:#212529;font-family:var(--jp-code-font-family, monospace);"
          "white-space:pre;overflow:hidden;text-overflow:ellipsis;vertical-align:middle;box-sizing:border-box")
_BUTTON = ("display:inline-block;padding:2px 10px;margin:2px;border:1px solid #ced4da;border-radius:2px;"
           "background:#e9ecef;color:#495057;white-space:nowrap")
_INLINE = "display:inline-block;vertical-align:middle;max-width:100%"
_LABEL = "display:inline-block;text-align:right;padding-right:6px;white-space:nowrap;vertical-align:middle"


def _hidden(widget: W.Widget) -> bool:
    layout = getattr(widget, "layout", None)
    return layout is not None and (layout.display == "none" or layout.visibility == "hidden")


def _label(widget: W.Widget) -> str:
    """The description in front of a control, as wide as the control's own label."""
    text = getattr(widget, "description", "")
    style = getattr(widget, "style", None)
    width = getattr(style, "description_width", "") or ""
    if not text or width == "0px":  # a label that takes no room on screen (for screen readers) neither
        return ""
    return f'<span style="{_LABEL};{f"width:{esc(width)}" if width else ""}">{esc(text)}</span>'


def _width(widget: W.Widget) -> str:
    width = getattr(getattr(widget, "layout", None), "width", None)
    return f"width:{esc(width)};max-width:100%;" if width else ""


def _px(value: str | None) -> int | None:
    """``"230px"`` -> 230; anything else (``"auto"``, ``"50%"``, ``None``) -> None."""
    if value and value.endswith("px") and value[:-2].isdigit():
        return int(value[:-2])
    return None


def _field(widget: W.Widget, text: str, placeholder: str = "") -> str:
    """A control's label and the text it holds (or its placeholder, greyed), in an inert box."""
    layout = widget.layout
    border = f"border:{esc(layout.border)};" if layout.border else ""
    shown = esc(text) if text else f'<span style="color:#adb5bd">{esc(placeholder)}</span>'
    total = _px(layout.width)
    label = _px(getattr(getattr(widget, "style", None), "description_width", None)) or 0
    width = f"width:{total - label - 10}px;" if total and total - label > 40 else ""
    box = f'<span class="mbe-picture-field" style="{_FIELD};{border}{width}">{shown or "&nbsp;"}</span>'
    return f'<span style="{_INLINE};margin:2px;{_width(widget)}">{_label(widget)}{box}</span>'


def _options(widget: W.Widget) -> list[tuple[str, Any]]:
    """``(label, value)`` of each option of a selection widget (options given as pairs or as values)."""
    return [(str(o[0]), o[1]) if isinstance(o, tuple) else (str(o), o) for o in widget.options]


def _box(widget: W.Box) -> str:
    """A box of widgets: a column stacks them (blocks), a row lines them up and wraps (inline blocks).

    Only plain block and inline-block layout: sanitizers (JupyterLab's for an untrusted notebook,
    GitHub's) drop most flexbox properties, and the picture must still read in the right order."""
    layout = widget.layout
    column = isinstance(widget, W.VBox) or "column" in (layout.flex_flow or "")
    styles = ["max-width:100%"]
    for name in ("border", "padding", "margin", "width", "max_height"):
        value = getattr(layout, name, None)
        if value and not (name == "width" and value.endswith("%")):
            styles.append(f"{name.replace('_', '-')}:{esc(value)}")
    if layout.max_height:
        styles.append("overflow:hidden")
    children = [picture(child) for child in widget.children]
    if column:
        inner = "".join(f"<div>{c}</div>" for c in children if c)
    else:
        inner = "".join(f'<span style="{_INLINE}">{c}</span>' for c in children if c)
    return f'<div style="{";".join(styles)}">{inner}</div>'


def _tab(widget: W.Tab) -> str:
    """The tab titles, the open one marked, and the open tab's content."""
    index = widget.selected_index or 0
    titles = []
    for i, title in enumerate(widget.titles):
        mark = ("border-bottom:2px solid #1976d2;font-weight:600" if i == index
                else "color:#5c636a")
        titles.append(f'<span style="display:inline-block;padding:3px 12px;{mark}">{esc(title)}</span>')
    content = picture(widget.children[index]) if widget.children else ""
    return (f'<div style="border-bottom:1px solid #dee2e6">{"".join(titles)}</div>'
            f'<div style="padding:6px 8px">{content}</div>')


def picture(widget: W.Widget) -> str:
    """Static, inert HTML of one widget and everything in it (hidden widgets are left out)."""
    if _hidden(widget):
        return ""
    if isinstance(widget, (W.Image, PlotImage)):
        return ('<div style="padding:24px;margin:2px;border:1px dashed #adb5bd;color:#5c636a;'
                'text-align:center">the plot is drawn when the cell runs</div>')
    if isinstance(widget, W.Tab):
        return _tab(widget)
    if isinstance(widget, W.Box):
        return _box(widget)
    if isinstance(widget, (W.HTML, W.HTMLMath)):
        return f'<div style="max-width:100%;overflow:hidden">{widget.value}</div>' if widget.value else ""
    if isinstance(widget, W.Label):
        return f"<span>{esc(widget.value)}</span>"
    if isinstance(widget, W.Button):
        return f'<span class="mbe-picture-button" style="{_BUTTON}">{esc(widget.description)}</span>'
    if isinstance(widget, W.Checkbox):
        mark = "&#9745;" if widget.value else "&#9744;"
        return (f'<span style="margin:2px 8px 2px 2px;white-space:nowrap">{mark} '
                f"{esc(widget.description)}</span>")
    if isinstance(widget, W.ToggleButtons):
        buttons = []
        for label, value in _options(widget):
            chosen = "background:#1976d2;color:white;border-color:#1976d2" if value == widget.value else ""
            buttons.append(f'<span style="{_BUTTON};{chosen}">{esc(label)}</span>')
        return f'<div style="margin:2px">{"".join(buttons)}</div>'
    if isinstance(widget, (W.Dropdown, W.Select, W.RadioButtons)):
        return _field(widget, f"{widget.label if widget.label is not None else ''}  \u25be")
    if hasattr(widget, "value") and hasattr(widget, "description"):  # text and number boxes
        return _field(widget, str(widget.value), getattr(widget, "placeholder", ""))
    return ""


def panel_picture(panel: W.Widget, what: str) -> str:
    """A panel's picture under its label: what the panel is, and "run this cell to use it"."""
    note = (f'<div class="mbe-picture-label" style="padding:3px 8px;margin-bottom:4px;background:#fff9db;'
            f'border-left:4px solid #fab005;font-size:0.95em">&#9654; <b>{esc(what)}</b> &mdash; a picture '
            f"of the panel as its cell left it: {RUN_TO_USE}</div>")
    return (f'<div class="mbe-picture" style="max-width:100%;overflow-x:auto">{note}'
            f'<div style="opacity:0.85">{picture(panel)}</div></div>')


class StaticView:
    """Mixin for a panel: what its output keeps in a saved notebook, beside the live widget.

    A panel's mimebundle holds three representations: the widget view (the live panel, which JupyterLab
    and Notebook 7 prefer whenever the widget exists), ``text/html`` (its :func:`picture`, under the
    label "run this cell to use it") and ``text/plain`` (what the panel is, and the same words).  The
    course saves no widget state (:func:`modbus_edu.course.strip_widget_state` drops the view), so a
    notebook read without running it -- on GitHub, on nbviewer, before Run All -- shows the picture,
    never controls that ignore input.  ``repr()`` stays the live summary for code and tests.
    """

    def static_text(self) -> str:
        """What this panel is, in a few words (each panel says its own)."""
        return type(self).__name__

    def static_html(self) -> str:
        """The labelled picture of the panel as it is now."""
        return panel_picture(self, self.static_text())  # type: ignore[arg-type]

    def _repr_mimebundle_(self, **kwargs: Any) -> Any:
        data = super()._repr_mimebundle_(**kwargs)  # type: ignore[misc]
        if isinstance(data, dict) and "text/plain" in data:
            data["text/plain"] = f"[{self.static_text()}: {RUN_TO_USE}]"
            data["text/html"] = self.static_html()
        return data
