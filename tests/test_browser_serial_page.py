"""A real device from the browser, in Chromium: JupyterLab's page owns the serial port (Web Serial), the
kernel talks to it through the widget's messages.

The page gets a stand-in ``navigator.serial`` (tests/browser/serial_stand_in.js, injected before JupyterLab
loads) whose port is a WebSocket to a local bridge (tests/browser/serial_bridge.py, bound to 127.0.0.1):
behind it a pty, and on the pty's other end pymodbus's RTU server, a real third-party slave, whose answers
come back one byte per character time at 9600 baud. Through it:

* a notebook cell's master (``await master.awrite_multiple_registers`` then
  ``await master.aread_holding_registers``) writes two registers and reads them back, while the kernel
  keeps handling the widget's messages (ipykernel dispatches comm messages during an awaiting cell);
* in the same kernel, a *blocking* read is refused at once with the line that says to await;
* the test tool, connected to "browser serial port (Web Serial)" and clicked in the page, reads holding
  registers (its poll runs as a task on the kernel's loop);
* in a page without Web Serial (Firefox, Safari), the widget shows one line naming Chrome or Edge, a
  request prints that line, and Run All goes on to the last cell.

The transcript (the bridge's bytes each way, the stand-in's timing in the page) goes to
tests/artifacts/webserial_transcript.json. Skipped without chromium or playwright, failed in CI (as
tests/test_browser.py). Every wait has an absolute timeout.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import nbformat
import pytest

HERE = Path(__file__).resolve().parent
ARTIFACTS = HERE / "artifacts"
sys.path.insert(0, str(HERE))
from browser import lab_driver  # noqa: E402
from browser.jupyter_harness import KERNEL_NAME, JupyterLab  # noqa: E402
from test_browser import _require_browser  # noqa: E402

from modbus_edu.errors import LinkError  # noqa: E402
from modbus_edu.links.browser_serial import _NOT_OPEN  # noqa: E402

VIEWPORT = {"width": 1400, "height": 900}
STAND_IN = (HERE / "browser" / "serial_stand_in.js").read_text()
BRIDGE = HERE / "browser" / "serial_bridge.py"

DEVICE_CELLS = [
    'import modbus_edu as mb\nfrom modbus_edu.widgets import TestTool\n'
    'port = mb.browser_serial(baudrate=9600, parity="E")\nport',
    'master = mb.Master(port, timeout=2.0)\n'
    'await master.awrite_multiple_registers(unit=1, address=10, values=[4321, 8765])\n'
    'back = await master.aread_holding_registers(unit=1, address=10, count=2)\n'
    'print("read back:", back)\nprint("stats:", master.stats.summary())',
    'try:\n    master.read_holding_registers(unit=1, address=0, count=1)\n'
    'except mb.ModbusError as exc:\n    print("blocking:", exc)',
    'port.close()\ntool = TestTool("rtu_master")\n'
    'tool.baudrate.value, tool.parity.value, tool.length.value = 9600, "E", 4\n'
    'tool.connection.value = "browser"\ntool.connect()\ntool',
    'print("tool read:", tool.values, tool.counts)\nprint(tool.master.link.summary())',
]

NO_SERIAL_CELLS = [
    'import modbus_edu as mb\nport = mb.browser_serial(baudrate=9600, parity="E")\nport',
    'master = mb.Master(port, timeout=1.0)\ntry:\n'
    '    print(await master.aread_holding_registers(unit=1, address=0, count=2))\n'
    'except mb.ModbusError as exc:\n    print(exc)',
    'print("the rest of the notebook runs:", mb.crc16(b"123456789") == 0x4B37)',
]


def _notebook(path: Path, cells: list[str]) -> Path:
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(source) for source in cells]
    nb.metadata["kernelspec"] = {"name": KERNEL_NAME, "display_name": "modbus_edu test (project venv)",
                                 "language": "python"}
    nbformat.write(nb, path)
    return path


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    sync_playwright = _require_browser()
    root = tmp_path_factory.mktemp("webserial") / "root"
    root.mkdir()
    _notebook(root / "device.ipynb", DEVICE_CELLS)
    _notebook(root / "no_serial.ipynb", NO_SERIAL_CELLS)
    ARTIFACTS.mkdir(exist_ok=True)
    with JupyterLab(root) as server, sync_playwright() as p:
        server.browser = p.chromium.launch(executable_path=lab_driver.CHROMIUM, args=lab_driver.BROWSER_ARGS)
        try:
            yield server
        finally:
            server.browser.close()


@pytest.fixture
def bridge(tmp_path):
    """The bridge process: (its WebSocket URL, its transcript file); stopped at the end."""
    transcript = tmp_path / "bridge.jsonl"
    proc = subprocess.Popen([sys.executable, str(BRIDGE), "--baud", "9600", "--parity", "E",
                             "--transcript", str(transcript), "--lifetime", "600"],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        deadline = time.monotonic() + 30
        line = ""
        while time.monotonic() < deadline and not line.startswith("READY"):
            line = proc.stdout.readline()
            if not line and proc.poll() is not None:
                break
        assert line.startswith("READY"), f"the bridge did not start: {line}{proc.stdout.read()}"
        yield f"ws://127.0.0.1:{line.split()[1]}/serial", transcript
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(timeout=5)


def _page(lab, init_script: str | None):
    lab.shutdown_sessions()
    context = lab.browser.new_context(viewport=VIEWPORT)
    if init_script:
        context.add_init_script(init_script)
    page = context.new_page()
    page.set_default_timeout(30_000)
    return context, page, lab_driver.ConsoleErrors(page)


def _cell(page, index: int):
    return page.locator(".jp-Notebook .jp-CodeCell").nth(index)


def _run_cell(page, index: int, timeout_s: float = 60) -> str:
    """Run one cell (click it, Ctrl+Enter) and wait for its execution count; return its output text.
    Right after the page loads the notebook's session may not be wired yet: a cell that did not start
    ("[ ]:" after 5 s) is asked again, as lab_driver.run_all_cells does."""
    cell = _cell(page, index)
    prompt = cell.locator(".jp-InputArea-prompt")
    deadline = time.monotonic() + timeout_s
    before = prompt.inner_text().strip()
    while time.monotonic() < deadline:
        lab_driver.accept_dialogs(page)
        cell.locator(".jp-InputArea-editor").click()
        page.keyboard.press("Control+Enter")
        started = time.monotonic()
        while time.monotonic() < deadline:
            text = prompt.inner_text().strip()
            if text.startswith("[") and text[1:-2].isdigit() and text != before:
                lab_driver.wait_kernel_idle(page, int(max(1.0, deadline - time.monotonic()) * 1000))
                return cell.locator(".jp-OutputArea").inner_text()
            if text == "[ ]:" and time.monotonic() - started > 5:
                break  # not started: ask again
            page.wait_for_timeout(100)
    page.screenshot(path=str(ARTIFACTS / f"webserial_cell_{index}.png"))
    raise TimeoutError(f"cell {index} did not finish within {timeout_s} s: {prompt.inner_text()}")


def _choose_port(page, index: int) -> None:
    """Click the cell's 'choose serial port' button; wait until the page says the port is open."""
    cell = _cell(page, index)
    cell.locator(".mbe-webserial-choose").click()
    status = cell.locator(".mbe-webserial-status")
    try:
        page.wait_for_function("(el) => el.innerText.startsWith('port open')", arg=status.element_handle(),
                               timeout=15_000)
    except Exception as exc:
        page.screenshot(path=str(ARTIFACTS / f"webserial_port_{index}.png"))
        raise AssertionError(f"the port did not open; the page says: {status.inner_text()!r}; "
                             f"cell: {cell.inner_text()[-600:]!r}") from exc


def test_a_master_and_the_test_tool_reach_pymodbus_through_the_page_s_serial_port(lab, bridge):
    url, transcript = bridge
    context, page, console = _page(lab, STAND_IN.replace("__BRIDGE_URL__", url))
    try:
        lab_driver.open_notebook(page, lab.url("lab/workspaces/webserial/tree/device.ipynb?reset"))
        _run_cell(page, 0)
        _choose_port(page, 0)
        script = _run_cell(page, 1)
        blocking = _run_cell(page, 2)
        _run_cell(page, 3)
        _choose_port(page, 3)
        tool = _cell(page, 3)
        tool.locator(".mbe-tt-read").click()
        page.wait_for_function("(el) => el.innerText.includes('poll 1: Read Holding Registers')",
                               arg=tool.element_handle(), timeout=15_000)
        report = _run_cell(page, 4)
        timing = page.evaluate("window.__serialTiming")
    finally:
        context.close()
    bridge_log = [json.loads(line) for line in transcript.read_text().splitlines()]
    (ARTIFACTS / "webserial_transcript.json").write_text(json.dumps(
        {"bridge": bridge_log, "page": timing, "outputs": [script, blocking, report]}, indent=1) + "\n")

    assert "read back: [4321, 8765]" in script
    assert "2 requests: 2 valid" in script
    assert "blocking:" in blocking and "await master.aread_holding_registers" in blocking
    assert "tool read: [100, 101, 102, 103]" in report and "'valid': 1" in report
    sent = [entry["hex"] for entry in bridge_log if entry["dir"] == "page->slave"]
    assert sent[0] == "01 10 00 0a 00 02 04 10 e1 22 3d fe 57"  # FC 16: 4321, 8765 at 10
    assert sent[1] == "01 03 00 0a 00 02 e4 09"
    assert sent[2] == "01 03 00 00 00 04 44 09"  # the test tool's read once: the blocking call sent nothing
    assert len(sent) == 3
    received = [entry for entry in bridge_log if entry["dir"] == "slave->page"]
    # the slave's answers leave one byte per character time (11 bits at 9600 baud: 1.146 ms)
    gaps = [b["t"] - a["t"] for a, b in zip(received, received[1:]) if b["t"] - a["t"] < 0.05]
    assert len(received) == 8 + 9 + 13 and min(gaps) >= 0.00110
    assert [e["options"]["baudRate"] for e in timing if e["dir"] == "open"] == [9600, 9600]
    assert all(e["options"]["parity"] == "even" for e in timing if e["dir"] == "open")
    assert not console.errors, console.errors


def test_without_web_serial_one_line_names_chrome_or_edge_and_the_notebook_goes_on(lab):
    context, page, console = _page(lab, "delete Navigator.prototype.serial;")
    try:
        lab_driver.open_notebook(page, lab.url("lab/workspaces/noserial/tree/no_serial.ipynb?reset"))
        lab_driver.run_all(page, 120)
        line = _cell(page, 0).locator(".mbe-webserial-unavailable").inner_text()
        outputs = [_cell(page, i).locator(".jp-OutputArea").inner_text() for i in (1, 2)]
        has_serial = page.evaluate("'serial' in navigator")
    finally:
        context.close()
    assert not has_serial
    assert "Chrome or Edge" in line and "\n" not in line.strip()
    # the request says so in one line too: the page's own line once its word has reached the kernel, or,
    # under Run All (the cells' requests are queued ahead of the page's messages), that no port was chosen
    request = outputs[0].strip()
    assert "\n" not in request and "Chrome or Edge" in request
    assert request in (line.strip(), str(LinkError(_NOT_OPEN["waiting"])))
    assert "the rest of the notebook runs: True" in outputs[1]
    assert not console.errors, console.errors
