"""The panels for everyone, headless: every control carries a label a screen reader reads,
the coloured bytes keep a text label, and the colours the panels write pass WCAG AA contrast (4.5:1 for
text).  The browser test (tests/test_browser.py) runs axe-core and the keyboard on the same panels.
"""

from __future__ import annotations

import html
import re

import ipywidgets as W
import pytest

from modbus_edu.widgets import CrcExplorer, FrameBuilder, FrameDecoder, MeterDashboard, TestTool
from modbus_edu.widgets.common import (
    PALETTE,
    PANEL_CLASSES,
    PANEL_CSS,
    PANEL_SCRIPT,
    MessageLine,
    frame_html,
    legend_html,
    message_html,
    panel_style,
    stale_html,
)
from modbus_edu.widgets.testtool.controls import ROLES

#: A widget a person types into or chooses with: it must say what it is.
INPUTS = (W.Text, W.Textarea, W.Dropdown, W.IntText, W.FloatText, W.BoundedIntText, W.BoundedFloatText,
          W.Checkbox, W.ToggleButtons, W.Select, W.RadioButtons, W.IntSlider, W.FloatSlider)


def _panels():
    slave = TestTool(role="rtu_slave", unit=1, length=4)
    master = TestTool(role="rtu_master", partner=slave, unit=1, length=4)
    from modbus_edu.devices import PowerMeter

    return {
        "frame builder": FrameBuilder(mode="rtu", unit=1, function=16, address=1, values="10, 0x0102"),
        "frame decoder": FrameDecoder("01 03 00 00 00 01 84 0B"),
        "CRC explorer": CrcExplorer("01 03 00 00 00 01"),
        "test tool (RTU master)": master,
        "test tool (RTU slave)": slave,
        "TCP server": TestTool(role="tcp_server", unit=1, length=4),
        "meter dashboard": MeterDashboard(PowerMeter(unit=1, trial=1)),
    }


def _walk(widget):
    """The widget and everything in it (boxes and tabs), hidden ones included."""
    yield widget
    for child in getattr(widget, "children", ()) or ():
        yield from _walk(child)


# --- contrast (WCAG 2.1, 1.4.3) ------------------------------------------------------------------------
def _luminance(colour: str) -> float:
    rgb = [int(colour.lstrip("#")[i:i + 2], 16) / 255 for i in (0, 2, 4)]
    lin = [c / 12.92 if c <= 0.03928 else ((c + 0.055) / 1.055) ** 2.4 for c in rgb]
    return 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]


def contrast(a: str, b: str) -> float:
    hi, lo = sorted((_luminance(a), _luminance(b)), reverse=True)
    return (hi + 0.05) / (lo + 0.05)


def test_the_contrast_formula_is_wcag_s():
    assert contrast("#000000", "#ffffff") == pytest.approx(21.0)
    assert contrast("#777777", "#ffffff") == pytest.approx(4.48, abs=0.01)  # the classic just-fails grey


#: The backgrounds text sits on: the page, the test tool's role colours, JupyterLab's tab bar.
BACKGROUNDS = ["#ffffff", "#eeeeee", *(r.background for r in ROLES.values())]


@pytest.mark.parametrize("kind", ["info", "ok", "warn", "error"])
def test_message_colours_pass_aa_on_every_panel_background(kind):
    colours = re.findall(r"color: (#[0-9a-fA-F]{6})", message_html("x", kind))
    for colour in colours:
        for background in BACKGROUNDS:
            assert contrast(colour, background) >= 4.5, (kind, colour, background)


def test_every_text_colour_the_panels_write_passes_aa():
    """Every ``color:#rrggbb`` in every panel's HTML (messages, counters, grid heads, status lines, the
    CRC steps, the dashboard's raw column) reads at 4.5:1 or better on the panel's background."""
    seen = set()
    for name, panel in _panels().items():
        background = getattr(getattr(panel, "layout", None), "background", None) or "#ffffff"
        for widget in _walk(panel):
            for colour in re.findall(r"(?<![-\w])color:\s*(#[0-9a-fA-F]{6})\b", getattr(widget, "value", "")
                                     if isinstance(widget, W.HTML) else ""):
                seen.add(colour)
                assert contrast(colour, "#ffffff") >= 4.5, (name, colour)
                if background.startswith("#") and len(background) == 7:
                    assert contrast(colour, background) >= 4.5, (name, colour, background)
    assert len(seen) >= 3  # the walk found the panels' coloured text


def test_bytes_on_their_field_colours_read_at_aa_contrast():
    for colour in PALETTE:
        assert contrast("#212529", colour) >= 4.5, colour  # the body text JupyterLab writes them in
        assert contrast("#343a40", colour) >= 4.5, colour  # the field numbers


# --- labels --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", list(_panels()))
def test_every_control_says_what_it_is(name):
    """Each input carries a description (the <label> a screen reader reads with it, as plain text, not
    HTML) or at least a tooltip; each button a description or a tooltip; each image a tooltip (its
    title, which axe-core accepts as its text alternative)."""
    panel = _panels()[name]
    inputs = 0
    for widget in _walk(panel):
        if isinstance(widget, INPUTS):
            inputs += 1
            said = (getattr(widget, "description", "") or "").strip() or (widget.tooltip or "").strip()
            assert said, f"{name}: a {type(widget).__name__} without a label: {widget!r}"[:300]
            assert not getattr(widget, "description_allow_html", False), f"{name}: {widget.description}"
        elif isinstance(widget, W.Button):
            assert (widget.description or "").strip() or (widget.tooltip or "").strip(), f"{name}: {widget!r}"
        elif isinstance(widget, W.Image):
            raise AssertionError(f"{name}: ipywidgets' Image has no text alternative: use PlotImage")
    assert inputs > 0


@pytest.mark.parametrize("name", list(_panels()))
def test_every_panel_carries_the_focus_ring_stylesheet_hidden_from_its_picture(name):
    panel = _panels()[name]
    styles = [w for w in _walk(panel) if isinstance(w, W.HTML) and "mbe-panel-style" in w._dom_classes]
    assert len(styles) == 1 and styles[0].value.startswith(PANEL_CSS) and styles[0].layout.display == "none"
    assert any(c in panel._dom_classes for c in PANEL_CLASSES)
    picture = panel.static_html()
    assert "outline" not in picture  # the picture leaves the stylesheet out, and the script
    assert "onerror" not in picture and "mbe-panel-script" not in picture


def test_the_panel_script_rides_on_an_image_that_never_loads_and_finds_every_kind_of_panel():
    value = panel_style().value
    hooks = re.findall(r'<img class="mbe-panel-script" alt="" src="data:," onerror="([^"]+)">', value)
    assert len(hooks) == 1
    script = html.unescape(hooks[0])
    assert script == PANEL_SCRIPT.strip().replace("__PANELS__", ", ".join(f".{c}" for c in PANEL_CLASSES))
    for cls in PANEL_CLASSES:
        assert f".{cls}" in script
    # keys without a modifier stop at the panel (JupyterLab's shortcuts listen on the document)
    assert "stopPropagation" in script and "e.ctrlKey" in script and "'Escape'" in script
    for attribute in ("aria-hidden", "aria-pressed", "aria-live", "aria-invalid", "aria-describedby"):
        assert attribute in script


def test_the_stylesheet_draws_a_focus_ring_in_every_panel_and_darkens_the_tab_titles():
    for cls in PANEL_CLASSES:
        assert f".{cls} :focus-visible" in PANEL_CSS and f".{cls} .lm-TabBar-tab" in PANEL_CSS
    assert "outline: 2px solid" in PANEL_CSS


def test_boxes_that_scroll_can_be_reached_with_the_keyboard_and_say_what_they_hold():
    panels = _panels()
    master, dash, crc = panels["test tool (RTU master)"], panels["meter dashboard"], panels["CRC explorer"]
    for box in (master.tx_log, master.rx_log, crc.step_view, dash.table):
        assert isinstance(box, W.HTML) and box.tabbable is True and box.tooltip
        assert box.layout.overflow == "auto"
        assert "mbe-scroll" in box._dom_classes  # the page names it (a region) by its tooltip


@pytest.mark.parametrize("name", list(_panels()))
def test_what_comes_to_say_something_is_a_live_region(name):
    """Every message line, and the views whose change is news (a field's error, the CRC's step and
    result), are live regions in the page; logs and tables are not (they would talk without end)."""
    panel = _panels()[name]
    lines = [w for w in _walk(panel) if isinstance(w, MessageLine)]
    assert lines and all("mbe-live" in w._dom_classes for w in lines)
    live_views = [w for w in _walk(panel) if "mbe-live" in getattr(w, "_dom_classes", ())]
    if isinstance(panel, CrcExplorer):
        assert panel.result_view in live_views and panel.step_view in live_views
    if isinstance(panel, FrameBuilder):
        assert all(label in live_views for label in panel._error_labels.values())
    if isinstance(panel, TestTool):
        assert panel.tx_log not in live_views and panel.rx_log not in live_views


def test_a_field_that_does_not_read_is_described_by_the_view_that_says_why():
    fb = FrameBuilder(mode="rtu", unit=1, function=3, address=0, count=126)
    box, label = fb.count, fb._error_labels["count"]
    assert "mbe-invalid" in box._dom_classes and "quantity of registers is 126" in label.value
    assert f"mbe-described-{label.model_id}" in box._dom_classes
    assert f"mbe-says-{label.model_id}" in label._dom_classes
    fb.count.value = "1"
    assert "mbe-invalid" not in box._dom_classes
    described = [c for c in box._dom_classes if c.startswith("mbe-described-")]
    assert described == [f"mbe-described-{label.model_id}"]  # one, and kept: valid, it describes nothing
    decoder = FrameDecoder("01 0")
    assert "mbe-invalid" in decoder.text._dom_classes
    assert f"mbe-described-{decoder.message.model_id}" in decoder.text._dom_classes


def test_a_button_greyed_out_by_a_click_in_the_page_hands_the_focus_on():
    crc = CrcExplorer("01 03")
    focused = []
    crc.back.focus = lambda: focused.append("back")
    crc.next_bit.focus = lambda: focused.append("next bit")
    crc.run_to_end.click()  # from code: the learner may be typing elsewhere, no focus moves
    assert crc.run_to_end.disabled and focused == []
    crc.reset.click()
    crc.run_to_end._handle_custom_msg({"event": "click"}, [])  # the click as the page sends it
    assert crc.run_to_end.disabled and focused == ["back"]
    crc.back._handle_custom_msg({"event": "click"}, [])  # one step back: still enabled, focus stays
    assert not crc.back.disabled and focused == ["back"]
    crc.reset._handle_custom_msg({"event": "click"}, [])
    assert crc.reset.disabled and focused == ["back", "next bit"]


def test_the_grid_rows_scroll_together_not_each_on_its_own():
    slave = TestTool(role="rtu_slave", unit=1, length=12)
    rows = [r for r in slave.grid.children if isinstance(r, W.HBox)]
    assert len(rows) == 3 and "mbe-tt-grid-head" in rows[0]._dom_classes
    assert all(r.layout.overflow == "visible" and r.layout.flex == "0 0 auto" for r in rows)
    assert slave.grid.layout.overflow == "auto"


def test_the_plot_has_a_text_alternative_that_says_what_it_shows():
    from modbus_edu.devices import PowerMeter

    dash = MeterDashboard(PowerMeter(unit=1, trial=1))
    dash.run(3)
    alt = re.search(r'<img class="mbe-md-plot" alt="([^"]+)"', dash.image.value).group(1)
    assert "trend plot of" in alt and "3 readings" in alt
    assert dash.image.png == dash.plot_png and dash.plot_png.startswith(b"\x89PNG")
    assert "base64" not in dash.static_html() and "the plot is drawn when the cell runs" in dash.static_html()


# --- never colour alone ----------------------------------------------------------------------------------
def test_each_field_s_bytes_and_its_legend_chip_carry_the_same_number_and_the_legend_names_it():
    dissection = FrameBuilder(mode="rtu", unit=1, function=16, address=1, values="10, 0x0102").dissection
    rows = list(dissection.rows)
    frame, legend = frame_html(dissection), legend_html(dissection)
    numbers_in_frame = re.findall(r'<sup class="mbe-field-number"[^>]*>(\d+)</sup>', frame)
    assert numbers_in_frame == [str(i) for i in range(1, len(rows) + 1)]
    items = re.findall(r'class="mbe-legend-item".*?>(\d+)</span>([^<]+)</span>', legend)
    assert [int(n) for n, _ in items] == list(range(1, len(rows) + 1))
    assert [text for _, text in items] == [row.field.replace("'", "&#x27;") for row in rows]
    for row in rows:  # the tooltip of the bytes names the field too
        assert f'title="{row.field}' in frame.replace("&#x27;", "'")


def _through(colour: str, opacity: float) -> str:
    """``colour`` drawn at ``opacity`` on white."""
    rgb = [int(colour.lstrip("#")[i:i + 2], 16) for i in (0, 2, 4)]
    return "#" + "".join(f"{round(opacity * c + (1 - opacity) * 255):02x}" for c in rgb)


def test_a_stale_view_stays_readable_and_is_marked_by_more_than_colour():
    """Every text colour the panels write (the CRC explorer's grey bytes, #5c636a, the lightest) still
    reads at AA when a view is greyed out (the opacity, if any, of the stale style)."""
    html = stale_html("<b>frame</b>")
    found = re.search(r"opacity:([0-9.]+)", html)
    opacity = float(found.group(1)) if found else 1.0
    colours = {"#212529", "#5c636a"}  # JupyterLab's text, and the grey of bytes not reached yet
    for panel in _panels().values():
        for widget in _walk(panel):
            if isinstance(widget, W.HTML):
                colours |= set(re.findall(r"(?<![-\w])color:\s*(#[0-9a-fA-F]{6})\b", widget.value))
    for colour in colours:
        assert contrast(_through(colour, opacity), "#ffffff") >= 4.5, (colour, opacity)
    assert "dashed" in html and 'title="the last good result' in html
    assert "grayscale" in html  # greyed: the colours go


def test_the_decoder_marks_its_field_when_the_frame_breaks_a_rule_not_only_when_it_is_not_hex():
    decoder = FrameDecoder("01 03 00 00 00 01 84 0B")  # a wrong CRC
    assert "CRC" in decoder.message.text and decoder.message.kind == "error"
    assert "mbe-invalid" in decoder.text._dom_classes
    assert f"mbe-described-{decoder.message.model_id}" in decoder.text._dom_classes
    decoder.text.value = "01 03 00 00 00 01 84 0A"
    assert "mbe-invalid" not in decoder.text._dom_classes and decoder.message.kind == "ok"


def test_every_number_field_holds_its_default_on_its_step():
    """A browser marks a number field invalid when its value is off the grid min + k * step: each default
    must lie on it (or the step be "any": ``None``), or the field is invalid before anyone types."""
    for name, panel in _panels().items():
        for widget in _walk(panel):
            if isinstance(widget, (W.BoundedFloatText, W.BoundedIntText, W.FloatText, W.IntText)):
                step = getattr(widget, "step", None)
                if step is None:
                    continue
                low = getattr(widget, "min", 0) or 0
                ratio = (widget.value - low) / step
                assert abs(ratio - round(ratio)) < 1e-9, (name, widget.description, widget.value, low, step)


def test_the_panel_script_keeps_every_key_but_save_and_escape_leaves_the_panel():
    script = PANEL_SCRIPT
    keydown = script[script.index("panel.addEventListener('keydown', function (e) {\n      var accel"):]
    keydown = keydown[:keydown.index("});")]
    assert "letter === 's'" in keydown and "e.stopPropagation()" in keydown
    assert "!e.ctrlKey" not in keydown  # modifiers no longer let a key through
    assert "cell.focus()" in script and ".jp-Cell" in script
    assert "rangeOverflow" in script and "mbe-number-error" in script  # out of range: refused, described


def test_the_test_tool_s_lamps_say_on_or_off_by_shape_and_tooltip():
    slave = TestTool(role="rtu_slave", unit=1, length=4)
    master = TestTool(role="rtu_master", partner=slave, unit=1, length=4)
    assert "TX lamp off" in master.counters.value and "&#9675;" in master.counters.value
    master.poll_once()
    assert "TX lamp on" in master.counters.value and "RX lamp on" in master.counters.value
    assert "&#9675;" not in master.counters.value
