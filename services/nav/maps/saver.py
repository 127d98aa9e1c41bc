"""GridSaver: a received occupancy grid into the maps folder (``map_server/save_grid``), and
Nav2's map_saver (``map_saver/save_map``) on the same writer.

``save_grid`` (zenros_msgs/SaveGrid) is how the mapping node saves the map it built: a map
folder as map_saver writes it (YAML, PGM, PNG), recorded as built by SLAM with the robot's
``map_to_odom`` at the time, so ``list_maps`` shows it and nav can localise on it. It answers
a `ResultCode`: INVALID for a bad name (empty or path-like), an empty or malformed grid or a
bad type; CONFLICT when the name is the map in use (its grid would change under the running
navigation).

``save_map`` follows nav2_map_server's map_saver: the grid (the node takes it from
``map_topic``) is written to ``map_url`` with ``image_format`` (pgm, png; default pgm),
``map_mode`` (trinary, scale, raw; default trinary) and the thresholds (default 0.65 /
0.196 when 0). A ``map_url`` that is a bare name goes into the maps folder (as save_grid,
trinary only: the store's maps are trinary); otherwise it is a file path without extension
(``/tmp/site`` writes ``/tmp/site.yaml`` and ``/tmp/site.pgm``), which must be absolute,
its folder existing.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from zenros.errors import MapError
from zenros.maps import GridMap, MapMeta, grid_to_pixels, write_image, write_meta
from zenros.msgs.nav2_msgs import SaveMapRequest
from zenros.msgs.nav_msgs import OccupancyGrid
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.slam import SaveGridRequest, SaveGridResponse

from .navdata import check_name
from .mapmeta import MapRecord, check_record
from .store import MapStore

__all__ = ["GridSaver", "SaveRefused"]

_FORMATS = ("pgm", "png")
_MODES = ("trinary", "scale", "raw")


class SaveRefused(ValueError):
    """A save that cannot be done; ``code`` is its `ResultCode`."""

    def __init__(self, code: ResultCode, reason: str) -> None:
        super().__init__(reason)
        self.code = code


def grid_of(msg: OccupancyGrid) -> GridMap:
    """The grid of ``msg``, or `SaveRefused` INVALID saying what is wrong with it."""
    try:
        grid = GridMap.from_msg(msg)
    except (MapError, ValueError, TypeError) as exc:
        raise SaveRefused(ResultCode.INVALID, str(exc)) from exc
    if grid.width == 0 or grid.height == 0:
        raise SaveRefused(ResultCode.INVALID,
                          f"the grid is empty ({grid.width}x{grid.height} cells)")
    return grid


class GridSaver:
    """Writes grids into ``store``; ``in_use()`` names the map navigation runs on."""

    def __init__(self, store: MapStore, in_use: Callable[[], str]) -> None:
        self.store = store
        self.in_use = in_use

    def save_grid(self, name: str, grid: GridMap, record: MapRecord) -> str:
        try:
            check_name("map", name)
            check_record(record)
        except ValueError as exc:
            raise SaveRefused(ResultCode.INVALID, str(exc)) from exc
        if name == self.in_use():
            raise SaveRefused(ResultCode.CONFLICT,
                              f"map {name!r} is the map in use; save under another name")
        try:
            return self.store.save_grid(name, grid, record)
        except (MapError, ValueError) as exc:
            raise SaveRefused(ResultCode.INVALID, str(exc)) from exc
        except OSError as exc:
            raise SaveRefused(ResultCode.FAILED, f"cannot write map {name!r}: {exc}") from exc

    def handle_save_grid(self, req: SaveGridRequest) -> SaveGridResponse:
        try:
            grid = grid_of(req.grid)
            record = MapRecord(type=req.type, levels=list(req.levels), slam_type="lidar",
                               built_by_slam=True,
                               map_to_odom=req.map_to_odom if req.use_map_to_odom else None)
            name = self.save_grid(req.name, grid, record)
        except SaveRefused as exc:
            return SaveGridResponse(code=int(exc.code), message=str(exc), name=req.name)
        return SaveGridResponse(code=int(ResultCode.OK), message=f"saved map {name!r}",
                                name=name)

    def save_map(self, msg: OccupancyGrid, req: SaveMapRequest) -> str:
        """map_saver's save: where it was written (a map name or the YAML path)."""
        fmt = (req.image_format or "pgm").lower()
        mode = req.map_mode or "trinary"
        if fmt not in _FORMATS:
            raise SaveRefused(ResultCode.INVALID, f"image_format must be one of "
                              f"{', '.join(_FORMATS)}, got {req.image_format!r}")
        if mode not in _MODES:
            raise SaveRefused(ResultCode.INVALID, f"map_mode must be one of "
                              f"{', '.join(_MODES)}, got {req.map_mode!r}")
        if mode == "scale" and fmt != "png":
            raise SaveRefused(ResultCode.INVALID, "map_mode scale needs image_format png "
                              "(unknown cells are transparent)")
        occ = req.occupied_thresh or 0.65
        free = req.free_thresh or 0.196
        if not 0.0 <= free < occ <= 1.0:
            raise SaveRefused(ResultCode.INVALID, f"thresholds must satisfy 0 <= free_thresh "
                              f"< occupied_thresh <= 1, got {free} and {occ}")
        grid = grid_of(msg)
        url = req.map_url.removeprefix("file://")
        if "/" not in url:
            if mode != "trinary" or (occ, free) != (0.65, 0.196):
                raise SaveRefused(ResultCode.INVALID, "maps in the maps folder are trinary "
                                  "with thresholds 0.65/0.196; give a file path for others")
            return self.save_grid(url, grid, MapRecord(built_by_slam=True))
        path = Path(url)
        if not path.is_absolute() or not path.parent.is_dir() or not path.name:
            raise SaveRefused(ResultCode.INVALID, f"map_url {req.map_url!r}: give a map name "
                              "or an absolute path (without extension) in an existing folder")
        yaml_path = path.with_name(path.name + ".yaml")
        image = path.with_name(f"{path.name}.{fmt}")
        try:
            write_image(grid_to_pixels(grid.grid, mode=mode, occupied_thresh=occ,
                                       free_thresh=free), image)
            write_meta(MapMeta(image=image, resolution=grid.resolution, origin=grid.origin,
                               negate=False, occupied_thresh=occ, free_thresh=free,
                               mode=mode), yaml_path)  # type: ignore[arg-type]
        except (MapError, OSError) as exc:
            raise SaveRefused(ResultCode.FAILED, f"cannot write {yaml_path}: {exc}") from exc
        return str(yaml_path)
