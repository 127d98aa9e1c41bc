"""The camera renderer against known geometry: a wall's height in the image is the pinhole's,
obstacles stand in front of walls and hide behind them, the back of the robot is another view,
and a still robot's frame is not rendered twice."""

from __future__ import annotations

import math

import numpy as np
import pytest
from zenros.services.chassis.camera import DOCK_ID, Camera, CameraConfig
from zenros.services.chassis.laser import Laser, LaserConfig
from zenros.services.chassis.obstacles import Obstacle
from zenros.services.chassis.world import World


def camera(world: World, **kw: float) -> Camera:
    cfg = CameraConfig(**kw)  # type: ignore[arg-type]
    return Camera(world, cfg, Laser(world, LaserConfig(beams=1, range_max=cfg.range_max)))


def wall_rows(image: np.ndarray, col: int) -> tuple[int, int]:
    """First and last row of the wall's colour band in column ``col`` (bright, yellowish)."""
    px = image[:, col].astype(int)
    wall = (px[:, 0] > px[:, 2] + 15) & (px[:, 1] > px[:, 2] + 10) & (px[:, 0] < 250)
    rows = np.nonzero(wall)[0]
    assert rows.size, "no wall in this column"
    return int(rows[0]), int(rows[-1])


def test_a_wall_spans_the_rows_a_pinhole_gives(hall: World) -> None:
    world = hall  # walls' faces at x = 0.05 and 19.95
    cam = camera(world)
    c = cam.config
    image = cam.render(9.95, 5.0, 0.0)  # 10 m from the east wall, facing it
    assert image.shape == (480, 640, 3) and image.dtype == np.uint8
    top, bottom = wall_rows(image, 300)
    d = 10.0  # depth along the axis: the same in every column for a wall square to it
    assert top == pytest.approx(240 - c.f * (c.wall_height - c.z) / d, abs=1.5)
    assert bottom == pytest.approx(240 + c.f * c.z / d, abs=1.5)
    # half the distance: twice as tall
    near = cam.render(14.95, 5.0, 0.0)
    t2, b2 = wall_rows(near, 300)
    assert (b2 - t2) == pytest.approx(2 * (bottom - top), rel=0.05)
    # above the wall the ceiling, below it the floor
    assert tuple(image[5, 320]) != tuple(image[470, 320])


def test_obstacles_stand_in_front_of_walls_and_hide_behind_them(hall: World) -> None:
    world = hall
    cam = camera(world)
    empty = cam.render(5.0, 5.0, 0.0).copy()
    box = Obstacle("crate", "box", 8.0, 5.0, size_x=0.5, size_y=0.5)
    seen = cam.render(5.0, 5.0, 0.0, [box])
    r, g, b = (int(v) for v in seen[250, 320])
    assert r > g + 40 and r > b + 40  # the obstacle's orange, not the wall's
    assert not np.array_equal(seen, empty)
    # a robot's body is blue; the dock green
    robot = cam.render(5.0, 5.0, 0.0, [Obstacle("robot:r2", "circle", 8.0, 5.0, radius=0.3)])
    r, g, b = (int(v) for v in robot[250, 320])
    assert b > r + 40
    dock = cam.render(5.0, 5.0, 0.0, [Obstacle(DOCK_ID, "box", 8.0, 5.0, size_x=0.1, size_y=0.5)])
    r, g, b = (int(v) for v in dock[280, 320])
    assert g > r + 40 and g > b + 20
    # behind the wall (outside the room) nothing shows
    hidden = cam.render(5.0, 5.0, 0.0, [Obstacle("far", "circle", 25.0, 5.0, radius=1.0)])
    assert np.array_equal(hidden, empty)


def test_the_view_turns_with_the_camera_and_a_still_one_is_not_rendered_again(
        hall: World) -> None:
    world = hall
    cam = camera(world)
    east = cam.render(15.0, 5.0, 0.0)
    east_copy = east.copy()
    assert cam.render(15.0, 5.0, 0.0) is east  # the same frame: not rendered again
    west = cam.render(15.0, 5.0, math.pi)
    t_e, b_e = wall_rows(east_copy, 300)
    t_w, b_w = wall_rows(west, 300)
    assert (b_e - t_e) > 2 * (b_w - t_w)  # the east wall is 5 m off, the west one 15 m


@pytest.mark.parametrize("kw, word", [({"width": 4}, "size"), ({"hfov": 3.5}, "hfov"),
                                      ({"z": 3.0}, "camera z")])
def test_bad_configurations_are_refused(kw: dict[str, float], word: str) -> None:
    with pytest.raises(ValueError, match=word):
        CameraConfig(**kw)  # type: ignore[arg-type]
