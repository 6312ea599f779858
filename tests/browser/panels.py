"""What every panel must be in a real browser (issue 12), measured with the page's own layout.

* rendered as controls (inputs, selects or buttons, not the text fallback);
* at most :data:`MAX_HEIGHT` px tall, in each of its tabs;
* nothing wider than the box that holds it unless that box scrolls (no clipped frames or logs), the
  panel within the output area, and the panel and its tabs never scrolling sideways (their content
  fits their width);
* logs that scroll inside their own box, both ways.
"""

from __future__ import annotations

import re
from pathlib import Path

MAX_HEIGHT = 700
PANEL_CLASSES = ("mbe-framebuilder", "mbe-framedecoder", "mbe-crcexplorer", "mbe-testtool",
                 "mbe-meterdashboard")
PANEL_SELECTOR = ", ".join(f".{c}" for c in PANEL_CLASSES)

# For one panel: its size, the output area's width, and every visible element that sticks out of the
# nearest box that clips it (overflow other than visible) while that box does not scroll.
_MEASURE = r"""
(panel) => {
  const outer = panel.closest('.jp-OutputArea-output') || panel.parentElement;
  const describe = el => el.tagName.toLowerCase() + (el.className && typeof el.className === 'string'
      ? '.' + el.className.trim().split(/\s+/).slice(0, 3).join('.') : '');
  const clips = el => getComputedStyle(el).overflowX !== 'visible';
  const scrolls = el => ['auto', 'scroll'].includes(getComputedStyle(el).overflowX);
  const problems = [];
  for (const el of panel.querySelectorAll('*')) {
    const r = el.getBoundingClientRect();
    if (r.width === 0 || r.height === 0 || el.offsetParent === null) continue;
    let box = el.parentElement;
    while (box && box !== outer && !clips(box)) box = box.parentElement;
    if (!box) continue;
    const b = box.getBoundingClientRect();
    if ((r.right > b.right + 1 || r.left < b.left - 1) && !scrolls(box)) {
      problems.push(`${describe(el)} (${Math.round(r.left)}..${Math.round(r.right)}) sticks out of `
        + `${describe(box)} (${Math.round(b.left)}..${Math.round(b.right)}), which does not scroll`);
    }
  }
  // the panel and its tabs never scroll sideways: their content fits the width they have
  for (const el of [panel, ...panel.querySelectorAll('.jupyter-widget-tab, .widget-tab-contents')]) {
    if (el.offsetParent !== null && el.scrollWidth > el.clientWidth + 1) {
      problems.push(`${describe(el)} overflows sideways: ${el.scrollWidth} px of content in `
        + `${el.clientWidth} px`);
    }
  }
  const p = panel.getBoundingClientRect(), o = outer.getBoundingClientRect();
  if (p.right > o.right + 1) {
    problems.push(`the panel (right ${p.right}) runs past the output area (${o.right})`);
  }
  return {height: p.height, width: p.width, outputWidth: o.width, contentWidth: panel.scrollWidth,
          innerWidth: panel.clientWidth,
          controls: panel.querySelectorAll('input, select, textarea, button').length,
          problems: problems.slice(0, 10)};
}
"""

_SCROLL = r"""
(log) => {
  const s = getComputedStyle(log);
  const before = log.scrollLeft;
  log.scrollLeft = 60;
  const movedX = log.scrollLeft !== before;
  log.scrollLeft = before;
  return {overflowX: s.overflowX, overflowY: s.overflowY, scrollWidth: log.scrollWidth,
          clientWidth: log.clientWidth, scrollHeight: log.scrollHeight, clientHeight: log.clientHeight,
          movedX: movedX};
}
"""


def panel_kind(panel) -> str:
    classes = panel.get_attribute("class") or ""
    return next((c.removeprefix("mbe-") for c in PANEL_CLASSES if c in classes.split()), "panel")


def measure(panel) -> dict:
    panel.scroll_into_view_if_needed()
    return panel.evaluate(_MEASURE)


def tab_titles(panel) -> list:
    """The tab titles of the panel's own tab bar (TestTool, MeterDashboard), else []."""
    return panel.locator(".lm-TabBar-tab").all()


def check_panel(page, panel, name: str, artifacts: Path) -> dict:
    """Measure one panel in each of its tabs; screenshot it; return the figures and the problems."""
    kind = panel_kind(panel)
    result = {"name": name, "kind": kind, "heights": [], "problems": [], "shots": []}
    tabs = tab_titles(panel)
    states = [(None, "")] if not tabs else [(tab, tab.inner_text().strip()) for tab in tabs]
    for tab, title in states:
        if tab is not None:
            tab.click()
            page.wait_for_timeout(150)
        m = measure(panel)
        label = f"{kind}[{title}]" if title else kind
        result["heights"].append((title or "-", round(m["height"])))
        result["output_width"] = round(m["outputWidth"])
        result["width"] = round(m["width"])
        result.setdefault("content_widths", []).append((title or "-", m["contentWidth"], m["innerWidth"]))
        if m["controls"] == 0:
            result["problems"].append(f"{label}: no controls rendered")
        if m["height"] > MAX_HEIGHT:
            result["problems"].append(f"{label}: {m['height']:.0f} px tall (at most {MAX_HEIGHT})")
        result["problems"] += [f"{label}: {p}" for p in m["problems"]]
        if title == "traffic":
            for log in panel.locator(".mbe-tt-tx-log, .mbe-tt-rx-log").all():
                s = log.evaluate(_SCROLL)
                if s["overflowX"] not in ("auto", "scroll") or s["overflowY"] not in ("auto", "scroll"):
                    result["problems"].append(f"{label}: a log does not scroll ({s})")
                elif s["scrollWidth"] > s["clientWidth"] and not s["movedX"]:
                    result["problems"].append(f"{label}: a wide log does not scroll sideways ({s})")
                result.setdefault("logs", []).append(s)
        if tab is None or title in ("data", "traffic", "trend"):
            shot = artifacts / f"{name}-{kind}{'-' + title if title else ''}.png"
            panel.screenshot(path=str(shot))
            result["shots"].append(shot.name)
    if tabs:
        tabs[0].click()
    return result


def safe_name(path: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", Path(path).stem)


__all__ = ["MAX_HEIGHT", "PANEL_SELECTOR", "check_panel", "measure", "panel_kind", "safe_name"]


# A test tool's grid (the inputs of its data tab, drawn even while another tab is shown) and its counters.
_TOOL_SHOWS = r"""
(tool) => ({
  grid: [...tool.querySelectorAll('.mbe-tt-cell input')].map(i => i.value),
  counts: Object.fromEntries([...tool.querySelectorAll('[class*="mbe-tt-count-"]')].map(
      b => [b.className.match(/mbe-tt-count-(\w+)/)[1], Number(b.innerText)])),
})
"""


def tool_shows(tool) -> dict:
    """What a TestTool panel shows on screen now: ``{"grid": [cell texts], "counts": {name: n}}``."""
    return tool.evaluate(_TOOL_SHOWS)
