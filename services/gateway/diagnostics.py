"""The gateway's diagnostics (``/diagnostics``): its front ends and their clients, and
whether the robot's data reaches it, through an `Updater` (docs/diagnostics.md)."""

from __future__ import annotations

from typing import Any

from zenros.diagnostics import OK, WARN, DiagnosticStatusWrapper, Updater

__all__ = ["gateway_diagnostics"]


def gateway_diagnostics(node: Any) -> Updater:
    """An Updater on ``node`` (a `GatewayNode`): ``front ends`` and ``clients``."""
    up = Updater(node)
    up.setHardwareID("none")
    def front_ends(stat: DiagnosticStatusWrapper) -> None:
        names = [end.name for end in node.front_ends.started]
        stat.summary(OK, f"{len(names)} up: {', '.join(names)}")
        for name in names:
            port = _port(node, name)
            stat.add(name, port if port is not None else "on")

    def clients(stat: DiagnosticStatusWrapper) -> None:
        topics = node.topics
        odom, state = topics.fresh("odom"), topics.fresh("chassis/state")
        if odom and state:
            stat.summary(OK, "robot data flowing")
        else:
            stat.summary(WARN, "no robot data for 2 s: " + ", ".join(
                t for t, ok in (("odom", odom), ("chassis/state", state)) if not ok))
        stat.add("rosbridge clients", len(node.rosbridge.clients) if node.rosbridge else 0)
        stat.add("odom fresh", odom)
        stat.add("chassis/state fresh", state)

    up.add("front ends", front_ends)
    up.add("clients", clients)
    return up


def _port(node: Any, front_end: str) -> int | None:
    """The TCP port a front end of ``node`` listens on (None: not a TCP server)."""
    attr = {"REST": "rest_port", "topic WebSocket": "ws_port", "Modbus": "modbus_port"}.get(
        front_end)
    if attr is not None:
        return int(getattr(node, attr))
    if front_end == "rosbridge" and node.rosbridge is not None:
        return int(node.rosbridge.port)
    return None
