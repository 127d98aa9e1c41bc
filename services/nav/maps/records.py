"""Records: the per-map services for paths, nav points, keep-out shapes and the charge pose.

Every request names a map (empty: the current one) and, for paths, a path. Unknown maps
and paths are refused with the known names; writes are checked (`navdata.check_*`) and
persisted before the reply. ``on_keepout_change(map_name)`` runs after walls or areas of
a map change, so the costmaps can be rebuilt.
"""

from __future__ import annotations

from collections.abc import Callable

from zenros.errors import MapError, MapItemNotFoundError
from zenros.msgs.geometry_msgs import Pose2D
from zenros.msgs.zenros_msgs.nav import (
    DeleteNavPointsRequest,
    DeleteNavPointsResponse,
    DeletePathRequest,
    DeletePathResponse,
    GetChargePoseRequest,
    GetChargePoseResponse,
    GetForbiddenAreasRequest,
    GetForbiddenAreasResponse,
    GetNavPointsRequest,
    GetNavPointsResponse,
    GetPathRequest,
    GetPathResponse,
    GetVirtualWallsRequest,
    GetVirtualWallsResponse,
    ListPathsRequest,
    ListPathsResponse,
    NavPoint,
    PathRef,
    SetChargePoseRequest,
    SetChargePoseResponse,
    SetForbiddenAreasRequest,
    SetForbiddenAreasResponse,
    SetNavPointsRequest,
    SetNavPointsResponse,
    SetPathRequest,
    SetPathResponse,
    SetVirtualWallsRequest,
    SetVirtualWallsResponse,
)
from zenros.se2 import Pose2

from .navdata import (
    MapNavData,
    StoredPath,
    check_area,
    check_name,
    check_nav_points,
    check_points,
    check_pose,
    check_wall,
)
from .server import MapServer

__all__ = ["Records"]


class Records:
    """Service handlers over the maps' `MapNavData`."""

    def __init__(self, maps: MapServer, current_pose: Callable[[], Pose2 | None],
                 on_keepout_change: Callable[[str], None] | None = None) -> None:
        self.maps = maps
        self.store = maps.store
        self.current_pose = current_pose
        self.on_keepout_change = on_keepout_change

    # ------------------------------------------------------------------ lookups

    def _path(self, map_name: str, path_name: str) -> tuple[str, StoredPath]:
        name = self.maps.resolve(map_name)
        paths = self.store.nav_data(name).paths
        if path_name not in paths:
            known = ", ".join(sorted(paths)) or "none"
            raise MapItemNotFoundError(f"unknown path {path_name!r} on map {name!r}; known paths: {known}")
        return name, paths[path_name]

    def nav_points(self, map_name: str, path_name: str) -> tuple[str, list[NavPoint]]:
        """A path's nav points (for patrol and go-to-index callers)."""
        name, path = self._path(map_name, path_name)
        return name, list(path.nav_points)

    def charge_pose(self, map_name: str = "") -> Pose2 | None:
        p = self.store.nav_data(self.maps.resolve(map_name)).charge_pose
        return None if p is None else Pose2(p.x, p.y, p.theta)

    def keepout(self, map_name: str = "") -> MapNavData:
        return self.store.nav_data(self.maps.resolve(map_name))

    # ------------------------------------------------------------------ paths

    def handle_list_paths(self, req: ListPathsRequest) -> ListPathsResponse:
        names = [self.maps.resolve(req.map_name)] if req.map_name else self.store.names()
        refs: list[PathRef] = []
        for m in names:
            try:
                paths = self.store.nav_data(m).paths
            except MapError:
                continue
            refs.extend(PathRef(map_name=m, path_name=p) for p in sorted(paths))
        return ListPathsResponse(paths=refs)

    def handle_get_path(self, req: GetPathRequest) -> GetPathResponse:
        name, path = self._path(req.map_name, req.path_name)
        return GetPathResponse(map_name=name, path_name=req.path_name, points=path.points)

    def handle_set_path(self, req: SetPathRequest) -> SetPathResponse:
        name = self.maps.resolve(req.map_name)
        path_name = check_name("path", req.path_name)
        points = check_points("path", req.points)

        def change(d: MapNavData) -> None:
            old = d.paths.get(path_name, StoredPath())
            d.paths[path_name] = StoredPath(points=points, nav_points=old.nav_points)

        self.store.update_nav_data(name, change)
        return SetPathResponse(map_name=name, path_name=path_name, points=points)

    def handle_delete_path(self, req: DeletePathRequest) -> DeletePathResponse:
        name, _ = self._path(req.map_name, req.path_name)
        self.store.update_nav_data(name, lambda d: d.paths.pop(req.path_name, None))
        return DeletePathResponse()

    # ------------------------------------------------------------------ nav points

    def handle_get_nav_points(self, req: GetNavPointsRequest) -> GetNavPointsResponse:
        name, path = self._path(req.map_name, req.path_name)
        return GetNavPointsResponse(map_name=name, path_name=req.path_name,
                                    points=path.nav_points)

    def handle_set_nav_points(self, req: SetNavPointsRequest) -> SetNavPointsResponse:
        name = self.maps.resolve(req.map_name)
        path_name = check_name("path", req.path_name)
        points = check_nav_points(req.points)

        def change(d: MapNavData) -> None:
            old = d.paths.get(path_name, StoredPath())
            d.paths[path_name] = StoredPath(points=old.points, nav_points=points)

        self.store.update_nav_data(name, change)
        return SetNavPointsResponse(map_name=name, path_name=path_name, points=points)

    def handle_delete_nav_points(self, req: DeleteNavPointsRequest) -> DeleteNavPointsResponse:
        name, _ = self._path(req.map_name, req.path_name)

        def change(d: MapNavData) -> None:
            d.paths[req.path_name] = StoredPath(points=d.paths[req.path_name].points)

        self.store.update_nav_data(name, change)
        return DeleteNavPointsResponse()

    # ------------------------------------------------------------------ keep-out

    def handle_get_virtual_walls(self, req: GetVirtualWallsRequest) -> GetVirtualWallsResponse:
        name = self.maps.resolve(req.map_name)
        return GetVirtualWallsResponse(map_name=name,
                                       walls=self.store.nav_data(name).virtual_walls)

    def handle_set_virtual_walls(self, req: SetVirtualWallsRequest) -> SetVirtualWallsResponse:
        name = self.maps.resolve(req.map_name)
        walls = [check_wall(i, w) for i, w in enumerate(req.walls)]

        def change(d: MapNavData) -> None:
            d.virtual_walls = walls

        self.store.update_nav_data(name, change)
        self._keepout_changed(name)
        return SetVirtualWallsResponse(map_name=name, walls=walls)

    def handle_get_forbidden_areas(self, req: GetForbiddenAreasRequest
                                   ) -> GetForbiddenAreasResponse:
        name = self.maps.resolve(req.map_name)
        return GetForbiddenAreasResponse(map_name=name,
                                         areas=self.store.nav_data(name).forbidden_areas)

    def handle_set_forbidden_areas(self, req: SetForbiddenAreasRequest
                                   ) -> SetForbiddenAreasResponse:
        name = self.maps.resolve(req.map_name)
        areas = [check_area(i, a) for i, a in enumerate(req.areas)]

        def change(d: MapNavData) -> None:
            d.forbidden_areas = areas

        self.store.update_nav_data(name, change)
        self._keepout_changed(name)
        return SetForbiddenAreasResponse(map_name=name, areas=areas)

    def _keepout_changed(self, name: str) -> None:
        if self.on_keepout_change is not None:
            self.on_keepout_change(name)

    # ------------------------------------------------------------------ charge pose

    def handle_get_charge_pose(self, req: GetChargePoseRequest) -> GetChargePoseResponse:
        name = self.maps.resolve(req.map_name)
        pose = self.store.nav_data(name).charge_pose
        return GetChargePoseResponse(map_name=name, is_set=pose is not None,
                                     pose=pose or Pose2D())

    def handle_set_charge_pose(self, req: SetChargePoseRequest) -> SetChargePoseResponse:
        name = self.maps.resolve(req.map_name)
        if req.use_current_pose:
            now = self.current_pose()
            if now is None:
                raise MapError("the robot's pose is not known yet (no localisation)")
            pose = Pose2D(x=now.x, y=now.y, theta=now.theta)
        else:
            pose = check_pose("charge pose", req.pose)

        def change(d: MapNavData) -> None:
            d.charge_pose = pose

        self.store.update_nav_data(name, change)
        return SetChargePoseResponse(map_name=name, pose=pose)
