"""The coverage planner (services/nav/planning/coverage.py), called directly."""

from __future__ import annotations

import math

import numpy as np
import pytest
from zenros.services.nav.planning.coverage import (
    MAX_INPUT_POINTS,
    CoverageError,
    CoveragePlan,
    Field,
    plan_coverage,
    validate_field,
)

RECT = [[0, 0, 0], [10, 0, 0], [10, 6, 0], [0, 6, 0], [0, 0, 0]]
HOLE = [[4, 2, 0], [6, 2, 0], [6, 4, 0], [4, 4, 0]]
L_SHAPE = [[0, 0], [8, 0], [8, 3], [3, 3], [3, 8], [0, 8]]


def segments(plan: CoveragePlan) -> np.ndarray:
    return plan.path.reshape(-1, 2, 2)


def inside(points: np.ndarray, poly: list[list[float]]) -> np.ndarray:
    """Point in polygon, boundary included (within 1e-6)."""
    p = np.asarray([q[:2] for q in poly], dtype=float)
    a, b = p, np.roll(p, -1, axis=0)
    out = []
    for x, y in points:
        d = b - a
        t = np.clip(((x - a[:, 0]) * d[:, 0] + (y - a[:, 1]) * d[:, 1])
                    / np.maximum((d * d).sum(axis=1), 1e-12), 0, 1)
        near = np.hypot(a[:, 0] + t * d[:, 0] - x, a[:, 1] + t * d[:, 1] - y).min() < 1e-6
        cross = ((a[:, 1] > y) != (b[:, 1] > y)) & (
            x < a[:, 0] + (y - a[:, 1]) * d[:, 0] / np.where(d[:, 1] == 0, 1, d[:, 1]))
        out.append(near or bool(np.count_nonzero(cross) % 2))
    return np.asarray(out)


def distance_to_path(points: np.ndarray, plan: CoveragePlan) -> np.ndarray:
    """Distance from each point to the nearest swath segment (connections not counted)."""
    seg = segments(plan)
    a, b = seg[:, 0][None], seg[:, 1][None]
    d = b - a
    p = points[:, None, :]
    t = np.clip(((p - a) * d).sum(-1) / np.maximum((d * d).sum(-1), 1e-12), 0, 1)
    return np.asarray(np.linalg.norm(a + t[..., None] * d - p, axis=-1).min(axis=1))


def grid(x0: float, x1: float, y0: float, y1: float, step: float = 0.1) -> np.ndarray:
    xs, ys = np.meshgrid(np.arange(x0, x1 + 1e-9, step), np.arange(y0, y1 + 1e-9, step))
    return np.stack([xs.ravel(), ys.ravel()], axis=1)


@pytest.mark.parametrize("width", [0.5, 0.7, 1.0, 2.5, 7.0])
def test_rectangle_swath_count_and_alternating_directions(width: float) -> None:
    plan = plan_coverage(validate_field(RECT), width)
    assert plan.swaths == math.ceil(6 / width)
    seg = segments(plan)
    assert len(seg) == plan.swaths
    assert np.allclose(seg[:, 0, 1], seg[:, 1, 1])  # every swath along x (angle 0)
    assert np.allclose(np.abs(seg[:, 1, 0] - seg[:, 0, 0]), 10)
    dirs = np.sign(seg[:, 1, 0] - seg[:, 0, 0])
    assert np.all(dirs[1:] == -dirs[:-1])
    ys = seg[:, 0, 1]
    assert np.all(np.diff(ys) > 0) and np.all(np.diff(ys) <= width + 1e-9)
    # every point of the rectangle is within op_width / 2 of a swath
    assert distance_to_path(grid(0, 10, 0, 6), plan).max() <= width / 2 + 1e-9


def test_hole_splits_swaths_and_nothing_enters_it() -> None:
    plan = plan_coverage(validate_field(RECT, [HOLE]), 0.5)
    seg = segments(plan)
    assert len(seg) > plan.swaths  # swaths across the hole became two segments
    samples = np.concatenate([seg[:, 0] + (seg[:, 1] - seg[:, 0]) * f
                              for f in np.linspace(0, 1, 21)[:, None, None]])
    assert inside(samples, RECT).all()
    hole = np.asarray(HOLE, dtype=float)[:, :2]
    strictly_in = ((samples[:, 0] > 4 + 1e-9) & (samples[:, 0] < 6 - 1e-9)
                   & (samples[:, 1] > 2 + 1e-9) & (samples[:, 1] < 4 - 1e-9))
    assert not strictly_in.any() and hole.shape == (4, 2)
    pts = grid(0, 10, 0, 6)
    region = pts[~((pts[:, 0] > 4) & (pts[:, 0] < 6) & (pts[:, 1] > 2) & (pts[:, 1] < 4))]
    assert distance_to_path(region, plan).max() <= 0.25 + 1e-9
    # each swath segment is driven once, opposite to the one before it in its cell
    assert len({tuple(s.round(6).ravel()) for s in seg}) == len(seg)


def test_swath_angle_is_honoured() -> None:
    for angle in (30.0, 90.0, 135.0):
        plan = plan_coverage(validate_field(RECT), 0.5, swath_angle=angle)
        d = segments(plan)[:, 1] - segments(plan)[:, 0]
        heading = np.degrees(np.arctan2(d[:, 1], d[:, 0])) % 180
        assert np.allclose(heading, angle % 180, atol=1e-6)
        assert plan.swath_angle == pytest.approx(angle)
        samples = np.concatenate([segments(plan)[:, 0], segments(plan)[:, 1]])
        assert inside(samples, RECT).all()
        # corners not square to the swaths are cut; everything op_width / 2 inside is covered
        assert distance_to_path(grid(0.25, 9.75, 0.25, 5.75, 0.2), plan).max() <= 0.25 + 1e-9


def test_automatic_angle_needs_the_fewest_swaths() -> None:
    tall = [[0, 0], [3, 0], [3, 20], [0, 20]]
    plan = plan_coverage(validate_field(tall), 1.0, swath_angle=-1)
    assert plan.swath_angle == pytest.approx(90.0) and plan.swaths == 3
    c, s = math.cos(math.radians(25)), math.sin(math.radians(25))
    tilted = [[20 * c, 20 * s], [20 * c - 4 * s, 20 * s + 4 * c], [-4 * s, 4 * c], [0, 0]]
    auto = plan_coverage(validate_field(tilted), 1.0, swath_angle=-2)
    assert auto.swath_angle == pytest.approx(25.0) and auto.swaths == 4
    for angle in range(0, 180, 15):
        assert plan_coverage(validate_field(tilted), 1.0, angle).swaths >= auto.swaths


def test_headland_is_kept_clear() -> None:
    plan = plan_coverage(validate_field(RECT, [HOLE]), 0.5, headland_width=1.0)
    assert plan.swaths == math.ceil((6 - 2) / 0.5)
    seg = segments(plan)
    samples = np.concatenate([seg[:, 0] + (seg[:, 1] - seg[:, 0]) * f
                              for f in np.linspace(0, 1, 41)[:, None, None]])
    x, y = samples[:, 0], samples[:, 1]
    to_border = np.minimum.reduce([x, 10 - x, y, 6 - y])
    dx = np.maximum.reduce([4 - x, np.zeros_like(x), x - 6])
    dy = np.maximum.reduce([2 - y, np.zeros_like(y), y - 4])
    assert to_border.min() >= 1.0 - 1e-9
    assert np.hypot(dx, dy).min() >= 1.0 - 1e-9
    inner = grid(1, 9, 1, 5)
    far = np.hypot(np.maximum.reduce([4 - inner[:, 0], 0 * inner[:, 0], inner[:, 0] - 6]),
                   np.maximum.reduce([2 - inner[:, 1], 0 * inner[:, 1], inner[:, 1] - 4]))
    assert distance_to_path(inner[far >= 1.25], plan).max() <= 0.25 + 1e-9


def test_concave_border_is_covered_and_stays_inside() -> None:
    plan = plan_coverage(validate_field(L_SHAPE), 0.4, headland_width=0.2)
    seg = segments(plan)
    samples = np.concatenate([seg[:, 0] + (seg[:, 1] - seg[:, 0]) * f
                              for f in np.linspace(0, 1, 21)[:, None, None]])
    assert inside(samples, [list(p) for p in L_SHAPE]).all()
    pts = grid(0.2, 7.8, 0.2, 7.8)
    region = pts[(pts[:, 1] <= 2.8) | (pts[:, 0] <= 2.8)]
    assert distance_to_path(region, plan).max() <= 0.2 + 1e-6
    starts = [tuple(s) for s in seg[:, 0]]
    assert len(set(starts)) == len(starts)


@pytest.mark.parametrize(("border", "holes", "words"), [
    ([[0, 0], [1, 0]], [], "at least 3"),
    ([[0, 0], [1, 1], [2, 2]], [], "no area"),
    ([[0, 0], [float("nan"), 0], [1, 1]], [], "finite"),
    ([[0, 0], [2, 2], [2, 0], [0, 2]], [], "intersects itself"),
    (RECT, [[[20, 20], [21, 20], [21, 21]]], "hole 0 is not inside"),
    (RECT, [[[5, 5], [12, 5], [5, 5.5]]], "hole 0"),
    ([[0, 0, 0, 0], [1, 0], [1, 1]], [], "[x, y, z]"),
])
def test_bad_fields_are_refused(border: list[list[float]], holes: list[list[list[float]]],
                                words: str) -> None:
    with pytest.raises(CoverageError, match=None) as err:
        validate_field(border, holes)
    assert words in str(err.value)


def test_bad_numbers_and_limits_are_refused() -> None:
    field = validate_field(RECT)
    for kw, words in (({"op_width": 0.0}, "op_width must be > 0"),
                      ({"op_width": -1.0}, "op_width"),
                      ({"op_width": float("nan")}, "finite"),
                      ({"op_width": 1.0, "headland_width": -1.0}, "headland_width"),
                      ({"op_width": 1.0, "turn_radius": float("inf")}, "turn_radius"),
                      ({"op_width": 1.0, "headland_width": 3.0}, "nothing"),
                      ({"op_width": 1e-5}, "raise op_width")):
        with pytest.raises(CoverageError) as err:
            plan_coverage(field, **kw)
        assert words in str(err.value)
    many = [[math.cos(t), math.sin(t)] for t in np.linspace(0, 6, MAX_INPUT_POINTS + 1)]
    with pytest.raises(CoverageError, match="limit"):
        validate_field(many)
    assert isinstance(field, Field)


def radii(points: np.ndarray) -> np.ndarray:
    """Circumradius of every three consecutive points (inf where they are in line)."""
    a, b, c = points[:-2], points[1:-1], points[2:]
    ab, bc, ca = (np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1),
                  np.linalg.norm(a - c, axis=1))
    cross = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    with np.errstate(divide="ignore"):
        return np.asarray(np.where(cross < 1e-12, np.inf, ab * bc * ca / (2 * cross)))


@pytest.mark.parametrize(("radius", "reach"), [
    (0.4, 0.4),  # spacing 1 >= 2r: a U of two quarter circles
    (1.0, 1.0 + math.sqrt(4 - 1.5 ** 2)),  # spacing 1 < 2r: an omega turn
])
def test_turns_keep_the_turn_radius(radius: float, reach: float) -> None:
    field = validate_field(RECT)
    plain = plan_coverage(field, 1.0)
    plan = plan_coverage(field, 1.0, turn_radius=radius)
    assert plan.segments == plain.segments == 6
    # the swaths are all there, in the same order, the turns in between
    it = iter(map(tuple, plan.path.round(9).tolist()))
    assert all(p in it for p in map(tuple, plain.path.round(9).tolist()))
    assert radii(plan.path).min() >= radius - 1e-6
    outside = plan.path[(plan.path[:, 0] < 0) | (plan.path[:, 0] > 10)]
    assert len(outside) >= 5 * 8  # every one of the five turns is sampled
    assert np.abs(outside[:, 0] - 5).max() == pytest.approx(5 + reach, abs=0.01)  # sampled
    steps = np.linalg.norm(np.diff(plan.path, axis=0), axis=1)
    assert steps.max() == pytest.approx(10.0)  # the swaths: nothing jumps


def test_large_border_is_checked_quickly_and_a_far_crossing_is_found() -> None:
    ring = [[50 * math.cos(t), 50 * math.sin(t)]
            for t in np.linspace(0, 2 * math.pi, 9000, endpoint=False)]
    assert len(validate_field(ring).border) == 9000
    ring[4500] = [60.0, 0.0]  # the far side's vertex pulled across the first edges
    with pytest.raises(CoverageError, match="intersects itself"):
        validate_field(ring)
