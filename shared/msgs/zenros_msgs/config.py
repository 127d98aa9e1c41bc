"""zenros_msgs for the gateway's configuration (``/system/config``, docs/robot-api.md §3.6):
the tasks service's ``change_setting_action`` changes it through ``system/set_config``, the
same keys, checks and store ``POST /system/config`` uses.
"""

from __future__ import annotations

from ...message import Message, define_service

__all__ = ["SetConfig", "SetConfigRequest", "SetConfigResponse"]


class SetConfigRequest(Message):
    """``settings``: a JSON object of configuration keys and their new values (any subset of
    the keys ``GET /system/config`` shows, ``maps`` aside); ``check_only``: answer whether
    they would be taken, changing nothing."""

    __msgtype__ = "zenros_msgs/SetConfigRequest"
    settings: str = "{}"
    check_only: bool = False  # only check ``settings``; change nothing


class SetConfigResponse(Message):
    """``success`` false with the reason in ``message`` (nothing changed then);
    ``previous``: the changed keys' values before, as a JSON object."""

    __msgtype__ = "zenros_msgs/SetConfigResponse"
    success: bool = False
    message: str = ""
    previous: str = "{}"


SetConfig = define_service("zenros_msgs/SetConfig", SetConfigRequest, SetConfigResponse)
