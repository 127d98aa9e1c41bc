"""`GatewayConfig`: the docs/robot-api.md §1.4 server configuration file
(``galileo_api/config.json``)."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import msgspec
from zenros.errors import ConfigError

__all__ = ["GatewayConfig", "default_config_path", "load_config"]


class GatewayConfig(msgspec.Struct, forbid_unknown_fields=False):
    """The keys of §1.4. Token checking is ON unless ``no_token_check`` is true."""

    username: str = "admin"
    password: str = "admin"
    allow_update: bool = False
    no_token_check: bool = False
    auto_charge: bool = False
    host_commands: dict[str, list[str]] = msgspec.field(default_factory=dict)
    update_source: str = ""  # a folder of wheels or a package index URL (docs/robot-api.md §3.4)
    update_package: str = "zenros"
    # the simulated ONVIF camera (docs/robot-api.md §17): its address as /system/onvif_cameras
    # lists it (port 0: the REST port, where its MJPEG stream is served) and its credentials
    # (empty: it takes any)
    onvif_ip: str = "127.0.0.1"
    onvif_port: int = 0
    onvif_username: str = ""
    onvif_password: str = ""


def default_config_path() -> Path:
    """``$ZENROS_HOME/galileo_api/config.json`` (``~/.zenros`` by default)."""
    home = Path(os.environ.get("ZENROS_HOME") or Path.home() / ".zenros")
    return home / "galileo_api" / "config.json"


def load_config(path: Path | None, overrides: dict[str, Any] | None = None) -> GatewayConfig:
    """Read the file (missing file: defaults) and apply ``overrides`` on top.

    Raises:
        ConfigError: the file is not JSON or a key has the wrong type (names the key).
    """
    data: dict[str, Any] = {}
    if path is not None and path.exists():
        try:
            data = json.loads(path.read_text())
        except json.JSONDecodeError as exc:
            raise ConfigError(f"{path}: not JSON: {exc}") from exc
        if not isinstance(data, dict):
            raise ConfigError(f"{path}: expected a JSON object, got {type(data).__name__}")
    data.update(overrides or {})
    try:
        return msgspec.convert(data, GatewayConfig)
    except msgspec.ValidationError as exc:
        raise ConfigError(f"{path or 'gateway config'}: {exc}") from exc
