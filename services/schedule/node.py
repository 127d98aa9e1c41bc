"""`ScheduleServerNode`: a schedule server's map exchange over zenros services.

Parameters: ``server_id`` (the ID robots name it by, the robot API's ``server_id``;
"local"), ``data_dir`` (where the archives are kept; default ``$ZENROS_HOME/schedule/
<server_id>``). Services, absolute so any robot's namespace reaches them:
``/schedule/<server_id>/put_map`` (a map archive in: checked whole, then kept under a new
``map_id``), ``get_map`` (an archive out by ``map_id``), ``list_maps``. A refused archive is
answered with its reason and keeps nothing. docs/fleet.md, "Schedule server".

The traffic schedule (docs/fleet.md, "Traffic schedule"): ``request_route`` (a robot's
route in, how far it may drive out), ``release_route``, the latched ``reservations`` topic,
on the map ``traffic_map`` (default: the demo office).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Annotated

import msgspec
from msgspec import Meta
from zenros import Node
from zenros.home import data_dir
from zenros.maps import load_map
from zenros.maps.archive import MAX_ARCHIVE, ArchiveError
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.schedule import (
    GetMapArchive,
    GetMapArchiveRequest,
    GetMapArchiveResponse,
    ListMapArchives,
    ListMapArchivesRequest,
    ListMapArchivesResponse,
    PutMapArchive,
    PutMapArchiveRequest,
    PutMapArchiveResponse,
    schedule_service,
)
from zenros.msgs.zenros_msgs.traffic import (
    ReleaseRoute,
    ReleaseRouteRequest,
    ReleaseRouteResponse,
    RequestRoute,
    RequestRouteRequest,
    RequestRouteResponse,
    TrafficReservations,
)
from zenros.qos import QOS_LATCHED

from .manager import TrafficManager
from .segments import SegmentMap
from .store import MapShelf
from .traffic import TrafficTable

__all__ = ["ScheduleParameters", "ScheduleServerNode"]

DEMO_MAP = Path(__file__).resolve().parents[2] / "deploy" / "maps" / "office" / "office.yaml"
Positive = Annotated[float, Meta(gt=0)]

ServerId = Annotated[str, Meta(pattern=r"^[A-Za-z0-9_]{1,64}$", description=(
    "the ID robots name this server by (letters, digits, _)"))]


class ScheduleParameters(msgspec.Struct, kw_only=True, frozen=True):
    server_id: ServerId = "local"
    data_dir: Annotated[str, Meta(description=(
        "where the map archives are kept (default $ZENROS_HOME/schedule/<server_id>)"))] = ""
    traffic_map: Annotated[str, Meta(description=(
        "map_server YAML the traffic schedule is kept on (default: the demo office)"))] = ""
    passing_width: Annotated[Positive, Meta(description=(
        "free width two robots need to pass each other (m); narrower is one robot at a "
        "time"))] = 1.3
    cell_size: Annotated[Positive, Meta(description="traffic cell side (m)")] = 0.5
    lease: Annotated[Positive, Meta(description=(
        "seconds a route is held without a renewal (a request's own lease wins)"))] = 3.0
    horizon: Annotated[Positive, Meta(description=(
        "seconds of a route ahead that are granted at once"))] = 15.0
    stand_off: Annotated[Positive, Meta(description=(
        "metres of route before a refused narrow segment where the robot waits"))] = 0.9
    passing_length: Annotated[Positive, Meta(description=(
        "metres of wide route between narrow segments that make a passing place"))] = 1.5


_STATUS_CODES = {404: ResultCode.NOT_FOUND, 413: ResultCode.INVALID}


class ScheduleServerNode(Node):
    node_name = "schedule_server"

    def setup(self) -> None:
        self.params = self.declare_parameters(ScheduleParameters, read_only=True)
        sid = self.params.server_id
        folder = (data_dir(self.params.data_dir) if self.params.data_dir
                  else data_dir() / "schedule" / sid)
        self.shelf = MapShelf(folder)
        self.create_service(PutMapArchive, schedule_service(sid, "put_map"), self.on_put)
        self.create_service(GetMapArchive, schedule_service(sid, "get_map"), self.on_get)
        self.create_service(ListMapArchives, schedule_service(sid, "list_maps"), self.on_list)
        self.logger.info("schedule server %r: %d map(s) in %s", sid, len(self.shelf.list()),
                         folder)
        self._setup_traffic()

    def _setup_traffic(self) -> None:
        p = self.params
        path = Path(p.traffic_map) if p.traffic_map else DEMO_MAP
        segments = SegmentMap(load_map(path), path.stem, cell_size=p.cell_size,
                              passing_width=p.passing_width)
        table = TrafficTable(segments, horizon=p.horizon, stand_off=p.stand_off,
                             passing_length=p.passing_length)
        self.traffic = TrafficManager(table, p.server_id, path.stem, p.lease)
        sid = p.server_id
        self.create_service(RequestRoute, schedule_service(sid, "request_route"),
                            self.on_request_route)
        self.create_service(ReleaseRoute, schedule_service(sid, "release_route"),
                            self.on_release_route)
        self.reservations_pub = self.create_publisher(
            TrafficReservations, schedule_service(sid, "reservations"), QOS_LATCHED)
        self.create_timer(0.5, self.on_traffic_tick)
        self.logger.info("traffic schedule on map %r: %d narrow segment(s) under %.2f m",
                         path.stem, len(segments.narrow), p.passing_width)

    def on_request_route(self, req: RequestRouteRequest) -> RequestRouteResponse:
        res = self.traffic.request(req, self.now().nanoseconds * 1e-9)
        self._publish_reservations()
        return res

    def on_release_route(self, req: ReleaseRouteRequest) -> ReleaseRouteResponse:
        res = self.traffic.release(req)
        self._publish_reservations()
        return res

    def on_traffic_tick(self) -> None:
        """Leases run out even when nobody asks."""
        for name in self.traffic.expire(self.now().nanoseconds * 1e-9):
            self.logger.info("robot %r's traffic lease ran out: its reservations are free",
                             name)
        self._publish_reservations()

    def _publish_reservations(self) -> None:
        if self.traffic.changed():
            now = self.now()
            self.reservations_pub.publish(self.traffic.reservations(now.nanoseconds * 1e-9, now))

    def on_put(self, req: PutMapArchiveRequest) -> PutMapArchiveResponse:
        if len(req.data) > MAX_ARCHIVE:
            return PutMapArchiveResponse(code=ResultCode.INVALID, message=(
                f"archive too large: {len(req.data)} bytes (limit {MAX_ARCHIVE})"))
        try:
            info = self.shelf.put(req.data, self.now())
        except ArchiveError as exc:
            return PutMapArchiveResponse(code=_STATUS_CODES.get(exc.status, ResultCode.INVALID),
                                         message=f"not a map archive: {exc.detail}")
        self.logger.info("kept map %r from %s as %s (%d bytes)", info.name,
                         req.source or "a client", info.map_id, info.size)
        return PutMapArchiveResponse(info=info)

    def on_get(self, req: GetMapArchiveRequest) -> GetMapArchiveResponse:
        if not re.fullmatch(r"[0-9a-f]{32}", req.map_id):
            return GetMapArchiveResponse(code=ResultCode.NOT_FOUND, message=(
                f"no map {req.map_id!r} on this schedule server (map ids are 32 hex digits: "
                "list_maps names them)"))
        try:
            info, data = self.shelf.get(req.map_id)
        except ArchiveError as exc:
            return GetMapArchiveResponse(code=ResultCode.NOT_FOUND, message=exc.detail)
        return GetMapArchiveResponse(info=info, data=data)

    def on_list(self, req: ListMapArchivesRequest) -> ListMapArchivesResponse:
        return ListMapArchivesResponse(maps=self.shelf.list())
