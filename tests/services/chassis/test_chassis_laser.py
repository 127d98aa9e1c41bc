"""Laser ray casting against known geometry: walls, obstacles, max range, noise, speed."""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import pytest
from zenros.maps import GridMap, load_map
from zenros.services.chassis.laser import Laser, LaserConfig
from zenros.services.chassis.obstacles import Obstacle, ObstacleError, ray_hits
from zenros.services.chassis.world import World

OFFICE = Path(__file__).parents[3] / "deploy" / "maps" / "office" / "office.yaml"


def beam(cfg: LaserConfig, angle: float) -> int:
    return int(round((angle - cfg.angle_min) / cfg.angle_increment)) % cfg.beams


def test_walls_at_known_distances(room: World) -> None:
    cfg = LaserConfig()
    r = Laser(room, cfg).ranges(1.0, 1.0, 0.0)
    assert r.dtype == np.float32 and r.size == 360
    # wall faces: x = 0.05 and 4.95, y = 0.05 and 2.95
    assert r[beam(cfg, 0.0)] == pytest.approx(3.95, abs=1e-4)
    assert r[beam(cfg, math.pi / 2)] == pytest.approx(1.95, abs=1e-4)
    assert r[beam(cfg, -math.pi)] == pytest.approx(0.95, abs=1e-4)
    assert r[beam(cfg, -math.pi / 2)] == pytest.approx(0.95, abs=1e-4)
    # a diagonal beam to the corner region: x wall hit at 45 degrees from (1, 1): 0.95*sqrt2
    assert r[beam(cfg, -3 * math.pi / 4)] == pytest.approx(0.95 * math.sqrt(2), abs=1e-3)
    # every beam of the closed room hits a wall within the room's diagonal
    assert np.all(np.isfinite(r)) and r.max() < math.hypot(4.9, 2.9)


def test_heading_rotates_the_scan(room: World) -> None:
    cfg = LaserConfig()
    r = Laser(room, cfg).ranges(1.0, 1.0, math.pi / 2)
    assert r[beam(cfg, 0.0)] == pytest.approx(1.95, abs=1e-4)  # straight ahead is +y now


def test_max_and_min_range_give_inf(room: World) -> None:
    cfg = LaserConfig(range_max=2.0, range_min=0.5)
    r = Laser(room, cfg).ranges(1.0, 1.0, 0.0)
    assert np.isinf(r[beam(cfg, 0.0)])  # 3.95 m > range_max
    assert r[beam(cfg, math.pi / 2)] == pytest.approx(1.95, abs=1e-4)
    near = Laser(room, cfg).ranges(0.3, 1.0, 0.0)
    assert np.isinf(near[beam(cfg, -math.pi)])  # 0.25 m < range_min


def test_obstacles_cast_exact_shadows(room: World) -> None:
    cfg = LaserConfig()
    room.set_obstacles([Obstacle("c", "circle", 3.0, 1.0, radius=0.5),
                        Obstacle("b", "box", 1.0, 2.0, theta=math.pi / 4, size_x=0.4,
                                 size_y=0.4)])
    r = Laser(room, cfg).ranges(1.0, 1.0, 0.0)
    assert r[beam(cfg, 0.0)] == pytest.approx(1.5, abs=1e-5)  # circle at 3 - 0.5
    # the box is a diamond: its lower corner at y = 2 - 0.2*sqrt2
    assert r[beam(cfg, math.pi / 2)] == pytest.approx(1.0 - 0.2 * math.sqrt(2), abs=1e-5)
    assert r[beam(cfg, -math.pi)] == pytest.approx(0.95, abs=1e-4)  # unaffected
    room.remove_obstacles(["c"])
    assert Laser(room, cfg).ranges(1.0, 1.0, 0.0)[beam(cfg, 0.0)] == pytest.approx(3.95,
                                                                                    abs=1e-4)


def test_ray_hits_inside_and_parallel() -> None:
    dx, dy = np.array([1.0, 0.0, -1.0]), np.array([0.0, 1.0, 0.0])
    box = Obstacle("b", "box", 2.0, 0.0, size_x=1.0, size_y=1.0)
    assert ray_hits([box], 0.0, 0.0, dx, dy).tolist() == [1.5, math.inf, math.inf]
    assert ray_hits([box], 2.0, 0.0, dx, dy).tolist() == [0.0, 0.0, 0.0]
    with pytest.raises(ObstacleError, match="a circle needs radius > 0"):
        Obstacle("x", "circle", 0.0, 0.0)


def test_a_thin_wall_and_off_map() -> None:
    grid = np.zeros((40, 40), np.int8)
    grid[:, 20] = 100  # a one-cell wall at x = 1.0 .. 1.05
    w = World(GridMap(grid, 0.05, (0.0, 0.0, 0.0)))
    cfg = LaserConfig(beams=720)
    r = Laser(w, cfg).ranges(0.52, 1.0, 0.0)
    assert r[beam(cfg, 0.0)] == pytest.approx(0.48, abs=1e-4)
    # grazing beams never pass through the wall
    fan = r[beam(cfg, -0.8):beam(cfg, 0.8)]
    assert np.all(np.isfinite(fan)) and np.all(fan >= 0.48 - 1e-4)
    assert np.isinf(r[beam(cfg, -math.pi)])  # west: off the map, no return
    assert np.all(np.isinf(Laser(w, cfg).ranges(1.02, 1.0, 0.0)))  # inside the wall


def test_a_scan_from_where_the_last_was_is_not_cast_again(room: World) -> None:
    cfg = LaserConfig()
    laser = Laser(room, cfg)
    first = laser.ranges(1.0, 1.0, 0.0)
    casts: list[int] = []
    trace = laser._trace
    laser._trace = lambda *a: (casts.append(1), trace(*a))[1]  # type: ignore[method-assign]
    again = laser.ranges(1.0, 1.0, 0.0)
    assert casts == [] and np.array_equal(again, first) and again is not first
    again[:] = 0  # each scan its own array: the cache is not handed out
    assert np.array_equal(laser.ranges(1.0, 1.0, 0.0), first) and casts == []
    # an obstacle appears, moves, goes; the robot turns: cast again each time
    room.set_obstacles([Obstacle("c", "circle", 3.0, 1.0, radius=0.5)])
    assert laser.ranges(1.0, 1.0, 0.0)[beam(cfg, 0.0)] == pytest.approx(1.5, abs=1e-5)
    room.set_obstacles([Obstacle("c", "circle", 2.5, 1.0, radius=0.5)])
    assert laser.ranges(1.0, 1.0, 0.0)[beam(cfg, 0.0)] == pytest.approx(1.0, abs=1e-5)
    room.remove_obstacles(["c"])
    assert np.array_equal(laser.ranges(1.0, 1.0, 0.0), first)
    assert laser.ranges(1.0, 1.0, math.pi / 2)[beam(cfg, 0.0)] == pytest.approx(1.95, abs=1e-4)
    assert len(casts) == 4


def test_noise_is_drawn_for_each_scan_from_the_same_place(room: World) -> None:
    cfg = LaserConfig(noise=0.01)
    laser = Laser(room, cfg, np.random.default_rng(1))
    a, b = laser.ranges(1.0, 1.0, 0.0), laser.ranges(1.0, 1.0, 0.0)
    assert not np.array_equal(a, b)
    assert np.allclose(a, b, atol=0.1)


def test_noise_is_applied_to_returns_only(room: World) -> None:
    cfg = LaserConfig(noise=0.01, range_max=3.0)
    r = Laser(room, cfg, np.random.default_rng(1)).ranges(1.0, 1.0, 0.0)
    assert np.isinf(r[beam(cfg, 0.0)])
    assert r[beam(cfg, math.pi / 2)] != pytest.approx(1.95, abs=1e-6)
    assert r[beam(cfg, math.pi / 2)] == pytest.approx(1.95, abs=0.06)


def test_office_scan_is_fast_and_agrees_with_dense_sampling() -> None:
    world = World(load_map(OFFICE))
    laser = Laser(world, LaserConfig())
    rng = np.random.default_rng(3)
    poses = []
    while len(poses) < 30:
        x, y = rng.uniform(-3, 27), rng.uniform(-9.7, 9.7)
        if world.body_free(x, y, 0.2):
            poses.append((x, y, rng.uniform(-math.pi, math.pi)))
    for x, y, th in poses[:5]:
        r = laser.ranges(x, y, th)
        ang = laser._angles + th
        # reference: 1 mm steps along every beam
        steps = np.arange(1, 12001) * 0.001
        px = x + np.outer(np.cos(ang), steps)
        py = y + np.outer(np.sin(ang), steps)
        col = np.floor((px - world.ox) / world.res).astype(int)
        row = np.floor((py - world.oy) / world.res).astype(int)
        inside = (row >= 0) & (row < world.height) & (col >= 0) & (col < world.width)
        solid = np.zeros_like(inside)
        solid[inside] = world.solid[row[inside], col[inside]]
        first = np.where(solid.any(axis=1), steps[solid.argmax(axis=1)], np.inf)
        both = np.isfinite(first) & np.isfinite(r)
        assert np.mean(np.abs(r[both] - first[both]) < 0.002) > 0.99
    t0 = time.perf_counter()
    for p in poses:
        laser.ranges(*p)
    per_scan = (time.perf_counter() - t0) / len(poses)
    assert per_scan < 0.02  # generous for a loaded CI box; bench/sim.py reports the figure
