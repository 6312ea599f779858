"""The course as an offline JupyterLite site (`make lite OFFLINE=1`), every notebook run in Debian's
chromium (playwright) with every request that would leave 127.0.0.1 blocked and counted.

* all 18 notebooks run to their last cell with no error (11, 15 and 17 skip their cells tagged as
  needing sockets or certificates; 12's server and test tools meet inside the page,
  ``modbus_edu.links.in_page``; a cell that draws shows the picture the build drew);
* a build exercise's right answer is accepted, a wrong one refused with its misconception named;
* the frame builder panel follows typing;
* 16's Web Serial panel renders as controls (anywidget and its extension are in the site), and one
  awaited read goes through it to pymodbus's RTU server (a stand-in ``navigator.serial``);
* 0 requests blocked, per notebook;
* a cell that stops is scrolled into view with its message, and the toolbar's busy indicator turns idle
  with the status bar (``lite/page.js``);
* the published site with its CDN blocked (a school firewall) says what failed, and points to the
  offline site and Binder, within :data:`CDN_MESSAGE_BOUND_S`.

The per-notebook table (notebook, cells run, result, seconds, requests blocked) is printed and written
to tests/artifacts/lite.json with the site's size, its build time and the time to the first executed
cell.  The published mode's configuration (Pyodide from its CDN at the kernel's version) is read from a
published build's jupyter-lite.json.  Skipped locally, with the reason, where chromium, playwright, node
or npm is missing; with ``CI`` set that is a failure (as in tests/test_browser.py).  Firefox ESR and
WebKitGTK run the site in tests/test_lite_browsers.py.
"""

from __future__ import annotations

import functools
import json
import re
import shutil
import subprocess
import sys
import threading
import time
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pytest

from modbus_edu.pictures import FIGURE_IN_WORDS

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(ROOT / "lite"))
import build_site  # noqa: E402
from browser import lab_driver, lite_probe  # noqa: E402
from test_browser import _in_ci, _require_browser  # noqa: E402
from test_browser_serial_page import STAND_IN, bridge  # noqa: E402,F401  (bridge: a fixture, for 16)

SITE = ROOT / "_site"
ARTIFACTS = HERE / "artifacts"
NOTEBOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
RUN_TIMEOUT_S = 600  # one notebook in Pyodide on two shared cores: generous but absolute
WEB_SERIAL_NOTEBOOK = "16_first_real_device.ipynb"  # its Web Serial panel, driven through a stand-in port
CDN_MESSAGE_BOUND_S = 30  # the published site, its CDN blocked: the page says so within this
pytestmark = pytest.mark.slow


class _Quiet(SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def _make_lite(offline: bool) -> float:
    if shutil.which("node") is None or shutil.which("npm") is None:
        reason = "the offline site needs node and npm (Pyodide's core comes from the npm package)"
        if _in_ci():
            pytest.fail(reason + " -- and CI is set, so this is a failure, not a skip")
        pytest.skip(reason)
    start = time.monotonic()
    mode = ["OFFLINE=1"] if offline else []
    subprocess.run(["make", "-C", str(ROOT), "lite", f"PYTHON={sys.executable}", *mode],
                   check=True, timeout=1800, capture_output=True)
    return time.monotonic() - start


@pytest.fixture(scope="module")
def figures():
    found: dict = {"notebooks": []}
    yield found
    ARTIFACTS.mkdir(exist_ok=True)
    (ARTIFACTS / "lite.json").write_text(json.dumps(found, indent=1) + "\n")


@pytest.fixture(scope="module")
def site(figures):
    """`make lite OFFLINE=1`, served on 127.0.0.1, and one chromium whose every outside request is blocked."""
    sync_playwright = _require_browser()
    figures["build_seconds"] = round(_make_lite(offline=True), 1)
    du = subprocess.run(["du", "-sh", str(SITE)], capture_output=True, text=True)
    figures["site_size"] = du.stdout.split()[0]
    server = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(SITE)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    origin = f"http://127.0.0.1:{server.server_address[1]}/"
    blocked: list[str] = []

    def route(r):
        url = r.request.url
        if url.startswith(origin) or url.startswith(("data:", "blob:")):
            r.continue_()
        else:
            blocked.append(url)
            r.abort()

    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=lab_driver.CHROMIUM, args=lab_driver.BROWSER_ARGS)

            def fresh_context():
                """A context of its own per notebook: JupyterLite keeps its workspace (the notebooks open
                before) in the browser's storage, which a new context starts without."""
                context = browser.new_context(viewport={"width": 1400, "height": 900})
                context.route("**/*", route)
                return context

            yield fresh_context, origin, blocked
            browser.close()
    finally:
        server.shutdown()


def _prompts(page) -> list[str]:
    return [p.strip() for p in page.locator(".jp-CodeCell .jp-InputArea-prompt").all_inner_texts()]


def _errors(page) -> list[str]:
    texts = page.locator('.jp-OutputArea-output[data-mime-type="application/vnd.jupyter.stderr"]')
    return [t.strip() for t in texts.all_inner_texts() if t.strip()]


def _open(fresh_context, origin: str, name: str, init_script: str | None = None):
    context = fresh_context()
    if init_script:
        context.add_init_script(init_script)
    page = context.new_page()
    page.set_default_timeout(60_000)
    page.goto(f"{origin}lab/index.html?path={name}", wait_until="domcontentloaded", timeout=120_000)
    page.wait_for_selector(".jp-NotebookPanel .jp-Cell", timeout=120_000)
    lab_driver.accept_dialogs(page, settle_ms=2000)
    lab_driver.wait_kernel_idle(page, timeout_ms=300_000)
    return page


def _run_all(page) -> tuple[list[str], float]:
    """Run > Run All Cells; wait until the kernel is idle and no cell waits.  Returns the prompts and when
    the first cell had run (seconds after the click)."""
    start = time.monotonic()
    lab_driver.run_all_cells(page)
    first = previous = None
    deadline = start + RUN_TIMEOUT_S
    while time.monotonic() < deadline:
        prompts = _prompts(page)
        if first is None and prompts and re.fullmatch(r"\[\d+\]:", prompts[0]):
            first = time.monotonic() - start
        # done: no cell waits (after an error the rest show "[ ]:"), twice in a row
        settled = first is not None and not any(p == "[*]:" for p in prompts)
        if settled and previous == prompts:
            return prompts, first
        previous = prompts if settled else None
        page.wait_for_timeout(500)
    raise TimeoutError(f"the cells did not finish within {RUN_TIMEOUT_S} s: {_prompts(page)}")


def _run_cell(page, code: str) -> str:
    """Add a cell at the end of the notebook, type ``code`` (one line), run it; return its output."""
    page.locator(".jp-NotebookPanel .jp-Cell").last.click()
    page.keyboard.press("Escape")
    page.keyboard.press("b")
    page.keyboard.press("Enter")
    page.keyboard.type(code)
    cell = page.locator(".jp-CodeCell").last.element_handle()  # before Shift+Enter adds another below
    page.keyboard.press("Shift+Enter")
    page.wait_for_function("(el) => /\\[\\d+\\]/.test(el.querySelector('.jp-InputArea-prompt').innerText)",
                           arg=cell, timeout=120_000)
    return cell.query_selector(".jp-OutputArea").inner_text()


@pytest.fixture(scope="module")
def published(figures):
    """`make lite`: the published site in _site (the offline fixture, used after, builds over it)."""
    figures["published_build_seconds"] = round(_make_lite(offline=False), 1)
    return SITE


def test_published_mode_loads_pyodide_from_its_cdn_at_the_kernel_s_version(published):
    """The default build (`make lite`): its jupyter-lite.json sends the kernel to Pyodide's CDN at the one
    version the bundled kernel expects, the same version lite/package.json pins for the offline site."""
    kernel_expects = subprocess.run(
        [str(ROOT / ".venv-lite" / "bin" / "python"), "-c",
         "from jupyterlite_pyodide_kernel.constants import PYODIDE_VERSION; print(PYODIDE_VERSION)"],
        capture_output=True, text=True, check=True).stdout.strip()
    npm_pin = json.loads((ROOT / "lite" / "package.json").read_text())["dependencies"]["pyodide"]
    config = json.loads((SITE / "jupyter-lite.json").read_text())["jupyter-config-data"]
    kernel = config["litePluginSettings"][build_site.KERNEL_PLUGIN]
    assert kernel["pyodideUrl"] == f"https://cdn.jsdelivr.net/pyodide/v{kernel_expects}/full/pyodide.mjs"
    assert kernel_expects == build_site.PYODIDE_VERSION == npm_pin
    assert kernel["disablePyPIFallback"] is True
    assert not (SITE / "static" / "pyodide").exists()  # nothing of Pyodide bundled: the CDN serves it
    wheels = {w.name.split("-")[0] for w in (SITE / "pypi").glob("*.whl")}
    assert {"modbus_edu", "pymodbus", "pyserial", "tqdm", "ipywidgets"} <= wheels
    plots = json.loads((SITE / "files" / "01_data_model.ipynb").read_text())["cells"][0]["source"]
    assert "%pip install -q matplotlib" in "".join(plots)
    assert config["exposeAppInBrowser"] == "true"  # the page script reaches the notebooks
    for page in build_site.PAGES:
        assert f'<script src="../{build_site.PAGE_SCRIPT}"' in (SITE / page / "index.html").read_text()


def test_published_site_with_its_cdn_blocked_says_what_failed(published, figures):
    """A school firewall: every request to Pyodide's CDN is aborted.  Within CDN_MESSAGE_BOUND_S the page
    says that Python cannot start because the CDN is out of reach, and points to the offline copy and to
    Binder (where before, the status bar said "Python (Pyodide) | Unknown" for minutes)."""
    sync_playwright = _require_browser()
    server = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(published)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    origin = f"http://127.0.0.1:{server.server_address[1]}/"
    blocked: list[str] = []

    def route(r):
        if r.request.url.startswith(origin):
            r.continue_()
        else:
            blocked.append(r.request.url)
            r.abort("blockedbyclient")

    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=lab_driver.CHROMIUM, args=lab_driver.BROWSER_ARGS)
            page = browser.new_page()
            page.route("**/*", route)
            start = time.monotonic()
            page.goto(f"{origin}lab/index.html?path=00_welcome.ipynb", wait_until="domcontentloaded")
            alert = page.locator("#mbe-page-alert")
            alert.wait_for(state="visible", timeout=CDN_MESSAGE_BOUND_S * 1000)
            figures["cdn_blocked_message_after_s"] = round(time.monotonic() - start, 1)
            text = alert.inner_text()
            browser.close()
    finally:
        server.shutdown()
    assert "Python cannot start" in text and "cdn.jsdelivr.net" in text, text
    assert "offline copy" in text and "Binder" in text, text
    assert any("cdn.jsdelivr.net" in url for url in blocked), blocked[:5]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_every_notebook_runs_to_its_last_cell(site, figures, path, request):
    fresh_context, origin, blocked = site
    blocked_before = len(blocked)
    start = time.monotonic()
    serial = request.getfixturevalue("bridge") if path.name == WEB_SERIAL_NOTEBOOK else None
    stand_in = STAND_IN.replace("__BRIDGE_URL__", serial[0]) if serial else None
    page = _open(fresh_context, origin, path.name, stand_in)
    try:
        prompts, first = _run_all(page)
        errors = _errors(page)
        ran = sum(bool(re.fullmatch(r"\[\d+\]:", p)) for p in prompts)
        stopped = f"stopped: {errors[0] if errors else '?'}"
        result = "all cells" if not errors and ran == len(prompts) else stopped
        seconds = time.monotonic() - start
        requests_blocked = len(blocked) - blocked_before
        figures["notebooks"].append({"notebook": path.name, "cells run": f"{ran}/{len(prompts)}",
                                     "result": result[:160], "seconds": round(seconds, 1),
                                     "first cell after s": round(first, 1),
                                     "requests blocked": requests_blocked})
        print(f"\n{path.name:38} {ran:>3}/{len(prompts):<3} {seconds:6.1f} s  blocked {requests_blocked}"
              f"  {result[:120]}")
        assert not errors and ran == len(prompts), (ran, len(prompts), errors[:3])
        if build_site.needs_plotting(json.loads(path.read_text())):
            _pictures_shown(page, path)
        if path.name == "02_function_codes.ipynb":
            _exercise_and_panel(page)
        if serial:
            _web_serial_panel(page, serial[1], figures)
    finally:
        page.context.close()
    assert blocked == [], f"{len(blocked)} requests tried to leave the site: {blocked[:5]}"


def _pictures_shown(page, path: Path) -> None:
    """Offline, each cell that drew a picture when the course was built shows that picture (a PNG the
    size the build drew it), with its words and the one line that says where to change it."""
    drawn = [cell for cell in json.loads(path.read_text())["cells"] if cell["cell_type"] == "code"
             and any("image/png" in output.get("data", {}) for output in cell.get("outputs", []))]
    images = page.locator('.jp-OutputArea-output img[src^="data:image/png"]')
    assert images.count() >= len(drawn) > 0, (images.count(), len(drawn))
    line = "drawn from this cell when the course was built"
    lines = page.locator(".jp-OutputArea-output").filter(has_text=line)
    assert lines.count() == len(drawn)
    words = page.locator(".jp-OutputArea-output").filter(has_text=FIGURE_IN_WORDS)  # each with its words
    assert words.count() >= len(drawn), (words.count(), len(drawn))
    assert all(box["width"] > 300 for box in (image.bounding_box() for image in images.all()))


def _exercise_and_panel(page) -> None:
    """In a notebook that ran: a build exercise judged in the browser; the frame builder following typing."""
    # a learner's own CRC, typed as one line (the library's own crc16 is refused: "write your own")
    own_crc = ("def crc16(data):\\n    reg = 0xFFFF\\n    for b in data:\\n        reg ^= b\\n"
               "        for _ in range(8):\\n"
               "            reg = (reg >> 1) ^ 0xA001 if reg & 1 else reg >> 1\\n"
               "    return reg")
    right = _run_cell(page, f'exec("{own_crc}"); from modbus_edu.exercises import check; '
                            'check("03.5", crc16)')
    assert "Right!" in right, right
    wrong = _run_cell(page, "from modbus_edu.exercises.misconceptions import crc16_unreflected; "
                            'check("03.5", crc16_unreflected)')
    assert "Not yet" in wrong and "An unreflected CRC" in wrong, wrong
    fb = page.locator(".mbe-framebuilder").first
    fb.scroll_into_view_if_needed()
    address = fb.locator(".mbe-field-address input")
    address.click()
    page.keyboard.press("Control+A")
    page.keyboard.type("107", delay=40)
    page.wait_for_function(
        "(el) => el.querySelector('.mbe-frame-hex').innerText.includes('00 6B')",
        arg=fb.element_handle(), timeout=30_000)


def _web_serial_panel(page, transcript: Path, figures: dict) -> None:
    """16's "From the browser" cell shows the Web Serial panel as the page's widget, from the site's own
    anywidget (its wheel for the kernel, its extension for the page), not as the still picture of a
    button: the enabled *choose serial port* button and its line.  Then requests through it: the page's
    ``navigator.serial`` is the tests' stand-in (tests/browser/serial_stand_in.js), its port a WebSocket
    to pymodbus's RTU server behind a pty (tests/browser/serial_bridge.py).  JupyterLite's kernel hands
    the page's messages to Python only between cells: a read awaited in one cell times out and says so
    (not "check the wiring"); a read started as a task in one cell has its answer in the next."""
    page.locator(".jp-OutputArea-output .mbe-webserial").first.wait_for(state="attached", timeout=30_000)
    web = page.evaluate(f"({lite_probe.web_serial('document')})")
    assert web["navigator_serial"], web
    assert lite_probe.web_serial_shown(web), web
    panel = page.locator(".jp-OutputArea-output .mbe-webserial").first
    panel.locator(".mbe-webserial-choose").click()
    page.wait_for_function("(el) => el.innerText.includes('port open')", arg=panel.element_handle(),
                           timeout=30_000)
    awaited = _run_cell(page, "import asyncio; lite_master = mb.Master(port, timeout=1.0); "
                              "print(*await asyncio.gather(lite_master.aread_holding_registers("
                              "unit=1, address=0, count=2), return_exceptions=True))")
    start = time.monotonic()
    _run_cell(page, "lite_task = asyncio.ensure_future("
                    "lite_master.aread_holding_registers(unit=1, address=2, count=2))")
    deadline = start + 30
    answer = "waiting"
    while "waiting" in answer and time.monotonic() < deadline:  # each cell lets the page's bytes in
        answer = _run_cell(page, "print('read:', lite_task.result() if lite_task.done() else 'waiting')")
    figures["web_serial_task_read_s"] = round(time.monotonic() - start, 2)
    bridge_log = [json.loads(line) for line in transcript.read_text().splitlines()]
    figures["web_serial_transcript"] = bridge_log
    assert "only between cells" in awaited and "task.result() in the next" in awaited, awaited
    assert "read: [102, 103]" in answer, answer
    assert [e["hex"] for e in bridge_log if e["dir"] == "page->slave"] == [
        "01 03 00 00 00 02 c4 0b", "01 03 00 02 00 02 65 cb"]


def test_a_cell_that_stops_is_shown_and_the_busy_indicator_follows_the_kernel(site, figures):
    """Run All stops at a cell that raises: the page scrolls that cell's message into view (Run All had
    left it at the last cell), and the toolbar's indicator turns idle with the status bar (JupyterLite's
    kernel client cancels the queued cells without the idle status the indicator waits for: the site's
    page script gives it)."""
    fresh_context, origin, blocked = site
    page = _open(fresh_context, origin, "00_welcome.ipynb")
    try:
        page.locator(".jp-NotebookPanel .jp-CodeCell").nth(2).click()
        page.keyboard.press("Escape")
        page.keyboard.press("b")
        page.keyboard.press("Enter")
        page.keyboard.type("raise ValueError('the one line the learner must see')")
        page.keyboard.press("Escape")
        lab_driver.run_all_cells(page)
        deadline = time.monotonic() + RUN_TIMEOUT_S
        while time.monotonic() < deadline:
            prompts = _prompts(page)
            status = page.locator(".jp-StatusBar-Widget").first.inner_text()
            if "[*]:" not in prompts and "[ ]:" in prompts and "| Idle" in status:
                break
            page.wait_for_timeout(250)
        else:
            raise TimeoutError(f"Run All did not stop: {_prompts(page)}")
        stopped_at = time.monotonic()
        page.wait_for_selector('.jp-Notebook-ExecutionIndicator[data-status="idle"]', timeout=10_000)
        figures["indicator_idle_after_status_bar_s"] = round(time.monotonic() - stopped_at, 1)
        message = page.locator(".jp-OutputArea-output").filter(has_text="the one line the learner must see")
        message.first.wait_for(state="visible")
        page.wait_for_timeout(2000)  # the page script scrolls 0.15, 0.6 and 1.5 s after the error
        box = message.first.bounding_box()
        viewport = page.viewport_size
        assert box is not None and 0 <= box["y"] and box["y"] + box["height"] <= viewport["height"], box
        active = page.locator(".jp-Notebook .jp-Cell.jp-mod-active")
        assert "the one line the learner must see" in active.inner_text()
    finally:
        page.context.close()
    assert blocked == []
