"""tf2's tree walks, ported step for step: ``walkToTopParent`` and ``getLatestCommonTime``.

This is the reference path: it handles every case (re-parenting inside the window, empty
caches, loops, extrapolation errors with tf2's messages). `Chain` is the fast path for the
common case, and falls back here whenever it cannot answer.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

from ..errors import (
    ConnectivityException,
    ExtrapolationException,
    LookupException,
)
from .cache import Cache
from .rigid import IDENTITY, Tf, compose, inverse

__all__ = ["connectivity_error", "latest_common_time", "loop_error", "walk"]

_MAX = 1 << 62


def connectivity_error(target: str, source: str) -> ConnectivityException:
    """tf2's message for two frames in different trees (the missing space is tf2's)."""
    return ConnectivityException(
        f"Could not find a connection between '{target}' and '{source}' because they are "
        "not part of the same tree.Tf has two or more unconnected trees."
    )


def loop_error(describe: Callable[[], str]) -> LookupException:
    """tf2's loop message, followed by the frame dump."""
    return LookupException(
        "The tf tree is invalid because it contains a loop.\n" + describe()
    )


def _suffix(e: ExtrapolationException, source: str, target: str) -> ExtrapolationException:
    msg = f"{e}, when looking up transform from frame [{source}] to frame [{target}]"
    return type(e)(msg)


def latest_common_time(
    caches: Mapping[str, Cache], target: str, source: str, limit: int,
    describe: Callable[[], str],
) -> int:
    """The newest time at which every dynamic link between the two frames has data.

    Static links are ignored; 0 if the path is all static. The common ancestor's own link
    to its parent does not count.

    Raises:
        ConnectivityException: no common ancestor.
        LookupException: a loop was met.
    """
    if source == target:
        cache = caches.get(source)
        return cache.newest() if cache is not None else 0
    lct: list[tuple[int, str]] = []
    frame, common, depth = source, _MAX, 0
    while True:
        cache = caches.get(frame)
        latest = cache.latest() if cache is not None else None
        if latest is None:
            break
        if latest[0] != 0:
            common = min(common, latest[0])
        lct.append(latest)
        frame = latest[1]
        if frame == target:
            return 0 if common == _MAX else common
        depth += 1
        if depth > limit:
            raise loop_error(describe)
    parents = {p for _, p in lct}
    frame, common, depth = target, _MAX, 0
    common_parent: str | None = None
    while True:
        cache = caches.get(frame)
        latest = cache.latest() if cache is not None else None
        if latest is None:
            break
        if latest[0] != 0:
            common = min(common, latest[0])
        if latest[1] in parents:
            common_parent = latest[1]
            break
        frame = latest[1]
        if frame == source:
            return 0 if common == _MAX else common
        depth += 1
        if depth > limit:
            raise loop_error(describe)
    if common_parent is None:
        raise connectivity_error(target, source)
    for stamp, parent in lct:
        if stamp != 0:
            common = min(common, stamp)
        if parent == common_parent:
            break
    return 0 if common == _MAX else common


def walk(
    caches: Mapping[str, Cache], target: str, source: str, t: int, limit: int,
    describe: Callable[[], str],
) -> Tf:
    """``T_target_source`` at ``t`` (nanoseconds, not 0), walking as tf2 does.

    Raises:
        ExtrapolationException: a link has no data at ``t`` (the subclass says which way).
        ConnectivityException: the frames are not connected at ``t``.
        LookupException: a loop was met.
    """
    frame, top, acc = source, source, IDENTITY
    error: ExtrapolationException | None = None
    depth = 0
    while True:
        cache = caches.get(frame)
        if cache is None:
            top = frame
            break
        try:
            val, parent = cache.get(t)
        except ExtrapolationException as e:
            error, top = e, frame
            break
        if frame == target:  # target is an ancestor of source
            return acc
        acc = compose(val, acc)
        top, frame = frame, parent
        depth += 1
        if depth > limit:
            raise loop_error(describe)
    frame, tacc, depth = target, IDENTITY, 0
    while frame != top:
        cache = caches.get(frame)
        if cache is None:
            break
        try:
            val, parent = cache.get(t)
        except ExtrapolationException as e:
            raise _suffix(e, source, target) from None
        if frame == source:  # source is an ancestor of target
            return inverse(tacc)
        tacc = compose(val, tacc)
        frame = parent
        depth += 1
        if depth > limit:
            raise loop_error(describe)
    if frame != top:
        if error is not None:
            raise _suffix(error, source, target)
        raise connectivity_error(target, source)
    return compose(inverse(tacc), acc)
