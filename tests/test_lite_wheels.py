"""What the Lite site carries for the Web Serial panel (no build, no network): anywidget and what it
imports at run time are among the wheels collected and installed at the project's pins, and anywidget's
JupyterLab extension is taken from the very wheel piplite installs (tests/test_lite.py and
tests/test_lite_browsers.py see the panel render in the built site)."""

from __future__ import annotations

import json
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "lite"))
import build_site  # noqa: E402
import wheels  # noqa: E402

WEB_SERIAL = ["anywidget", "psygnal", "typing-extensions"]


def test_anywidget_and_what_it_imports_are_collected_at_the_project_s_pins():
    pins = wheels.pinned(WEB_SERIAL)
    lock = (ROOT / "binder" / "requirements.txt").read_text()
    for pin in pins:
        assert pin in lock, (pin, "not the learner's pin")
    assert set(WEB_SERIAL) <= set(wheels.COURSE)
    installed = {build_site._norm(name) for name in build_site.COURSE_WHEELS}
    assert set(WEB_SERIAL) <= installed
    setup = build_site.first_cell(offline=True, plots=False, sockets=False)["source"]
    assert all(name in setup for name in ("anywidget", "psygnal", "typing_extensions")), setup


def _wheel(path: Path, names: list[str]) -> Path:
    with zipfile.ZipFile(path, "w") as archive:
        for name in names:
            archive.writestr(name, "{}")
    return path


def test_the_site_takes_anywidget_s_extension_from_the_wheel_it_installs(tmp_path):
    extension = "anywidget-0.11.0.data/data/share/jupyter/labextensions/anywidget/package.json"
    anywidget = _wheel(tmp_path / "anywidget-0.11.0-py3-none-any.whl", ["anywidget/__init__.py", extension])
    other = _wheel(tmp_path / "pymodbus-3.16.1-py3-none-any.whl", ["pymodbus/__init__.py"])
    assert build_site.lab_extension_wheels([other, anywidget]) == [anywidget]
    build_site.write_config(tmp_path, [other, anywidget], offline=True)
    config = json.loads((tmp_path / "jupyter_lite_config.json").read_text())
    assert config["LiteBuildConfig"]["federated_extensions"] == [str(anywidget)]
    assert config["PipliteAddon"]["piplite_urls"] == [str(other), str(anywidget)]


def test_an_anywidget_wheel_without_its_extension_stops_the_build(tmp_path):
    bare = _wheel(tmp_path / "anywidget-0.11.0-py3-none-any.whl", ["anywidget/__init__.py"])
    with pytest.raises(SystemExit, match="holds no JupyterLab extension"):
        build_site.lab_extension_wheels([bare])
