"""Build the course as a JupyterLite site: the notebooks run on Pyodide, in the browser, from any static
host, with nothing to install.  `make lite` runs this in .venv-lite (lite/requirements.txt).

    python lite/build_site.py --wheels DIR --out _site             # published: Pyodide from its CDN
    python lite/build_site.py --wheels DIR --out _site --offline   # offline: no request leaves the site

The site holds the course's notebooks and worked solutions and, for piplite, the library's wheel and the
pure-Python wheels it needs (``lite/wheels.py`` collects them).  The site's copy of each notebook, never
the source, is changed at build time:

* a first cell installs the library from the site's own wheels (``%pip install``), so a learner installs
  nothing; a notebook that draws also installs matplotlib (published: from Pyodide's CDN) and the
  pictures its cells drew when it was executed on CPython (``modbus_edu_pictures``, a wheel of data
  made here by :func:`pictures_wheel`), and calls :func:`modbus_edu.pictures.draw_offline`: where
  matplotlib is missing (offline) each cell that draws runs its other statements and shows its picture,
  so the notebook runs to its last cell;
* a cell tagged ``needs-sockets`` (notebooks 11, 15 and 17: servers and links on real sockets) or
  ``needs-cryptography`` (17: certificates, made with the compiled ``cryptography`` package) is kept as
  commented-out code with one line saying what it needs and that a local Python or Binder runs it, so Run
  All goes on.  Everything else runs, captures included (scapy is pure Python: its wheel is bundled).

Offline, Pyodide's core comes from the npm package pinned in lite/package.json (``npm ci`` in lite/), and
the packages the kernel loads from Pyodide's lock (micropip, packaging, IPython and the rest, all pure
Python) are downloaded once from PyPI at the lock's versions and bundled, the lock rewritten with their
file names and SHA-256 checksums.  Everything else is removed from the lock: nothing is fetched elsewhere.
"""

from __future__ import annotations

import argparse
import base64
import hashlib
import json
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
NPM_PYODIDE = ROOT / "lite" / "node_modules" / "pyodide"
PYODIDE_VERSION = "314.0.6"  # what jupyterlite-pyodide-kernel 0.8.6 expects; lite/package.json pins it too
PYODIDE_PYTHON = "3.14"  # the Python that Pyodide 314 is
CDN = f"https://cdn.jsdelivr.net/pyodide/v{PYODIDE_VERSION}/full/pyodide.mjs"
KERNEL_PLUGIN = "@jupyterlite/pyodide-kernel-extension:kernel"
BINDER = "https://mybinder.org/v2/gh/modbus-edu/modbus_edu/main"
# What the kernel loads from Pyodide's lock before the first cell runs (with their dependencies).
KERNEL_PACKAGES = ["micropip", "packaging", "ipython", "jedi", "traitlets", "matplotlib-inline"]
# What the first cell installs with piplite, without dependencies: scapy writes and reads captures (pure
# Python); anywidget, psygnal and typing_extensions carry the Web Serial panel (mb.browser_serial);
# cryptography, compiled, is left out: it makes certificates for TLS, which a web page cannot speak.
COURSE_WHEELS = ["modbus_edu", "pymodbus", "pyserial", "tqdm", "ipywidgets", "jupyterlab_widgets", "scapy",
                 "anywidget", "psygnal", "typing_extensions"]
LAB_EXTENSION_WHEELS = ["anywidget"]
"""The wheels whose JupyterLab extension (share/jupyter/labextensions inside the wheel) the site carries,
taken from the very wheel piplite installs, so the page's side and the kernel's side are one version
(jupyterlab_widgets' extension comes from the build's environment, lite/requirements.txt)."""
SOCKETS_TAG = "needs-sockets"
SKIPPED = {SOCKETS_TAG: "this cell opens sockets",
           "needs-cryptography": "this cell makes certificates with the cryptography package, which a "
                                 "browser's copy of the course does not carry"}
"""The tags of the cells a browser cannot run, and why (the one line the cell shows instead)."""
PLOTS = re.compile(r"\bmatplotlib\b|\bplotstyle\b")
PICTURES = "modbus_edu_pictures"  # the pictures' package (modbus_edu.pictures.PACKAGE reads it)
PICTURES_VERSION = "1.0"


def _source(cell: dict) -> str:
    src = cell.get("source", "")
    return "".join(src) if isinstance(src, list) else src


def needs_plotting(nb: dict) -> bool:
    return any(c["cell_type"] == "code" and PLOTS.search(_source(c)) for c in nb["cells"])


def first_cell(offline: bool, plots: bool, sockets: bool) -> dict:
    lines = ["# In the browser (JupyterLite): install the course's library from this site.",
             f"%pip install -q --no-deps {' '.join(COURSE_WHEELS)}"]
    if plots:
        lines[-1] += f" {PICTURES}"
        if not offline:
            lines.append("%pip install -q matplotlib")
        lines += ["from modbus_edu.pictures import draw_offline", "",
                  "draw_offline()  # without matplotlib, a cell that draws shows the picture it drew"]
    if sockets:
        lines += ["print(\"The cells of this notebook that open sockets or make certificates need a local "
                  f"Python or Binder ({BINDER}): in the browser they are skipped.\")"]
    return {"cell_type": "code", "execution_count": None, "id": "lite-setup",
            "metadata": {"tags": ["lite-setup"]}, "outputs": [], "source": "\n".join(lines)}


def _why_skipped(cell: dict) -> str | None:
    """Why a browser cannot run ``cell`` (from its tags), or None."""
    tags = cell.get("metadata", {}).get("tags", [])
    return next((why for tag, why in SKIPPED.items() if tag in tags), None)


def skipped(cell: dict, why: str) -> dict:
    code = "\n".join(f"# {line}" if line else "#" for line in _source(cell).splitlines())
    return {**cell, "execution_count": None, "outputs": [],
            "source": f"# Skipped in the browser: {why} (a local Python or Binder runs it).\n" + code}


def site_notebook(nb: dict, offline: bool) -> dict:
    cells = nb["cells"]
    sockets = any(_why_skipped(c) for c in cells)
    cells = [skipped(c, _why_skipped(c)) if _why_skipped(c) else c for c in cells]
    return {**nb, "cells": [first_cell(offline, needs_plotting(nb), sockets), *cells]}


def stage_contents(dest: Path, offline: bool) -> None:
    shutil.rmtree(dest, ignore_errors=True)
    dest.mkdir(parents=True)
    for path in sorted(NOTEBOOKS.glob("[0-9][0-9]_*.ipynb")):
        nb = json.loads(path.read_text(encoding="utf-8"))
        (dest / path.name).write_text(json.dumps(site_notebook(nb, offline), indent=1, ensure_ascii=False),
                                      encoding="utf-8")
    shutil.copytree(NOTEBOOKS / "solutions", dest / "solutions")


def drawn_pictures(notebooks: list[Path]) -> dict[str, list[dict[str, str]]]:
    """Each drawing cell's key (:func:`modbus_edu.pictures.cell_key`) -> the pictures it drew, each as
    ``{"png": base64, "alt": its words}`` (the ``alt`` :func:`modbus_edu.plotstyle.show` stored with it), from
    the executed notebooks; a drawing cell that drew nothing (its imports) maps to an empty list."""
    sys.path.insert(0, str(ROOT))
    from modbus_edu.pictures import cell_key, draws

    found: dict[str, list[dict[str, str]]] = {}
    for path in notebooks:
        for cell in json.loads(path.read_text(encoding="utf-8"))["cells"]:
            source = _source(cell)
            if cell["cell_type"] == "code" and draws(source):
                found[cell_key(source)] = [
                    {"png": "".join(output["data"]["image/png"]).replace("\n", ""),
                     "alt": output.get("metadata", {}).get("image/png", {}).get("alt", "")}
                    for output in cell.get("outputs", []) if "image/png" in output.get("data", {})]
    return found


def pictures_wheel(notebooks: list[Path], out: Path) -> Path:
    """A wheel of data, ``modbus_edu_pictures``: the pictures the course's cells drew (pictures.json)."""
    pictures = json.dumps(drawn_pictures(notebooks), sort_keys=True).encode()
    dist = f"{PICTURES}-{PICTURES_VERSION}.dist-info"
    summary = "The pictures the modbus_edu course's cells drew when it was built (data only)"
    files = {
        f"{PICTURES}/__init__.py": f'"""{summary}."""\n'.encode(),
        f"{PICTURES}/pictures.json": pictures,
        f"{dist}/METADATA": (f"Metadata-Version: 2.1\nName: {PICTURES}\nVersion: {PICTURES_VERSION}\n"
                             f"Summary: {summary}\n").encode(),
        f"{dist}/WHEEL": b"Wheel-Version: 1.0\nGenerator: modbus_edu lite/build_site.py\n"
                         b"Root-Is-Purelib: true\nTag: py3-none-any\n",
    }
    record = [f"{name},sha256={_digest(data)},{len(data)}" for name, data in files.items()]
    files[f"{dist}/RECORD"] = ("\n".join([*record, f"{dist}/RECORD,,"]) + "\n").encode()
    out.mkdir(parents=True, exist_ok=True)
    wheel = out / f"{PICTURES}-{PICTURES_VERSION}-py3-none-any.whl"
    with zipfile.ZipFile(wheel, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in files.items():
            archive.writestr(zipfile.ZipInfo(name, date_time=(2026, 1, 1, 0, 0, 0)), data)
    return wheel


def _digest(data: bytes) -> str:
    return base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _norm(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def stage_offline_pyodide(static: Path, cache: Path) -> list[str]:
    """Pyodide's core from the npm package and the kernel's packages from PyPI, with a lock of just them."""
    if not (NPM_PYODIDE / "pyodide.mjs").exists():
        raise SystemExit(f"{NPM_PYODIDE} is missing: run `npm ci` in lite/ (make lite does)")
    npm_version = json.loads((NPM_PYODIDE / "package.json").read_text())["version"]
    if npm_version != PYODIDE_VERSION:
        raise SystemExit(f"lite/package.json gives Pyodide {npm_version}, "
                         f"the kernel expects {PYODIDE_VERSION}")
    target = static / "pyodide"
    shutil.rmtree(target, ignore_errors=True)
    shutil.copytree(NPM_PYODIDE, target,
                    ignore=shutil.ignore_patterns("*.map", "*.d.ts", "*.html", "README.md"))
    lock = json.loads((NPM_PYODIDE / "pyodide-lock.json").read_text())
    packages = lock["packages"]
    wanted: list[str] = []
    todo = list(KERNEL_PACKAGES)
    while todo:
        name = _norm(todo.pop())
        if name not in wanted:
            wanted.append(name)
            todo += packages[name]["depends"]
    cache.mkdir(parents=True, exist_ok=True)
    for name in sorted(wanted):
        entry = packages[name]
        if not entry["file_name"].endswith("-none-any.whl"):
            raise SystemExit(f"{name} is not pure Python in Pyodide's lock: it cannot be bundled from PyPI")
        wheel = cache / entry["file_name"]
        if not wheel.exists():
            subprocess.run([sys.executable, "-m", "pip", "--disable-pip-version-check", "-q", "download",
                            "--no-deps", "--only-binary=:all:", "--python-version", PYODIDE_PYTHON,
                            "-d", str(cache),
                            f"{name}=={entry['version']}"], check=True)
        if not wheel.exists():
            raise SystemExit(f"PyPI gave no {entry['file_name']} for {name}=={entry['version']}")
        shutil.copy2(wheel, target / wheel.name)
        entry["sha256"] = _sha256(wheel)
    lock["packages"] = {name: packages[name] for name in sorted(wanted)}
    (target / "pyodide-lock.json").write_text(json.dumps(lock, indent=1))
    return sorted(wanted)


def write_config(lite_dir: Path, wheels: list[Path], offline: bool) -> None:
    settings: dict = {"disablePyPIFallback": True}
    if not offline:
        settings["pyodideUrl"] = CDN
    (lite_dir / "jupyter-lite.json").write_text(json.dumps({
        "jupyter-lite-schema-version": 0,
        # exposeAppInBrowser: the page script (lite/page.js) reaches the notebooks as window.jupyterapp
        "jupyter-config-data": {"appName": "modbus_edu", "exposeAppInBrowser": "true",
                                "litePluginSettings": {KERNEL_PLUGIN: settings}},
    }, indent=1))
    # every cell stays in the page (no windowing): the browser's find and a screen reader see the whole
    # notebook, and a test reads every cell's prompt and output
    (lite_dir / "overrides.json").write_text(json.dumps({
        "@jupyterlab/notebook-extension:tracker": {"windowingMode": "none"}}, indent=1))
    (lite_dir / "jupyter_lite_config.json").write_text(json.dumps({
        "LiteBuildConfig": {"federated_extensions": [str(w) for w in lab_extension_wheels(wheels)]},
        "PipliteAddon": {"piplite_urls": [str(w) for w in wheels]},
    }, indent=1))


def lab_extension_wheels(wheels: list[Path]) -> list[Path]:
    """The wheels of :data:`LAB_EXTENSION_WHEELS` among ``wheels``, each checked to hold its extension."""
    found = [w for w in wheels if _norm(w.name.split("-")[0]) in {_norm(n) for n in LAB_EXTENSION_WHEELS}]
    for wheel in found:
        with zipfile.ZipFile(wheel) as archive:
            if not any("/share/jupyter/labextensions/" in name and name.endswith("/package.json")
                       for name in archive.namelist()):
                raise SystemExit(f"{wheel.name} holds no JupyterLab extension: the page could not draw its "
                                 "widget")
    return found


def build(wheels_dir: Path, out: Path, offline: bool, work: Path) -> None:
    wheels = sorted(wheels_dir.resolve().glob("*.whl"))
    names = {_norm(w.name.split("-")[0]) for w in wheels}
    missing = [n for n in [*COURSE_WHEELS, "comm"] if _norm(n) not in names]
    if missing:
        raise SystemExit(f"{wheels_dir} has no wheel for {', '.join(missing)}: run lite/wheels.py first")
    lite_dir = work / ("offline" if offline else "published")
    shutil.rmtree(lite_dir, ignore_errors=True)
    lite_dir.mkdir(parents=True)
    stage_contents(lite_dir / "content", offline)
    if offline:
        bundled = stage_offline_pyodide(lite_dir / "static", work / "pyodide-wheels")
        print(f"offline: Pyodide {PYODIDE_VERSION} from npm, "
              f"bundled {len(bundled)} packages: {' '.join(bundled)}")
    notebooks = sorted(NOTEBOOKS.glob("[0-9][0-9]_*.ipynb"))
    wheels.append(pictures_wheel(notebooks, lite_dir / "pictures"))
    write_config(lite_dir, wheels, offline)
    shutil.rmtree(out, ignore_errors=True)
    subprocess.run([str(Path(sys.executable).parent / "jupyter"), "lite", "build",
                    "--lite-dir", str(lite_dir), "--contents", str(lite_dir / "content"),
                    "--output-dir", str(out.resolve()),
                    "--settings-overrides", str(lite_dir / "overrides.json"), "--no-sourcemaps"],
                   check=True, cwd=lite_dir)
    add_page_script(out, offline)
    print(f"built {out} ({'offline' if offline else f'published, Pyodide from {CDN}'})")


PAGE_SCRIPT = "modbus_edu_page.js"
PAGES = ["lab", "notebooks"]  # the pages a learner opens a notebook in
CDN_PROBE_TIMEOUT_S = 15
"""Published: how long the page waits for Pyodide's CDN to answer before it says the CDN is out of reach."""
START_BOUND_S = {"published": 120, "offline": 300}
"""How long the page lets a kernel take to start before it says so (offline: a slow computer, no network)."""


def add_page_script(out: Path, offline: bool) -> None:
    """The course's page script (lite/page.js) into the site, and a tag for it in the notebook pages: a
    cell that stops is scrolled into view and the busy indicator follows the kernel; a kernel that cannot
    start (the published site's CDN out of reach) is said in the page, with the offline site and Binder."""
    settings = {"cdn": "" if offline else CDN, "binder": BINDER, "probe_timeout_s": CDN_PROBE_TIMEOUT_S,
                "start_bound_s": START_BOUND_S["offline" if offline else "published"]}
    script = (ROOT / "lite" / "page.js").read_text(encoding="utf-8")
    (out / PAGE_SCRIPT).write_text(script.replace("__SETTINGS__", json.dumps(settings)), encoding="utf-8")
    tag = f'<script src="../{PAGE_SCRIPT}" defer></script>'
    for page in PAGES:
        index = out / page / "index.html"
        html = index.read_text(encoding="utf-8")
        if tag not in html:
            index.write_text(html.replace("</head>", f"  {tag}\n</head>", 1), encoding="utf-8")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--wheels", type=Path, required=True, help="the wheels lite/wheels.py collected")
    parser.add_argument("--out", type=Path, default=ROOT / "_site")
    parser.add_argument("--offline", action="store_true", help="bundle Pyodide: no request leaves the site")
    parser.add_argument("--work", type=Path, default=ROOT / "build" / "lite")
    args = parser.parse_args()
    build(args.wheels, args.out, args.offline, args.work)


if __name__ == "__main__":
    main()
