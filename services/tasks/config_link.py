"""`ConfigLink`: the gateway's ``/system/config`` settings for the tasks service
(``change_setting_action``), over the gateway's ``system/set_config``
(zenros_msgs/SetConfig): the keys, checks and store ``POST /system/config`` uses."""

from __future__ import annotations

import json
from typing import Any

from zenros.errors import ZenrosError
from zenros.msgs.zenros_msgs import SetConfig, SetConfigRequest
from zenros.node import Node

from .outcome import Outcome

__all__ = ["ConfigLink"]


class ConfigLink:
    """Settings changes through the gateway; the client made at the first."""

    def __init__(self, node: Node, server_wait: float = 5.0) -> None:
        self.node = node
        self.server_wait = server_wait
        self._client: Any = None

    def change(self, settings: dict[str, Any], check_only: bool = False) -> Outcome:
        """`Robot.change_settings`."""
        if self._client is None:
            self._client = self.node.create_client(SetConfig, "system/set_config")
        if not self._client.wait_for_service(self.server_wait):
            return Outcome("error", "no gateway serves system/set_config (it keeps the "
                                    "robot's /system/config settings)")
        try:
            text = json.dumps(settings)
        except (TypeError, ValueError) as exc:
            return Outcome("error", f"settings: {exc}")
        try:
            res = self._client.call(SetConfigRequest(settings=text, check_only=check_only),
                                    timeout=self.server_wait)
        except ZenrosError as exc:
            return Outcome("error", f"change settings: {exc}")
        if not res.success:
            return Outcome("error", res.message)
        return Outcome("complete", res.message)
