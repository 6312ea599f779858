"""The widgets in a real browser: JupyterLab + Debian's chromium (headless), driven by playwright.

What it proves that the headless tests cannot: the panels *render* as real DOM controls (the widget
manager loaded the ipywidgets JavaScript, the kernel's comm messages arrived), and a change made in the
page travels to the kernel and back (the frame shown changes).

Skipped, with the reason, when /usr/bin/chromium or playwright is missing -- unless the environment
variable ``CI`` is set (``.ci/run`` installs chromium): then a missing browser FAILS the test.
Screenshots go to tests/artifacts/ (gitignored), with panels.json: each panel's measured height per tab
and the typing latency.

The tests share one JupyterLab and one chromium (1400 x 900, as a learner's screen):

* the test notebook (tests/browser/widgets_test.ipynb): panels render and respond; the frame builder,
  frame decoder and CRC explorer follow the typing, key by key, without Enter (the latency from the
  last key to the new frame on screen is measured); an incomplete or invalid field shows its error
  beside the field, once;
* every course notebook with a panel, after Kernel > Restart Kernel and Run All Cells: each panel is
  controls (the live widget, not its static picture), at most 700 px tall in every tab, nothing
  clipped, no sideways overflow, logs that scroll both ways;
* a notebook executed by ``course.execute`` and opened without running: no widget state was saved, so
  no dead controls are drawn; each panel shows its static HTML picture, labelled "run this cell to use
  it";
* the panels for everyone, one test per panel of the test notebook (run once, in a page tall enough to
  hold a whole panel): axe-core (npm, pinned by package-lock.json; tests/browser/axe.py) injected into
  the page and run on the panel's DOM node in each of its tabs finds no violation of serious or critical
  impact (the counts by rule go to panels.json); and from the keyboard alone, Tab reaches every control
  with a visible focus ring, and Enter, the arrow keys or typing do the panel's main action.

No JavaScript console errors anywhere.  Every wait has an absolute timeout.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import sys
import time
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
NOTEBOOK = HERE / "browser" / "widgets_test.ipynb"
COURSE = HERE.parent / "notebooks"
ARTIFACTS = HERE / "artifacts"
CHROMIUM = "/usr/bin/chromium"
VIEWPORT = {"width": 1400, "height": 900}
RUN_ALL_TIMEOUT_S = 240  # one notebook's Restart & Run All on two shared cores, generous but absolute

sys.path.insert(0, str(HERE))
from browser import a11y, axe, lab_driver, panels  # noqa: E402
from browser.jupyter_harness import JupyterLab, copy_notebook  # noqa: E402

FIGURES: dict = {"panels": [], "typing_latency_ms": {}}
RUN_TO_USE = "run this cell to use it"


def _panel_notebooks() -> list[Path]:
    """The course notebooks that show a panel (they import modbus_edu.widgets)."""
    return sorted(p for p in COURSE.glob("[0-9][0-9]_*.ipynb") if "modbus_edu.widgets" in p.read_text())


def _save_figures() -> None:
    ARTIFACTS.mkdir(exist_ok=True)
    (ARTIFACTS / "panels.json").write_text(json.dumps(FIGURES, indent=1) + "\n")


def _in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() not in ("", "0", "false", "no")


def _require_browser():
    """Return playwright's sync_playwright, or skip (locally) / fail (in CI) with the reason."""
    problems = []
    if not (os.path.isfile(CHROMIUM) and os.access(CHROMIUM, os.X_OK)):
        problems.append(f"{CHROMIUM} is not installed (apt-get install chromium)")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        sync_playwright = None
        problems.append("the playwright Python package is not installed (pip install playwright)")
    if problems:
        reason = "browser test needs a browser: " + "; ".join(problems)
        if _in_ci():
            pytest.fail(reason + " -- and CI is set, so this is a failure, not a skip")
        pytest.skip(reason)
    return sync_playwright


def _frame_hex(page) -> str:
    return page.locator(".mbe-framebuilder .mbe-frame-hex").inner_text().strip()


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    """One JupyterLab (its root holds copies of the notebooks) and one chromium for the module."""
    sync_playwright = _require_browser()
    root = tmp_path_factory.mktemp("lab") / "root"
    shutil.copytree(COURSE, root, ignore=shutil.ignore_patterns(".ipynb_checkpoints"))
    ARTIFACTS.mkdir(exist_ok=True)
    with JupyterLab(root) as server, sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=lab_driver.BROWSER_ARGS)
        server.browser = browser
        try:
            yield server
        finally:
            browser.close()
            _save_figures()


def _open(lab, nb: Path):
    """A fresh page (1400 x 900) on the notebook alone (a workspace of its own, reset), collecting
    console errors from the start."""
    lab.shutdown_sessions()  # the previous page's kernel
    page = lab.browser.new_page(viewport=VIEWPORT)
    page.set_default_timeout(30_000)
    console = lab_driver.ConsoleErrors(page)
    workspace = re.sub(r"[^a-z0-9]+", "-", nb.stem.lower())
    lab_driver.open_notebook(page, lab.url(f"lab/workspaces/{workspace}/tree/{nb.name}?reset"))
    return page, console


def _type_keys(page, box, text: str) -> None:
    """Select what ``box`` holds and type ``text`` over it key by key, as a learner does: no Enter, no Tab."""
    box.click()
    page.keyboard.press("Control+A")
    page.keyboard.type(text, delay=40)  # 40 ms a key: quicker than the panels' pause, as fingers are


def _shows(page, selector: str, want: str, timeout: int = 15_000) -> None:
    page.wait_for_function("([sel, want]) => { const el = document.querySelector(sel);"
                           " return !!el && el.innerText.trim() === want; }",
                           arg=[selector, want], timeout=timeout)


def _typing_latency_ms(page, box, text: str, selector: str, want: str) -> float:
    """Type ``text`` into ``box`` key by key, without Enter; milliseconds from the last key until
    ``selector`` shows ``want``.  The field keeps the focus and exactly what was typed."""
    _type_keys(page, box, text)
    start = time.perf_counter()
    _shows(page, selector, want)
    ms = (time.perf_counter() - start) * 1000
    assert box.evaluate("el => el === document.activeElement"), "typing lost the focus"
    assert box.input_value() == text, "the kernel overwrote what was being typed"
    return ms


def test_widgets_render_and_respond_in_jupyterlab(lab):
    from modbus_edu.framing import RtuFrame
    from modbus_edu.pdu import ReadHoldingRegistersRequest

    started = time.monotonic()
    nb = copy_notebook(NOTEBOOK, lab.root_dir)
    shot = ARTIFACTS / "browser_widgets.png"
    page, console = _open(lab, nb)
    try:
        lab_driver.run_all(page, timeout_s=90, on_retry=console.forgive)

        errors = lab_driver.cell_errors(page)
        assert not errors, f"a cell raised:\n{errors}"
        # the kernel is the project's interpreter
        first_output = page.locator(".jp-CodeCell").first.locator(".jp-OutputArea-output").inner_text()
        assert first_output.strip() == sys.executable

        # real controls, not "Loading widget..." and not the text fallback "FrameBuilder(children=..."
        fb = page.locator(".mbe-framebuilder")
        fb.wait_for(state="visible")
        assert fb.locator(".widget-dropdown select").count() >= 3
        assert fb.locator(".widget-text input").first.is_visible()
        tool = page.locator(".mbe-testtool").first
        tool.wait_for(state="visible")
        assert tool.locator(".widget-button, button").count() >= 3
        assert page.locator(".jupyter-widgets").count() > 10
        outputs = " ".join(page.locator(".jp-OutputArea").all_inner_texts())
        assert "Loading widget" not in outputs
        assert not re.search(r"(FrameBuilder|TestTool|VBox)\(", outputs), outputs[:500]

        expected = RtuFrame(unit=1, pdu=ReadHoldingRegistersRequest(address=0, count=1)).encode()
        assert _frame_hex(page) == expected.hex(" ").upper()

        # the live panels, not their pictures: the widget view outranks the text/html beside it
        assert RUN_TO_USE not in outputs and page.locator(".mbe-picture").count() == 0

        # type into the page key by key, never Enter: the kernel rebuilds the frame a moment after the
        # last key and the page shows it (the latency: the last key to the new frame on screen)
        latency = FIGURES["typing_latency_ms"]
        count = fb.locator(".mbe-field-count input")
        for i, (value, n) in enumerate((("5", 5), ("12", 12), ("1", 1))):
            changed = RtuFrame(unit=1, pdu=ReadHoldingRegistersRequest(address=0, count=n)).encode()
            ms = _typing_latency_ms(page, count, value, ".mbe-framebuilder .mbe-frame-hex",
                                    changed.hex(" ").upper())
            if i:  # the first change also warms up the comm
                latency.setdefault("frame builder", []).append(round(ms, 1))
        address = fb.locator(".mbe-field-address input")
        # half-typed: "0x" is not a number yet, and says so beside the field while the learner types on
        _type_keys(page, address, "0x")
        error = fb.locator(".mbe-field-error-address")
        error.wait_for(state="visible", timeout=15_000)
        assert "not a whole number" in error.inner_text()
        assert fb.locator(".mbe-field-address.mbe-invalid").count() == 1
        page.keyboard.type("6B", delay=40)
        changed = RtuFrame(unit=1, pdu=ReadHoldingRegistersRequest(address=107, count=1)).encode()
        _shows(page, ".mbe-framebuilder .mbe-frame-hex", changed.hex(" ").upper())
        error.wait_for(state="hidden", timeout=15_000)
        assert address.input_value() == "0x6B"

        # the decoder: a frame typed key by key is dissected without Enter
        decoder = page.locator(".mbe-framedecoder")
        text = decoder.locator(".mbe-decoder-input textarea")
        for i, frame in enumerate(("11 03 00 6B 00 03 76 87", "01 03 00 00 00 01 84 0A")):
            ms = _typing_latency_ms(page, text, frame, ".mbe-framedecoder .mbe-frame-hex", frame)
            if i:
                latency.setdefault("frame decoder", []).append(round(ms, 1))
        assert "Read Holding Registers" in decoder.locator(".mbe-message-line").inner_text()
        _type_keys(page, text, "01 0")  # half a byte: the message under the field says so
        page.wait_for_function("() => document.querySelector('.mbe-framedecoder .mbe-message-line')"
                               ".innerText.includes('hex')", timeout=15_000)
        assert decoder.locator(".mbe-decoder-input.mbe-invalid").count() == 1

        # the CRC explorer: the bytes typed key by key are the bytes it steps through
        crc = page.locator(".mbe-crcexplorer")
        crc_input = crc.locator(".mbe-crc-input input")
        for i, data in enumerate(("11 03 00 6B", "01 03 00 00 00 01")):
            ms = _typing_latency_ms(page, crc_input, data, ".mbe-crcexplorer .mbe-crc-bytes",
                                    f"bytes: {data}")
            if i:
                latency.setdefault("CRC explorer", []).append(round(ms, 1))
        crc.locator(".mbe-crc-run-to-end").click()
        page.wait_for_function("() => document.querySelector('.mbe-crcexplorer .mbe-crc-result')"
                               ".innerText.includes('CRC = 0x0A84')", timeout=15_000)

        # Tab moves from one field to the next
        address = fb.locator(".mbe-field-address input")
        address.focus()
        page.keyboard.press("Tab")
        assert page.evaluate("() => !!document.activeElement.closest('.mbe-field-count')")

        # an invalid field: its error beside that field, once, the field marked, the frame kept
        _type_keys(page, count, "126")
        error = fb.locator(".mbe-field-error-count")
        error.wait_for(state="visible", timeout=15_000)
        assert "quantity of registers is 126" in error.inner_text()
        assert fb.inner_text().count("quantity of registers is 126") == 1  # once
        field_box = fb.locator(".mbe-field-count").bounding_box()
        error_box = error.bounding_box()
        assert error_box["x"] >= field_box["x"] + field_box["width"] - 1  # beside the field ...
        assert abs((error_box["y"] + error_box["height"] / 2)
                   - (field_box["y"] + field_box["height"] / 2)) < field_box["height"]  # ... on its line
        assert fb.locator(".mbe-field-count.mbe-invalid").count() == 1
        assert fb.locator(".mbe-stale .mbe-frame-hex").count() == 1  # the last good frame, greyed
        fb.screenshot(path=str(ARTIFACTS / "browser_framebuilder_error.png"))
        _type_keys(page, count, "1")
        error.wait_for(state="hidden", timeout=15_000)

        # switching to TCP shows the transaction id field, which RTU hides
        tid = fb.locator(".mbe-field-transaction-id")
        assert not tid.is_visible()
        fb.locator(".mbe-field-mode select").select_option("TCP")
        tid.wait_for(state="visible", timeout=15_000)
        page.wait_for_function(
            "() => document.querySelector('.mbe-framebuilder .mbe-frame-hex').innerText.trim()"
            ".startsWith('00 01 00 00 00 06 01 03 00 6B')", timeout=15_000)

        # the dashboard's trend plot arrived as an image
        plot = page.locator(".mbe-meterdashboard .mbe-md-plot").first
        plot.wait_for(state="visible")
        assert plot.evaluate("img => img.naturalWidth") > 100

        # the master tool polls continuously on the kernel's asyncio loop: press start in the page,
        # watch the poll counter grow while the notebook stays responsive, press stop
        master = page.locator(".mbe-role-rtu_master").first
        polls = master.locator(".mbe-tt-count-polls")
        assert polls.inner_text().strip() == "2"
        master.locator(".mbe-tt-start").click()
        page.wait_for_function(
            "() => Number(document.querySelector('.mbe-role-rtu_master .mbe-tt-count-polls')"
            ".innerText) >= 6", timeout=20_000)
        master.locator(".mbe-tt-stop").click()
        lab_driver.wait_kernel_idle(page)
        slave_requests = page.locator(".mbe-role-rtu_slave .mbe-tt-count-requests").inner_text()
        assert int(slave_requests) >= 6
        valid = int(master.locator(".mbe-tt-count-valid").inner_text())
        assert valid >= 6 and master.locator(".mbe-tt-count-timeouts").inner_text() == "0"

        # every button says what it does (a tooltip)
        untitled = page.evaluate(
            "sel => [...document.querySelectorAll(sel)].flatMap(p => [...p.querySelectorAll('button')])"
            ".filter(b => b.offsetParent !== null && !b.title).map(b => b.innerText)",
            panels.PANEL_SELECTOR)
        assert not untitled, f"buttons without a tooltip: {untitled}"

        page.screenshot(path=str(shot), full_page=True)
        for i, panel in enumerate(page.locator(panels.PANEL_SELECTOR).all()):
            result = panels.check_panel(page, panel, f"widgets_test-{i}", ARTIFACTS)
            FIGURES["panels"].append(result)
            assert not result["problems"], result["problems"]
        assert not console.errors, console.errors
    except Exception:
        try:
            page.screenshot(path=str(ARTIFACTS / "browser_widgets_failure.png"), full_page=True)
        except Exception:  # noqa: BLE001 - best effort
            pass
        print(lab.log_tail())
        raise
    finally:
        page.close()
    assert shot.exists() and shot.stat().st_size > 10_000
    elapsed = time.monotonic() - started
    print(f"browser test took {elapsed:.1f} s; typing latency {FIGURES['typing_latency_ms']} ms")
    assert elapsed < 180, f"the browser test took {elapsed:.0f} s, budget 180 s"


@pytest.mark.parametrize("notebook", _panel_notebooks(), ids=lambda p: p.stem)
def test_every_course_panel_fits_the_screen_after_restart_and_run_all(lab, notebook):
    started = time.monotonic()
    nb = copy_notebook(notebook, lab.root_dir, clear=True)
    page, console = _open(lab, nb)
    try:
        lab_driver.run_all(page, timeout_s=RUN_ALL_TIMEOUT_S, restart=True, on_retry=console.forgive)
        # every view drawn (the widget manager renders the last outputs a moment after the kernel idles;
        # on a loaded machine, after a notebook's plots, much later): within what is left of Run All's
        # own deadline, and never less than 30 s
        left = RUN_ALL_TIMEOUT_S - (time.monotonic() - started)
        page.wait_for_function(
            "sel => [...document.querySelectorAll(sel)].every("
            "el => el.querySelector('input, select, textarea, button'))",
            arg=panels.PANEL_SELECTOR, timeout=max(30_000, int(left * 1000)))
        found = page.locator(panels.PANEL_SELECTOR)
        # the TestTool's and the dashboard's inner boxes are not panels of their own
        all_panels = [p for p in found.all() if p.evaluate(
            "(el, sel) => !el.parentElement.closest(sel)", panels.PANEL_SELECTOR)]
        assert all_panels, f"{notebook.name} imports the widgets but shows no panel"
        problems = []
        for i, panel in enumerate(all_panels):
            result = panels.check_panel(page, panel, f"{notebook.stem}-{i}", ARTIFACTS)
            FIGURES["panels"].append(result)
            problems += result["problems"]
        outputs = " ".join(page.locator(".jp-OutputArea").all_inner_texts())
        assert "Error displaying widget" not in outputs and "Loading widget" not in outputs
        assert RUN_TO_USE not in outputs  # every panel live: its picture stays in the saved file only
        assert not problems, "\n".join(problems)
        assert not console.errors, console.errors
    except Exception:
        try:
            page.screenshot(path=str(ARTIFACTS / f"{notebook.stem}-failure.png"), full_page=True)
        except Exception:  # noqa: BLE001 - best effort
            pass
        raise
    finally:
        page.close()
        _save_figures()
    elapsed = time.monotonic() - started
    assert elapsed < RUN_ALL_TIMEOUT_S + 120, f"{notebook.name}: {elapsed:.0f} s"


def test_an_unrun_notebook_shows_each_panel_s_picture_and_no_dead_controls(lab, tmp_path):
    """No widget state is saved: opened without running, each panel is its static HTML picture under
    "run this cell to use it" (as on GitHub or nbviewer), never dead controls."""
    from modbus_edu.course import execute

    executed = tmp_path / "executed.ipynb"
    shutil.copy(NOTEBOOK, executed)
    execute(executed, timeout=120)
    saved = json.loads(executed.read_text())
    assert "widgets" not in saved["metadata"]
    pictures = [o["data"]["text/html"] for c in saved["cells"] for o in c.get("outputs", [])
                if RUN_TO_USE in "".join(o.get("data", {}).get("text/html", ""))]
    assert len(pictures) == 6
    nb = copy_notebook(executed, lab.root_dir)
    page, console = _open(lab, nb)
    try:
        page.wait_for_timeout(3000)  # the widget manager restores what it can
        outputs = page.locator(".jp-OutputArea-output")
        assert outputs.count() >= 6
        text = " ".join(outputs.all_inner_texts())
        assert "Error displaying widget" not in text and "Loading widget" not in text
        assert page.locator(".jp-OutputArea-output").locator("input, select, button, textarea").count() == 0
        assert page.locator(".jp-OutputArea-output .jupyter-widgets").count() == 0
        # each panel drawn from its text/html: the label, then its fields and its frame
        drawn = page.locator('.jp-OutputArea-output[data-mime-type="text/html"]', has_text=RUN_TO_USE)
        assert drawn.count() == 6, text[:800]
        for what in ("Frame builder panel", "Frame decoder panel", "CRC explorer panel",
                     "Modbus test tool panel, RTU master", "Modbus test tool panel, RTU slave",
                     "Meter dashboard panel"):
            assert f"{what}" in text, (what, text[:800])
        assert text.count(RUN_TO_USE) == 6
        builder = drawn.filter(has_text="Frame builder panel")
        assert "01 03 00 00 00 01 84 0A" in builder.inner_text()    # the frame the cell built
        assert "quantity" in builder.inner_text() and "CRC mismatch" in text
        # laid out as the panel is, even after the sanitizer of an untrusted notebook: the fields on
        # their lines (mode, role, function on one; unit, address, quantity each on its own), not in a row
        rows = builder.locator(".mbe-picture-field").evaluate_all(
            "els => els.map(e => Math.round(e.getBoundingClientRect().top))")
        assert len(rows) == 6 and len(set(rows)) == 4, rows
        for i in range(drawn.count()):
            box = drawn.nth(i).evaluate("el => [el.scrollWidth, el.clientWidth]")
            assert box[0] <= box[1] + 1, f"picture {i} overflows sideways: {box}"
        page.screenshot(path=str(ARTIFACTS / "unrun_notebook.png"), full_page=True)
        assert not console.errors, console.errors
    finally:
        page.close()


_FOLLOW_CELLS = [
    "import modbus_edu as mb\nfrom modbus_edu.widgets import TestTool\n\n"
    "stand_in = TestTool('rtu_slave', unit=1, address=0, length=4)\n"
    "stand_in.fill_increment(start=100, step=10)\nstand_in",
    # another link, in a later cell: the panel above must follow it by itself
    "program = mb.Master(mb.loopback_serial(stand_in.slave, baudrate=9600), timeout=1.0)\n"
    "program.write_single_register(unit=1, address=0, value=1234)\n"
    "program.write_multiple_registers(unit=1, address=1, values=[7, 8, 9])",
]


def test_a_test_tool_panel_follows_its_slave_s_traffic_from_another_link_on_screen(lab, tmp_path):
    """A stand-in slave's panel, shown in one cell, draws the writes another link makes in the next
    cell: the grid and the counters change on screen with no refresh() anywhere."""
    source = tmp_path / "follow_test.ipynb"
    cells = [{"cell_type": "code", "execution_count": None, "id": f"follow{i}", "metadata": {},
              "outputs": [], "source": text} for i, text in enumerate(_FOLLOW_CELLS)]
    source.write_text(json.dumps({"cells": cells, "metadata": {}, "nbformat": 4, "nbformat_minor": 5}))
    assert "refresh" not in source.read_text()
    nb = copy_notebook(source, lab.root_dir, clear=True)
    page, console = _open(lab, nb)
    try:
        lab_driver.run_all(page, timeout_s=90, on_retry=console.forgive)
        assert not lab_driver.cell_errors(page)
        tool = page.locator(".mbe-role-rtu_slave").first
        tool.wait_for(state="visible")
        page.wait_for_function(
            "() => { const t = document.querySelector('.mbe-role-rtu_slave');"
            " const b = t && t.querySelector('.mbe-tt-count-requests'); return !!b && b.innerText === '2'; }",
            timeout=15_000)
        shown = panels.tool_shows(tool)
        assert shown["grid"] == ["1234", "7", "8", "9"], shown
        assert shown["counts"]["requests"] == 2 and shown["counts"]["responses"] == 2, shown
        assert not console.errors, console.errors
    except Exception:
        try:
            page.screenshot(path=str(ARTIFACTS / "follow_failure.png"), full_page=True)
        except Exception:  # noqa: BLE001 - best effort
            pass
        print(lab.log_tail())
        raise
    finally:
        page.close()


# --- axe-core on every panel: 0 violations of serious or critical impact ----------------------
#: The panels of the test notebook, each by the selector of its outermost element.
AXE_PANELS = {
    "frame builder": ".mbe-framebuilder",
    "frame decoder": ".mbe-framedecoder",
    "CRC explorer": ".mbe-crcexplorer",
    "test tool (RTU master)": ".mbe-testtool.mbe-role-rtu_master",
    "test tool (RTU slave)": ".mbe-testtool.mbe-role-rtu_slave",
    "meter dashboard": ".mbe-meterdashboard",
}


#: Tall enough that a whole panel (at most panels.MAX_HEIGHT) is on screen below JupyterLab's bars.
AXE_VIEWPORT = {"width": VIEWPORT["width"], "height": panels.MAX_HEIGHT + 400}


@pytest.fixture(scope="module")
def panels_page(lab):
    """The test notebook run once in a page of its own, axe-core injected; shared by the panel checks."""
    try:
        script = axe.axe_script()
    except RuntimeError as exc:
        if _in_ci():
            pytest.fail(f"axe-core could not be installed: {exc}")
        pytest.skip(f"axe-core could not be installed: {exc}")
    nb = copy_notebook(NOTEBOOK, lab.root_dir)
    page, console = _open(lab, nb)
    try:
        page.set_viewport_size(AXE_VIEWPORT)
        lab_driver.run_all(page, timeout_s=90, on_retry=console.forgive)
        page.wait_for_function(
            "sels => sels.every(s => { const el = document.querySelector(s);"
            " return !!el && !!el.querySelector('input, select, textarea, button'); })",
            arg=list(AXE_PANELS.values()), timeout=30_000)
        page.add_script_tag(path=str(script))
        yield page, console
    finally:
        page.close()
        _save_figures()


@pytest.mark.parametrize("name", list(AXE_PANELS))
def test_axe_core_finds_no_serious_or_critical_violation_in_the_panel(panels_page, name):
    """axe-core (WCAG 2.1 A/AA and best practices), run inside JupyterLab on the panel's DOM node in
    each of its tabs: no violation of serious or critical impact.  The counts per panel (by rule, any
    impact) go to tests/artifacts/panels.json."""
    page, console = panels_page
    panel = page.locator(AXE_PANELS[name]).first
    panel.scroll_into_view_if_needed()
    violations = axe.run_axe(page, panel, panels.tab_titles(panel))
    found = axe.counts(violations)
    FIGURES.setdefault("axe", {"version": axe.pinned_version(), "panels": {}})["panels"][name] = found
    print(f"axe-core on the {name}: {json.dumps(found)}")
    serious = [v for v in violations if v["impact"] in axe.SERIOUS]
    assert not serious, f"{len(serious)} serious or critical:\n{axe.describe(serious)}"
    assert not console.errors, console.errors


def _press_enter_on(page, control) -> None:
    """Give ``control`` the keyboard focus and press Enter (no mouse)."""
    control.focus()
    page.keyboard.press("Enter")


#: For each panel: what Enter, an arrow key or a typed letter on one of its controls must do, in the page.
def _keyboard_action(page, name: str, panel) -> None:
    if name == "frame builder":  # a dropdown chosen by typing its first letter rebuilds the frame
        panel.locator(".mbe-field-role select").focus()
        page.keyboard.press("e")  # "exception response"
        _shows(page, ".mbe-framebuilder .mbe-frame-hex", "01 83 02 C0 F1")
        panel.locator(".mbe-field-role select").select_option(index=0)  # a request again, for the tests after
        panel.locator(".mbe-field-count input").wait_for(state="visible", timeout=15_000)
    elif name == "frame decoder":
        panel.locator(".mbe-decoder-input textarea").focus()
        page.keyboard.press("Control+A")
        page.keyboard.type("01 03 00 00 00 01 84 0A")
        _shows(page, ".mbe-framedecoder .mbe-frame-hex", "01 03 00 00 00 01 84 0A")
    elif name == "CRC explorer":
        _press_enter_on(page, panel.locator(".mbe-crc-reset"))
        page.wait_for_function("() => !document.querySelector('.mbe-crcexplorer .mbe-crc-result')"
                               ".innerText.includes('CRC =')", timeout=15_000)
        _press_enter_on(page, panel.locator(".mbe-crc-run-to-end"))
        page.wait_for_function("() => document.querySelector('.mbe-crcexplorer .mbe-crc-result')"
                               ".innerText.includes('CRC =')", timeout=15_000)
    elif name == "test tool (RTU master)":
        polls = int(panel.locator(".mbe-tt-count-polls").inner_text())
        _press_enter_on(page, panel.locator(".mbe-tt-read"))
        page.wait_for_function(
            "n => Number(document.querySelector('.mbe-role-rtu_master .mbe-tt-count-polls').innerText) > n",
            arg=polls, timeout=15_000)
    elif name == "meter dashboard":
        values = panel.locator(".lm-TabBar-tab").nth(1)
        panel.locator(".lm-TabBar-tab.lm-mod-current").focus()
        page.keyboard.press("ArrowRight")  # the tab bar: arrows move among the titles, Enter opens one
        page.keyboard.press("Enter")
        page.wait_for_function("el => el.classList.contains('lm-mod-current')", arg=values.element_handle(),
                               timeout=15_000)
        _press_enter_on(page, panel.locator(".mbe-md-read"))
        page.wait_for_function("() => document.querySelector('.mbe-meterdashboard .mbe-message-line')"
                               ".innerText.includes('read at')", timeout=15_000)
    elif name == "test tool (RTU slave)":
        data = panel.locator(".lm-TabBar-tab").nth(1)
        panel.locator(".lm-TabBar-tab.lm-mod-current").focus()
        page.keyboard.press("ArrowRight")
        page.keyboard.press("Enter")
        page.wait_for_function("el => el.classList.contains('lm-mod-current')", arg=data.element_handle(),
                               timeout=15_000)


@pytest.mark.parametrize("name", list(AXE_PANELS))
def test_the_panel_works_from_the_keyboard_alone(panels_page, name):
    """Tab reaches every control the panel shows, in the page's order (no tabindex > 0), each with a
    focus ring anyone can see (an outline of 2 px or more), in each of its tabs; the panel's main
    action answers Enter (buttons), the arrow keys (dropdowns, tab titles) or typing."""
    page, console = panels_page
    panel = page.locator(AXE_PANELS[name]).first
    panel.scroll_into_view_if_needed()
    tabs = panels.tab_titles(panel)
    results = {}
    for tab in tabs or [None]:
        if tab is not None:
            tab.click()
            page.wait_for_timeout(150)
        walk = axe.tab_through(page, panel, ring_cut=a11y.RING_CLIPPED)
        title = tab.inner_text().strip() if tab is not None else "-"
        results[title] = {"controls": walk["controls"], "reached": len(walk["reached"])}
        assert walk["controls"] > 0, f"{name} [{title}]: no control to reach"
        assert not walk["missed"], f"{name} [{title}]: Tab never reaches {len(walk['missed'])} controls"
        assert not walk["no_ring"], f"{name} [{title}]: no visible focus ring on {walk['no_ring']}"
        assert not walk["ring_cut"], f"{name} [{title}]: a focus ring cut off: {walk['ring_cut']}"
        assert walk["positive_tabindex"] == 0
    if tabs:
        tabs[0].click()
    FIGURES.setdefault("keyboard", {})[name] = results
    _keyboard_action(page, name, panel)
    assert not console.errors, console.errors


# --- beyond axe-core: the keys stay in the panel, a screen reader is told what changes ----------------
def _focused(page, selector: str) -> bool:
    return page.evaluate("sel => !!document.activeElement && !!document.activeElement.closest(sel)", selector)


def test_a_panel_keeps_its_keys_from_the_notebook(panels_page):
    """JupyterLab's command-mode keys do not reach a panel's controls: ↓ on a dropdown chooses the next
    function (the active cell stays), "m" on a button leaves the cell code and the panel on screen, and
    the arrow keys scroll a scroll box instead of moving to another cell."""
    page, console = panels_page
    before = a11y.notebook_state(page)
    assert before["panels"] == 4 and "code" in before["types"]

    function = page.locator(".mbe-framebuilder .mbe-field-function select")
    function.focus()
    active = a11y.notebook_state(page)["active"]
    first = function.input_value()
    page.keyboard.press("ArrowDown")
    select = function.element_handle()
    page.wait_for_function("([el, v]) => el.value !== v", arg=[select, first], timeout=5_000)
    assert _focused(page, ".mbe-field-function"), "↓ took the focus away from the dropdown"
    assert a11y.notebook_state(page)["active"] == active, "↓ moved to another cell"
    page.keyboard.press("ArrowUp")
    page.wait_for_function("([el, v]) => el.value === v", arg=[select, first], timeout=5_000)
    assert a11y.notebook_state(page)["active"] == active, "an arrow key moved to another cell"

    read = page.locator(".mbe-role-rtu_master .mbe-tt-read")
    read.focus()
    for key in ("m", "r", "a", "b"):  # to Markdown, to raw, insert a cell above, below
        page.keyboard.press(key)
    page.wait_for_timeout(300)
    after = a11y.notebook_state(page)
    assert after["types"] == before["types"], "a letter on a panel's button changed the notebook's cells"
    assert after["panels"] == before["panels"] and read.is_visible()
    assert _focused(page, ".mbe-tt-read")

    # the dashboard's table of values (its second tab) scrolls with ↓ once Tab (here: focus) is on it
    dash = page.locator(".mbe-meterdashboard")
    dash.locator(".lm-TabBar-tab").nth(1).click()
    table = dash.locator(".mbe-md-table")
    table.wait_for(state="visible")
    assert table.evaluate("el => el.scrollHeight > el.clientHeight"), "the table does not overflow: no test"
    table.focus()
    active = a11y.notebook_state(page)["active"]
    for _ in range(3):
        page.keyboard.press("ArrowDown")
    page.wait_for_function("el => el.scrollTop > 0", arg=table.element_handle(), timeout=5_000)
    assert a11y.notebook_state(page)["active"] == active and _focused(page, ".mbe-md-table")
    dash.locator(".lm-TabBar-tab").nth(0).click()

    # the test tool's TX log scrolls sideways with →
    master = page.locator(".mbe-role-rtu_master")
    master.locator(".lm-TabBar-tab", has_text="traffic").click()
    log = master.locator(".mbe-tt-tx-log")
    log.wait_for(state="visible")
    log.evaluate("el => { el.style.width = '120px'; }")  # narrower than its lines, whatever the font
    log.focus()
    active = a11y.notebook_state(page)["active"]
    for _ in range(3):
        page.keyboard.press("ArrowRight")
    page.wait_for_function("el => el.scrollLeft > 0", arg=log.element_handle(), timeout=5_000)
    log.evaluate("el => { el.style.width = ''; el.scrollLeft = 0; }")
    assert a11y.notebook_state(page)["active"] == active
    master.locator(".lm-TabBar-tab").nth(0).click()
    assert not console.errors, console.errors


def test_the_grid_s_head_stays_over_its_columns_and_is_no_scroll_box(panels_page):
    """Ten columns are wider than the RTU slave's grid: the grid scrolls, head and rows together; the
    head row neither clips "+9" nor scrolls on its own (a scroll box with nothing to focus, which
    axe-core calls serious: scrollable-region-focusable)."""
    page, console = panels_page
    slave = page.locator(".mbe-testtool.mbe-role-rtu_slave")
    slave.scroll_into_view_if_needed()
    slave.locator(".lm-TabBar-tab").nth(0).click()  # the tab with the device's parameters
    length = slave.get_by_label("length", exact=True)
    length.wait_for(state="visible", timeout=15_000)
    length.fill("12")
    length.press("Enter")
    slave.locator(".lm-TabBar-tab", has_text="data").click()
    page.wait_for_function("() => { const h = document.querySelector("
                           "'.mbe-role-rtu_slave .mbe-tt-grid-head');"
                           " return !!h && h.innerText.includes('+9'); }", timeout=15_000)
    grid = slave.locator(".mbe-tt-grid")
    measure = """grid => {
      const head = grid.querySelector('.mbe-tt-grid-head'), last = [...head.children].pop();
      const cells = [...grid.querySelectorAll('.mbe-tt-cell')];
      const rows = [...grid.children].filter(r => r.classList.contains('widget-hbox'));
      const h = last.getBoundingClientRect(), c = cells[9].getBoundingClientRect();
      return {wide: grid.scrollWidth > grid.clientWidth, head: last.innerText.trim(),
              aligned: Math.abs((h.left + h.right) / 2 - (c.left + c.right) / 2),
              rowScrolls: rows.filter(r => r.scrollWidth > r.clientWidth + 1
                                      && getComputedStyle(r).overflowX !== 'visible').length};
    }"""
    # the grid is redrawn as the twelve cells arrive: measure once its layout has settled (or the deadline)
    settled = ("() => { const s = (" + measure + ")(document.querySelector("
               "'.mbe-role-rtu_slave .mbe-tt-grid')); return s.wide && s.head === '+9' && s.aligned < 2 "
               "&& !s.rowScrolls; }")
    try:
        page.wait_for_function(settled, timeout=15_000)
    except Exception:  # playwright's timeout: the assertions below say what the layout is
        pass
    shape = grid.evaluate(measure)
    assert shape["rowScrolls"] == 0, f"a row of the grid scrolls on its own: {shape}"
    assert shape["wide"], f"ten columns fit: the test shows nothing ({shape})"
    assert shape["head"] == "+9" and shape["aligned"] < 2, shape
    found = axe.run_axe(page, slave, [])
    assert not [v for v in found if v["rule"] == "scrollable-region-focusable"], axe.describe(found)
    slave.locator(".lm-TabBar-tab").nth(0).click()
    length.fill("4")
    length.press("Enter")
    assert not console.errors, console.errors


def test_a_screen_reader_hears_names_states_and_changes(panels_page):
    """In chromium's accessibility tree: button names are words (no icon glyph), the CRC method's
    buttons say which one is pressed in a group named "method", the scroll boxes are named regions, the
    message lines are live regions, and a field that does not read is invalid and described by its
    error."""
    page, console = panels_page
    for name, selector in AXE_PANELS.items():
        buttons = a11y.nodes(page, selector, role="button")
        assert buttons or name in ("frame builder", "frame decoder"), name
        glyphs = {b["name"]: a11y.icon_glyphs(b["name"]) for b in buttons if a11y.icon_glyphs(b["name"])}
        assert not glyphs, f"{name}: icon glyphs in button names: {glyphs}"
        if name != "test tool (RTU slave)":
            status = a11y.nodes(page, selector, role="status")
            assert status and all(s.get("live") == "polite" for s in status), (name, status)
    assert {"read once", "start", "stop", "clear history"} <= {
        b["name"] for b in a11y.nodes(page, ".mbe-meterdashboard", role="button")}

    method = a11y.nodes(page, ".mbe-crcexplorer .mbe-crc-method", role="button")
    assert [m["pressed"] for m in method].count("true") == 1 and len(method) >= 3, method
    group = a11y.nodes(page, ".mbe-crcexplorer", role="group", name="method")
    assert group, "the method's buttons are no group named by their label"
    page.locator(".mbe-crcexplorer .mbe-crc-method button").nth(1).click()
    page.wait_for_function("() => document.querySelector('.mbe-crc-method button:nth-child(2)')"
                           ".getAttribute('aria-pressed') === 'true'", timeout=10_000)
    method = a11y.nodes(page, ".mbe-crcexplorer .mbe-crc-method", role="button")
    assert [m["pressed"] for m in method].index("true") == 1, method
    page.locator(".mbe-crcexplorer .mbe-crc-method button").nth(0).click()

    master, dash = page.locator(".mbe-role-rtu_master"), page.locator(".mbe-meterdashboard")
    master.locator(".lm-TabBar-tab", has_text="traffic").click()
    dash.locator(".lm-TabBar-tab", has_text="values").click()
    page.wait_for_timeout(300)
    regions = {r["name"] for r in a11y.nodes(page, ".mbe-testtool.mbe-role-rtu_master", role="region")}
    assert {"TX log: the frames sent (scrolls)", "RX log: the frames received (scrolls)"} <= regions
    assert a11y.nodes(page, ".mbe-meterdashboard", role="region")
    for panel in (master, dash):
        panel.locator(".lm-TabBar-tab").nth(0).click()
    assert a11y.nodes(page, ".mbe-crcexplorer", role="region", name="the current step (scrolls)")

    # a bad field: invalid, described by its error, which came in a live region
    count = page.locator(".mbe-framebuilder .mbe-field-count input")
    count.click()
    page.keyboard.press("Control+A")
    page.keyboard.type("126", delay=40)
    page.locator(".mbe-field-error-count").wait_for(state="visible", timeout=15_000)
    page.wait_for_function("() => document.querySelector('.mbe-field-count input')"
                           ".getAttribute('aria-invalid') === 'true'", timeout=10_000)
    field = [n for n in a11y.nodes(page, ".mbe-framebuilder .mbe-field-count", role="textbox")]
    assert field and field[0].get("invalid") == "true", field
    assert "quantity of registers is 126" in field[0]["description"], field
    said = [s for s in a11y.nodes(page, ".mbe-framebuilder", role="status")
            if "quantity of registers is 126" in s["name"] or "126" in json.dumps(s)]
    errors = page.locator(".mbe-field-error-count .widget-html-content")
    assert errors.get_attribute("role") == "status" and errors.get_attribute("aria-live") == "polite", said
    page.keyboard.press("Control+A")
    page.keyboard.type("1", delay=40)
    page.locator(".mbe-field-error-count").wait_for(state="hidden", timeout=15_000)
    page.wait_for_function("() => !document.querySelector('.mbe-field-count input')"
                           ".hasAttribute('aria-invalid')", timeout=10_000)
    assert not console.errors, console.errors


def test_a_button_that_greys_itself_out_hands_the_focus_on(panels_page):
    """"run to end" (greyed at the end) leaves the focus on "back"; "start" on "stop" and back: never
    on the page's body."""
    page, console = panels_page
    crc = page.locator(".mbe-crcexplorer")
    if crc.locator(".mbe-crc-run-to-end").is_disabled():
        crc.locator(".mbe-crc-reset").click()
        page.wait_for_function("() => !document.querySelector('.mbe-crc-run-to-end').disabled",
                               timeout=10_000)
    crc.locator(".mbe-crc-run-to-end").focus()
    page.keyboard.press("Enter")
    page.wait_for_function("() => document.querySelector('.mbe-crc-run-to-end').disabled", timeout=10_000)
    page.wait_for_function("() => !!document.activeElement.closest('.mbe-crc-back')", timeout=10_000)
    page.keyboard.press("Enter")  # back one step: the focus can go on stepping
    page.wait_for_function("() => !document.querySelector('.mbe-crc-run-to-end').disabled", timeout=10_000)

    master = page.locator(".mbe-role-rtu_master")
    master.locator(".mbe-tt-start").focus()
    page.keyboard.press("Enter")
    page.wait_for_function("() => !!document.activeElement.closest('.mbe-role-rtu_master .mbe-tt-stop')",
                           timeout=10_000)
    page.keyboard.press("Enter")
    page.wait_for_function("() => !!document.activeElement.closest('.mbe-role-rtu_master .mbe-tt-start')",
                           timeout=10_000)
    lab_driver.wait_kernel_idle(page)
    assert not console.errors, console.errors


# --- round two: shortcuts with modifiers, Escape, number fields, contrast when stale, reflow, rings ---------
#: On which control of each panel the keys are pressed: a select or a button whose own action (if any) is
#: harmless to the tests after.
KEY_TARGETS = {
    "frame builder": ".mbe-field-function select",
    "frame decoder": ".mbe-field-mode select",
    "CRC explorer": ".mbe-crc-method button.mod-active",
    "test tool (RTU master)": ".mbe-tt-read",
    "test tool (RTU slave)": ".mbe-tt-reset",
    "meter dashboard": ".mbe-md-read",
}
#: JupyterLab's notebook shortcuts with a modifier that reached the notebook from a panel (issue 38), and
#: Shift+Enter (run and move on).
MODIFIER_KEYS = ("Control+Backspace", "Control+Enter", "Alt+Enter", "Shift+Enter", "Control+Shift+ArrowDown",
                 "Control+a")


def _key_target(page, name: str):
    control = page.locator(AXE_PANELS[name]).first.locator(KEY_TARGETS[name]).first
    control.scroll_into_view_if_needed()
    control.focus()
    return control


def test_shortcuts_with_modifiers_stay_in_the_panel_and_ctrl_s_still_saves(panels_page):
    """On a focused button or select of every panel, each notebook shortcut with Ctrl, Alt or Shift does
    nothing to the notebook: no cell merged, run, added, moved or selected, no page text selected, the
    focus where it was.  The table (panel, key, what happened) goes to panels.json.  Ctrl+S still saves."""
    page, console = panels_page
    table, leaks = [], []
    for name in AXE_PANELS:
        control = _key_target(page, name)
        kept = control.evaluate("el => el.tagName === 'SELECT' ? el.value : null")
        for key in MODIFIER_KEYS:
            control.focus()
            before = a11y.snapshot(page, panels.PANEL_SELECTOR)
            page.keyboard.press(key)
            page.wait_for_timeout(120)  # a leak shows at once: the notebook acts in the page
            changed = a11y.what_changed(before, a11y.snapshot(page, panels.PANEL_SELECTOR))
            table.append({"panel": name, "key": key, "happened": "; ".join(changed) or
                          f"nothing to the notebook; the focus stays on the {KEY_TARGETS[name].split()[-1]}"})
            if changed:
                leaks.append(f"{name}, {key}: {changed}")
        if kept is not None and control.input_value() != kept:  # a select may take Ctrl+↓ as ↓
            control.select_option(kept)
            assert control.input_value() == kept
    lab_driver.wait_kernel_idle(page)
    FIGURES["shortcuts"] = table
    print("\n".join(f"| {row['panel']} | {row['key']} | {row['happened']} |" for row in table))
    assert not leaks, "\n".join(leaks)

    _key_target(page, "test tool (RTU master)")
    with page.expect_request(lambda r: r.method == "PUT" and "/api/contents/" in r.url, timeout=15_000):
        page.keyboard.press("Control+s")
    assert _focused(page, ".mbe-tt-read")
    assert not console.errors, console.errors


def test_escape_leaves_the_panel_for_its_cell_in_command_mode(panels_page):
    """Escape on any control of a panel (a text field too) puts the focus on the panel's cell, the
    notebook in command mode with that cell active: ↓ then goes to the next cell."""
    page, console = panels_page
    for name in AXE_PANELS:
        panel = page.locator(AXE_PANELS[name]).first
        cell = panel.evaluate("p => [...document.querySelectorAll('.jp-Notebook .jp-Cell')]"
                              ".indexOf(p.closest('.jp-Cell'))")
        for control in (_key_target(page, name), panel.locator("input[type=text], textarea").first):
            if not control.count() or not control.is_visible():
                continue
            control.focus()
            page.keyboard.press("Escape")
            state = a11y.snapshot(page, panels.PANEL_SELECTOR)
            assert state["focus"] == f"cell {cell}" and state["mode"] == "command", (name, state)
            assert state["active"] == cell, (name, state)
        if name == "frame builder":
            page.keyboard.press("ArrowDown")  # command mode: the next cell
            assert a11y.snapshot(page, panels.PANEL_SELECTOR)["active"] == cell + 1
    assert not console.errors, console.errors


def test_number_fields_are_valid_at_their_defaults_and_refuse_a_value_out_of_range(panels_page):
    """Every number field of every panel is valid in the browser as the panel starts (its default on its
    step); ↓ and ↑ on an interval give valid values; a unit of 300 in the test tool is refused, not
    clamped to 255: the field keeps 300, is invalid and described by what it takes, until 1 is typed."""
    page, console = panels_page
    invalid = page.evaluate(
        "sel => [...document.querySelectorAll(sel)]"
        ".flatMap(p => [...p.querySelectorAll('input[type=number]')]).filter(i => !i.checkValidity())"
        ".map(i => [i.closest('.widget-inline-hbox').innerText.trim(), i.value, i.min, i.step])",
        panels.PANEL_SELECTOR)
    assert not invalid, f"number fields invalid at their defaults: {invalid}"

    interval = page.locator(".mbe-meterdashboard input[type=number]")
    interval.fill("0.2")
    interval.press("Tab")
    for key in ("ArrowDown", "ArrowUp"):
        interval.focus()
        page.keyboard.press(key)
        value, valid = interval.evaluate("el => [Number(el.value), el.checkValidity()]")
        assert valid and value >= 0.01, (key, value)
    interval.fill("1")
    interval.press("Tab")

    unit = page.locator(".mbe-role-rtu_master .mbe-tt-unit input")
    unit.fill("300")
    unit.press("Tab")
    page.wait_for_timeout(500)  # ipywidgets answered a change at once: it would have made it 255
    assert unit.input_value() == "300", "a unit of 300 was changed, not refused"
    field = a11y.nodes(page, ".mbe-role-rtu_master .mbe-tt-unit", role="spinbutton")
    assert field and field[0].get("invalid") == "true", field
    assert "0 to 255" in field[0]["description"] and "still 1" in field[0]["description"], field
    note = page.locator(".mbe-role-rtu_master .mbe-tt-unit .mbe-number-error")
    assert note.is_visible() and note.get_attribute("role") == "status"
    unit.fill("1")
    unit.press("Tab")
    page.wait_for_function("el => !el.hasAttribute('aria-invalid')", arg=unit.element_handle(), timeout=5_000)
    assert not note.count()
    assert not console.errors, console.errors


def test_a_bad_input_greys_results_out_at_aa_contrast_and_the_decoder_marks_a_crc_error(panels_page):
    """The CRC explorer's greyed bytes and steps (its input does not read) still read at 4.5:1; the frame
    decoder's text area, holding a frame with a wrong CRC, is invalid and described by the error."""
    page, console = panels_page
    crc = page.locator(".mbe-crcexplorer")
    box = crc.locator(".mbe-crc-input input")
    good = box.input_value()
    box.fill("01 03 00 0G")
    crc.locator(".mbe-stale").first.wait_for(state="visible", timeout=15_000)
    for stale in crc.locator(".mbe-stale").all():  # the bytes, the step, the result, the history
        worst = stale.evaluate(a11y.TEXT_CONTRAST)
        assert worst[0] >= 4.5, f"greyed text at {worst[0]}:1 ({worst[1]}, {worst[2]!r})"
    box.fill(good)
    crc.locator(".mbe-stale").first.wait_for(state="detached", timeout=15_000)

    text = page.locator(".mbe-framedecoder .mbe-decoder-input textarea")
    text.fill("01 03 00 00 00 01 84 0B")
    page.wait_for_function("el => el.getAttribute('aria-invalid') === 'true'", arg=text.element_handle(),
                           timeout=15_000)
    field = a11y.nodes(page, ".mbe-framedecoder .mbe-decoder-input", role="textbox")
    assert field and field[0].get("invalid") == "true" and "CRC" in field[0]["description"], field
    text.fill("01 03 00 00 00 01 84 0A")
    page.wait_for_function("el => !el.hasAttribute('aria-invalid')", arg=text.element_handle(),
                           timeout=15_000)
    assert not console.errors, console.errors


#: 200% zoom of a 1280 x 720 screen: 640 x 360 CSS px (WCAG 1.4.10 Reflow).
ZOOMED = {"width": 640, "height": 360}


def test_at_200_percent_zoom_every_panel_reflows_to_one_column(panels_page):
    """At 640 x 360 CSS px (the file browser folded away, as a learner at that zoom would), in every tab
    of every panel (and the panels without tabs at 420 px as well): nothing sticks out of the panel
    sideways or scrolls sideways, except the boxes made to
    scroll (logs, tables, the grid, the CRC's steps); every button and tab title is at least 24 x 24 px."""
    page, console = panels_page
    page.set_viewport_size(ZOOMED)
    side = page.locator(".jp-SideBar.jp-mod-left .lm-TabBar-tab.lm-mod-current")
    folded = side.count() > 0
    if folded:
        side.first.click()
    try:
        page.wait_for_timeout(500)
        problems, widths = [], {}
        for name, selector in AXE_PANELS.items():
            panel = page.locator(selector).first
            panel.scroll_into_view_if_needed()
            for tab in panels.tab_titles(panel) or [None]:
                if tab is not None:
                    tab.click()
                    page.wait_for_timeout(150)
                title = f"{name} [{tab.inner_text().strip()}]" if tab is not None else name
                found = panel.evaluate(a11y.REFLOW)
                widths[title] = found["width"]
                problems += [f"{title}: {p}" for p in found["problems"] + found["small"]]
            if panels.tab_titles(panel):
                panels.tab_titles(panel)[0].click()
            else:  # narrower still (a sidebar open as well): one column all the same
                panel.evaluate("p => { p.style.maxWidth = '420px'; }")
                found = panel.evaluate(a11y.REFLOW)
                panel.evaluate("p => { p.style.maxWidth = ''; }")
                problems += [f"{name} at 420 px: {p}" for p in found["problems"] + found["small"]]
            panel.screenshot(path=str(ARTIFACTS / f"zoom200-{name.replace(' ', '_')}.png"))
        FIGURES["zoom_200_panel_widths"] = widths
        assert not problems, "\n".join(problems)
    finally:
        page.set_viewport_size(AXE_VIEWPORT)
        if folded:
            page.locator(".jp-SideBar.jp-mod-left .lm-TabBar-tab").first.click()
    assert not console.errors, console.errors
