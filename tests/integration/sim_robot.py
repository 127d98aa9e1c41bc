"""The simulated robot the nav, tasks and gateway integration tests drive, in one process: the
chassis (10x by default), nav on sim time, tasks and a user node, each on a Zenoh session of its
own (linked on loopback), and a gateway beside tasks when a test talks REST.

Module-scoped rigs build on these (``with gateway_robot(tmp) as robot:``), so a module starts
the robot once and its tests reset what they moved (tests/README.md, "Rigs").
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
from zenros.context import Context
from zenros.node import Node
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.node import GatewayNode
from zenros.services.gateway.testing import running_gateway
from zenros.services.nav.node import NavNode
from zenros.services.tasks.node import TasksNode
from zenros.testing import linked_contexts, wait_until

__all__ = ["GatewayRobot", "SimRobot", "gateway_robot", "sim_robot"]


@dataclass
class SimRobot:
    chassis: ChassisNode
    nav: NavNode
    tasks: TasksNode | None
    user: Node
    contexts: list[Context]


@dataclass
class GatewayRobot(SimRobot):
    gw: GatewayNode
    http: httpx.Client
    """The gateway's REST API (``/api/v1``), token check off."""

    def add_nav_points(self, map_name: str, path: str, data: str) -> None:
        """``POST /navigation/nav_points`` (docs/robot-api.md §6.6: its text form), checked."""
        r = self.http.post("/navigation/nav_points", json={
            "map_name": map_name, "path_name": path, "path_data": data})
        assert r.status_code == 200, r.text


@contextmanager
def sim_robot(home: Path, *, tasks: bool = True, chassis: dict[str, Any] | None = None,
              nav: dict[str, Any] | None = None) -> Iterator[SimRobot]:
    """The chassis (``speed`` 10, ``seed`` 1, or ``chassis``'s values), nav (maps under
    ``home/maps``, on sim time, plus ``nav``'s values), tasks if ``tasks`` (``home/tasks``) and
    a user node, localized before it is handed out; every node closed on the way out."""
    with linked_contexts(4 if tasks else 3) as ctxs:
        nodes: list[Node] = []
        try:
            ch = ChassisNode("chassis", context=ctxs[0], parameter_overrides={
                "speed": 10.0, "seed": 1, **(chassis or {})})
            nodes.append(ch)
            nv = NavNode("nav", context=ctxs[1], parameter_overrides={
                "use_sim_time": True, "maps_dir": str(home / "maps"), **(nav or {})})
            nodes.append(nv)
            ts = None
            if tasks:
                ts = TasksNode(context=ctxs[2], parameter_overrides={
                    "data_dir": str(home / "tasks"), "use_sim_time": True})
                nodes.append(ts)
            user = Node("user", context=ctxs[-1])
            nodes.append(user)
            wait_until(lambda: nv.core.localizer.pose() is not None, 10)
            yield SimRobot(ch, nv, ts, user, ctxs)
        finally:
            for n in reversed(nodes):
                n.close()


@contextmanager
def gateway_robot(home: Path, **kw: Any) -> Iterator[GatewayRobot]:
    """`sim_robot` with a gateway on the tasks' session (token check off, settings under
    ``home``), once it serves the tasks' calls and nav's goals."""
    with sim_robot(home, **kw) as robot, \
            running_gateway(robot.contexts[2], home, no_token_check=True) as gw, \
            httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1",
                         timeout=20) as http:
        assert gw.nav_actions.navigate.wait_for_server(10)
        assert gw.graph.wait_for_service("/tasks/create", 10)
        yield GatewayRobot(robot.chassis, robot.nav, robot.tasks, robot.user, robot.contexts,
                           gw, http)
