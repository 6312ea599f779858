"""What a screen reader is told about a panel: chromium's own accessibility tree, read over the DevTools
protocol (the computed role, name, description and states of each node, as assistive technology gets
them), and where the keyboard is in JupyterLab's notebook."""

from __future__ import annotations

import json

#: FontAwesome draws its icons with glyphs of Unicode's private use area: never a word.
PRIVATE_USE = range(0xE000, 0xF900)


def _session(page):
    cdp = getattr(page, "_mbe_cdp", None)
    if cdp is None:
        cdp = page.context.new_cdp_session(page)
        cdp.send("Accessibility.enable")
        page._mbe_cdp = cdp
    return cdp


def nodes(page, selector: str, role: str | None = None, name: str | None = None) -> list[dict]:
    """The accessibility nodes (not ignored) under the first element ``selector`` finds, by role and/or
    name, each as ``{"role", "name", "description", and every property: "pressed", "invalid", "live"...}``."""
    cdp = _session(page)
    found = cdp.send("Runtime.evaluate", {"expression": f"document.querySelector({json.dumps(selector)})"})
    query = {"objectId": found["result"]["objectId"]}
    if role:
        query["role"] = role
    if name:
        query["accessibleName"] = name
    out = []
    for node in cdp.send("Accessibility.queryAXTree", query)["nodes"]:
        if node.get("ignored"):
            continue
        item = {"role": node.get("role", {}).get("value"), "name": node.get("name", {}).get("value", ""),
                "description": node.get("description", {}).get("value", "")}
        for prop in node.get("properties", []):
            item[prop["name"]] = prop.get("value", {}).get("value")
        out.append(item)
    return out


def icon_glyphs(name: str) -> list[str]:
    """The private-use characters (icon glyphs) in an accessible name, as U+XXXX."""
    return [f"U+{ord(c):04X}" for c in name if ord(c) in PRIVATE_USE]


#: The notebook as the keyboard leaves it: which cell is active, each cell's type, and the panels shown.
NOTEBOOK_STATE = r"""
() => {
  const cells = [...document.querySelectorAll('.jp-NotebookPanel:not(.lm-mod-hidden) .jp-Notebook .jp-Cell')];
  return {active: cells.findIndex(c => c.classList.contains('jp-mod-active')),
          types: cells.map(c => c.classList.contains('jp-CodeCell') ? 'code'
                                : c.classList.contains('jp-MarkdownCell') ? 'markdown' : 'raw'),
          panels: document.querySelectorAll('.mbe-framebuilder, .mbe-crcexplorer, .mbe-testtool').length};
}
"""


def notebook_state(page) -> dict:
    return page.evaluate(NOTEBOOK_STATE)


__all__ = ["nodes", "icon_glyphs", "notebook_state", "PRIVATE_USE"]
