"""Landmark relocalisation: the robot's pose in ``map`` from the reflectors it sees.

`locate` matches reflector observations (centres in ``base_link``, from
`reflectors.detect`) to a map's landmarks without trusting any pose: every pair of
observations whose distance apart agrees (within ``pair_tolerance``) with a pair of
landmarks proposes a pose (the 2-point rigid fit); each proposal places all observations in
the map and counts those within ``gate`` of a landmark (one landmark each). The proposal
with the most matches, refitted on them by least squares (`fit_rigid`), wins; proposals
equally good (as many matches, a residual within ``rival_rms``) but at different poses (a
symmetric layout) are told apart by the rough pose when there is one, and refused as
ambiguous when there is not. Plain numpy, no I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from zenros.se2 import Pose2, angle_diff

__all__ = ["LandmarkError", "LandmarkFix", "LocateParams", "fit_rigid", "locate"]


class LandmarkError(ValueError):
    """No pose: too few reflectors seen or matched, or more than one pose fits."""


@dataclass(frozen=True)
class LocateParams:
    gate: float = 0.25
    """Metres: an observation placed by a pose matches a landmark this near."""
    pair_tolerance: float = 0.12
    """Metres: two observations' distance apart and two landmarks' agree within this."""
    min_matches: int = 2
    max_rms: float = 0.1
    """Metres: a fit whose residual is larger is refused."""
    distinct_xy: float = 0.5
    distinct_theta: float = 0.3
    """Two poses farther apart than this (m or rad) are different answers."""
    rival_rms: float = 0.02
    """Metres: another answer is a rival of the best only if its residual is within this
    of the best's (a near-symmetric layout fits worse the wrong way round)."""
    max_observations: int = 12
    """The nearest this many observations are matched (the search is quadratic in them)."""


@dataclass(frozen=True)
class LandmarkFix:
    """The robot's pose in ``map``, the landmark index of each observation used
    (``matches``: (observation, landmark) pairs) and the fit's RMS residual (m)."""

    pose: Pose2
    matches: tuple[tuple[int, int], ...]
    rms: float


def fit_rigid(src: np.ndarray, dst: np.ndarray) -> Pose2:
    """The rigid motion (rotation then translation) taking ``src`` points onto ``dst``
    (both (n, 2), n >= 2) with the least squared error.

    Raises:
        LandmarkError: fewer than two pairs, or the points coincide.
    """
    if len(src) < 2 or len(src) != len(dst):
        raise LandmarkError(f"a fit needs two or more point pairs, got {len(src)}")
    cs, cd = src.mean(axis=0), dst.mean(axis=0)
    s, d = src - cs, dst - cd
    dot = float(np.sum(s * d))
    cross = float(np.sum(s[:, 0] * d[:, 1] - s[:, 1] * d[:, 0]))
    if math.hypot(dot, cross) < 1e-12:
        raise LandmarkError("the reflectors seen coincide: no heading can be fitted")
    theta = math.atan2(cross, dot)
    c, si = math.cos(theta), math.sin(theta)
    return Pose2(float(cd[0] - (c * cs[0] - si * cs[1])),
                 float(cd[1] - (si * cs[0] + c * cs[1])), theta)


def _place(pose: Pose2, pts: np.ndarray) -> np.ndarray:
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    return np.column_stack([pose.x + c * pts[:, 0] - s * pts[:, 1],
                            pose.y + s * pts[:, 0] + c * pts[:, 1]])


def _associate(obs: np.ndarray, marks: np.ndarray, pose: Pose2,
               gate: float) -> list[tuple[int, int]]:
    """(observation, landmark) pairs within ``gate`` at ``pose``, nearest first, each
    landmark and observation used once."""
    d = np.hypot(*(_place(pose, obs)[:, None, :] - marks[None, :, :]).transpose(2, 0, 1))
    pairs: list[tuple[int, int]] = []
    used_o: set[int] = set()
    used_m: set[int] = set()
    for flat in np.argsort(d, axis=None):
        i, j = divmod(int(flat), marks.shape[0])
        if d[i, j] > gate:
            break
        if i not in used_o and j not in used_m:
            pairs.append((i, j))
            used_o.add(i)
            used_m.add(j)
    return pairs


def _refit(obs: np.ndarray, marks: np.ndarray, pairs: list[tuple[int, int]]
           ) -> tuple[Pose2, float]:
    o = obs[[i for i, _ in pairs]]
    m = marks[[j for _, j in pairs]]
    pose = fit_rigid(o, m)
    rms = float(np.sqrt(np.mean(np.sum((_place(pose, o) - m) ** 2, axis=1))))
    return pose, rms


def _distinct(a: Pose2, b: Pose2, p: LocateParams) -> bool:
    return (math.hypot(a.x - b.x, a.y - b.y) > p.distinct_xy
            or abs(angle_diff(a.theta, b.theta)) > p.distinct_theta)


def _proposals(obs: np.ndarray, marks: np.ndarray, p: LocateParams) -> list[Pose2]:
    """The poses that two observation-landmark pairs of matching distance propose, and
    that place the most observations within ``gate`` of a landmark (vectorised: every
    proposal is scored at once)."""
    md = np.hypot(*(marks[:, None, :] - marks[None, :, :]).transpose(2, 0, 1))
    np.fill_diagonal(md, np.inf)
    parts = []
    n = len(obs)
    for i in range(n):
        for k in range(i + 1, n):
            a, b = np.nonzero(np.abs(md - math.dist(obs[i], obs[k])) <= p.pair_tolerance)
            if a.size:
                parts.append(np.column_stack([np.full(a.size, i), np.full(a.size, k), a, b]))
    if not parts:
        return []
    i, k, a, b = np.concatenate(parts).T
    vo, vm = obs[k] - obs[i], marks[b] - marks[a]
    theta = np.arctan2(vo[:, 0] * vm[:, 1] - vo[:, 1] * vm[:, 0],
                       vo[:, 0] * vm[:, 0] + vo[:, 1] * vm[:, 1])
    c, s = np.cos(theta), np.sin(theta)
    mo, mm = (obs[i] + obs[k]) / 2, (marks[a] + marks[b]) / 2
    tx = mm[:, 0] - (c * mo[:, 0] - s * mo[:, 1])
    ty = mm[:, 1] - (s * mo[:, 0] + c * mo[:, 1])
    px = tx[:, None] + c[:, None] * obs[None, :, 0] - s[:, None] * obs[None, :, 1]
    py = ty[:, None] + s[:, None] * obs[None, :, 0] + c[:, None] * obs[None, :, 1]
    near = np.hypot(px[:, :, None] - marks[None, None, :, 0],
                    py[:, :, None] - marks[None, None, :, 1]).min(axis=2)
    score = (near <= p.gate).sum(axis=1)
    top = np.nonzero(score == score.max())[0]
    return [Pose2(float(tx[h]), float(ty[h]), float(theta[h])) for h in top]


def _hypotheses(obs: np.ndarray, marks: np.ndarray, p: LocateParams
                ) -> list[tuple[int, float, Pose2, tuple[tuple[int, int], ...]]]:
    """The best proposals with their matches refitted by least squares: (matches, rms,
    pose, pairs), one per set of matches."""
    seen: set[tuple[tuple[int, int], ...]] = set()
    out = []
    for guess in _proposals(obs, marks, p):
        pairs = _associate(obs, marks, guess, p.gate)
        key = tuple(sorted(pairs))
        if len(pairs) < 2 or key in seen:
            continue
        seen.add(key)
        try:
            pose, rms = _refit(obs, marks, pairs)
        except LandmarkError:
            continue
        out.append((len(pairs), rms, pose, key))
    return out


def locate(observations: np.ndarray, landmarks: np.ndarray, rough: Pose2 | None = None,
           params: LocateParams | None = None) -> LandmarkFix:
    """The robot's pose from reflector ``observations`` ((n, 2) in ``base_link``) and the
    map's ``landmarks`` ((m, 2) in ``map``), near ``rough`` when given.

    Raises:
        LandmarkError: fewer than ``min_matches`` reflectors seen or matched, a residual
            above ``max_rms``, or several poses fitting alike with no ``rough`` to choose.
    """
    params = params or LocateParams()
    obs = np.asarray(observations, dtype=np.float64).reshape(-1, 2)
    marks = np.asarray(landmarks, dtype=np.float64).reshape(-1, 2)
    need = max(2, params.min_matches)
    if len(marks) < need:
        raise LandmarkError(f"the map has {len(marks)} landmark(s); relocalising needs "
                            f"at least {need}")
    if len(obs) < need:
        raise LandmarkError(f"the scan shows {len(obs)} reflector(s); relocalising needs "
                            f"at least {need}")
    if len(obs) > params.max_observations:
        obs = obs[np.argsort(np.hypot(obs[:, 0], obs[:, 1]))[:params.max_observations]]
    hyps = [h for h in _hypotheses(obs, marks, params) if h[1] <= params.max_rms]
    best = max((h[0] for h in hyps), default=0)
    if best < need:
        raise LandmarkError(f"{len(obs)} reflector(s) seen, but no pose matches {need} of "
                            f"them to the map's {len(marks)} landmarks")
    top = sorted((h for h in hyps if h[0] == best), key=lambda h: h[1])
    top = [h for h in top if h[1] <= top[0][1] + params.rival_rms]
    answers: list[tuple[int, float, Pose2, tuple[tuple[int, int], ...]]] = []
    for h in top:
        if all(_distinct(h[2], a[2], params) for a in answers):
            answers.append(h)
    if len(answers) > 1:
        if rough is None:
            raise LandmarkError(f"{len(answers)} poses fit the {best} reflectors seen "
                                "equally well; give a rough pose (use_estimate) to choose")
        answers.sort(key=lambda h: math.hypot(h[2].x - rough.x, h[2].y - rough.y)
                     + abs(angle_diff(h[2].theta, rough.theta)))
    _, rms, pose, pairs = answers[0]
    return LandmarkFix(pose, pairs, rms)

