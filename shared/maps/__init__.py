"""zenros.maps: map_server maps (YAML + PGM/PNG) to and from numpy grids and OccupancyGrid.

    from zenros.maps import load_map, load_poses
    m = load_map("deploy/maps/office/office.yaml")   # GridMap: grid (int8, row 0 bottom)
    msg = m.to_msg()                                 # nav_msgs/OccupancyGrid
    poses = load_poses("deploy/maps/office/office.yaml")  # start and dock poses, if given
    marks = load_landmarks("deploy/maps/office/office.yaml")  # its reflectors, if any

Errors are `zenros.errors.MapError` (a ValueError) naming the file and the key.
Semantics follow map_server/Nav2 (specs/tf-nav.md, Part D1); see docs/maps.md.
"""

from .convert import FREE, OCCUPIED, UNKNOWN, grid_to_pixels, pixels_to_grid
from .grid import GridMap, load_map, save_map
from .image import encode_image, read_image, write_image
from .landmarks import LANDMARKS_FILE, Reflector, landmarks_path, load_landmarks, save_landmarks
from .meta import MapMeta, Mode, read_meta, write_meta
from .poses import POSES_FILE, MapPose, MapPoses, load_poses, poses_path, save_poses

__all__ = [
    "FREE",
    "LANDMARKS_FILE",
    "OCCUPIED",
    "POSES_FILE",
    "UNKNOWN",
    "GridMap",
    "MapMeta",
    "MapPose",
    "MapPoses",
    "Mode",
    "Reflector",
    "encode_image",
    "grid_to_pixels",
    "landmarks_path",
    "load_landmarks",
    "load_map",
    "load_poses",
    "pixels_to_grid",
    "poses_path",
    "read_image",
    "read_meta",
    "save_landmarks",
    "save_map",
    "save_poses",
    "write_image",
    "write_meta",
]
