"""Start a private JupyterLab server for the browser tests, and stop it again.

The server runs with the interpreter that runs the tests (``sys.executable``), so the notebook's kernel
is the project's environment.  Everything Jupyter writes (config, runtime files, workspaces, settings)
goes into a temporary directory; a kernelspec named ``modbus-edu-test`` pointing at ``sys.executable``
is written into a private ``JUPYTER_PATH`` and the test notebook asks for that kernel by name.
"""

from __future__ import annotations

import json
import os
import secrets
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from dataclasses import dataclass, field
from pathlib import Path

KERNEL_NAME = "modbus-edu-test"
REPO_ROOT = Path(__file__).resolve().parents[2]


def free_port() -> int:
    """A TCP port on 127.0.0.1 that nobody listens on right now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def write_kernelspec(jupyter_path: Path) -> Path:
    """Write a kernelspec that starts ipykernel with this very interpreter."""
    kdir = jupyter_path / "kernels" / KERNEL_NAME
    kdir.mkdir(parents=True, exist_ok=True)
    spec = {
        "argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
        "display_name": "modbus_edu test (project venv)",
        "language": "python",
        "env": {"PYTHONPATH": str(REPO_ROOT)},
    }
    (kdir / "kernel.json").write_text(json.dumps(spec, indent=1))
    return kdir


def quiet_lab_settings(settings_dir: Path) -> None:
    """Switch off JupyterLab's news and update checks (no network, no pop-up over the notebook), and
    the notebook's windowing (cells off screen are rendered too)."""
    d = settings_dir / "@jupyterlab" / "apputils-extension"
    d.mkdir(parents=True, exist_ok=True)
    (d / "notification.jupyterlab-settings").write_text(
        json.dumps({"checkForUpdates": False, "fetchNews": "false"})
    )
    # every cell rendered and laid out, so that panels far down a notebook can be measured
    n = settings_dir / "@jupyterlab" / "notebook-extension"
    n.mkdir(parents=True, exist_ok=True)
    (n / "tracker.jupyterlab-settings").write_text(json.dumps({"windowingMode": "none"}))


@dataclass
class JupyterLab:
    """A running JupyterLab; use as a context manager.  ``url(path)`` adds the token."""

    root_dir: Path
    port: int = field(default_factory=free_port)
    token: str = field(default_factory=lambda: secrets.token_hex(24))
    startup_timeout: float = 60.0
    proc: subprocess.Popen | None = None
    log_path: Path | None = None

    @property
    def base(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    def url(self, path: str = "lab") -> str:
        sep = "&" if "?" in path else "?"
        return f"{self.base}/{path.lstrip('/')}{sep}token={self.token}"

    def _env(self, home: Path) -> dict[str, str]:
        env = dict(os.environ)
        jpath = home / "jupyter_path"
        write_kernelspec(jpath)
        settings = home / "lab_settings"
        quiet_lab_settings(settings)
        for name, sub in [
            ("JUPYTER_CONFIG_DIR", "config"),
            ("JUPYTER_RUNTIME_DIR", "runtime"),
            ("JUPYTER_DATA_DIR", "data"),
            ("JUPYTERLAB_WORKSPACES_DIR", "workspaces"),
            ("IPYTHONDIR", "ipython"),
            ("MPLCONFIGDIR", "mpl"),
        ]:
            (home / sub).mkdir(parents=True, exist_ok=True)
            env[name] = str(home / sub)
        # no news feed, no update check: the test runs offline and nothing pops up over the notebook
        (home / "config" / "jupyter_lab_config.json").write_text(json.dumps({
            "LabApp": {"news_url": None, "check_for_updates_class": "jupyterlab.NeverCheckForUpdate"},
        }))
        env["JUPYTER_PATH"] = str(jpath)
        env["JUPYTERLAB_SETTINGS_DIR"] = str(settings)
        env["JUPYTER_PLATFORM_DIRS"] = "1"
        env["PYTHONPATH"] = os.pathsep.join(p for p in [str(REPO_ROOT), env.get("PYTHONPATH", "")] if p)
        # the kernel, too, must see the project's venv first
        env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
        return env

    def start(self) -> JupyterLab:
        home = self.root_dir.parent / "jupyter_home"
        home.mkdir(parents=True, exist_ok=True)
        self.log_path = home / "server.log"
        cmd = [
            sys.executable, "-m", "jupyter", "lab",
            "--no-browser",
            "--ServerApp.ip=127.0.0.1",
            f"--ServerApp.port={self.port}",
            "--ServerApp.port_retries=0",
            f"--IdentityProvider.token={self.token}",
            f"--ServerApp.root_dir={self.root_dir}",
            "--ServerApp.terminals_enabled=False",
            # only the project's kernel exists, so nothing can pick another interpreter
            f"--KernelSpecManager.allowed_kernelspecs={KERNEL_NAME}",
        ]
        if hasattr(os, "geteuid") and os.geteuid() == 0:  # containers often run as root
            cmd.append("--allow-root")
        log = open(self.log_path, "wb")  # noqa: SIM115 - closed in stop()
        self._log = log
        env = self._env(home)
        # matplotlib's font cache, built once here: in the fresh MPLCONFIGDIR the first plot of a Run All
        # (notebook 03's) would build it, slowly on a loaded machine, and say so on stderr
        subprocess.run([sys.executable, "-c", "import matplotlib.font_manager"], env=env, check=True,
                       capture_output=True, timeout=self.startup_timeout)
        self.proc = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT,
                                     cwd=str(self.root_dir))
        deadline = time.monotonic() + self.startup_timeout
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError(f"JupyterLab exited with {self.proc.returncode}:\n{self.log_tail()}")
            try:
                with urllib.request.urlopen(self.url("api/status"), timeout=2) as r:
                    if r.status == 200:
                        return self
            except (urllib.error.URLError, ConnectionError, TimeoutError, OSError):
                pass
            time.sleep(0.25)
        self.stop()
        raise RuntimeError(f"JupyterLab did not answer within {self.startup_timeout} s:\n{self.log_tail()}")

    def shutdown_sessions(self) -> int:
        """Close every notebook session (and so its kernel): a finished page leaves no kernel running."""
        try:
            with urllib.request.urlopen(self.url("api/sessions"), timeout=10) as r:
                sessions = json.loads(r.read())
        except (urllib.error.URLError, ConnectionError, TimeoutError, OSError, ValueError):
            return 0
        for s in sessions:
            req = urllib.request.Request(self.url(f"api/sessions/{s['id']}"), method="DELETE")
            try:
                urllib.request.urlopen(req, timeout=15).close()
            except (urllib.error.URLError, ConnectionError, TimeoutError, OSError):
                pass
        return len(sessions)

    def log_tail(self, n: int = 4000) -> str:
        try:
            return self.log_path.read_text(errors="replace")[-n:] if self.log_path else ""
        except OSError:
            return ""

    def stop(self) -> None:
        """Ask the server to shut down (it stops its kernels), then make sure the process is gone."""
        if self.proc is None:
            return
        if self.proc.poll() is None:
            try:
                req = urllib.request.Request(self.url("api/shutdown"), method="POST", data=b"")
                urllib.request.urlopen(req, timeout=5).close()
            except (urllib.error.URLError, ConnectionError, TimeoutError, OSError):
                pass
            try:
                self.proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                self.proc.terminate()
                try:
                    self.proc.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    self.proc.kill()
                    self.proc.wait(timeout=5)
        self._log.close()
        self.proc = None

    def __enter__(self) -> JupyterLab:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()


def copy_notebook(src: Path, dest_dir: Path, clear: bool = False) -> Path:
    """Copy the test notebook into the server's root, naming the private kernel in its metadata.

    ``clear``: without stored outputs, execution counts or widget state, so that whatever the page
    shows after a run was made by that run."""
    nb = json.loads(src.read_text())
    if clear:
        nb.get("metadata", {}).pop("widgets", None)
        for cell in nb.get("cells", []):
            if cell.get("cell_type") == "code":
                cell["outputs"], cell["execution_count"] = [], None
    nb.setdefault("metadata", {})["kernelspec"] = {
        "name": KERNEL_NAME, "display_name": "modbus_edu test (project venv)", "language": "python",
    }
    dest = dest_dir / src.name
    dest.write_text(json.dumps(nb, indent=1))
    return dest


__all__ = ["JupyterLab", "KERNEL_NAME", "copy_notebook", "free_port"]
