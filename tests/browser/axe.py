"""axe-core in the browser test's page: the accessibility rules (WCAG 2.1 A and AA, and axe's best
practices) checked on one panel's DOM node.

axe-core comes from npm, pinned by the repository's package.json and package-lock.json; :func:`axe_script`
runs ``npm ci`` when node_modules does not hold the pinned version yet (so CI and a fresh clone install it
with the test), and returns the path of ``axe.min.js``, which playwright injects into the page
(``page.add_script_tag(path=...)``).  Nothing is fetched by the page itself.

:func:`run_axe` runs ``axe.run`` on the panel's element, in each of its tabs (a hidden tab is not checked
by axe), and returns every violation once (by rule and node); :func:`counts` sums them by impact and rule.
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[2]
LOCK = REPO_ROOT / "package-lock.json"
AXE_DIR = REPO_ROOT / "node_modules" / "axe-core"
NPM_TIMEOUT_S = 300
SERIOUS = ("serious", "critical")

#: The rule sets run: the WCAG 2.0 and 2.1 success criteria of levels A and AA, and axe's best practices.
TAGS = ["wcag2a", "wcag2aa", "wcag21a", "wcag21aa", "best-practice"]


def pinned_version() -> str:
    """The axe-core version package-lock.json pins."""
    return json.loads(LOCK.read_text())["packages"]["node_modules/axe-core"]["version"]


def installed_version() -> str | None:
    try:
        return json.loads((AXE_DIR / "package.json").read_text())["version"]
    except (OSError, ValueError, KeyError):
        return None


def axe_script() -> Path:
    """``node_modules/axe-core/axe.min.js`` at the pinned version, installed by ``npm ci`` if needed.

    Raises RuntimeError, with the reason, when npm is missing or the install fails."""
    if installed_version() != pinned_version():
        npm = shutil.which("npm")
        if npm is None:
            raise RuntimeError("npm is not installed (apt-get install npm): it installs axe-core from "
                               "package-lock.json")
        done = subprocess.run([npm, "ci", "--ignore-scripts", "--no-audit", "--no-fund"], cwd=REPO_ROOT,
                              capture_output=True, text=True, timeout=NPM_TIMEOUT_S)
        if done.returncode != 0 or installed_version() != pinned_version():
            raise RuntimeError(f"npm ci did not install axe-core {pinned_version()}:\n"
                               f"{done.stdout[-1500:]}{done.stderr[-1500:]}")
    return AXE_DIR / "axe.min.js"


def inject(page) -> str:
    """Put axe-core into the page (once); returns its version as the page reports it."""
    if not page.evaluate("() => typeof window.axe !== 'undefined'"):
        page.add_script_tag(path=str(axe_script()))
    return page.evaluate("() => window.axe.version")


_RUN = r"""
async ([panel, tags]) => {
  const result = await window.axe.run(panel, {runOnly: {type: 'tag', values: tags},
                                              resultTypes: ['violations']});
  return result.violations.map(v => ({
    id: v.id, impact: v.impact, help: v.help,
    nodes: v.nodes.map(n => ({target: n.target.join(' '), impact: n.impact,
                              html: n.html.slice(0, 160), summary: (n.failureSummary || '').slice(0, 300)}))
  }));
}
"""


# axe checks colours only where the text is on screen: the notebook scrolls, so the panel is brought to
# the top of the notebook's scroll box and must then lie wholly inside what that box shows.  Host page
# quirk: JupyterLab 4 wraps its whole shell in a .jp-ThemedContainer of height 0 with overflow hidden
# (the shell is positioned outside it, so nothing is cut off on screen); axe takes every panel for
# clipped by that box and would skip the colour contrast of all its text.  Such an empty clipping
# ancestor is set to overflow: visible (it draws nothing, so the page looks the same).
_ON_SCREEN = r"""
(panel) => {
  for (let a = panel.parentElement; a; a = a.parentElement) {
    const r = a.getBoundingClientRect(), s = getComputedStyle(a);
    if ((r.height === 0 || r.width === 0) && s.overflow !== 'visible') a.style.overflow = 'visible';
  }
  panel.scrollIntoView({block: 'start'});
  const box = panel.closest('.jp-WindowedPanel-outer, .jp-Notebook') || document.documentElement;
  const p = panel.getBoundingClientRect(), b = box.getBoundingClientRect();
  return p.top >= b.top - 1 && p.bottom <= Math.min(b.bottom, window.innerHeight) + 1;
}
"""


# axe's own judgement of the panel's first line of text: visible on screen (else every colour goes unchecked)
_SEES_TEXT = r"""
(panel) => {
  const walker = document.createTreeWalker(panel, NodeFilter.SHOW_TEXT,
      {acceptNode: t => t.textContent.trim() && t.parentElement.offsetParent !== null
                        ? NodeFilter.FILTER_ACCEPT : NodeFilter.FILTER_SKIP});
  const text = walker.nextNode();
  if (!text) return false;
  window.axe.setup(document);
  try { return window.axe.commons.dom.isVisibleOnScreen(text.parentElement); }
  finally { window.axe.teardown(); }
}
"""


def run_axe(page, panel, tabs: list | None = None) -> list[dict]:
    """axe-core's violations on ``panel`` (a playwright locator), in each of ``tabs`` (tab locators,
    clicked in turn; none: the panel as shown).  Each (rule, node) once: one dict per violating node,
    with the rule's id, the node's impact, the rule's help and the node's target and HTML.

    The page must be tall enough for the panel (the test's pages are): a panel not wholly on screen
    raises AssertionError, since axe would skip the colours of the part it cannot see."""
    inject(page)
    seen: dict[tuple[str, str], dict] = {}
    for tab in tabs or [None]:
        if tab is not None:
            tab.click()
            page.wait_for_timeout(150)
        handle = panel.element_handle()
        assert handle.evaluate(_ON_SCREEN), "the panel is not wholly on screen: axe would skip colours"
        assert page.evaluate(_SEES_TEXT, handle), "axe takes the panel's text for hidden"
        for rule in page.evaluate(_RUN, [handle, TAGS]):
            for node in rule["nodes"]:
                key = (rule["id"], node["target"])
                seen.setdefault(key, {"rule": rule["id"], "impact": node["impact"] or rule["impact"],
                                      "help": rule["help"], **node})
    if tabs:
        tabs[0].click()
    return list(seen.values())


def counts(violations: list[dict]) -> dict:
    """``{"serious_or_critical": n, "total": n, "by_rule": {rule: [impact, nodes]}}``."""
    by_rule: dict[str, list] = {}
    for v in violations:
        entry = by_rule.setdefault(v["rule"], [v["impact"], 0])
        entry[1] += 1
    return {"serious_or_critical": sum(v["impact"] in SERIOUS for v in violations),
            "total": len(violations), "by_rule": dict(sorted(by_rule.items()))}


def describe(violations: list[dict]) -> str:
    """One line per violating node: impact, rule, what it asks, where."""
    return "\n".join(f"{v['impact']}: {v['rule']} ({v['help']}) at {v['target']}: {v['html']}"
                     for v in violations)





# --- the keyboard alone ------------------------------------------------------------------------------
# Every control of the panel that is shown now (and every box that scrolls), in the page's order; and for
# the element that has the focus: whether it is in the panel, what it is, and whether its focus ring is
# one anyone can see (an outline at least 2 px wide, not "none").
_CONTROLS = r"""
(panel) => [...panel.querySelectorAll('input, select, textarea, button, [tabindex]')]
  .filter(el => !el.disabled && el.tabIndex >= 0 && el.offsetParent !== null
                && el.getClientRects().length > 0 && getComputedStyle(el).visibility !== 'hidden')
  .map(el => { el.dataset.axeKey = el.dataset.axeKey || String(Math.random()).slice(2);
               return el.dataset.axeKey; })
"""

_FOCUSED = r"""
(panel) => {
  const el = document.activeElement;
  if (!el || !panel.contains(el)) return null;
  const s = getComputedStyle(el);
  return {key: el.dataset.axeKey || '', tag: el.tagName.toLowerCase(),
          what: (el.getAttribute('aria-label') || el.title || el.innerText || el.id || '').slice(0, 40),
          ring: s.outlineStyle !== 'none' && parseFloat(s.outlineWidth) >= 2,
          tabindex: el.tabIndex};
}
"""


def tab_through(page, panel, max_presses: int = 80, ring_cut: str | None = None) -> dict:
    """Focus the panel's first control, then press Tab until the focus leaves the panel.

    Returns ``{"controls": n, "reached": [...], "missed": [...], "no_ring": [...], "ring_cut": [...],
    "positive_tabindex": n}``: the controls reached (in order), those never reached, those without a
    visible focus ring, those whose ring is cut off (``ring_cut``: a function of the focused element
    that says where its ring is cut, or null), and how many elements force their own order
    (tabindex > 0)."""
    keys = panel.evaluate(_CONTROLS)
    if not keys:
        return {"controls": 0, "reached": [], "missed": [], "no_ring": [], "ring_cut": [],
                "positive_tabindex": 0}
    panel.locator(f'[data-axe-key="{keys[0]}"]').focus()
    reached, no_ring, cut = [], [], []
    for _ in range(max_presses):
        now = panel.evaluate(_FOCUSED)
        if now is None:
            break
        if not reached or reached[-1] != now["key"]:
            reached.append(now["key"])
            if not now["ring"]:
                no_ring.append(f"{now['tag']} {now['what']!r}")
            where = page.evaluate(f"({ring_cut})(document.activeElement)") if ring_cut else None
            if where:
                cut.append(f"{now['tag']} {now['what']!r}: {where}")
        page.keyboard.press("Tab")
    positive = panel.evaluate("p => [...p.querySelectorAll('[tabindex]')].filter(e => e.tabIndex > 0).length")
    return {"controls": len(keys), "reached": reached, "missed": [k for k in keys if k not in reached],
            "no_ring": no_ring, "ring_cut": cut, "positive_tabindex": positive}
__all__ = ["SERIOUS", "TAGS", "axe_script", "counts", "describe", "inject", "pinned_version", "run_axe",
           "tab_through"]
