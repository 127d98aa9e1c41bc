"""Message, service and action types by ROS name, the standard types (`zenros.msgs`) included.

`zenros.message` holds the tables types register in as they are defined; this module sits
above `zenros.msgs` and imports it, so a lookup always sees the standard types and
`zenros.message` never imports the messages defined on it.
"""

from __future__ import annotations

from . import msgs  # noqa: F401  (importing registers the standard types)
from .message import TABLES, ActionType, Message, ServiceType, find_registered

__all__ = ["lookup_action", "lookup_service", "lookup_type", "registered_actions",
           "registered_services", "registered_types"]


def lookup_type(name: str) -> type[Message]:
    """The message class registered under a ROS type name (``pkg/Name``, ``pkg/msg/Name`` or
    an unambiguous ``Name``).

    Raises:
        UnknownTypeError: No such type (the message names the closest ones), or a short
            name more than one package defines.
    """
    cls: type[Message] = find_registered(TABLES.messages, "message", name)
    return cls


def lookup_service(name: str) -> ServiceType:
    """The service type registered under a ROS type name (as `lookup_type`)."""
    srv: ServiceType = find_registered(TABLES.services, "service", name)
    return srv


def lookup_action(name: str) -> ActionType:
    """The action type registered under a ROS type name (as `lookup_type`)."""
    act: ActionType = find_registered(TABLES.actions, "action", name)
    return act


def registered_types() -> dict[str, type[Message]]:
    """Every registered message class, by wire type name."""
    return dict(TABLES.messages)


def registered_services() -> dict[str, ServiceType]:
    """Every registered service type, by wire type name."""
    return dict(TABLES.services)


def registered_actions() -> dict[str, ActionType]:
    """Every registered action type, by wire type name."""
    return dict(TABLES.actions)
