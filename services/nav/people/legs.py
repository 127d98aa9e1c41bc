"""The leg detector: people found in a laser scan's points by the shape of their legs.

The scan's points (in ``base_link``, in the scan's angular order) are cut into clusters
where two neighbours are more than `GAP` m apart; a cluster is a leg when it is
`LEG_MIN`..`LEG_MAX` m across, has at least `MIN_POINTS` points and faces the laser (its
points no farther apart than `GRAZING` times the beams' spacing at their range: a wall seen
at a grazing angle has its points spread wide), and stands free (the points beside it are
`JUMP` m farther, or another leg, or none: a chunk of wall has more wall beside it); two legs whose centres are
`PAIR_MIN`..`PAIR_MAX` m apart are a person, at their midpoint. A single leg (the other hidden
behind it) is a person too when no pair uses it and ``singles`` is true.
"""

from __future__ import annotations

import numpy as np

__all__ = ["GAP", "LEG_MAX", "LEG_MIN", "PAIR_MAX", "PAIR_MIN", "detect_legs",
           "detect_people"]

GAP = 0.1  # m between neighbouring points that starts a new cluster
LEG_MIN = 0.02  # m: a cluster's extent, first to last point
LEG_MAX = 0.25
MIN_POINTS = 2
PAIR_MIN = 0.1  # m between two legs' centres
PAIR_MAX = 0.5
MAX_RANGE = 6.0  # m: legs farther are too few points to tell from clutter
JUMP = 0.1  # m a leg stands in front of what the laser sees beside it
GRAZING = 2.0  # a cluster whose points are this many beam spacings apart is a grazed wall


def detect_legs(points: np.ndarray) -> np.ndarray:
    """Centres (K, 2) of the leg-sized clusters of ``points`` (N, 2), in scan order."""
    if len(points) < MIN_POINTS:
        return np.zeros((0, 2))
    step = np.hypot(*np.diff(points, axis=0).T)
    cuts = np.flatnonzero(step > GAP) + 1
    starts = np.concatenate([[0], cuts]).tolist()
    ends = np.concatenate([cuts, [len(points)]]).tolist()
    sized = [e - s >= MIN_POINTS and LEG_MIN <= float(np.hypot(*(points[e - 1] - points[s])))
             <= LEG_MAX and not _flat(points[s:e]) for s, e in zip(starts, ends, strict=True)]
    ranges = np.hypot(points[:, 0], points[:, 1])
    bearings = np.arctan2(points[:, 1], points[:, 0])
    legs = []
    for k, (s, e) in enumerate(zip(starts, ends, strict=True)):
        if not sized[k]:
            continue
        beam = float(np.median(np.abs(np.diff(bearings[s:e]))))
        if not (_apart(k - 1, s - 1, s, sized, ranges, bearings, beam)
                and _apart(k + 1, e, e - 1, sized, ranges, bearings, beam)):
            continue
        centre = points[s:e].mean(axis=0)
        if float(np.hypot(*centre)) <= MAX_RANGE:
            legs.append(centre)
    return np.array(legs).reshape(-1, 2)


def _apart(k: int, i: int, edge: int, sized: list[bool], ranges: np.ndarray,
           bearings: np.ndarray, beam: float) -> bool:
    """Whether a cluster's neighbour on one side (cluster ``k``, point ``i``; the cluster's
    ``edge`` point) leaves it standing free: no point there (none, or some beams off), a
    leg-sized cluster (the other leg), or a point `JUMP` m farther (the background). A wall
    chunk has its wall's next point at about its own range."""
    if i < 0 or i >= len(ranges) or not 0 <= k < len(sized) or sized[k]:
        return True
    off = abs(float(np.angle(np.exp(1j * (bearings[i] - bearings[edge])))))
    return off > 2.5 * beam or float(ranges[i]) >= float(ranges[edge]) + JUMP


def _flat(cluster: np.ndarray) -> bool:
    """Whether the cluster's points are spread wider than the beams' spacing at their range
    allows a surface facing the laser: a wall seen at a grazing angle, not a leg."""
    ranges = np.hypot(cluster[:, 0], cluster[:, 1])
    bearings = np.unwrap(np.arctan2(cluster[:, 1], cluster[:, 0]))
    across = float(ranges.mean()) * float(np.abs(np.diff(bearings)).mean())
    step = float(np.hypot(*np.diff(cluster, axis=0).T).mean())
    return across <= 0 or step > GRAZING * across


def detect_people(points: np.ndarray, singles: bool = False) -> np.ndarray:
    """People (M, 2) in ``points``' frame: pairs of legs, nearest pairs first matched
    greedily; nearest person first."""
    legs = detect_legs(points)
    n = len(legs)
    used = np.zeros(n, dtype=bool)
    people = []
    if n >= 2:
        d = np.hypot(legs[:, None, 0] - legs[None, :, 0], legs[:, None, 1] - legs[None, :, 1])
        pairs = sorted((float(d[i, j]), i, j) for i in range(n) for j in range(i + 1, n)
                       if PAIR_MIN <= d[i, j] <= PAIR_MAX)
        for _, i, j in pairs:
            if not (used[i] or used[j]):
                used[i] = used[j] = True
                people.append((legs[i] + legs[j]) / 2)
    if singles:
        people.extend(legs[~used])
    out = np.array(people).reshape(-1, 2)
    return out[np.argsort(np.hypot(out[:, 0], out[:, 1]))]
