"""The schedule server's map exchange (docs/robot-api.md §6.3 ``upload_map``,
``download_map``): a robot puts the archive of a map it has (`zenros.maps.archive`) on a
schedule server, and any robot of the fleet gets it from there by its ``map_id``.

The services are ``/schedule/<server_id>/put_map``, ``get_map`` and ``list_maps``
(`schedule_service`); ``code`` is a `ResultCode` and ``message`` says why when it is not OK.
"""

from __future__ import annotations

import msgspec

from ...message import Message, define_service
from ..builtin_interfaces import Time

__all__ = [
    "GetMapArchive", "GetMapArchiveRequest", "GetMapArchiveResponse", "ListMapArchives",
    "ListMapArchivesRequest", "ListMapArchivesResponse", "MapArchiveInfo", "PutMapArchive",
    "PutMapArchiveRequest", "PutMapArchiveResponse", "schedule_service",
]


def schedule_service(server_id: str, name: str) -> str:
    """The absolute name of schedule server ``server_id``'s service ``name``."""
    return f"/schedule/{server_id}/{name}"


class MapArchiveInfo(Message):
    """One map the server holds: ``map_id`` names it there; the rest is its manifest's."""

    __msgtype__ = "zenros_msgs/MapArchiveInfo"
    map_id: str = ""
    name: str = ""
    size: int = 0  # bytes of the archive
    width: int = 0
    height: int = 0
    resolution: float = 0.0
    md5sum: str = ""
    stamp: Time = msgspec.field(default_factory=Time)  # when it was put


class PutMapArchiveRequest(Message):
    """A map archive (``download_map_from_robot``'s zip) to keep; ``source`` says who put
    it (a robot's namespace)."""

    __msgtype__ = "zenros_msgs/PutMapArchiveRequest"
    data: bytes = b""
    source: str = ""


class PutMapArchiveResponse(Message):
    __msgtype__ = "zenros_msgs/PutMapArchiveResponse"
    code: int = 0
    message: str = ""
    info: MapArchiveInfo = msgspec.field(default_factory=MapArchiveInfo)


class GetMapArchiveRequest(Message):
    __msgtype__ = "zenros_msgs/GetMapArchiveRequest"
    map_id: str = ""


class GetMapArchiveResponse(Message):
    __msgtype__ = "zenros_msgs/GetMapArchiveResponse"
    code: int = 0
    message: str = ""
    info: MapArchiveInfo = msgspec.field(default_factory=MapArchiveInfo)
    data: bytes = b""


class ListMapArchivesRequest(Message):
    __msgtype__ = "zenros_msgs/ListMapArchivesRequest"


class ListMapArchivesResponse(Message):
    __msgtype__ = "zenros_msgs/ListMapArchivesResponse"
    maps: list[MapArchiveInfo] = msgspec.field(default_factory=list)


PutMapArchive = define_service("zenros_msgs/PutMapArchive", PutMapArchiveRequest,
                               PutMapArchiveResponse)
GetMapArchive = define_service("zenros_msgs/GetMapArchive", GetMapArchiveRequest,
                               GetMapArchiveResponse)
ListMapArchives = define_service("zenros_msgs/ListMapArchives", ListMapArchivesRequest,
                                 ListMapArchivesResponse)
