"""Cost values: Nav2's cost bytes, the static layer's occupancy→cost and the published scale."""

from __future__ import annotations

import numpy as np

__all__ = [
    "FREE_SPACE",
    "INSCRIBED_INFLATED_OBSTACLE",
    "LETHAL_OBSTACLE",
    "MAX_NON_OBSTACLE",
    "NO_INFORMATION",
    "OCCUPANCY_OF_COST",
    "cost_to_occupancy",
    "occupancy_to_cost",
]

NO_INFORMATION = 255
LETHAL_OBSTACLE = 254
INSCRIBED_INFLATED_OBSTACLE = 253
MAX_NON_OBSTACLE = 252
FREE_SPACE = 0


def _occupancy_table() -> np.ndarray:
    """costmap_2d's translation table for the published grid: 0 → 0, 253 → 99, 254 → 100,
    255 → −1, and 1..252 → 1 + 97·(c − 1)/251 (integer division), i.e. 1..98."""
    t = np.empty(256, dtype=np.int8)
    t[0] = 0
    for c in range(1, 253):
        t[c] = 1 + (97 * (c - 1)) // 251
    t[253] = 99
    t[254] = 100
    t[255] = -1
    return t


OCCUPANCY_OF_COST: np.ndarray = _occupancy_table()
"""``OCCUPANCY_OF_COST[cost]``: the int8 value Nav2 publishes for a cost byte."""


def cost_to_occupancy(costs: np.ndarray) -> np.ndarray:
    """A uint8 cost grid in Nav2's published OccupancyGrid scale (int8, −1..100)."""
    return OCCUPANCY_OF_COST[np.asarray(costs, dtype=np.uint8)]


def occupancy_to_cost(
    occupancy: np.ndarray,
    *,
    track_unknown_space: bool = False,
    lethal_cost_threshold: int = 100,
    trinary_costmap: bool = True,
) -> np.ndarray:
    """The static layer's cost of each occupancy cell (int8 −1 / 0..100), Nav2's rules:
    −1 → 255 if ``track_unknown_space`` else 0; ≥ ``lethal_cost_threshold`` → 254; with
    ``trinary_costmap`` everything else → 0, otherwise ``v / threshold · 254`` (truncated).
    Like Nav2, a cell is read as an unsigned byte (so −2 counts as 254, lethal)."""
    occ = np.asarray(occupancy)
    v = occ.astype(np.int8).view(np.uint8)  # Nav2 reads the int8 as an unsigned byte: −1 → 255
    out = np.zeros(occ.shape, dtype=np.uint8)
    unknown = v == 255
    lethal = (v >= lethal_cost_threshold) & ~unknown
    if not trinary_costmap:
        mid = ~unknown & ~lethal
        scaled = (v.astype(np.float64) / lethal_cost_threshold * LETHAL_OBSTACLE).astype(np.uint8)
        out[mid] = scaled[mid]
    out[lethal] = LETHAL_OBSTACLE
    out[unknown] = NO_INFORMATION if track_unknown_space else FREE_SPACE
    return out
