"""`ScheduleServerNode`: a schedule server's map exchange over zenros services.

Parameters: ``server_id`` (the ID robots name it by, the robot API's ``server_id``;
"local"), ``data_dir`` (where the archives are kept; default ``$ZENROS_HOME/schedule/
<server_id>``). Services, absolute so any robot's namespace reaches them:
``/schedule/<server_id>/put_map`` (a map archive in: checked whole, then kept under a new
``map_id``), ``get_map`` (an archive out by ``map_id``), ``list_maps``. A refused archive is
answered with its reason and keeps nothing. docs/fleet.md, "Schedule server".
"""

from __future__ import annotations

import re
from typing import Annotated

import msgspec
from msgspec import Meta
from zenros import Node
from zenros.home import data_dir
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

from .store import MapShelf

__all__ = ["ScheduleParameters", "ScheduleServerNode"]

ServerId = Annotated[str, Meta(pattern=r"^[A-Za-z0-9_]{1,64}$", description=(
    "the ID robots name this server by (letters, digits, _)"))]


class ScheduleParameters(msgspec.Struct, kw_only=True, frozen=True):
    server_id: ServerId = "local"
    data_dir: Annotated[str, Meta(description=(
        "where the map archives are kept (default $ZENROS_HOME/schedule/<server_id>)"))] = ""


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
