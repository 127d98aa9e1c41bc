"""`NavServices`: the nav service's map, path, nav-point, wall and charge-pose services, and
its ``map`` and ``initialpose`` topics, for the REST handlers.

A call names its service by type: ``await nav.call(zm.GetNavPoints, request)`` is a
``GetNavPointsResponse``; `SERVICES` maps each type to nav's service name. A refusal becomes
the port error of nav's `ResultCode`, with nav's reason.
"""

from __future__ import annotations

from typing import Any, Final

from zenros.message import Q, S, ServiceType
from zenros.msgs import zenros_msgs as zm
from zenros.msgs.geometry_msgs import Point, Pose, PoseStamped, PoseWithCovarianceStamped
from zenros.msgs.nav_msgs import OccupancyGrid
from zenros.msgs.std_msgs import Header
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.rpc import Client
from zenros.tf.convert import yaw_to_msg

from ..errors import PortError, port_error
from ..state.presence import Presence
from .calls import call_port

__all__ = ["SERVICES", "NavServices", "pose_stamped"]

SERVICES: Final[dict[ServiceType[Any, Any], str]] = {
    **zm.NAV_SERVICE_NAMES, zm.SetScheduleMode: "set_schedule_mode",
    zm.GetScheduleMode: "get_schedule_mode"}
"""Nav's services the gateway calls, by type: one service per type."""


def pose_stamped(x: float, y: float, theta: float) -> PoseStamped:
    return PoseStamped(header=Header(frame_id="map"), pose=Pose(
        position=Point(x=x, y=y),
        orientation=yaw_to_msg(theta)))


class NavServices:
    """``await call(srv, request)`` → ``srv``'s response; the current map grid from ``map``
    (latched); `publish_initialpose`."""

    def __init__(self, node: Node, presence: Presence, timeout: float = 10.0) -> None:
        self.node = node
        self.timeout = timeout
        self.presence = presence
        self._clients: dict[ServiceType[Any, Any], Client[Any, Any]] = {
            srv: node.create_client(srv, name) for srv, name in SERVICES.items()}
        self.initialpose = node.create_publisher(PoseWithCovarianceStamped, "initialpose", 10)
        self.grid: OccupancyGrid | None = None
        node.create_subscription(OccupancyGrid, "map", self._on_map, QOS_LATCHED)

    def _on_map(self, msg: OccupancyGrid) -> None:
        self.grid = msg

    async def call(self, srv: ServiceType[Q, S], request: Q) -> S:
        """Call nav's service of type ``srv``; its response, or the port error of nav's
        refusal (`Unavailable` when nav does not serve it, `NoAnswer` when it is slow)."""
        client: Client[Q, S] = self._clients[srv]
        # the kind of a refusal comes from nav's code, never its wording
        return await call_port(client, request, self.timeout,
                               lambda: self.presence.error("nav", f"no server for {client.name}"),
                               "the nav service", lambda exc: port_error(exc.code, exc.reason))

    async def maps(self) -> tuple[list[str], str]:
        """(stored map names, current map); empty when nav does not answer."""
        try:
            res = await self.call(zm.ListMaps, zm.ListMapsRequest())
        except PortError:
            return [], ""
        return sorted(m.name for m in res.maps), str(res.current)

    async def current_map(self) -> str:
        """The current map's name."""
        res = await self.call(zm.GetCurrentMap, zm.GetCurrentMapRequest())
        return str(res.name)

    def publish_initialpose(self, x: float, y: float, theta: float) -> None:
        """Tell localization the robot is at (``x``, ``y``, ``theta``) on the map."""
        msg = PoseWithCovarianceStamped(header=Header(frame_id="map"))
        msg.pose.pose = pose_stamped(x, y, theta).pose
        self.initialpose.publish(msg)
