"""Run steps in WebKitGTK (Safari's engine): Debian's WebKitWebDriver driven by selenium, in a process of
its own so that the test can always end it (the driver and the browser with it).

Reads a JSON spec on stdin, as ``firefox_lite.mjs`` does: ``{"url": ..., "steps": [{"poll": expression,
"timeout_s": seconds} | {"eval": expression}]}``.  ``DISPLAY`` must name an X display.  Each stage is
told on stderr with the seconds since the start (so a run that ends early says where it was); the last
line on stdout is ``{"browser": version, "results": [the value of each eval]}``.

Every call to the driver has a deadline: selenium's HTTP client waits forever by default (its timeout
is the socket module's default, None), so a page that keeps its main thread busy would hold a call
forever.
"""

from __future__ import annotations

import json
import os
import socket
import sys
import time

from selenium import webdriver
from selenium.webdriver.webkitgtk.options import Options
from selenium.webdriver.webkitgtk.service import Service

DRIVER = "/usr/bin/WebKitWebDriver"
CALL_TIMEOUT_S = 300  # one WebDriver command: a loaded machine may keep WebKit's main thread busy for a
# minute or more while Pyodide starts (a poll is many short commands; the test's deadline bounds them all)
START = time.monotonic()


def told(stage: str) -> None:
    print(f"[{time.monotonic() - START:7.1f} s] {stage}", file=sys.stderr, flush=True)


def main() -> int:
    spec = json.load(sys.stdin)
    socket.setdefaulttimeout(CALL_TIMEOUT_S)  # read by selenium's client when the driver is made
    service = Service(executable_path=DRIVER, env=dict(os.environ))
    driver = webdriver.WebKitGTK(options=Options(), service=service)
    told("session started")
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
