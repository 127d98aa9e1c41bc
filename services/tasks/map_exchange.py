"""`MapExchange`: the ``upload_map_action`` and ``download_map_action`` of a task
(docs/robot-api.md §6.3 ``upload_map``, ``download_map``): the current map's archive put on a
schedule server, and an archive got from one imported into nav's maps
(`zenros.maps.transfer`), by the tasks service's own service calls. docs/fleet.md,
"Schedule server"."""

from __future__ import annotations

from typing import Any, Final

from zenros.errors import ZenrosError
from zenros.maps.archive import ArchiveError, read_archive
from zenros.maps.transfer import export_map, import_map
from zenros.message import ServiceType
from zenros.msgs.zenros_msgs.nav import NAV_SERVICE_NAMES, GetCurrentMap, GetCurrentMapRequest
from zenros.msgs.zenros_msgs.schedule import (
    GetMapArchive,
    GetMapArchiveRequest,
    PutMapArchive,
    PutMapArchiveRequest,
    schedule_service,
)
from zenros.node import Node

from .robot import Outcome

__all__ = ["MapExchange", "NavRefused"]

CALL_TIMEOUT: Final = 30.0  # s for one call (an archive of up to 64 MB travels in one)


class NavRefused(ZenrosError):
    """Nav answered a call with a code that is not OK (its message says why)."""


class MapExchange:
    """The map transfers of one tasks node; each call bounded by ``timeout``."""

    def __init__(self, node: Node, timeout: float = CALL_TIMEOUT) -> None:
        self.node = node
        self.timeout = timeout
        self._nav_clients: dict[Any, Any] = {}

    def _nav(self, srv: ServiceType[Any, Any], request: Any) -> Any:
        client = self._nav_clients.get(srv)
        if client is None:
            client = self._nav_clients[srv] = self.node.create_client(
                srv, NAV_SERVICE_NAMES[srv])
        res = client.call(request, timeout=self.timeout)
        if getattr(res, "code", 0):
            raise NavRefused(f"nav's {NAV_SERVICE_NAMES[srv]}: {res.message}")
        return res

    def _schedule(self, srv: ServiceType[Any, Any], server_id: str, name: str,
                  request: Any) -> Any:
        client = self.node.create_client(srv, schedule_service(server_id, name))
        try:
            return client.call(request, timeout=self.timeout)
        finally:
            self.node.destroy(client)

    def upload(self, server_id: str) -> Outcome:
        """Put the current map on schedule server ``server_id``."""
        try:
            current = self._nav(GetCurrentMap, GetCurrentMapRequest()).name
            data = export_map(self._nav, current)
        except (ZenrosError, ArchiveError) as exc:
            return Outcome("error", f"cannot read the current map: {_why(exc)}")
        try:
            res = self._schedule(PutMapArchive, server_id, "put_map", PutMapArchiveRequest(
                data=data, source=self.node.namespace))
        except ZenrosError as exc:
            return Outcome("error", f"schedule server {server_id!r}: {exc}")
        if res.code:
            return Outcome("error", f"schedule server {server_id!r} refused map "
                                    f"{current!r}: {res.message}")
        return Outcome("complete", f"map {current!r} is {res.info.map_id} on schedule server "
                                   f"{server_id!r}")

    def download(self, server_id: str, map_id: str) -> Outcome:
        """Get map ``map_id`` from schedule server ``server_id`` into nav's maps."""
        try:
            res = self._schedule(GetMapArchive, server_id, "get_map",
                                 GetMapArchiveRequest(map_id=map_id))
        except ZenrosError as exc:
            return Outcome("error", f"schedule server {server_id!r}: {exc}")
        if res.code:
            return Outcome("error", f"schedule server {server_id!r}: {res.message}")
        try:
            done = import_map(self._nav, res.info.name, read_archive(res.data), (NavRefused,))
        except (ZenrosError, ArchiveError) as exc:
            return Outcome("error", f"map {map_id} not imported: {_why(exc)}")
        skipped = f"; skipped {'; '.join(done['skipped'])}" if done["skipped"] else ""
        return Outcome("complete", f"map {done['name']!r} from schedule server {server_id!r}: "
                                   f"{done['paths']} path(s), {done['connections']} point "
                                   f"connection(s){skipped}")


def _why(exc: BaseException) -> str:
    return str(getattr(exc, "detail", None) or exc)
