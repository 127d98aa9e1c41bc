"""Connections: the point connections between maps (docs/robot-api.md §6.7), kept by the map store.

Stored in ``connections.yaml`` at the root of the maps folder (they join nav points of
different maps, so no single map folder owns them). Each joins exactly two existing nav
points ``{map, path, index}`` that are not the same point, as ``direct`` (the same physical
spot in two maps) or ``elevator``; two points are joined at most once. A connection whose
map, path or point was deleted later stays listed; route planning skips it. A malformed
file does not stop nav: every connection call answers an error naming it.
"""

from __future__ import annotations

import os
import threading
import time
import uuid
from pathlib import Path
from typing import Final

import msgspec
import msgspec.yaml
from zenros.errors import MapError, MapItemNotFoundError
from zenros.msgs.zenros_msgs.nav import (
    AddPointConnectionRequest,
    AddPointConnectionResponse,
    ConnectionPoint,
    DeletePointConnectionRequest,
    DeletePointConnectionResponse,
    ListPointConnectionsRequest,
    ListPointConnectionsResponse,
    PointConnection,
    PointRef,
)

from .store import MapStore

__all__ = ["CONNECTIONS_FILE", "TYPES", "Connections"]

CONNECTIONS_FILE: Final = "connections.yaml"
TYPES: Final = ("direct", "elevator")


class _File(msgspec.Struct, kw_only=True):
    connections: list[PointConnection] = msgspec.field(default_factory=list)


def _label(p: PointRef) -> str:
    return f"{p.map_name}/{p.path_name}[{p.index}]"


def _new_oid() -> str:
    """24 hex digits as a MongoDB ObjectId: 4 bytes of seconds, 8 random bytes."""
    return f"{int(time.time()) & 0xFFFFFFFF:08x}{os.urandom(8).hex()}"


class Connections:
    """The stored connections, with the list/add/delete service handlers; thread-safe."""

    def __init__(self, store: MapStore) -> None:
        self.store = store
        self.path = Path(store.root) / CONNECTIONS_FILE
        self._lock = threading.Lock()
        self._broken: MapError | None = None
        try:
            self._items = self._read()
        except MapError as exc:  # nav still runs; every call names the bad file
            self._broken, self._items = exc, []

    def _read(self) -> list[PointConnection]:
        if not self.path.is_file():
            return []
        try:
            return msgspec.yaml.decode(self.path.read_bytes(), type=_File).connections
        except (OSError, msgspec.ValidationError, msgspec.DecodeError) as exc:
            raise MapError(f"{self.path}: {exc}") from exc

    def _write(self, items: list[PointConnection]) -> None:
        tmp = self.path.with_name(self.path.name + ".tmp")
        tmp.write_bytes(msgspec.yaml.encode(_File(connections=items)))
        tmp.replace(self.path)

    def all(self) -> list[PointConnection]:
        with self._lock:
            self._check_readable()
            return list(self._items)

    def _check_readable(self) -> None:
        if self._broken is not None:
            raise MapError(f"point connections unreadable (fix or remove the file): "
                           f"{self._broken}")

    def check_point(self, ref: PointRef) -> None:
        """Raise `MapError` naming what is missing when ``ref`` is not a stored nav point."""
        name = self.store.require(ref.map_name)
        paths = self.store.nav_data(name).paths
        if ref.path_name not in paths:
            known = ", ".join(sorted(paths)) or "none"
            raise MapItemNotFoundError(f"unknown path {ref.path_name!r} on map {name!r}; known paths: "
                           f"{known}")
        n = len(paths[ref.path_name].nav_points)
        if not 0 <= ref.index < n:
            raise MapItemNotFoundError(f"unknown nav point {ref.index} of path {ref.path_name!r} on map "
                           f"{name!r}: it has {n}" + (f" (0..{n - 1})" if n else ""))

    # ------------------------------------------------------------------ service handlers

    def handle_list(self, req: ListPointConnectionsRequest) -> ListPointConnectionsResponse:
        points: list[ConnectionPoint] = []
        for m in self.store.names():
            try:
                paths = self.store.nav_data(m).paths
            except MapError:
                continue  # a damaged folder is skipped, as in list_maps
            for path_name in sorted(paths):
                for i, p in enumerate(paths[path_name].nav_points):
                    points.append(ConnectionPoint(map_name=m, path_name=path_name, index=i,
                                                  name=p.name, x=p.x, y=p.y, theta=p.theta))
        return ListPointConnectionsResponse(points=points, connections=self.all())

    def handle_add(self, req: AddPointConnectionRequest) -> AddPointConnectionResponse:
        if req.type not in TYPES:
            raise ValueError(f"invalid connection type {req.type!r}: use "
                             + " or ".join(repr(t) for t in TYPES))
        if len(req.points) != 2:
            raise ValueError(f"a connection joins exactly 2 points, got {len(req.points)}")
        a, b = (PointRef(map_name=p.map_name, path_name=p.path_name, index=p.index)
                for p in req.points)
        if a == b:
            raise ValueError(f"a connection joins two different points, got {_label(a)} "
                             "twice")
        for p in (a, b):
            self.check_point(p)
        conn = PointConnection(id=str(uuid.uuid4()), oid=_new_oid(), type=req.type,
                               is_available=bool(req.is_available), points=[a, b])
        with self._lock:
            self._check_readable()
            for c in self._items:
                if {_label(p) for p in c.points} == {_label(a), _label(b)}:
                    raise ValueError(f"{_label(a)} and {_label(b)} are already connected "
                                     f"(connection {c.id})")
            items = [*self._items, conn]
            self._write(items)
            self._items = items
        return AddPointConnectionResponse(connection=conn)

    def handle_delete(self, req: DeletePointConnectionRequest
                      ) -> DeletePointConnectionResponse:
        with self._lock:
            self._check_readable()
            items = [c for c in self._items if c.id != req.id]
            if len(items) == len(self._items):
                raise MapItemNotFoundError(f"unknown connection id {req.id!r}")
            self._write(items)
            self._items = items
        return DeletePointConnectionResponse()
