"""MapServer: the current map and the map services (load, list, import, switch, current).

The map in use changes only when a new one has loaded completely; a failure raises (or
answers) an error naming the file and field, and the current map stays. ``on_change`` is
called with the new map's name and grid after every switch.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from pathlib import Path

from zenros.errors import MapError
from zenros.maps import GridMap, load_map, read_meta
from zenros.msgs.nav2_msgs import LoadMapRequest, LoadMapResponse
from zenros.msgs.zenros_msgs.nav import (
    GetCurrentMapRequest,
    GetCurrentMapResponse,
    ImportMapRequest,
    ImportMapResponse,
    ListMapsRequest,
    ListMapsResponse,
    MapInfo,
    SwitchMapRequest,
    SwitchMapResponse,
)

from .store import MapStore

__all__ = ["MapServer"]


class MapServer:
    """The map in use, taken from a `MapStore`."""

    def __init__(self, store: MapStore,
                 on_change: Callable[[str, GridMap], None] | None = None) -> None:
        self.store = store
        self.on_change = on_change
        self._lock = threading.RLock()
        self.current = ""
        self.grid: GridMap | None = None
        self.info: MapInfo | None = None

    def resolve(self, map_name: str) -> str:
        """``map_name``, or the current map's name when it is empty (checked to exist)."""
        name = map_name or self.current
        if not name:
            raise MapError("no map is loaded")
        return self.store.require(name)

    def start(self, yaml_path: str | Path) -> str:
        """Import the map at ``yaml_path`` and make it current (the ``map`` parameter)."""
        return self.switch(self.store.import_map(yaml_path))

    def switch(self, name: str) -> str:
        """Make the stored map ``name`` current; raises `MapError` and keeps the old one."""
        with self._lock:
            grid = self.store.load(name)
            info = self.store.info(name, grid)
            self.current, self.grid, self.info = name, grid, info
        if self.on_change is not None:
            self.on_change(name, grid)
        return name

    # ------------------------------------------------------------------ service handlers

    def handle_load_map(self, req: LoadMapRequest) -> LoadMapResponse:
        """nav2_msgs/LoadMap: import ``map_url`` (a map_server YAML) and switch to it."""
        url = req.map_url.removeprefix("file://")
        if not url or not Path(url).is_file():
            return LoadMapResponse(result=LoadMapResponse.RESULT_MAP_DOES_NOT_EXIST)
        try:
            read_meta(url)
        except MapError:
            return LoadMapResponse(result=LoadMapResponse.RESULT_INVALID_MAP_METADATA)
        try:
            load_map(url)
        except MapError:
            return LoadMapResponse(result=LoadMapResponse.RESULT_INVALID_MAP_DATA)
        try:
            self.start(url)
        except (MapError, ValueError, OSError):
            return LoadMapResponse(result=LoadMapResponse.RESULT_UNDEFINED_FAILURE)
        assert self.grid is not None
        return LoadMapResponse(map=self.grid.to_msg(), result=LoadMapResponse.RESULT_SUCCESS)

    def handle_list_maps(self, req: ListMapsRequest) -> ListMapsResponse:
        names = [self.store.require(req.name)] if req.name else self.store.names()
        maps = []
        for n in names:
            try:
                maps.append(self.store.info(n))
            except MapError:
                continue  # a damaged folder is skipped, not fatal to the listing
        return ListMapsResponse(maps=maps, current=self.current)

    def handle_current_map(self, req: GetCurrentMapRequest) -> GetCurrentMapResponse:
        info = self.info
        if info is None:
            raise MapError("no map is loaded")
        return GetCurrentMapResponse(name=info.name, md5sum=info.md5sum, info=info)

    def handle_import_map(self, req: ImportMapRequest) -> ImportMapResponse:
        if not req.yaml_path:
            raise ValueError("yaml_path is required")
        name = self.store.import_map(req.yaml_path, req.name, overwrite=req.overwrite)
        if name == self.current:
            self.switch(name)
        return ImportMapResponse(info=self.store.info(name))

    def handle_switch_map(self, req: SwitchMapRequest) -> SwitchMapResponse:
        try:
            self.switch(req.map_name)
        except (MapError, ValueError) as exc:
            return SwitchMapResponse(success=False, message=str(exc))
        assert self.info is not None
        return SwitchMapResponse(success=True, message=f"switched to map {self.current!r}",
                                 info=self.info)
