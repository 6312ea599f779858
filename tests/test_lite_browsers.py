"""The offline Lite site in every browser a class brings: Chromium, Firefox ESR and WebKitGTK (Safari's
engine), each the Debian package, none downloaded.

* Chromium: playwright (tests/test_lite.py runs every notebook in it; here the same short notebook);
* Firefox ESR: puppeteer-core (npm, pinned in package.json and package-lock.json) over WebDriver BiDi,
  ``tests/browser/firefox_lite.mjs``;
* WebKitGTK: selenium (pinned in binder/requirements-test.txt) and Debian's ``WebKitWebDriver``, on a
  display of its own (Xvfb).

In each, one short notebook (:data:`~browser.lite_probe.NOTEBOOK`) is opened and run, and the same
questions are asked of the page (:mod:`browser.lite_probe`): the kernel starts (Pyodide 314.0.6, which
runs without JSPI, as Firefox and WebKit need), its first cell's ``%pip install`` works, an exercise's
``check`` gives its message, a panel renders as controls, a drawing cell shows its picture, and the Web
Serial panel (``mb.browser_serial``, an anywidget) renders from the site's own anywidget: where the
browser has ``navigator.serial`` (Firefox ESR 153) its *choose serial port* button, where it has not
(WebKitGTK; Chromium here, its ``navigator.serial`` removed) the one line that names Chrome or Edge.
The table (browser, version, the six answers, seconds) is printed and written to
tests/artifacts/lite_browsers.json.

A browser or driver that is missing skips its test with the reason; with ``CI`` set it is a failure.
The offline site is built (`make lite OFFLINE=1`) unless _site already is one.
"""

from __future__ import annotations

import functools
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
from http.server import ThreadingHTTPServer
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
from browser import lab_driver, lite_probe  # noqa: E402
from test_browser import _in_ci, _require_browser  # noqa: E402
from test_lite import ARTIFACTS, SITE, _make_lite, _Quiet  # noqa: E402

FIREFOX = "/usr/bin/firefox-esr"
WEBKIT_DRIVER = "/usr/bin/WebKitWebDriver"
START_TIMEOUT_S = 600  # Pyodide's start in a browser without a JIT tier it likes, on two shared cores
RUN_TIMEOUT_S = 600
pytestmark = pytest.mark.slow


def _missing(reason: str) -> None:
    if _in_ci():
        pytest.fail(reason + " -- and CI is set, so this is a failure, not a skip")
    pytest.skip(reason)


@pytest.fixture(scope="module")
def table():
    rows: list[dict] = []
    yield rows
    ARTIFACTS.mkdir(exist_ok=True)
    (ARTIFACTS / "lite_browsers.json").write_text(json.dumps(rows, indent=1) + "\n")
    print("\nbrowser        version                 kernel pip  check panel picture serial  seconds")
    for row in rows:
        marks = "  ".join("yes" if row[k] else "NO " for k in ("kernel", "pip", "check", "panel", "picture",
                                                               "web serial"))
        print(f"{row['browser']:14} {row['version'][:22]:22}  {marks}    {row['seconds']:6.1f}")


@pytest.fixture(scope="module")
def notebook_url():
    """The offline site on 127.0.0.1, and the URL of the probe's notebook in it."""
    if not (SITE / "static" / "pyodide" / "pyodide.mjs").exists():
        _make_lite(offline=True)
    server = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(SITE)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    yield f"http://127.0.0.1:{server.server_address[1]}/lab/index.html?path={lite_probe.NOTEBOOK}"
    server.shutdown()


def _record(table: list, browser: str, version: str, result: dict, seconds: float) -> dict:
    answers = lite_probe.judge(result)
    table.append({"browser": browser, "version": version, **answers, "seconds": round(seconds, 1),
                  "result": result})
    return answers


def _assert_all(answers: dict, result: dict) -> None:
    assert all(answers.values()), (answers, {k: v for k, v in result.items() if k != "user_agent"})


def test_chromium(notebook_url, table):
    """Chromium, here with its ``navigator.serial`` taken away before the page loads (as in a browser
    without Web Serial): the panel must say so in its one line (tests/test_lite.py sees Chromium's own
    Web Serial in notebook 16, its button and a read through it)."""
    sync_playwright = _require_browser()
    start = time.monotonic()
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=lab_driver.CHROMIUM, args=lab_driver.BROWSER_ARGS)
        page = browser.new_page(viewport={"width": 1400, "height": 900})
        page.add_init_script("delete Navigator.prototype.serial;")
        page.goto(notebook_url, wait_until="domcontentloaded", timeout=120_000)
        page.wait_for_function(lite_probe.READY, timeout=START_TIMEOUT_S * 1000, polling=500)
        page.evaluate(lite_probe.RUN_ALL)
        page.wait_for_function(lite_probe.DONE, timeout=RUN_TIMEOUT_S * 1000, polling=500)
        result = page.evaluate(lite_probe.RESULT)
        version = browser.version
        browser.close()
    _assert_all(_record(table, "Chromium", f"{version} (no navigator.serial)", result,
                        time.monotonic() - start), result)
    assert not result["web_serial"]["navigator_serial"], result["web_serial"]


def test_firefox_esr(notebook_url, table):
    """Firefox ESR driven over WebDriver BiDi by puppeteer-core (no browser download)."""
    node, npm = shutil.which("node"), shutil.which("npm")
    if not os.path.exists(FIREFOX) or node is None or npm is None:
        _missing(f"Firefox ESR ({FIREFOX}: apt-get install firefox-esr), node and npm are needed")
    if not (ROOT / "node_modules" / "puppeteer-core" / "package.json").exists():
        subprocess.run([npm, "ci", "--ignore-scripts", "--no-audit", "--no-fund"], cwd=ROOT, check=True,
                       capture_output=True, timeout=600)
    start = time.monotonic()
    done = _run_group([node, str(HERE / "browser" / "firefox_lite.mjs"), FIREFOX], _spec(notebook_url),
                      dict(os.environ), START_TIMEOUT_S + RUN_TIMEOUT_S + 120)
    lines = done.stdout.strip().splitlines()
    assert done.returncode == 0 and lines, (done.returncode, done.stdout[-2000:], done.stderr[-2000:])
    out = json.loads(lines[-1])
    result = out["results"][-1]
    _assert_all(_record(table, "Firefox ESR", out["browser"], result, time.monotonic() - start), result)


@pytest.fixture
def display():
    """A display of its own for WebKitGTK: Xvfb, on the first free display number."""
    xvfb = shutil.which("Xvfb")
    if xvfb is None:
        _missing("Xvfb is needed for WebKitGTK (apt-get install xvfb)")
    read, write = os.pipe()
    server = subprocess.Popen([xvfb, "-displayfd", str(write), "-screen", "0", "1400x900x24", "-nolisten",
                               "tcp"], pass_fds=[write], stderr=subprocess.DEVNULL)
    os.close(write)
    try:
        said = b""
        while not said.endswith(b"\n"):  # the number and its newline may come in two writes: closing the
            chunk = os.read(read, 16)      # pipe between them stops Xvfb ("Cannot write display number")
            if not chunk:
                break
            said += chunk
        os.close(read)
        number = said.decode().strip()
        if not number or server.poll() is not None:
            pytest.fail("Xvfb did not start")
        yield f":{number}"
    finally:
        server.terminate()
        server.wait(timeout=10)


def test_webkitgtk(notebook_url, table, display):
    """WebKitGTK, Safari's engine: Debian's WebKitWebDriver driven by selenium, on Xvfb, in a process
    group of its own (tests/browser/webkit_lite.py) that is ended, browser and all, at the deadline."""
    if not os.path.exists(WEBKIT_DRIVER):
        _missing(f"WebKitGTK's driver ({WEBKIT_DRIVER}: apt-get install webkit2gtk-driver) is needed")
    start = time.monotonic()
    done = _run_group([sys.executable, str(HERE / "browser" / "webkit_lite.py")], _spec(notebook_url),
                      dict(os.environ, DISPLAY=display), START_TIMEOUT_S + RUN_TIMEOUT_S + 120)
    lines = done.stdout.strip().splitlines()
    told = "\n".join(line[:1600] for line in done.stderr.splitlines() if line.startswith("["))
    assert done.returncode == 0 and lines, f"exit {done.returncode}; it said:\n{told}\n{done.stderr[-1500:]}"
    out = json.loads(lines[-1])
    result = out["results"][-1]
    _assert_all(_record(table, "WebKitGTK", out["browser"], result, time.monotonic() - start), result)


def _spec(notebook_url: str) -> str:
    """The steps every driven browser takes: the kernel ready, run all, every cell done, the answers."""
    return json.dumps({"url": notebook_url, "steps": [
        {"poll": lite_probe.READY, "timeout_s": START_TIMEOUT_S},
        {"eval": lite_probe.RUN_ALL},
        {"poll": lite_probe.DONE, "timeout_s": RUN_TIMEOUT_S},
        {"eval": lite_probe.RESULT}]})


def _run_group(command: list[str], stdin: str, env: dict, timeout_s: float) -> subprocess.CompletedProcess:
    """Run ``command`` in a session of its own; at the deadline the whole group (a driver and the
    browser it started) is killed, and the test fails with what the run had said so far."""
    process = subprocess.Popen(command, cwd=ROOT, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = process.communicate(stdin, timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        out, err = process.communicate()
        pytest.fail(f"{command[-1]} did not end within {timeout_s:.0f} s; it said:\n{err[-3000:]}")
    return subprocess.CompletedProcess(command, process.returncode, out, err)


STALLING_DRIVER = '''#!{python}
"""A WebKitWebDriver that starts a browser (a sleeping child), then never answers a new session."""
import os, subprocess, sys, time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
browser = subprocess.Popen(["sleep", "600"])
with open({pids!r}, "a") as pids:
    pids.write(f"{{browser.pid}}\\n")
class Stall(BaseHTTPRequestHandler):
    def do_GET(self):  # the driver's status: ready
        body = b'{{"value": {{"ready": true, "message": ""}}}}'
        self.send_response(200)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)
        if self.path == "/shutdown":
            os._exit(0)
    def do_POST(self):
        time.sleep(600)
ThreadingHTTPServer(("127.0.0.1", int(sys.argv[sys.argv.index("-p") + 1])), Stall).serve_forever()
'''


def test_a_webkit_session_that_never_starts_is_tried_again_and_ended(tmp_path):
    """The driver's session start has a deadline of its own: a driver whose browser never answers is
    tried again, and each failed try ends the driver and the browser it started (no process is left)."""
    pids = tmp_path / "browsers"
    driver = tmp_path / "WebKitWebDriver"
    driver.write_text(STALLING_DRIVER.format(python=sys.executable, pids=str(pids)))
    driver.chmod(0o755)
    script = ("import sys; sys.path.insert(0, 'tests/browser'); import webkit_lite as w; "
              f"w.DRIVER = {str(driver)!r}; w.SESSION_TIMEOUT_S = 2; w.SESSION_TRIES = 2; w.start_session()")
    done = _run_group([sys.executable, "-c", script], "", dict(os.environ), 60)
    assert done.returncode != 0
    said = done.stderr
    assert "try 1: no session (ReadTimeoutError" in said and "try 2: no session" in said, said
    assert "gave no session in 2 tries of 2 s" in done.stderr
    started = [int(pid) for pid in pids.read_text().split()]
    assert len(started) == 2
    for pid in started:
        try:
            os.waitpid(pid, os.WNOHANG)
        except ChildProcessError:
            pass
        stat = Path(f"/proc/{pid}/stat")
        assert not stat.exists() or stat.read_text().split()[2] == "Z", pid  # gone, or dead and unreaped
