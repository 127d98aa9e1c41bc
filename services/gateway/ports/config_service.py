"""``system/set_config`` (zenros_msgs/SetConfig): the gateway's ``/system/config`` for the
robot's other services (the tasks service's ``change_setting_action``): the keys, checks and
store ``POST /system/config`` uses, so a change made either way is the same change."""

from __future__ import annotations

import json
from typing import Any

import msgspec
from zenros.msgs.zenros_msgs import SetConfig, SetConfigRequest, SetConfigResponse
from zenros.node import Node

from ..state.settings import KEYS, Settings, SettingsPatch

__all__ = ["ConfigService"]


class ConfigService:
    """Serves ``system/set_config`` on ``node`` with ``settings``."""

    def __init__(self, node: Node, settings: Settings) -> None:
        self.settings = settings
        node.create_service(SetConfig, "system/set_config", self.set)

    def set(self, req: SetConfigRequest, res: SetConfigResponse) -> SetConfigResponse:
        try:
            patch, previous = self.check(req.settings)
        except ValueError as exc:
            return SetConfigResponse(message=str(exc))
        if req.check_only:
            return SetConfigResponse(success=True, previous=json.dumps(previous),
                                     message="valid settings")
        self.settings.update(patch)
        return SetConfigResponse(success=True, previous=json.dumps(previous),
                                 message="set " + ", ".join(
                                     f"{k}={v!r}" for k, v in json.loads(req.settings).items()))

    def check(self, text: str) -> tuple[Any, dict[str, Any]]:
        """``text`` as a settings patch, and the values its keys have now.

        Raises:
            ValueError: not a JSON object, an unknown key (named), a wrong value (its key).
        """
        try:
            given = json.loads(text)
        except ValueError as exc:
            raise ValueError(f"settings: not JSON ({exc})") from exc
        if not isinstance(given, dict) or not given:
            raise ValueError("settings: expected a non-empty object of configuration keys")
        for key in given:
            if key not in KEYS:
                raise ValueError(f"unknown configuration key {key!r}; known: "
                                 + ", ".join(KEYS))
        try:
            patch = msgspec.convert(given, SettingsPatch)
        except msgspec.ValidationError as exc:
            raise ValueError(f"settings: {exc}") from exc
        now = self.settings.as_dict()
        return patch, {k: now[k] for k in given}
