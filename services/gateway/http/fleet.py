"""`FleetApi`: one gateway's robot API for several robots: ``/api/v1/robots/<name>/...`` for
each, ``/api/v1/...`` for the default robot, and ``GET /api/v1/robots``, the list."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any
from urllib.parse import parse_qsl

from starlette.types import Receive, Scope, Send

from ..state.status import system_status_name
from ..state.tokens import TokenStore
from .api import PREFIX, PREFIX_KEY, Api, error_body, send_json

__all__ = ["ROBOTS", "FleetApi", "robot_summary"]

ROBOTS = PREFIX + "/robots"


def robot_summary(name: str, api: Api) -> dict[str, Any]:
    """What ``GET /api/v1/robots`` says of one robot: its state, battery, pose, e-stop."""
    ctx = api.ctx
    state = ctx.core.state
    pose = None if state.pose is None else {"x": state.pose[0], "y": state.pose[1],
                                            "theta": state.pose[2]}
    return {"name": name, "online": ctx.topics.fresh("odom"),
            "state": system_status_name(ctx.core.status), "estop": state.estop,
            "battery": round(state.battery_percent, 1), "charging": state.charging,
            "pose": pose, "target_status": state.goal.status}


class FleetApi:
    """Routes each robot's paths to its `Api` (the same handlers, on that robot's ports).

    Robots join with `add` (configured at start, or found in the graph later); the list
    keeps that order. A name the gateway does not serve is a 404 that says where the list is.
    """

    def __init__(self, tokens: TokenStore, default: str,
                 on_list: Callable[[], None] | None = None) -> None:
        self.tokens = tokens
        self.default = default
        self.robots: dict[str, Api] = {}
        self.on_list = on_list  # called before each list (e.g. a look at the graph)

    def add(self, name: str, api: Api) -> None:
        self.robots[name] = api
        api.in_fleet = True  # its OpenAPI document lists /robots and /robots/{robot}/...
        api.openapi.clear()

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        path: str = scope["path"]
        if path.rstrip("/") == ROBOTS:
            await self._list(scope, send)
            return
        if path.startswith(ROBOTS + "/"):
            name = path[len(ROBOTS) + 1:].partition("/")[0]
            api = self.robots.get(name)
            if api is None:
                await send_json(send, 404, error_body(
                    f"no robot {name!r} on this gateway (GET {ROBOTS} lists its robots)"))
                return
            await api({**scope, PREFIX_KEY: f"{ROBOTS}/{name}"}, receive, send)
            return
        api = self.robots.get(self.default)
        if api is None:
            await send_json(send, 503, error_body(
                f"the default robot {self.default!r} is not in the graph yet; "
                f"GET {ROBOTS} lists the robots there are"), [(b"retry-after", b"2")])
            return
        await api(scope, receive, send)

    async def _list(self, scope: Scope, send: Send) -> None:
        if scope["method"] not in ("GET", "HEAD"):
            await send_json(send, 405, error_body(
                f"{scope['method']} not allowed on {scope['path']}; allowed: GET"))
            return
        query = dict(parse_qsl(scope.get("query_string", b"").decode("latin-1")))
        problem = self.tokens.problem(query.pop("token", None))
        if problem is not None:
            await send_json(send, 401, error_body(problem))
            return
        if query:
            await send_json(send, 400, error_body(
                f"unknown query parameter(s): {', '.join(sorted(query))}"))
            return
        if self.on_list is not None:
            self.on_list()
        await send_json(send, 200, {
            "default": self.default,
            "robots": [robot_summary(name, api) for name, api in self.robots.items()]})
