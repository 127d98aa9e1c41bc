"""Several simulated robots in one world for the traffic schedule's tests and bench: a
chassis and nav per robot (``/robot<k>``, in one process), their chassis sharing
``/sim/world``, each robot on its own sim clock (``/robot<k>/clock``: several chassis must
not each publish ``/clock``) and TF tree, optionally in schedule mode with a schedule server
on the same map; and a `Watch` of what happened: the true poses (closest approach, robots
inside one corridor at once), the bumpers, and the manager's reservations.

docs/fleet.md, "Traffic schedule"; tests/integration/test_traffic_robots.py,
bench/traffic.py.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

from zenros.action import ActionClient
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.nav2_msgs import NavigateToPose, NavigateToPoseGoal
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.zenros_msgs import ChassisState
from zenros.msgs.zenros_msgs.traffic import TrafficReservations
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.se2 import Pose2
from zenros.services.chassis.node import ChassisNode
from zenros.services.nav.actions.convert import pose_stamped
from zenros.services.nav.node import NavNode
from zenros.services.schedule.node import ScheduleServerNode
from zenros.testing import linked_contexts, wait_until

__all__ = ["Fleet", "Rect", "Watch", "traffic_robots"]

REMAPS = ["/clock:=clock", "/tf:=tf", "/tf_static:=tf_static", "/diagnostics:=diagnostics"]


@dataclass(frozen=True)
class Rect:
    """An axis-aligned box of the map (a corridor), for counting who is inside."""

    x0: float
    y0: float
    x1: float
    y1: float

    def holds(self, x: float, y: float) -> bool:
        return self.x0 <= x <= self.x1 and self.y0 <= y <= self.y1


@dataclass
class Watch:
    """What the user node saw, from the robots' true poses, chassis states and the
    manager's reservations (thread-safe: samples come on Zenoh's threads)."""

    corridors: Sequence[Rect] = ()
    truth: dict[str, tuple[float, float]] = field(default_factory=dict)
    closest: float = math.inf
    """The smallest distance between two robots' true centres seen."""
    bumped: set[str] = field(default_factory=set)
    """Robots whose bumper was ever pressed."""
    together: set[tuple[int, frozenset[str]]] = field(default_factory=set)
    """(corridor, robots) for every two robots seen inside one corridor at once."""
    shared_holds: list[tuple[int, list[str]]] = field(default_factory=list)
    """(segment, robots) for every reservations message with a segment held by two."""
    reservations: int = 0
    _lock: threading.Lock = field(default_factory=threading.Lock)

    def on_truth(self, robot: str, msg: Odometry) -> None:
        p = msg.pose.pose.position
        with self._lock:
            self.truth[robot] = (p.x, p.y)
            for other, (x, y) in self.truth.items():
                if other != robot:
                    self.closest = min(self.closest, math.hypot(p.x - x, p.y - y))
            for k, c in enumerate(self.corridors):
                inside = frozenset(r for r, (x, y) in self.truth.items() if c.holds(x, y))
                if len(inside) > 1:
                    self.together.add((k, inside))

    def on_state(self, robot: str, msg: ChassisState) -> None:
        if msg.bumper:
            with self._lock:
                self.bumped.add(robot)

    def on_reservations(self, msg: TrafficReservations) -> None:
        holders: dict[int, list[str]] = {}
        for r in msg.robots:
            for h in r.holds:
                holders.setdefault(h.segment, []).append(r.robot)
        with self._lock:
            self.reservations += 1
            self.shared_holds += [(s, names) for s, names in holders.items() if len(names) > 1]


@dataclass
class Fleet:
    """The robots (``robot1``..), their nodes, the schedule server (None: no schedule mode)
    and the user node's watch and goal clients."""

    names: list[str]
    chassis: dict[str, ChassisNode]
    nav: dict[str, NavNode]
    server: ScheduleServerNode | None
    user: Node
    watch: Watch
    navigate: dict[str, ActionClient[NavigateToPoseGoal, object]]

    def goal(self, x: float, y: float, theta: float = 0.0) -> NavigateToPoseGoal:
        return NavigateToPoseGoal(pose=pose_stamped(Pose2(x, y, theta), Time()))

    def sim_time(self, robot: str) -> float:
        """Seconds of ``robot``'s own sim clock."""
        return float(self.nav[robot].now().nanoseconds) * 1e-9


@contextmanager
def traffic_robots(home: Path, world: Path, starts: Sequence[tuple[float, float, float]], *,
                   speed: float = 5.0, schedule_mode: bool = True,
                   corridors: Sequence[Rect] = (), server_params: dict[str, object] | None = None,
                   ) -> Iterator[Fleet]:
    """Robots ``robot1``.. at ``starts`` in ``world`` (chassis at ``speed``), nav in schedule
    mode when ``schedule_mode`` (a schedule server ``local`` on ``world``, with
    ``server_params``), localized and with their goal servers up before it is handed out;
    every node closed on the way out (in-process: no child process to stop)."""
    names = [f"robot{k}" for k in range(1, len(starts) + 1)]
    # each chassis on a session of its own: two chassis on one session deliver their bodies
    # to each other in-process, each under its own simulation lock, and deadlock (ABBA)
    with linked_contexts(len(starts) + 2) as ctxs:
        brains, misc, *bodies = ctxs
        nodes: list[Node] = []
        try:
            server = None
            if schedule_mode:
                server = ScheduleServerNode(context=misc, parameter_overrides={
                    "data_dir": str(home / "schedule"), "traffic_map": str(world),
                    **(server_params or {})})
                nodes.append(server)
            watch = Watch(corridors)
            user = Node("traffic_watch", context=misc)
            nodes.append(user)
            user.create_subscription(TrafficReservations, "/schedule/local/reservations",
                                     watch.on_reservations, QOS_LATCHED)
            chassis: dict[str, ChassisNode] = {}
            nav: dict[str, NavNode] = {}
            for name, start, body in zip(names, starts, bodies, strict=True):
                user.create_subscription(Odometry, f"/{name}/sim/ground_truth",
                                         partial(watch.on_truth, name))
                user.create_subscription(ChassisState, f"/{name}/chassis/state",
                                         partial(watch.on_state, name))
                chassis[name] = ChassisNode("chassis", namespace=f"/{name}", context=body,
                                            remappings=REMAPS, parameter_overrides={
                    "speed": speed, "seed": 1, "map": str(world), "start_pose": list(start),
                    "world_topic": "/sim/world", "camera_rate": 0.0, "ptz_camera": False})
                nodes.append(chassis[name])
            for name in names:
                nav[name] = NavNode("nav", namespace=f"/{name}", context=brains,
                                    remappings=REMAPS, parameter_overrides={
                    "use_sim_time": True, "maps_dir": str(home / name / "maps"),
                    "map": str(world), "schedule_mode": schedule_mode})
                nodes.append(nav[name])
            navigate: dict[str, ActionClient[NavigateToPoseGoal, object]] = {
                n: ActionClient(user, NavigateToPose, f"/{n}/navigate_to_pose") for n in names}
            for n in names:
                wait_until(lambda n=n: nav[n].core.localizer.pose() is not None, 30)
                assert navigate[n].wait_for_server(30), n
            yield Fleet(names, chassis, nav, server, user, watch, navigate)
        finally:
            for node in reversed(nodes):
                node.close()
