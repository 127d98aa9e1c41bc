"""The laser's intensities: plain returns by range, strong ones on the map's reflectors,
0 where nothing returns; and their cost per scan."""

from __future__ import annotations

import logging
import math
import shutil
import time
from pathlib import Path

import numpy as np
from zenros.maps import Reflector, load_landmarks, load_map
from zenros.params import Parameters
from zenros.se2 import Pose2
from zenros.services.chassis.config import DEMO_MAP, declare_chassis
from zenros.services.chassis.devices import LaserDevice
from zenros.services.chassis.laser import Laser, LaserConfig
from zenros.services.chassis.reflectors import PLAIN_FAR, PLAIN_NEAR, STRONG, Reflectors
from zenros.services.chassis.world import World


def _angles(cfg: LaserConfig) -> np.ndarray:
    return cfg.angle_min + np.arange(cfg.beams) * cfg.angle_increment


def test_strong_on_a_reflector_plain_elsewhere(room: World) -> None:
    """A strip on the east wall's face (x = 4.95) at y = 1.0, seen from (1, 1) facing east:
    the beams ending within its radius are strong, the rest plain."""
    cfg = LaserConfig()
    ranges = Laser(room, cfg).ranges(1.0, 1.0, 0.0)
    marks = Reflectors([Reflector("r", 4.95, 1.0, 0.05)])
    out = marks.intensities(1.0, 1.0, 0.0, _angles(cfg), ranges, cfg.range_max)
    assert out.dtype == np.float32 and out.shape == ranges.shape
    strong = np.nonzero(out >= STRONG)[0]
    assert strong.size >= 1
    ends_y = 1.0 + ranges[strong] * np.sin(_angles(cfg)[strong])
    assert np.all(np.abs(ends_y - 1.0) <= 0.06)
    plain = out[out < STRONG]
    assert plain.size == out.size - strong.size
    assert np.all((plain >= PLAIN_FAR) & (plain <= PLAIN_NEAR))


def test_no_return_no_intensity_and_no_reflectors(room: World) -> None:
    cfg = LaserConfig()
    ranges = np.full(cfg.beams, np.inf, dtype=np.float32)
    ranges[0] = 2.0
    out = Reflectors().intensities(0.0, 0.0, 0.0, _angles(cfg), ranges, cfg.range_max)
    assert out[0] == np.float32(PLAIN_NEAR - (PLAIN_NEAR - PLAIN_FAR) * 2.0 / 12.0)
    assert np.all(out[1:] == 0)


def test_a_reflector_out_of_reach_or_behind_a_wall_stays_dark(room: World) -> None:
    """A strip on the far side of the east wall (x = 5.05) is 10 cm from every end point."""
    cfg = LaserConfig()
    ranges = Laser(room, cfg).ranges(1.0, 1.0, 0.0)
    marks = Reflectors([Reflector("r", 5.05, 1.0, 0.04), Reflector("far", 40.0, 1.0)])
    out = marks.intensities(1.0, 1.0, 0.0, _angles(cfg), ranges, cfg.range_max)
    assert out.max() < STRONG


def test_intensities_cost_little(room: World) -> None:
    """Sixteen reflectors in reach add well under a millisecond to a 360-beam scan."""
    cfg = LaserConfig()
    ranges = Laser(room, cfg).ranges(2.5, 1.5, 0.3)
    marks = Reflectors([Reflector(str(i), 0.05 + 0.3 * i, 2.95) for i in range(16)])
    angles = _angles(cfg)
    best = math.inf
    for _ in range(5):
        t = time.perf_counter()
        for _ in range(20):
            marks.intensities(2.5, 1.5, 0.3, angles, ranges, cfg.range_max)
        best = min(best, (time.perf_counter() - t) / 20)
    assert best < 2e-3


def test_the_laser_device_takes_the_reflectors_of_the_floor_it_is_on(tmp_path: Path) -> None:
    """The office's strips are seen from the start; after the world takes another floor's
    map (a copy of the office with no landmarks.yaml) the scan has none."""
    cfg = declare_chassis(Parameters("/chassis", {"map": str(DEMO_MAP)}))
    laser = cfg.build(logging.getLogger("test")).device(LaserDevice)
    assert laser is not None and len(laser.reflectors) == len(load_landmarks(DEMO_MAP))
    assert laser.scan()[1].max() >= STRONG
    for name in ("office.yaml", "office.pgm"):
        shutil.copy(DEMO_MAP.parent / name, tmp_path / name)
    laser.chassis.sim.world.take_map(World(load_map(tmp_path / "office.yaml")))
    ranges, intensities = laser.scan()
    assert len(laser.reflectors) == 0 and intensities.max() < STRONG
    assert intensities.shape == ranges.shape


def test_a_scan_from_where_the_last_was_keeps_its_intensities(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """At rest the same ranges come from the same place: their intensities are not worked
    out again (a copy each scan); a move or other reflectors work them out anew."""
    cfg = declare_chassis(Parameters("/chassis", {"map": str(DEMO_MAP)}))
    laser = cfg.build(logging.getLogger("test")).device(LaserDevice)
    assert laser is not None
    worked: list[int] = []
    real = Reflectors.intensities

    def counted(self: Reflectors, *args: object) -> np.ndarray:
        worked.append(1)
        return real(self, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(Reflectors, "intensities", counted)
    first, again = laser.scan()[1], laser.scan()[1]
    assert len(worked) == 1 and np.array_equal(first, again) and first is not again
    assert first.max() >= STRONG
    laser.chassis.sim.teleport(Pose2(0.5, 0.0, 0.0))
    laser.scan()
    laser.set_reflectors(Reflectors())
    assert laser.scan()[1].max() < STRONG and len(worked) == 3
