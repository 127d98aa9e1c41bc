"""The inflation layer: Nav2's exponential cost decay around lethal cells.

``inflation_cost(d)`` is ``InflationLayer::computeCost`` with ``d`` in metres: 254 at the
obstacle, 253 within the inscribed radius, then ``int(252 · exp(−csf · (d − r_inscribed)))``,
and nothing (0) beyond ``ceil(inflation_radius / resolution)`` cells. Distances are exact
Euclidean distances between cell centres to the nearest source (lethal, and unknown with
``inflate_around_unknown``), from a bounded two-pass distance transform in numpy; the layer
combines with the master grid by maximum, and an unknown (255) cell takes an inflated cost
only when it is inscribed or lethal (or above free with ``inflate_unknown``), as in Nav2.

The distance transform is compiled (``_edt.c``, O(cells)) when built; the numpy code here
is the reference (``ZENROS_NAV_PURE=1`` selects it).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from zenros.errors import ConfigError

from .accel import edt as _edt
from .values import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    MAX_NON_OBSTACLE,
    NO_INFORMATION,
)

__all__ = ["Inflation", "distance_transform", "inflation_cost", "squared_distance"]


def inflation_cost(
    distance: float, inscribed_radius: float, cost_scaling_factor: float
) -> int:
    """Nav2's ``computeCost`` for a cell ``distance`` metres from the nearest obstacle."""
    if distance <= 0.0:
        return LETHAL_OBSTACLE
    if distance <= inscribed_radius:
        return INSCRIBED_INFLATED_OBSTACLE
    factor = math.exp(-1.0 * cost_scaling_factor * (distance - inscribed_radius))
    return int(MAX_NON_OBSTACLE * factor)


@dataclass(frozen=True, slots=True)
class Inflation:
    """Inflation parameters for one resolution, with the cost of every squared cell distance."""

    resolution: float
    inscribed_radius: float = 0.22
    inflation_radius: float = 0.55
    cost_scaling_factor: float = 10.0
    inflate_unknown: bool = False
    inflate_around_unknown: bool = False

    def __post_init__(self) -> None:
        for name in ("inscribed_radius", "inflation_radius", "cost_scaling_factor"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise ConfigError(f"{name} must be a finite number >= 0, got {v!r}")

    @property
    def cells(self) -> int:
        """The inflation radius in cells, Nav2's ``cellDistance``: ``ceil(radius / res)``."""
        return int(max(0.0, math.ceil(self.inflation_radius / self.resolution)))

    def table(self) -> np.ndarray:
        """``table[k]``: the cost at squared cell distance k (0 beyond the radius)."""
        return _cost_table(
            self.resolution, self.inscribed_radius, self.cells, self.cost_scaling_factor
        )

    def apply(self, region: np.ndarray, inner: tuple[slice, slice]) -> np.ndarray:
        """The inflated costs of ``region[inner]``: ``region`` holds the combined layer
        costs (uint8) and must reach ``cells`` beyond ``inner`` wherever the map does, so
        that every source within the radius is seen."""
        old = region[inner]
        sources = region == LETHAL_OBSTACLE
        if self.inflate_around_unknown:
            sources |= region == NO_INFORMATION
        if not sources.any():
            return old.copy()
        d2 = distance_transform(sources, self.cells)[inner]
        table = self.table()
        cost = table[np.minimum(d2, len(table) - 1)]
        unknown = old == NO_INFORMATION
        if self.inflate_unknown:
            take_unknown = unknown & (cost > FREE_SPACE)
        else:
            take_unknown = unknown & (cost >= INSCRIBED_INFLATED_OBSTACLE)
        return np.where(unknown, np.where(take_unknown, cost, old), np.maximum(old, cost))


@functools.lru_cache(maxsize=32)
def _cost_table(resolution: float, inscribed: float, cells: int, csf: float) -> np.ndarray:
    n = 2 * (cells + 1) * (cells + 1) + 1
    t = np.zeros(n, dtype=np.uint8)
    for k in range(n):
        d_cells = math.sqrt(k)
        if d_cells > cells:
            break
        t[k] = inflation_cost(d_cells * resolution, inscribed, csf)
    t.flags.writeable = False
    return t


def distance_transform(sources: np.ndarray, radius: int) -> np.ndarray:
    """``squared_distance``, by the compiled transform when it is built."""
    if _edt is None:
        return squared_distance(sources, radius)
    h, w = sources.shape
    raw = _edt.squared_distance(np.ascontiguousarray(sources, dtype=np.uint8), w, h, radius)
    return np.frombuffer(raw, dtype=np.int32).reshape(h, w)


def squared_distance(sources: np.ndarray, radius: int) -> np.ndarray:
    """Exact squared Euclidean distance in cells from each cell to the nearest source, for
    distances up to ``radius`` (int32; farther cells get a value above ``2·(radius+1)²``)."""
    h, w = sources.shape
    big = radius + 1
    rows = np.arange(h, dtype=np.int32)[:, None]
    # vertical distance to the nearest source in the same column (capped at big)
    above = np.where(sources, rows, np.int32(-10 * big - h))
    np.maximum.accumulate(above, axis=0, out=above)
    below = np.where(sources, rows, np.int32(10 * big + 2 * h))
    below = np.minimum.accumulate(below[::-1], axis=0)[::-1]
    g = np.minimum(rows - above, below - rows)
    np.minimum(g, big, out=g)
    g2 = g * g
    d2 = g2.copy()
    tmp = np.empty_like(d2)
    # horizontal pass: d² = min over |dx| ≤ radius of g²(x + dx) + dx²
    for dx in range(1, min(radius, w - 1) + 1):
        dd = np.int32(dx * dx)
        np.add(g2[:, dx:], dd, out=tmp[:, : w - dx])
        np.minimum(d2[:, : w - dx], tmp[:, : w - dx], out=d2[:, : w - dx])
        np.add(g2[:, : w - dx], dd, out=tmp[:, dx:])
        np.minimum(d2[:, dx:], tmp[:, dx:], out=d2[:, dx:])
    return d2
