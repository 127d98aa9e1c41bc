"""The laser's compiled ray march (``_march.c``) against its numpy reference, and the fallback.

Three ways to range a beam against the grid:

- ``exact``, below: a plain-Python cell-by-cell walk (Amanatides & Woo) in float64, slow and
  obviously right; it also reports how long the ray stays in the cell it hits (its chord).
- the compiled march: the same walk in C; it must agree with ``exact`` to float32 rounding.
- the numpy reference (`Laser._march`): a distance-field march that samples grazing beams
  every half cell, so a ray clipping only the corner of a solid cell by a chord shorter than
  half a cell may pass it (laser.py says so). Where it disagrees with ``exact``, the cell
  it missed must be such a corner (chord < half a cell), and it never ranges short.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from zenros.maps import GridMap, load_map
from zenros.services.chassis import laser as laser_mod
from zenros.services.chassis.laser import Laser, LaserConfig
from zenros.services.chassis.obstacles import Obstacle
from zenros.services.chassis.world import World

OFFICE = Path(__file__).parents[3] / "deploy" / "maps" / "office" / "office.yaml"
F32 = 2e-4  # metres: float32 rounding of a range up to 12 m, with margin

needs_compiled = pytest.mark.skipif(
    laser_mod.compiled is None,
    reason="the laser's C march is not built here (or ZENROS_CHASSIS_PURE is set)")


def exact(world: World, x: float, y: float, ang: float, range_max: float
          ) -> tuple[float, float]:
    """(range in metres, chord in cells of the solid cell hit) of one beam; (inf, 0) when it
    leaves the map or passes range_max / res + 1 cells without meeting a solid cell."""
    px, py = (x - world.ox) / world.res, (y - world.oy) / world.res
    cx, cy = math.floor(px), math.floor(py)
    if not (0 <= cx < world.width and 0 <= cy < world.height) or world.solid[cy, cx]:
        return math.inf, 0.0
    dx, dy = math.cos(ang), math.sin(ang)
    ddx = abs(1 / dx) if dx else math.inf
    ddy = abs(1 / dy) if dy else math.inf
    tx = (cx + 1 - px) * ddx if dx > 0 else (px - cx) * ddx if dx < 0 else math.inf
    ty = (cy + 1 - py) * ddy if dy > 0 else (py - cy) * ddy if dy < 0 else math.inf
    limit = range_max / world.res + 1
    while True:
        if tx < ty:
            t, tx, cx = tx, tx + ddx, cx + (1 if dx > 0 else -1)
        else:
            t, ty, cy = ty, ty + ddy, cy + (1 if dy > 0 else -1)
        if t > limit or not (0 <= cx < world.width and 0 <= cy < world.height):
            return math.inf, 0.0
        if world.solid[cy, cx]:
            return t * world.res, min(tx, ty) - t


def clip(r: np.ndarray, cfg: LaserConfig) -> np.ndarray:
    return np.where((r < cfg.range_min) | (r > cfg.range_max), np.inf, r)


def both_ways(laser: Laser, monkeypatch: pytest.MonkeyPatch, pose: tuple[float, float, float]
              ) -> tuple[np.ndarray, np.ndarray]:
    """(compiled, numpy reference) ranges of one scan, each cast (not the laser's last
    scan from the same pose again)."""
    laser._cast = None
    fast = laser.ranges(*pose)
    laser._cast = None
    with monkeypatch.context() as m:
        m.setattr(laser_mod, "compiled", None)
        ref = laser.ranges(*pose)
    return fast, ref


def check_scan(laser: Laser, monkeypatch: pytest.MonkeyPatch,
               pose: tuple[float, float, float]) -> int:
    """Assert the compiled scan equals ``exact`` and the reference misses only corners;
    returns how many beams the reference got wrong."""
    cfg, world = laser.config, laser.world
    fast, ref = both_ways(laser, monkeypatch, pose)
    x, y, th = pose
    missed = 0
    for i, a in enumerate(laser._angles):
        hit, chord = exact(world, x, y, float(a) + th, cfg.range_max)
        want = float(clip(np.array([hit]), cfg)[0])
        got, r = float(fast[i]), float(ref[i])
        assert got == pytest.approx(want, abs=F32) or (math.isinf(got) and math.isinf(want)), \
            (pose, i, got, want)
        if math.isinf(r) and math.isinf(want) or abs(r - want) <= F32:
            continue
        # the reference passed the first solid cell (maybe one nearer than range_min, where
        # the beam reports inf): only a corner clipped by < half a cell, and never short
        missed += 1
        assert r > hit, (pose, i, r, hit)
        assert chord < 0.5, (pose, i, r, hit, chord)
    return missed


def free_poses(world: World, n: int, seed: int) -> list[tuple[float, float, float]]:
    rng = np.random.default_rng(seed)
    poses: list[tuple[float, float, float]] = []
    while len(poses) < n:
        x = world.ox + rng.uniform(0, world.width * world.res)
        y = world.oy + rng.uniform(0, world.height * world.res)
        if world.body_free(x, y, 0.2):
            poses.append((x, y, rng.uniform(-math.pi, math.pi)))
    return poses


@needs_compiled
def test_compiled_matches_exact_walk_and_reference_on_the_office_map(
        monkeypatch: pytest.MonkeyPatch) -> None:
    world = World(load_map(OFFICE))
    laser = Laser(world, LaserConfig())
    missed = sum(check_scan(laser, monkeypatch, p) for p in free_poses(world, 12, 5))
    assert missed < 0.01 * 12 * 360  # corners are rare: the reference is right > 99 %


@needs_compiled
@pytest.mark.parametrize("seed", range(12))
def test_compiled_matches_on_random_maps_and_poses(seed: int,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(seed)
    h, w = int(rng.integers(3, 60)), int(rng.integers(3, 60))
    grid = np.where(rng.random((h, w)) < rng.uniform(0.0, 0.25), 100, 0).astype(np.int8)
    res = float(rng.choice([0.025, 0.05, 0.1]))
    world = World(GridMap(grid, res, (float(rng.uniform(-5, 5)), float(rng.uniform(-5, 5)),
                                      0.0)))
    cfg = LaserConfig(beams=int(rng.integers(1, 400)), range_min=float(rng.uniform(0, 0.1)),
                      range_max=float(rng.uniform(0.5, 6.0)),
                      fov=float(rng.uniform(0.1, 2 * math.pi)))
    laser = Laser(world, cfg)
    for _ in range(6):  # anywhere: in free cells, in walls, off the map
        pose = (world.ox + float(rng.uniform(-0.2, 1.2)) * w * res,
                world.oy + float(rng.uniform(-0.2, 1.2)) * h * res,
                float(rng.uniform(-math.pi, math.pi)))
        check_scan(laser, monkeypatch, pose)


@needs_compiled
def test_axis_parallel_and_diagonal_beams(room: World, monkeypatch: pytest.MonkeyPatch) -> None:
    laser = Laser(room, LaserConfig(beams=8))  # every 45 degrees
    for pose in [(1.0, 1.0, 0.0), (2.5, 1.5, 0.0), (0.075, 0.075, 0.0), (1.0, 1.0, math.pi)]:
        check_scan(laser, monkeypatch, pose)


@needs_compiled
def test_compiled_sees_a_corner_the_reference_may_miss(monkeypatch: pytest.MonkeyPatch) -> None:
    grid = np.zeros((40, 40), np.int8)
    grid[20, 20] = 100  # a lone cell: x 1.0 .. 1.05, y 1.0 .. 1.05
    world = World(GridMap(grid, 0.05, (0.0, 0.0, 0.0)))
    # a ray from (0.2, 0.2) aimed just inside the cell's corner (1.0, 1.05): its chord
    # through the cell is a thousandth of a cell
    ang = math.atan2(1.05 - 0.2 - 0.00005, 1.0 - 0.2)
    laser = Laser(world, LaserConfig(beams=1, fov=1e-3))  # its one beam at -fov / 2
    fast, ref = both_ways(laser, monkeypatch, (0.2, 0.2, ang - float(laser._angles[0])))
    want, chord = exact(world, 0.2, 0.2, ang, 12.0)
    assert chord < 0.01
    assert float(fast[0]) == pytest.approx(want, abs=F32)
    assert math.isinf(float(ref[0]))  # the reference's half-cell samples step over it


@needs_compiled
def test_obstacles_still_cut_the_compiled_scan(room: World) -> None:
    room.set_obstacles([Obstacle("c", "circle", 3.0, 1.0, radius=0.5)])
    cfg = LaserConfig()
    r = Laser(room, cfg).ranges(1.0, 1.0, 0.0)
    assert r[180] == pytest.approx(1.5, abs=1e-5)  # beam 180 points along +x


@needs_compiled
def test_compiled_march_refuses_bad_buffers() -> None:
    march = laser_mod.compiled
    assert march is not None
    kind = np.zeros(16, np.uint8)
    d = np.ones(3)
    with pytest.raises(ValueError, match="width\\*height"):
        march.march(kind, 5, 3, 1.0, 1.0, d, d, 10.0, 0.05, np.empty(3, np.float32))
    with pytest.raises(ValueError, match="one per beam"):
        march.march(kind, 4, 4, 1.0, 1.0, d, d, 10.0, 0.05, np.empty(2, np.float32))
    with pytest.raises(ValueError, match="one per beam"):
        march.march(kind, 4, 4, 1.0, 1.0, d.astype(np.float32), d, 10.0, 0.05,
                    np.empty(3, np.float32))


def test_reference_runs_when_compiled_march_is_off(room: World,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(laser_mod, "compiled", None)
    calls: list[int] = []
    real = Laser._march

    def spy(self: Laser, *args: object) -> np.ndarray:
        calls.append(1)
        return real(self, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(Laser, "_march", spy)
    r = Laser(room, LaserConfig()).ranges(1.0, 1.0, 0.0)
    assert calls == [1]
    assert r[180] == pytest.approx(3.95, abs=1e-4)


CHILD = """
import sys
{block}
from zenros.services.chassis import laser
from zenros.services.chassis.world import World
from zenros.maps import GridMap
import numpy as np
grid = np.zeros((20, 20), np.int8); grid[:, 15] = 100
r = laser.Laser(World(GridMap(grid, 0.1, (0.0, 0.0, 0.0))), laser.LaserConfig()).ranges(
    0.5, 1.0, 0.0)
print(laser.compiled is None, round(float(r[180]), 4))
"""


@pytest.mark.parametrize("how", ["absent", "env"])
def test_laser_falls_back_to_numpy_without_the_extension(how: str) -> None:
    """A fresh interpreter where ``_march`` cannot be imported (as on a machine without a C
    compiler) or ``ZENROS_CHASSIS_PURE=1`` is set: the numpy reference ranges the scan."""
    block = ("sys.modules['zenros.services.chassis._march'] = None  # import fails"
             if how == "absent" else "")
    env = {**os.environ, "ZENROS_CHASSIS_PURE": "1" if how == "env" else "0"}
    out = subprocess.run([sys.executable, "-c", CHILD.format(block=block)], env=env,
                         capture_output=True, text=True, timeout=50, check=True).stdout
    assert out.split() == ["True", "1.0"]  # wall face at x = 1.5, laser at x = 0.5
