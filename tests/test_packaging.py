"""Installs that keep their promises: the supported Pythons, the pins, the package, the Makefile, the class
copy and a hub's base image.

The tests marked ``slow`` build packages and virtual environments (minutes, and PyPI for what pip's cache
lacks); ``make test`` and CI run them, ``make test-unit`` leaves them out.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import zipfile
from importlib import metadata
from pathlib import Path

import pytest
from packaging.markers import Marker
from packaging.requirements import Requirement

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
LEARNER_PINS = ROOT / "binder" / "requirements.txt"
TEST_PINS = ROOT / "binder" / "requirements-test.txt"
TEST_TOOLS = {"pytest", "hypothesis", "ruff", "coverage", "playwright", "nbval", "build"}
PLATFORMS = {"linux": ("linux", "posix", "Linux"), "darwin": ("darwin", "posix", "Darwin"),
             "win32": ("win32", "nt", "Windows")}
REPO2DOCKER = "jupyter-repo2docker==2026.4.0"
"""The repo2docker release whose base environment (its conda lock files) a hub's image starts from."""


def supported_pythons() -> list[str]:
    """The supported Python versions, as pyproject.toml's classifiers list them."""
    found = [c.rsplit(" ", 1)[-1] for c in PYPROJECT["project"]["classifiers"]
             if re.fullmatch(r"Programming Language :: Python :: 3\.\d+", c)]
    return sorted(found, key=lambda v: tuple(map(int, v.split("."))))


def pins(path: Path) -> list[tuple[str, str, Marker | None]]:
    """(name, version, marker) for every line of a pinned requirements file."""
    found = []
    for line in path.read_text(encoding="utf-8").splitlines():
        line = line.split("  #")[0].split(" #")[0].strip()
        if not line or line.startswith("#"):
            continue
        requirement = Requirement(line)
        (specifier,) = requirement.specifier
        assert specifier.operator == "==", f"{path.name}: {line} is not pinned with =="
        found.append((requirement.name.lower().replace("_", "-"), specifier.version, requirement.marker))
    return found


def environment(python: str, platform: str) -> dict[str, str]:
    sys_platform, os_name, system = PLATFORMS[platform]
    return {"python_version": python, "python_full_version": f"{python}.0", "sys_platform": sys_platform,
            "os_name": os_name, "platform_system": system, "implementation_name": "cpython",
            "platform_python_implementation": "CPython", "platform_machine": "x86_64"}


def resolved(path: Path, python: str, platform: str) -> dict[str, str]:
    """The versions a pinned file installs on one Python and platform."""
    chosen: dict[str, str] = {}
    for name, version, marker in pins(path):
        if marker is None or marker.evaluate(environment(python, platform)):
            assert name not in chosen, f"{path.name} pins {name} twice for Python {python} on {platform}"
            chosen[name] = version
    return chosen


def interpreter(version: str) -> str | None:
    """A CPython of ``version`` on this machine: python3.X on the PATH, or pyenv's."""
    for candidate in [shutil.which(f"python{version}"),
                      *sorted(Path(os.environ.get("PYENV_ROOT", Path.home() / ".pyenv"))
                              .glob(f"versions/{version}.*/bin/python"))]:
        if candidate and subprocess.run([str(candidate), "--version"], capture_output=True).returncode == 0:
            return str(candidate)
    return None


# --- the supported Pythons: one place --------------------------------------------------------------------

def test_the_supported_pythons_are_said_once_and_everything_else_agrees():
    versions = supported_pythons()
    oldest = PYPROJECT["project"]["requires-python"]
    assert oldest == f">={versions[0]}", "requires-python and the oldest classifier disagree"
    minors = [int(v.split(".")[1]) for v in versions]
    assert minors == list(range(minors[0], minors[-1] + 1)), "the classifiers skip a version"
    assert PYPROJECT["tool"]["ruff"]["target-version"] == "py3" + versions[0].split(".")[1]
    runtime = (ROOT / "binder" / "runtime.txt").read_text().strip()
    assert runtime.removeprefix("python-") in versions
    assert f"Python {versions[0]} to {versions[-1]}" in (ROOT / "README.md").read_text(encoding="utf-8")
    ci = (ROOT / ".ci" / "run").read_text()
    assert "pyproject.toml" in ci and "make test-library" in ci, ".ci/run must read the versions, test them"
    assert versions[0] == "3.10", "the oldest supported Python is Ubuntu 22.04's"


@pytest.mark.parametrize("path", [LEARNER_PINS, TEST_PINS], ids=lambda p: p.name)
def test_the_pins_install_on_every_supported_python_and_platform(path):
    text = path.read_text(encoding="utf-8")
    assert "-e " not in text and "file:" not in text, "a local requirement stops Binder caching this layer"
    wanted = {"pymodbus", "pyserial", "tqdm", "jupyterlab", "ipywidgets", "matplotlib", "notebook"}
    for python in supported_pythons():
        for platform in PLATFORMS:
            chosen = resolved(path, python, platform)
            assert wanted <= set(chosen), (python, platform, wanted - set(chosen))
            assert chosen["pymodbus"].startswith("3.16."), chosen["pymodbus"]
            if platform == "win32":
                assert "colorama" in chosen, "Windows gets its own wheels (colorama for tqdm and pytest)"


def test_the_learner_does_not_install_the_test_tools_and_the_tests_use_the_learner_versions():
    learner, tests = pins(LEARNER_PINS), pins(TEST_PINS)
    assert not TEST_TOOLS & {name for name, _, _ in learner}
    assert TEST_TOOLS | {"modbus-tk", "umodbus"} <= {name for name, _, _ in tests}
    for python in supported_pythons():
        mine, theirs = resolved(LEARNER_PINS, python, "linux"), resolved(TEST_PINS, python, "linux")
        differ = {name: (version, theirs.get(name)) for name, version in mine.items()
                  if theirs.get(name) != version}
        assert not differ, f"Python {python}: the test pins change the learner's versions {differ}"


def test_this_environment_is_built_from_the_test_pins():
    python = f"{sys.version_info.major}.{sys.version_info.minor}"
    chosen = resolved(TEST_PINS, python, "linux" if sys.platform.startswith("linux") else sys.platform)
    for name in ("pymodbus", "jupyterlab", "ipywidgets", "nbval", "pyserial", "matplotlib"):
        assert metadata.version(name) == chosen[name], f"{name} is not the pinned version"


# --- what the library needs at run time --------------------------------------------------------------------

BLOCK_THE_COURSE = """
import sys
class Block:
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in ("matplotlib", "ipywidgets", "IPython", "jupyterlab", "notebook"):
            raise ImportError(f"No module named {name!r}")
sys.meta_path.insert(0, Block())
"""


def test_the_library_and_its_command_line_run_without_the_course_extra():
    code = BLOCK_THE_COURSE + """
import pkgutil, importlib, modbus_edu
for info in pkgutil.walk_packages(modbus_edu.__path__, "modbus_edu."):
    if info.name.split(".")[1] not in ("widgets", "plotstyle", "course", "__main__"):
        importlib.import_module(info.name)
from modbus_edu.cli import main
sys.exit(main(["crc", "01", "03", "00", "00", "00", "01"]))
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "84 0A" in done.stdout


@pytest.mark.parametrize("module", ["modbus_edu.widgets", "modbus_edu.plotstyle"])
def test_the_widgets_and_plots_say_how_to_install_the_course_extra(module):
    code = BLOCK_THE_COURSE + f"""
import modbus_edu
try:
    import {module}
except modbus_edu.MissingDependencyError as exc:
    assert isinstance(exc, ImportError)
    print(exc)
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert done.returncode == 0, done.stderr
    assert 'pip install "modbus-edu[course] @ git+https://github.com/modbus-edu/modbus_edu"' in done.stdout


def test_the_version_is_written_once():
    assert PYPROJECT["project"]["dynamic"] == ["version"] and "version" not in PYPROJECT["project"]
    assert PYPROJECT["tool"]["hatch"]["version"]["path"] == "modbus_edu/__init__.py"
    import modbus_edu

    assert re.fullmatch(r"\d+\.\d+\.\d+", modbus_edu.__version__)
    citation = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    assert f"version: {modbus_edu.__version__}" in citation
    assert f"## [{modbus_edu.__version__}]" in (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")


def test_licences_metadata_and_absolute_readme_links():
    project = PYPROJECT["project"]
    assert project["license"] == "MIT AND CC-BY-4.0"  # the sdist carries the notebooks
    assert project["license-files"] == ["LICENSE", "LICENSE-COURSE"]
    assert "MIT License" in (ROOT / "LICENSE").read_text()
    course = (ROOT / "LICENSE-COURSE").read_text(encoding="utf-8")
    assert "Creative Commons Attribution 4.0 International" in course
    assert "Section 3 – License Conditions" in course
    assert {"Homepage", "Source", "Issues", "Changelog"} <= set(project["urls"])
    assert project["authors"]
    classifiers = set(project["classifiers"])
    assert {"Topic :: Education", "Framework :: Jupyter", "Intended Audience :: Education"} <= classifiers
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "CC BY 4.0" in readme and "MIT" in readme
    # on PyPI a relative link leads nowhere (the course table's notebook links are its editors' to turn)
    prose = "\n".join(line for line in readme.splitlines() if not line.startswith("| "))
    for target in re.findall(r"\]\(([^)]+)\)", prose):
        assert re.match(r"https?://|#", target), f"README link {target} is relative"


def test_binder_installs_the_pins_first_and_the_package_after_copying_the_repository():
    post_build = ROOT / "binder" / "postBuild"
    assert os.access(post_build, os.X_OK)
    assert "pip install --no-cache-dir --no-deps ." in post_build.read_text()


def test_the_course_command_reports_a_missing_notebook_in_one_line():
    done = subprocess.run([sys.executable, "-m", "modbus_edu.course", "execute", "missing.ipynb"],
                          capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert done.returncode == 1
    assert done.stderr.strip().splitlines() == [
        "python -m modbus_edu.course: error: missing.ipynb is neither a notebook nor a folder of notebooks"]


def test_make_help_lists_every_target_and_clean_exists():
    if not shutil.which("make"):
        pytest.skip("make is not installed")
    done = subprocess.run(["make", "--no-print-directory", "help"], capture_output=True, text=True, cwd=ROOT)
    listed = {line.split(":")[0] for line in done.stdout.splitlines() if not line.startswith(" ")}
    wanted = {"help", "install", "lab", "test", "test-unit", "test-library", "notebooks", "clean", "release",
              "requirements"}
    assert wanted <= listed
    phony = re.search(r"^\.PHONY:(.*)$", (ROOT / "Makefile").read_text(), re.M).group(1).split()
    assert listed <= set(phony)


def test_the_class_copys_makefile_offers_only_what_works_there_and_it_has_a_gitignore(tmp_path):
    from modbus_edu.course.release import CLASS_TARGETS, release

    if not shutil.which("make"):
        pytest.skip("make is not installed")
    release(ROOT, tmp_path)
    done = subprocess.run(["make", "--no-print-directory", "help"], capture_output=True, text=True,
                          cwd=tmp_path, timeout=60)
    listed = [line.split(":")[0] for line in done.stdout.splitlines() if not line.startswith(" ")]
    assert listed == list(CLASS_TARGETS)
    makefile = (tmp_path / "Makefile").read_text(encoding="utf-8")
    assert "$(call venv,$(TEST_PINS))" not in makefile  # a learner's environment, never the test tools
    for target in listed:  # every file a target's recipe names is in the copy
        dry = subprocess.run(["make", "--no-print-directory", "-n", target], capture_output=True, text=True,
                             cwd=tmp_path, timeout=60, env={**os.environ, "PYTHON": sys.executable})
        assert dry.returncode == 0, dry.stderr
        named = re.findall(r"(?<![\w./-])((?:notebooks|binder|modbus_edu|tests|bench)/[\w./-]*)", dry.stdout)
        for path in named:
            assert (tmp_path / path).exists(), (target, path)
    ignored = (tmp_path / ".gitignore").read_text(encoding="utf-8").split()
    assert {".venv/", "__pycache__/", ".ipynb_checkpoints/"} <= set(ignored)
    # what belongs to the full repository only stays behind: the test tools' pins, and in `make clean`
    # the caches, the offline site and the release folder that the class copy never makes
    assert not (tmp_path / "binder" / "requirements-test.txt").exists()
    assert (tmp_path / "binder" / "requirements.txt").exists()
    dry = subprocess.run(["make", "--no-print-directory", "-n", "clean"], capture_output=True, text=True,
                         cwd=tmp_path, timeout=60)
    for artefact in (".pytest_cache", ".hypothesis", ".ruff_cache", ".coverage", "_site", "lite/", "release"):
        assert artefact not in dry.stdout, artefact
    assert ".venv" in dry.stdout


# --- slow: packages, virtual environments, the class copy, a hub's base image ------------------------------

@pytest.mark.slow
def test_the_wheel_and_the_sdist(tmp_path):
    done = subprocess.run([sys.executable, "-m", "build", "--outdir", str(tmp_path), str(ROOT)],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    (wheel,) = tmp_path.glob("*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert any(n.endswith("licenses/LICENSE") for n in names)
    assert any(n.endswith("licenses/LICENSE-COURSE") for n in names)
    assert "modbus_edu/devices/maps/power_meter.csv" in names
    assert not [n for n in names if n.startswith(("tests/", "notebooks/")) or "/tests/" in n]
    meta = zipfile.ZipFile(wheel).read(next(n for n in names if n.endswith("/METADATA"))).decode()
    requires = [Requirement(line.split(":", 1)[1]) for line in meta.splitlines()
                if line.startswith("Requires-Dist:")]
    plain = {r.name.lower() for r in requires if r.marker is None}
    # scapy: captures; cryptography: TLS; rich: the live table of `modbus-edu poll`
    assert plain == {"pymodbus", "pyserial", "tqdm", "scapy", "cryptography", "rich"}, plain
    course = {r.name.lower() for r in requires if r.marker and r.marker.evaluate({"extra": "course"})}
    assert {"jupyterlab", "ipywidgets", "matplotlib"} <= course
    (sdist,) = tmp_path.glob("*.tar.gz")
    import tarfile

    members = {m.split("/", 1)[1] for m in tarfile.open(sdist).getnames() if "/" in m}
    assert {"LICENSE", "LICENSE-COURSE", "CITATION.cff", "CHANGELOG.md", "binder/requirements.txt"} <= members


@pytest.mark.slow
def test_the_makefile_rebuilds_its_venv_when_the_python_or_the_pins_change(tmp_path):
    """In a small project laid out like this one: the stamp, and the one line saying why it rebuilds."""
    if not shutil.which("make"):
        pytest.skip("make is not installed")
    other = next((interpreter(v) for v in supported_pythons()
                  if v != f"{sys.version_info.major}.{sys.version_info.minor}" and interpreter(v)), None)
    shutil.copy(ROOT / "Makefile", tmp_path / "Makefile")
    (tmp_path / "binder").mkdir()
    (tmp_path / "binder" / "requirements.txt").write_text("# no pins\n")
    (tmp_path / "binder" / "requirements-test.txt").write_text("# no pins\n")
    (tmp_path / "modbus_edu").mkdir()
    (tmp_path / "modbus_edu" / "__init__.py").write_text('__version__ = "0.0.1"\n')
    (tmp_path / "pyproject.toml").write_text(
        '[build-system]\nrequires = ["hatchling>=1.27"]\nbuild-backend = "hatchling.build"\n'
        '[project]\nname = "modbus_edu"\nversion = "0.0.1"\nrequires-python = ">=3.10"\n')

    def make(*args: str) -> str:
        done = subprocess.run(["make", "--no-print-directory", "install", *args], cwd=tmp_path,
                              capture_output=True, text=True, timeout=600,
                              env={**os.environ, "PYTHON": sys.executable, "MAKEFLAGS": ""})
        return done.stdout + done.stderr

    first = make()
    stamp = tmp_path / ".venv" / "modbus-edu-stamp"
    assert stamp.exists() and "rebuilding" not in first, first
    assert make().count("rebuilding") == 0
    (tmp_path / "binder" / "requirements-test.txt").write_text("# no pins, changed\n")
    out = make()
    assert "rebuilding .venv from binder/requirements-test.txt: it was built from other pins than " \
           "binder/requirements-test.txt (the learner's pins of make lab lack the test tools" in out, out
    assert "it was built by" not in out  # the same Python: only the pins differ
    stamp.unlink()  # as an install stopped half-way leaves it
    assert "its install never finished" in make()
    if other:
        out = make(f"PYTHON={other}")
        # the stamp holds the interpreter that ran: a pyenv shim's is the version it resolves to
        ran = subprocess.run([other, "-c", "import sys; print(sys.executable)"], capture_output=True,
                             text=True, timeout=60).stdout.strip()
        assert "rebuilding" in out and ran in stamp.read_text().split(), out


@pytest.mark.slow
def test_the_class_copy_has_no_worked_solution_and_every_notebook_still_runs(tmp_path):
    destination = tmp_path / "class"
    done = subprocess.run([sys.executable, "-m", "modbus_edu.course", "release", str(destination)],
                          capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert done.returncode == 0, done.stderr
    assert not (destination / "notebooks" / "solutions").exists()
    assert not (destination / "tests").exists()
    notebooks = sorted((destination / "notebooks").glob("*.ipynb"))
    assert len(notebooks) == len(list((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb")))
    for path in notebooks:
        text = path.read_text(encoding="utf-8")
        assert "solutions/" not in text and "%load" not in text, path.name
    env = {**os.environ, "PYTHONPATH": str(destination)}
    run = subprocess.run([sys.executable, "-m", "modbus_edu.course", "execute", "notebooks"],
                         capture_output=True, text=True, cwd=destination, env=env, timeout=1800)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    assert run.stdout.count(" s\n") == len(notebooks)


def hub_base_requirements(lock: Path) -> list[str]:
    """The Python packages of one of repo2docker's conda lock files, as pip requirements.

    The lock lists conda packages; those with a Python build string (``py...``) are Python packages, under
    their PyPI names except for the few conda renames below."""
    renamed = {"brotli-python": "brotli", "python-fastjsonschema": "fastjsonschema",
               "jupyterhub-base": "jupyterhub", "nbconvert-core": "nbconvert"}
    found = []
    for line in lock.read_text().splitlines():
        match = re.search(r"/([^/]+)-([^-/]+)-([^-/]+)\.(?:conda|tar\.bz2)#", line)
        if match and match.group(3).startswith("py") and match.group(1) not in ("pip", "setuptools", "wheel"):
            found.append(f"{renamed.get(match.group(1), match.group(1))}=={match.group(2)}")
    return found


@pytest.mark.slow
def test_the_learner_pins_over_a_hub_base_image_pass_pip_check(tmp_path):
    """repo2docker's base environment for binder/runtime.txt's Python, read from repo2docker's own lock
    file, then the learner's pins over it, as a hub builds its image: ``pip check`` is clean."""
    version = (ROOT / "binder" / "runtime.txt").read_text().strip().removeprefix("python-")
    python = interpreter(version)
    if python is None:
        if os.environ.get("CI"):
            pytest.fail(f"no Python {version} (binder/runtime.txt's) on this machine")
        pytest.skip(f"no Python {version} (binder/runtime.txt's) on this machine")
    pip = [sys.executable, "-m", "pip"]
    subprocess.run([*pip, "download", "--quiet", "--no-deps", REPO2DOCKER, "-d", str(tmp_path)], check=True,
                   timeout=600)
    (wheel,) = tmp_path.glob("jupyter_repo2docker-*.whl")
    lock_name = f"repo2docker/buildpacks/conda/environment.py-{version}-linux-64.lock"
    (tmp_path / "base.lock").write_bytes(zipfile.ZipFile(wheel).read(lock_name))
    base = hub_base_requirements(tmp_path / "base.lock")
    assert any(line.startswith("notebook==7.") for line in base) and any(
        line.startswith("jupyterlab==4.") for line in base), base
    (tmp_path / "base.txt").write_text("\n".join(base) + "\n")
    subprocess.run([python, "-m", "venv", str(tmp_path / "hub")], check=True)
    hub = str(tmp_path / "hub" / "bin" / "python")
    for args in (["--no-deps", "-r", str(tmp_path / "base.txt")], ["-r", str(LEARNER_PINS)]):
        done = subprocess.run([hub, "-m", "pip", "install", "--quiet", *args], capture_output=True, text=True,
                              timeout=1500)
        assert done.returncode == 0, done.stderr[-3000:]
    check = subprocess.run([hub, "-m", "pip", "check"], capture_output=True, text=True)
    assert check.returncode == 0, check.stdout + check.stderr


def test_the_teaching_guide_names_every_exercise_and_the_readme_links_it():
    from modbus_edu.exercises import EXERCISES

    guide = (ROOT / "TEACHING.md").read_text(encoding="utf-8")
    rows = set(re.findall(r"^\| (\d\d\.\d+) \|", guide, re.M))
    assert rows == set(EXERCISES), set(EXERCISES) ^ rows
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "https://github.com/modbus-edu/modbus_edu/blob/main/TEACHING.md" in readme
