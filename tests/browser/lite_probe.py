"""What every browser is asked on the offline Lite site (tests/test_lite_browsers.py): JavaScript read in
the page through ``window.jupyterapp`` (the site exposes it for its page script), so that Chromium
(playwright), Firefox ESR (puppeteer-core over WebDriver BiDi) and WebKitGTK (selenium and
WebKitWebDriver) are asked the same questions and judged by the same :func:`judge`.

Each snippet is an expression; a driver evaluates it as a function body's ``return``.
"""

from __future__ import annotations

NOTEBOOK = "03_rtu_and_crc.ipynb"
"""One short notebook that has all five: the kernel, ``%pip install`` (every site notebook's first cell),
exercises and their ``check``, a panel (the CRC explorer) and cells that draw (offline: their pictures)."""

_PANEL = "(window.jupyterapp && window.jupyterapp.shell.currentWidget)"

READY = f"""(() => {{
  const w = {_PANEL};
  const kernel = w && w.sessionContext && w.sessionContext.session && w.sessionContext.session.kernel;
  return !!(kernel && kernel.status === "idle" && w.content && w.content.widgets.length > 0);
}})()"""
"""True once the notebook is open and its kernel has started (Pyodide loaded, idle)."""

RUN_ALL = """(() => { window.jupyterapp.commands.execute("notebook:run-all-cells"); return true; })()"""

DONE = f"""(() => {{
  const w = {_PANEL};
  const cells = w.content.widgets.filter((c) => c.model.type === "code");
  const kernel = w.sessionContext.session.kernel;
  const running = cells.some((c) => c.model.executionState === "running");
  return kernel.status === "idle" && !running && cells[0].model.executionCount !== null &&
    (cells[cells.length - 1].model.executionCount !== null ||
     !!w.content.node.querySelector('[data-mime-type="application/vnd.jupyter.stderr"]'));
}})()"""
"""True once Run All has finished (every cell ran, or one stopped it) and the kernel is idle."""

RESULT = f"""(() => {{
  const w = {_PANEL};
  const code = w.content.widgets.filter((c) => c.model.type === "code");
  const text = (c) => c.node.querySelector(".jp-OutputArea") ?
    c.node.querySelector(".jp-OutputArea").innerText.trim() : "";
  const errors = [...w.content.node.querySelectorAll(
    '[data-mime-type="application/vnd.jupyter.stderr"], [data-mime-type="application/vnd.jupyter.error"]')]
    .map((e) => e.innerText.trim()).filter((t) => t);
  const checks = code.filter((c) => /\\bcheck\\("/.test(c.model.sharedModel.getSource()));
  const panels = [...w.content.node.querySelectorAll(".jp-OutputArea-output .jupyter-widgets")]
    .filter((p) => p.querySelector("input, select, button, textarea"));
  const pictures = [...w.content.node.querySelectorAll('.jp-OutputArea-output img[src^="data:image/png"]')]
    .filter((i) => i.complete && i.naturalWidth > 300);
  return {{
    kernel: w.sessionContext.kernelDisplayName + " | " + w.sessionContext.session.kernel.status,
    cells: code.length,
    ran: code.filter((c) => c.model.executionCount !== null).length,
    pip_cell: {{ran: code[0].model.executionCount !== null,
               source: code[0].model.sharedModel.getSource().split("\\n")[1] || "", output: text(code[0])}},
    errors: errors,
    check_messages: checks.map(text).filter((t) => t),
    panel_controls: panels.length,
    pictures: pictures.length,
    user_agent: navigator.userAgent,
  }};
}})()"""


def judge(result: dict) -> dict[str, bool]:
    """The five questions, answered from a browser's :data:`RESULT`."""
    return {
        "kernel": result["kernel"].endswith("| idle") and result["ran"] == result["cells"],
        "pip": result["pip_cell"]["ran"] and "%pip install" in result["pip_cell"]["source"]
        and not result["errors"],
        "check": any("Exercise 03." in m and "not answered yet" in m for m in result["check_messages"]),
        "panel": result["panel_controls"] >= 1,
        "picture": result["pictures"] >= 1,
    }
