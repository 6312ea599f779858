"""Run steps in WebKitGTK (Safari's engine): Debian's WebKitWebDriver driven by selenium, in a process of
its own so that the test can always end it (the driver and the browser with it).

Reads a JSON spec on stdin, as ``firefox_lite.mjs`` does: ``{"url": ..., "steps": [{"poll": expression,
"timeout_s": seconds} | {"eval": expression}]}``.  ``DISPLAY`` must name an X display.  Each stage is
told on stderr with the seconds since the start (so a run that ends early says where it was); the last
line on stdout is ``{"browser": version, "results": [the value of each eval]}``.

Every call to the driver has a deadline: selenium's HTTP client waits forever by default (its timeout
is the socket module's default, None), so a page that keeps its main thread busy would hold a call
forever.

Starting the session has a short deadline of its own and is tried again: WebKitWebDriver picks a free
port, lets it go, and tells the browser to listen there, then waits for it without end; a browser that
stalls on its way up (or a port taken in between) would hold the session's start forever. A failed
try ends the driver and every browser process it started (this process's group), and says what the
driver and the browser printed.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import sys
import tempfile
import time

from selenium import webdriver
from selenium.webdriver.webkitgtk.options import Options
from selenium.webdriver.webkitgtk.service import Service

DRIVER = "/usr/bin/WebKitWebDriver"
CALL_TIMEOUT_S = 300  # one WebDriver command: a loaded machine may keep WebKit's main thread busy for a
# minute or more while Pyodide starts (a poll is many short commands; the test's deadline bounds them all)
SESSION_TIMEOUT_S = 90  # a session starts in about a second here; under load, in tens of seconds
SESSION_TRIES = 3
START = time.monotonic()


def told(stage: str) -> None:
    print(f"[{time.monotonic() - START:7.1f} s] {stage}", file=sys.stderr, flush=True)


def end_the_rest() -> None:
    """Kill every process of this process's group but this one: a driver and the browser it started."""
    group = os.getpgid(0)
    for entry in os.listdir("/proc"):
        try:
            if entry.isdigit() and int(entry) != os.getpid() and os.getpgid(int(entry)) == group:
                os.kill(int(entry), signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass


def start_session() -> webdriver.WebKitGTK:
    """A session, within ``SESSION_TIMEOUT_S`` a try and ``SESSION_TRIES`` tries; then every call gets
    ``CALL_TIMEOUT_S``."""
    for attempt in range(1, SESSION_TRIES + 1):
        with tempfile.TemporaryFile("w+") as log:
            socket.setdefaulttimeout(SESSION_TIMEOUT_S)  # read by selenium's client when the driver is made
            service = Service(executable_path=DRIVER, env=dict(os.environ), log_output=log)
            try:
                driver = webdriver.WebKitGTK(options=Options(), service=service)
            except Exception as exc:  # noqa: BLE001 - said, and tried again with a new driver and browser
                end_the_rest()
                log.seek(0)
                said = " | ".join(log.read().strip().splitlines()[-8:])[-1500:]
                told(f"try {attempt}: no session ({type(exc).__name__}: {str(exc)[:200]}); "
                     f"the driver and browser said: {said or 'nothing'}")
                continue
        driver.command_executor._client_config.timeout = CALL_TIMEOUT_S
        told(f"session started (try {attempt})")
        return driver
    raise RuntimeError(f"WebKitWebDriver gave no session in {SESSION_TRIES} tries of {SESSION_TIMEOUT_S} s")


def main() -> int:
    spec = json.load(sys.stdin)
    driver = start_session()
    results = []
    try:
        driver.set_page_load_timeout(CALL_TIMEOUT_S - 30)
        driver.set_script_timeout(CALL_TIMEOUT_S)
        driver.set_window_size(1400, 900)
        try:
            driver.get(spec["url"])
            told("page loaded")
        except Exception as exc:  # noqa: BLE001 - a load event late or lost: the first poll's deadline rules
            told(f"the page's load not confirmed ({type(exc).__name__}): polling it all the same")
        for step in spec["steps"]:
            if "eval" in step:
                results.append(driver.execute_script("return " + step["eval"]))
                told("evaluated")
                continue
            deadline = time.monotonic() + step["timeout_s"]
            while True:
                try:
                    if driver.execute_script("return " + step["poll"]):
                        break
                except Exception as exc:  # noqa: BLE001 - the page is still loading: ask again
                    last = f"{type(exc).__name__}: {str(exc)[:200]}"
                else:
                    last = "false"
                if time.monotonic() >= deadline:
                    told(f"not true within {step['timeout_s']} s (last answer: {last}): {step['poll'][:120]}")
                    return 1
                time.sleep(0.5)
            told("true: " + step["poll"][:80])
        version = driver.capabilities.get("browserVersion", "?")
    finally:
        driver.quit()
    print(json.dumps({"browser": version, "results": results}))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except Exception as exc:
        told(f"stopped by {type(exc).__name__}: {str(exc)[:300]}")
        raise
