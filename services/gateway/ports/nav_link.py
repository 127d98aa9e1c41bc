"""`NavLink`: the nav service's map, path, nav-point and charge-pose services, called from
REST handlers; a refusal becomes the port error of nav's `ResultCode`, with nav's reason."""

from __future__ import annotations

from typing import Any

from zenros.errors import ServiceError, ServiceUnavailableError, ZenrosTimeout
from zenros.message import ServiceType
from zenros.msgs import zenros_msgs as zm
from zenros.msgs.geometry_msgs import PoseWithCovarianceStamped
from zenros.msgs.nav_msgs import OccupancyGrid
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.rpc import Client

from ..errors import NoAnswer, PortError, port_error
from ..state.presence import Presence

__all__ = ["NavLink"]

SERVICES: dict[str, ServiceType] = {
    "map_server/list_maps": zm.ListMaps,
    "map_server/current_map": zm.GetCurrentMap,
    "map_server/import_map": zm.ImportMap,
    "switch_map": zm.SwitchMap,
    "list_paths": zm.ListPaths,
    "get_path": zm.GetPath,
    "set_path": zm.SetPath,
    "delete_path": zm.DeletePath,
    "get_nav_points": zm.GetNavPoints,
    "set_nav_points": zm.SetNavPoints,
    "delete_nav_points": zm.DeleteNavPoints,
    "get_charge_pose": zm.GetChargePose,
    "set_charge_pose": zm.SetChargePose,
    "get_virtual_walls": zm.GetVirtualWalls,
    "set_virtual_walls": zm.SetVirtualWalls,
    "get_forbidden_areas": zm.GetForbiddenAreas,
    "set_forbidden_areas": zm.SetForbiddenAreas,
    "list_point_connections": zm.ListPointConnections,
    "add_point_connection": zm.AddPointConnection,
    "delete_point_connection": zm.DeletePointConnection,
}


class NavLink:
    """`await call(name, request)`; the current map grid from ``map`` (latched)."""

    def __init__(self, node: Node, presence: Presence, timeout: float = 10.0) -> None:
        self.timeout = timeout
        self.presence = presence
        self._clients: dict[str, Client] = {
            name: node.create_client(srv, name) for name, srv in SERVICES.items()}
        self.initialpose = node.create_publisher(PoseWithCovarianceStamped, "initialpose", 10)
        self.grid: OccupancyGrid | None = None
        node.create_subscription(OccupancyGrid, "map", self._on_map, QOS_LATCHED)

    def _on_map(self, msg: OccupancyGrid) -> None:
        self.grid = msg

    async def maps(self) -> tuple[list[str], str]:
        """(stored map names, current map); empty when nav does not answer."""
        try:
            res = await self.call("map_server/list_maps", zm.ListMapsRequest())
        except PortError:
            return [], ""
        return sorted(m.name for m in res.maps), str(res.current)

    async def call(self, name: str, request: Any) -> Any:
        client = self._clients[name]
        try:
            return await client.call_async(request, self.timeout)
        except ServiceUnavailableError:
            raise self.presence.error("nav", f"no server for {client.name}") from None
        except ZenrosTimeout:
            raise NoAnswer(f"the nav service did not answer {client.name} within "
                           f"{self.timeout:g} s") from None
        except ServiceError as exc:  # the kind comes from nav's code, never its wording
            raise port_error(exc.code, exc.reason) from exc
