"""Drive a JupyterLab page with playwright: open a notebook, run all its cells, wait for the kernel.

Only stable JupyterLab 4 hooks are used: command ids on menu items (``data-command``), the notebook's
execution indicator (``data-status``) and the cells' input prompts ("[3]:" once a cell has run).
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable

BROWSER_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
CHROMIUM = "/usr/bin/chromium"


def wait_kernel_idle(page, timeout_ms: int = 60_000) -> None:
    """Wait until the notebook's kernel reports idle."""
    page.wait_for_selector('.jp-Notebook-ExecutionIndicator[data-status="idle"]', timeout=timeout_ms)


def accept_dialogs(page, settle_ms: int = 0) -> int:
    """Accept any JupyterLab dialog on the page (e.g. "Select Kernel", whose default is the notebook's
    own kernel); wait up to ``settle_ms`` for one to appear.  Returns how many were accepted."""
    accepted = 0
    deadline = time.monotonic() + settle_ms / 1000
    while True:
        dialog = page.locator(".jp-Dialog")
        if dialog.count():
            button = dialog.locator(".jp-Dialog-button.jp-mod-accept").first
            if button.count():
                button.click()
                accepted += 1
                page.wait_for_timeout(200)
                continue
        if time.monotonic() >= deadline:
            return accepted
        page.wait_for_timeout(100)


def open_notebook(page, url: str, timeout_ms: int = 60_000) -> None:
    """Load JupyterLab at the notebook's URL and wait for the notebook and its kernel."""
    page.goto(url, wait_until="domcontentloaded", timeout=timeout_ms)
    page.wait_for_selector(".jp-NotebookPanel .jp-Cell", timeout=timeout_ms)
    accept_dialogs(page, settle_ms=1000)
    wait_kernel_idle(page, timeout_ms)
    accept_dialogs(page)


def _prompts(page) -> list[str]:
    return [p.strip() for p in page.locator(".jp-CodeCell .jp-InputArea-prompt").all_inner_texts()]


def run_all_cells(page, attempts: int = 4) -> None:
    """Run every cell through the Run menu: Run > Run All Cells (command ``runmenu:run-all``).

    Right after the page loads the command can still be disabled (the notebook's session is not wired
    yet): then the menu is closed again and the click retried, until some cell shows "[*]" or a number.
    """
    for _ in range(attempts):
        accept_dialogs(page)
        page.locator(".lm-MenuBar-item", has_text=re.compile(r"^Run$")).first.click()
        item = page.locator('.lm-Menu-item[data-command="runmenu:run-all"]')
        item.wait_for(state="visible", timeout=10_000)
        if "lm-mod-disabled" in (item.get_attribute("class") or ""):
            page.keyboard.press("Escape")
            page.wait_for_timeout(500)
            continue
        item.click()
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline:
            if any(re.fullmatch(r"\[(\*|\d+)\]:", p) for p in _prompts(page)):
                return
            page.wait_for_timeout(100)
    raise TimeoutError("Run > Run All Cells did not start the cells")


class NothingRan(TimeoutError):
    """Run All was accepted, yet no cell ran: the first kernel died while starting (on a loaded
    machine its start can be cut short) and the cells queued for it went with it."""


def run_all(page, timeout_s: float, restart: bool = False, attempts: int = 3,
            on_retry: Callable[[], object] | None = None) -> list[str]:
    """Run > Run All Cells (or Kernel > Restart Kernel and Run All Cells) and wait for every cell; when
    no cell ran at all (:class:`NothingRan`), call ``on_retry`` and ask again, at most ``attempts``
    times."""
    deadline = time.monotonic() + timeout_s
    for attempt in range(attempts):
        (restart_and_run_all if restart else run_all_cells)(page)
        try:
            return wait_all_cells_ran(page, max(10.0, deadline - time.monotonic()))
        except NothingRan:
            if attempt == attempts - 1:
                raise
            wait_kernel_idle(page)
            if on_retry is not None:
                on_retry()
    raise AssertionError("unreachable")


def wait_all_cells_ran(page, timeout_s: float = 60.0) -> list[str]:
    """Wait until every code cell shows an execution count ("[n]:"), then for the kernel to be idle.

    Cells run in order, so once the last cell has its number and the kernel has stayed idle for a few
    seconds, an earlier prompt still showing "[*]:" is a prompt the page did not redraw: accepted.
    Returns the prompts it saw.
    """
    deadline = time.monotonic() + timeout_s
    prompts: list[str] = []
    idle_since = None
    while time.monotonic() < deadline:
        prompts = _prompts(page)
        numbered = [bool(re.fullmatch(r"\[\d+\]:", p)) for p in prompts]
        if prompts and all(numbered):
            wait_kernel_idle(page, int(max(1.0, deadline - time.monotonic()) * 1000))
            return prompts
        idle = page.locator('.jp-Notebook-ExecutionIndicator[data-status="idle"]').count() > 0
        if idle:
            idle_since = idle_since or time.monotonic()
            if time.monotonic() - idle_since > 3:
                if prompts and numbered[-1]:
                    return prompts
                if prompts and all(p == "[ ]:" for p in prompts) and time.monotonic() - idle_since > 6:
                    raise NothingRan(f"the kernel is idle and no cell ran; prompts: {prompts}")
                errors = cell_errors(page)
                if errors:  # Run All stopped at a cell that raised: say which, do not wait out the clock
                    raise RuntimeError("a cell raised, so Run All stopped:\n" + "\n".join(errors)[-3000:])
        else:
            idle_since = None
        time.sleep(0.2)
    raise TimeoutError(f"cells did not finish running; prompts: {prompts}")


def cell_errors(page) -> list[str]:
    """Texts of any error outputs (tracebacks) in the notebook."""
    return page.locator('.jp-OutputArea-output[data-mime-type="application/vnd.jupyter.stderr"], '
                        '.jp-RenderedText[data-mime-type="application/vnd.jupyter.error"]').all_inner_texts()


RESTART_TIMEOUT_S = 90
"""How long a Restart Kernel and Run All Cells may take to start the first cell (a new kernel starts)."""


def restart_and_run_all(page, attempts: int = 4) -> None:
    """Kernel > Restart Kernel and Run All Cells (command ``runmenu:restart-and-run-all``), accepting
    the "Restart kernel?" dialog; returns once some cell has started ("[*]:")."""
    for _ in range(attempts):
        accept_dialogs(page)
        page.locator(".lm-MenuBar-item", has_text=re.compile(r"^Kernel$")).first.click()
        item = page.locator('.lm-Menu-item[data-command="runmenu:restart-and-run-all"]')
        item.wait_for(state="visible", timeout=10_000)
        if "lm-mod-disabled" in (item.get_attribute("class") or ""):
            page.keyboard.press("Escape")
            page.wait_for_timeout(500)
            continue
        item.click()
        accept_dialogs(page, settle_ms=3000)
        # a restart starts a new kernel, which takes tens of seconds on a loaded machine: asking again
        # meanwhile finds no kernel to restart (JupyterLab's uncaught "No kernel to restart")
        deadline = time.monotonic() + RESTART_TIMEOUT_S
        while time.monotonic() < deadline:
            if any(p == "[*]:" or re.fullmatch(r"\[\d+\]:", p) for p in _prompts(page)):
                return
            page.wait_for_timeout(200)
        wait_kernel_idle(page)  # before asking again, whatever restart is under way has finished
    raise TimeoutError("Kernel > Restart Kernel and Run All Cells did not start the cells")


class ConsoleErrors:
    """Collect the page's JavaScript console errors and uncaught exceptions from now on."""

    #: Not the panels' doing: the browser's own requests (the favicon) and the offline lab's news.
    IGNORE = (re.compile(r"favicon"),)

    def __init__(self, page) -> None:
        self.errors: list[str] = []
        self.forgiven: list[str] = []
        page.on("console", self._console)
        page.on("pageerror", lambda exc: self.errors.append(f"uncaught: {exc}"))

    def forgive(self) -> None:
        """Set aside the errors so far: they belong to a kernel that died while starting (its
        websocket answered 500, then 404), before Run All was asked again; printed, not failed on."""
        self.forgiven += self.errors
        print(f"kernel start failed and Run All was asked again; its console errors: {self.errors}")
        self.errors = []

    def _console(self, msg) -> None:
        if msg.type == "error" and not any(p.search(msg.text) for p in self.IGNORE):
            self.errors.append(msg.text)
