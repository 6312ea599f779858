"""The TestTool's settings (:class:`~.controls.TestToolSettings`) as a JSON-able dict: save, load, apply,
restore."""

from __future__ import annotations

import contextlib
import dataclasses
import json
import math
import random
from pathlib import Path
from typing import Any

import ipywidgets as W

from ...errors import ConfigError, ModbusError, shown
from ...values import FORMATS
from .controls import CONFIG_KEYS, ROLES, TestToolSettings


class ConfigMixin:
    """Every setting as a dict or a JSON file: :meth:`config`, :meth:`apply_config`, save and load."""

    # =====================================================================================================
    # configuration
    # =====================================================================================================
    def settings(self) -> TestToolSettings:
        """Every setting, as the controls hold it now."""
        values = {key: self._config_widget(key).value for key in CONFIG_KEYS if key != "seed"}
        for key in ("timeout", "interval", "auto_interval"):
            values[key] = float(values[key])
        return TestToolSettings(**values, seed=self._seed)

    def config(self) -> dict[str, Any]:
        """Every setting as a JSON-able dict (what *save config* writes): :meth:`settings` as a dict."""
        return dataclasses.asdict(self.settings())

    def apply_config(self, config: dict[str, Any]) -> bool:
        """Set every setting found in ``config`` (a dict as :meth:`config` returns).  Unknown keys or bad
        values are reported on the message line and nothing is changed: a value outside a field's range
        is refused, never clamped.  Returns True on success."""
        try:
            if not isinstance(config, dict):
                raise ConfigError(f"a configuration is a dict (JSON object), got {type(config).__name__}")
            unknown = sorted(str(key) for key in config if key not in CONFIG_KEYS and key != "version")
            if unknown:
                raise ConfigError(f"unknown configuration key(s): {shown(', '.join(unknown), 80)}; "
                                  f"expected some of {', '.join(CONFIG_KEYS)}")
            if "role" in config and (not isinstance(config["role"], str) or config["role"] not in ROLES):
                raise ConfigError(f"unknown role {shown(config['role'])}: expected one of {', '.join(ROLES)}")
            display = config.get("display", FORMATS[0])
            if not isinstance(display, str) or display not in FORMATS:
                raise ConfigError(f"unknown display format {shown(display)}")
            before = self.config()
            key = "role"
            try:
                if "role" in config and config["role"] != self.role.value:
                    self.role.value = config["role"]
                for key in CONFIG_KEYS:
                    if key in ("role", "seed") or key not in config:
                        continue
                    self._check_setting(key, config[key])  # against the fields of the new role
                    self._config_widget(key).value = config[key]
                if "seed" in config:
                    key = "seed"
                    if isinstance(config["seed"], bool) or not isinstance(config["seed"], int):
                        raise ValueError("the seed is a whole number")
                    self._seed = config["seed"]
                    self._rng = random.Random(self._seed)
            except Exception as exc:  # a widget refused a value (TraitError): put everything back
                self._restore(before)
                why = str(exc) if isinstance(exc, ConfigError) else f"{type(exc).__name__}: {exc}"
                raise ConfigError(f"bad value for {shown(key)}: {shown(why, 160)}") from None
        except ModbusError as exc:
            self.message.error(exc)
            return False
        except (TypeError, ValueError, RecursionError) as exc:  # a value no check foresaw: say so
            self.message.error(ConfigError(f"this configuration cannot be used: {type(exc).__name__}"))
            return False
        self.refresh()
        return True

    def _check_setting(self, key: str, value: Any) -> None:
        """Refuse a value the field would not hold as given (a widget would clamp it without a word)."""
        widget = self._config_widget(key)
        current = widget.value
        if isinstance(current, bool):
            if not isinstance(value, bool):
                raise ConfigError(f"{key} is true or false, got {shown(value)}")
        elif isinstance(current, (int, float)) and not hasattr(widget, "options"):
            number = (int, float) if isinstance(current, float) else (int,)
            if isinstance(value, bool) or not isinstance(value, number) or (
                    isinstance(value, float) and not math.isfinite(value)):
                kind = "a number" if isinstance(current, float) else "a whole number"
                raise ConfigError(f"{key} is {kind}, got {shown(value)}")
            low, high = getattr(widget, "min", None), getattr(widget, "max", None)
            if (low is not None and value < low) or (high is not None and value > high):
                raise ConfigError(f"{key} must be {low} to {high}, got {shown(value)}")
        elif hasattr(widget, "options"):
            allowed = [option[1] if isinstance(option, tuple) else option for option in widget.options]
            if not any(type(value) is type(option) and value == option for option in allowed):
                raise ConfigError(f"{key} must be one of {shown(allowed, 120)}, got {shown(value)}")
        elif isinstance(current, str) and not isinstance(value, str):
            raise ConfigError(f"{key} is text, got {shown(value)}")

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
            config = read_config(target)
        except ConfigError as exc:
            self.message.error(exc)
            return False
        ok = self.apply_config(config)
        if ok:
            self.message.show(f"configuration loaded from {target}", "ok")
        return ok

    @classmethod
    def from_config(cls, source: str | Path | dict, **kwargs: Any) -> Any:
        """A new tool with the settings of a saved configuration (a path or a dict)."""
        config = dict(source) if isinstance(source, dict) else read_config(Path(source).expanduser())
        config.pop("version", None)
        role = config.pop("role", "rtu_master")
        if not isinstance(role, str) or role not in ROLES:
            raise ConfigError(f"unknown role {shown(role)}: expected one of {', '.join(ROLES)}")
        tool = cls(role, **kwargs)
        if not tool.apply_config(config):
            raise ConfigError(tool.message.text.split(": ", 1)[-1] or "the configuration was refused")
        return tool


def read_config(path: Path) -> dict[str, Any]:
    """A saved configuration: the JSON object in ``path``, or a ConfigError saying what is wrong."""
    try:
        config = json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ConfigError(f"cannot read {path}: {exc.strerror or exc}") from None
    except (ValueError, RecursionError) as exc:  # not JSON, or nested too deeply to read
        raise ConfigError(f"{path} is not valid JSON: {shown(str(exc), 120)}") from None
    if not isinstance(config, dict):
        raise ConfigError(f"{path} holds {type(config).__name__}, not a configuration (a JSON object)")
    return config

