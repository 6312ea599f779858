"""The TestTool's settings as a JSON-able dict: save, load, apply, restore."""

from __future__ import annotations

import contextlib
import json
import random
from pathlib import Path
from typing import Any

import ipywidgets as W

from ...errors import ConfigError, ModbusError
from ...values import FORMATS
from .controls import CONFIG_KEYS, ROLES


class ConfigMixin:
    """Every setting as a dict or a JSON file: :meth:`config`, :meth:`apply_config`, save and load."""

    # =====================================================================================================
    # configuration
    # =====================================================================================================
    def config(self) -> dict[str, Any]:
        """Every setting as a JSON-able dict (what *save config* writes)."""
        return {
            "role": self.role.value, "name": self.name.value, "connection": self.connection.value,
            "url": self.url.value, "baudrate": self.baudrate.value, "parity": self.parity.value,
            "stopbits": self.stopbits.value, "host": self.host.value, "port": self.port.value,
            "timeout": float(self.timeout.value), "unit": self.unit.value, "address": self.address.value,
            "length": self.length.value, "function": self.function.value,
            "transaction_id": self.transaction_id.value, "interval": float(self.interval.value),
            "continuous": self.continuous.value, "display": self.display.value,
            "fill_start": self.fill_start.value, "fill_increment": self.increment.value,
            "fill_step": self.fill_step.value, "auto_interval": float(self.auto_interval.value),
            "newest_on_top": self.newest_on_top.value, "seed": self._seed,
        }

    def apply_config(self, config: dict[str, Any]) -> bool:
        """Set every setting found in ``config`` (a dict as :meth:`config` returns).  Unknown keys or bad
        values are reported on the message line and nothing is changed.  Returns True on success."""
        try:
            if not isinstance(config, dict):
                raise ConfigError(f"a configuration is a dict (JSON object), got {type(config).__name__}")
            unknown = sorted(set(config) - set(CONFIG_KEYS) - {"version"})
            if unknown:
                raise ConfigError(f"unknown configuration key(s): {', '.join(unknown)}; "
                                  f"expected some of {', '.join(CONFIG_KEYS)}")
            if "role" in config and config["role"] not in ROLES:
                raise ConfigError(f"unknown role {config['role']!r}: expected one of {', '.join(ROLES)}")
            if "display" in config and config["display"] not in FORMATS:
                raise ConfigError(f"unknown display format {config['display']!r}")
            before = self.config()
            key = "role"
            try:
                if "role" in config and config["role"] != self.role.value:
                    self.role.value = config["role"]
                for key in CONFIG_KEYS:
                    if key in ("role", "seed") or key not in config:
                        continue
                    self._config_widget(key).value = config[key]
                if "seed" in config:
                    key = "seed"
                    if isinstance(config["seed"], bool) or not isinstance(config["seed"], int):
                        raise ValueError("the seed is a whole number")
                    self._seed = config["seed"]
                    self._rng = random.Random(self._seed)
            except Exception as exc:  # a widget refused a value (TraitError): put everything back
                self._restore(before)
                raise ConfigError(f"bad value for {key!r}: {config[key]!r} ({exc})") from None
        except ModbusError as exc:
            self.message.error(exc)
            return False
        self.refresh()
        return True

    def _restore(self, before: dict[str, Any]) -> None:
        if self.role.value != before["role"]:
            self.role.value = before["role"]
        for key in CONFIG_KEYS:
            if key not in ("role", "seed"):
                with contextlib.suppress(Exception):
                    self._config_widget(key).value = before[key]

    def _config_widget(self, key: str) -> W.ValueWidget:
        return self.increment if key == "fill_increment" else getattr(self, key)

    def save_config(self, path: str | Path | None = None) -> Path | None:
        """Write :meth:`config` as JSON to ``path`` (default: the *config file* field)."""
        target = Path(path if path is not None else self.config_path.value).expanduser()
        try:
            target.write_text(json.dumps({"version": 1, **self.config()}, indent=2) + "\n")
        except OSError as exc:
            self.message.error(ConfigError(
                f"cannot save the configuration to {target}: {exc.strerror or exc}"))
            return None
        self.message.show(f"configuration saved to {target}", "ok")
        return target

    def load_config(self, source: str | Path | dict[str, Any] | None = None) -> bool:
        """Load settings from a JSON file (default: the *config file* field) or from a dict."""
        if source is not None and not isinstance(source, (str, Path)):
            ok = self.apply_config(source)
            if ok:
                self.message.show("configuration loaded", "ok")
            return ok
        target = Path(source if source is not None else self.config_path.value).expanduser()
        try:
            config = json.loads(target.read_text())
        except OSError as exc:
            self.message.error(ConfigError(f"cannot read {target}: {exc.strerror or exc}"))
            return False
        except ValueError as exc:
            self.message.error(ConfigError(f"{target} is not valid JSON: {exc}"))
            return False
        ok = self.apply_config(config)
        if ok:
            self.message.show(f"configuration loaded from {target}", "ok")
        return ok

    @classmethod
    def from_config(cls, source: str | Path | dict, **kwargs: Any) -> Any:
        """A new tool with the settings of a saved configuration (a path or a dict)."""
        if isinstance(source, dict):
            config = dict(source)
        else:
            config = json.loads(Path(source).expanduser().read_text())
        config.pop("version", None)
        role = config.pop("role", "rtu_master")
        tool = cls(role, **kwargs)
        tool.apply_config(config)
        return tool

