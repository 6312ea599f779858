"""What every browser is asked on the offline Lite site (tests/test_lite_browsers.py): JavaScript read in
the page through ``window.jupyterapp`` (the site exposes it for its page script), so that Chromium
(playwright), Firefox ESR (puppeteer-core over WebDriver BiDi) and WebKitGTK (selenium and
WebKitWebDriver) are asked the same questions and judged by the same :func:`judge`.

Each snippet is an expression; a driver evaluates it as a function body's ``return``.
"""

from __future__ import annotations

import json

NOTEBOOK = "03_rtu_and_crc.ipynb"
"""One short notebook that has five of the six: the kernel, ``%pip install`` (every site notebook's first
cell), exercises and their ``check``, a panel (the CRC explorer) and cells that draw (offline: their
pictures); the sixth, the Web Serial panel (anywidget), is a cell the probe adds (:data:`WEB_SERIAL_CELL`)."""

_PANEL = "(window.jupyterapp && window.jupyterapp.shell.currentWidget)"

READY = f"""(() => {{
  const w = {_PANEL};
  const kernel = w && w.sessionContext && w.sessionContext.session && w.sessionContext.session.kernel;
  return !!(kernel && kernel.status === "idle" && w.content && w.content.widgets.length > 0);
}})()"""
"""True once the notebook is open and its kernel has started (Pyodide loaded, idle)."""

WEB_SERIAL_CELL = 'import modbus_edu as mb\nmb.browser_serial(baudrate=9600, parity="E")  # Web Serial'
"""The cell the probe adds at the notebook's end before Run All: the Web Serial panel, shown."""

RUN_ALL = f"""(() => {{
  const w = {_PANEL};
  const cells = w.content.model.sharedModel;
  const source = {json.dumps(WEB_SERIAL_CELL)};
  const n = cells.cells.length;
  if (n === 0 || cells.cells[n - 1].getSource() !== source) {{
    cells.insertCell(cells.cells.length, {{cell_type: "code", source: source}});
  }}
  // the last moment the kernel was seen anything but idle (a widget that renders after the last cell
  // sends its model a message, and the kernel is busy again for a moment): see DONE
  if (window.mbeBusyAt === undefined) {{
    window.mbeBusyAt = Date.now();
    w.sessionContext.statusChanged.connect((_, status) => {{
      if (status !== "idle") window.mbeBusyAt = Date.now();
    }});
  }}
  // Run All once the notebook has made the new cell's widget
  setTimeout(() => window.jupyterapp.commands.execute("notebook:run-all-cells"), 250);
  return true;
}})()"""
"""Add :data:`WEB_SERIAL_CELL` at the end (once), then Run All."""

DONE = f"""(() => {{
  const w = {_PANEL};
  const cells = w.content.widgets.filter((c) => c.model.type === "code");
  const kernel = w.sessionContext.session.kernel;
  const running = cells.some((c) => c.model.executionState === "running");
  const last = cells[cells.length - 1];
  // the last cell (the Web Serial panel) shows its widget, or what stands in for it, or an error
  const shown = !!last.node.querySelector(
    ".mbe-webserial, .mbe-webserial-picture, .jp-OutputArea-output pre, " +
    '[data-mime-type="application/vnd.jupyter.stderr"]');
  const settled = Date.now() - (window.mbeBusyAt || 0) >= 2000;
  return kernel.status === "idle" && settled && !running && cells[0].model.executionCount !== null &&
    ((last.model.executionCount !== null && shown) ||
     !!w.content.node.querySelector('[data-mime-type="application/vnd.jupyter.stderr"]'));
}})()"""
"""True once Run All has finished (every cell ran and the last one shows its output, or one cell stopped
it) and the kernel has been idle for 2 s (the widgets' own messages answered)."""

def web_serial(root: str) -> str:
    """An expression: what the Web Serial panels in the outputs under ``root`` (a JavaScript expression
    for an element) show, for :func:`web_serial_shown`."""
    found = f"(s) => [...{root}.querySelectorAll('.jp-OutputArea-output ' + s)]"
    return f"""{{
      navigator_serial: "serial" in navigator,
      choose: ({found})(".mbe-webserial-choose")
        .map((b) => ({{text: b.innerText.trim(), enabled: !b.disabled}})),
      status: ({found})(".mbe-webserial-status").map((e) => e.innerText.trim()),
      unavailable: ({found})(".mbe-webserial-unavailable").map((e) => e.innerText.trim()),
      picture: ({found})(".mbe-webserial-picture").length > 0,
    }}"""


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
    web_serial: {web_serial("w.content.node")},
    user_agent: navigator.userAgent,
  }};
}})()"""


def web_serial_shown(web: dict) -> bool:
    """The Web Serial panel rendered as the page's widget (not the still picture a page without anywidget's
    extension shows): with ``navigator.serial`` (Chromium; Firefox ESR 153 has it too), its enabled
    *choose serial port* button and its status line; without it (WebKitGTK), no button and the one line
    naming Chrome or Edge."""
    if web["picture"]:
        return False
    if web["navigator_serial"]:
        return (web["choose"] == [{"text": "choose serial port", "enabled": True}]
                and web["status"] == ["no port chosen yet"] and not web["unavailable"])
    return (not web["choose"] and len(web["unavailable"]) == 1
            and "no Web Serial" in web["unavailable"][0] and "Chrome or Edge" in web["unavailable"][0])


def judge(result: dict) -> dict[str, bool]:
    """The six questions, answered from a browser's :data:`RESULT`."""
    return {
        "kernel": result["kernel"].endswith("| idle") and result["ran"] == result["cells"],
        "pip": result["pip_cell"]["ran"] and "%pip install" in result["pip_cell"]["source"]
        and not result["errors"],
        "check": any("Exercise 03." in m and "not answered yet" in m for m in result["check_messages"]),
        "panel": result["panel_controls"] >= 1,
        "picture": result["pictures"] >= 1,
        "web serial": web_serial_shown(result["web_serial"]),
    }
