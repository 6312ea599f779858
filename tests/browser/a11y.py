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


#: What the keyboard may have done to the notebook: the cells (count, types, order by their first line,
#: execution counts), the active and the selected ones, the mode, the panels shown, whether any page text
#: is selected, and where the focus is (inside which panel, on what).
NOTEBOOK_SNAPSHOT = r"""
(panelSelector) => {
  const nb = document.querySelector('.jp-NotebookPanel:not(.lm-mod-hidden) .jp-Notebook');
  const cells = [...nb.querySelectorAll(':scope .jp-Cell')];
  const a = document.activeElement;
  return {
    cells: cells.map(c => (c.classList.contains('jp-CodeCell') ? 'code:' : 'text:')
                          + (c.querySelector('.cm-line') || c).textContent.slice(0, 30)),
    prompts: cells.map(c => (c.querySelector('.jp-InputArea-prompt') || {}).textContent || ''),
    active: cells.findIndex(c => c.classList.contains('jp-mod-active')),
    selected: cells.filter(c => c.classList.contains('jp-mod-selected')).length,
    mode: nb.classList.contains('jp-mod-editMode') ? 'edit' : 'command',
    panels: document.querySelectorAll(panelSelector).length,
    pageSelection: String(window.getSelection()).length,
    focus: a && a.closest(panelSelector) ? 'panel ' + a.tagName.toLowerCase()
           : a && a.classList.contains('jp-Cell') ? 'cell ' + cells.indexOf(a)
           : a ? a.tagName.toLowerCase() : 'none',
  };
}
"""


def snapshot(page, panel_selector: str) -> dict:
    return page.evaluate(NOTEBOOK_SNAPSHOT, panel_selector)


def what_changed(before: dict, after: dict) -> list[str]:
    """The differences between two snapshots, in words ("the cells: 8 -> 7", ...)."""
    out = []
    if len(after["cells"]) != len(before["cells"]):
        out.append(f"cells {len(before['cells'])} -> {len(after['cells'])}")
    elif after["cells"] != before["cells"]:
        out.append("cells moved or changed")
    if after["prompts"] != before["prompts"] and len(after["prompts"]) == len(before["prompts"]):
        out.append("a cell ran again")
    for key in ("active", "selected", "mode", "panels", "focus"):
        if after[key] != before[key]:
            out.append(f"{key} {before[key]} -> {after[key]}")
    if after["pageSelection"] > before["pageSelection"]:
        out.append("page text selected")
    return out


#: For the focused element: whether its focus ring (the outline, its width and offset around the border
#: box) lies wholly inside every ancestor that clips (overflow other than visible) up to the output area.
RING_CLIPPED = r"""
(el) => {
  const s = getComputedStyle(el);
  if (s.outlineStyle === 'none') return null;
  const grow = parseFloat(s.outlineWidth) + Math.max(0, parseFloat(s.outlineOffset) || 0);
  const r = el.getBoundingClientRect();
  const ring = {left: r.left - grow, right: r.right + grow, top: r.top - grow, bottom: r.bottom + grow};
  const stop = el.closest('.jp-OutputArea-output') || document.body;
  for (let a = el.parentElement; a && a !== stop; a = a.parentElement) {
    const cs = getComputedStyle(a);
    if (cs.overflowX === 'visible' && cs.overflowY === 'visible') continue;
    const b = a.getBoundingClientRect();
    const left = b.left + a.clientLeft, top = b.top + a.clientTop;
    const box = {left: left, top: top, right: left + a.clientWidth, bottom: top + a.clientHeight};
    const cut = [];
    if (cs.overflowX !== 'visible' && ring.left < box.left - 0.5) cut.push('left');
    if (cs.overflowX !== 'visible' && ring.right > box.right + 0.5) cut.push('right');
    if (cs.overflowY !== 'visible' && ring.top < box.top - 0.5) cut.push('top');
    if (cs.overflowY !== 'visible' && ring.bottom > box.bottom + 0.5) cut.push('bottom');
    if (cut.length) return cut.join('+') + ' by ' + a.tagName.toLowerCase() + '.'
                           + String(a.className).trim().split(/\s+/).slice(-2).join('.');
  }
  return null;
}
"""


#: The lowest contrast (WCAG) of the text inside ``selector`` as drawn: each text's colour with the
#: opacity of its element and ancestors, over the first background behind it, through a grayscale filter
#: where an ancestor has one.  Returns [ratio, colour, text] of the worst.
TEXT_CONTRAST = r"""
(root) => {
  const rgb = c => (c.match(/[\d.]+/g) || [0, 0, 0, 0]).map(Number);
  const f = v => { v /= 255; return v <= 0.03928 ? v / 12.92 : ((v + 0.055) / 1.055) ** 2.4; };
  const lum = ([r, g, b]) => 0.2126 * f(r) + 0.7152 * f(g) + 0.0722 * f(b);
  const grey = ([r, g, b]) => { const y = 0.2126 * r + 0.7152 * g + 0.0722 * b; return [y, y, y]; };
  let worst = [99, '', ''];
  const walker = document.createTreeWalker(root, NodeFilter.SHOW_TEXT);
  for (let t = walker.nextNode(); t; t = walker.nextNode()) {
    const el = t.parentElement;
    if (!t.textContent.trim() || el.offsetParent === null) continue;
    let fg = rgb(getComputedStyle(el).color), alpha = fg.length > 3 ? fg[3] : 1, bg = null, filtered = false;
    for (let a = el; a; a = a.parentElement) {
      const cs = getComputedStyle(a);
      alpha *= parseFloat(cs.opacity);
      if (cs.filter.includes('grayscale')) filtered = true;
      const b = rgb(cs.backgroundColor);
      if (!bg && (b.length === 3 || b[3] > 0)) bg = b.slice(0, 3);
    }
    bg = bg || [255, 255, 255];
    let shown = fg.slice(0, 3).map((v, i) => alpha * v + (1 - alpha) * bg[i]), back = bg;
    if (filtered) { shown = grey(shown); back = grey(back); }
    const [hi, lo] = [lum(shown), lum(back)].sort((x, y) => y - x);
    const ratio = (hi + 0.05) / (lo + 0.05);
    if (ratio < worst[0]) {
      worst = [Math.round(ratio * 100) / 100, getComputedStyle(el).color, t.textContent.trim().slice(0, 20)];
    }
  }
  return worst;
}
"""


#: At a narrow width: what sticks out of the panel sideways or scrolls sideways, and the buttons smaller
#: than 24 x 24 CSS px (WCAG 2.2, 2.5.8).  The boxes made to scroll (a log, a table, the grid, the CRC's
#: steps: named regions reached with Tab) may scroll; nothing else may.
REFLOW = r"""
(panel) => {
  const describe = el => el.tagName.toLowerCase() + '.' + (typeof el.className === 'string'
      ? el.className.trim().split(/\s+/).slice(-3).join('.') : '');
  const scrollBox = '.mbe-scroll, .mbe-tt-grid';
  const p = panel.getBoundingClientRect(), problems = [], small = [];
  if (panel.scrollWidth > panel.clientWidth + 1) {
    problems.push(`the panel scrolls sideways (${panel.scrollWidth} px in ${panel.clientWidth})`);
  }
  for (const el of panel.querySelectorAll('*')) {
    if (el.offsetParent === null) continue;
    const box = el.closest(scrollBox);
    if (box && box !== el) continue;
    const r = el.getBoundingClientRect();
    if (r.width === 0 || r.height === 0) continue;
    const span = (a, b) => `${Math.round(a)}..${Math.round(b)}`;
    if (r.right > p.right + 1 || r.left < p.left - 1) {
      problems.push(`${describe(el)} (${span(r.left, r.right)}) outside the panel `
                    + `(${span(p.left, p.right)})`);
    }
    else if (!box && el.scrollWidth > el.clientWidth + 1 && getComputedStyle(el).overflowX !== 'visible')
      problems.push(`${describe(el)} scrolls or clips sideways: ${el.scrollWidth} px in ${el.clientWidth}`);
    const target = el.tagName === 'BUTTON' || el.classList.contains('lm-TabBar-tab');
    if (target && (r.width < 24 || r.height < 24)) {
      small.push(`${el.innerText.trim() || describe(el)}: `
                 + `${Math.round(r.width)} x ${Math.round(r.height)} px`);
    }
  }
  return {width: Math.round(p.width), problems: problems.slice(0, 12), small: small};
}
"""


__all__ = ["nodes", "icon_glyphs", "notebook_state", "PRIVATE_USE", "snapshot", "what_changed",
           "RING_CLIPPED", "TEXT_CONTRAST", "REFLOW"]
