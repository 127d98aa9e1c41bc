"""`FrameStore`: the frame tree's storage, with tf2's insert rules, and what it can report.

Thread safe: one lock guards all state. Queries are added by `BufferCore`, waiting by
`Buffer`.
"""

from __future__ import annotations

import logging
import threading
from math import sqrt
from types import MethodType

from ..errors import InvalidArgumentException
from ..msgs.builtin_interfaces import Duration, Time
from ..msgs.geometry_msgs import TransformStamped
from .accel import speedups
from .cache import REJECTED, RESHAPED, Cache, StaticCache, TimeCache
from .chain import Chain, NoChain
from .report import frame_error, frames_as_string, frames_as_yaml, insert_problems, unknown_frame
from .rigid import Tf
from .stamps import NS, TimeLike, format_ns, from_ns, seconds, to_ns
from .walk import latest_common_time

log = logging.getLogger("zenros.tf")

DEFAULT_CACHE_TIME = 10.0
"""Seconds of history kept per dynamic link (tf2's ``BUFFER_CORE_DEFAULT_CACHE_TIME``)."""

__all__ = ["DEFAULT_CACHE_TIME", "FrameStore"]


class FrameStore:
    """Stores links (dynamic and static) per child frame, refusing what tf2 refuses.

    Args:
        cache_time: seconds of history kept for each dynamic link.
    """

    def __init__(self, cache_time: float | Duration = DEFAULT_CACHE_TIME) -> None:
        self.cache_time = seconds(cache_time)
        self._cache_ns = round(self.cache_time * NS)
        self._lock = threading.Lock()
        self._caches: dict[str, Cache] = {}
        self._frames: dict[str, None] = {}  # every known id, in order of appearance
        self._authority: dict[str, str] = {}
        self._chains: dict[tuple[str, str], Chain | NoChain] = {}
        self._watchers = 0  # blocked threads + pending async waits; set_transform wakes them
        self._inserter = None
        if speedups is not None and type(self).set_transform is FrameStore.set_transform:
            # The compiled hot path shadows the method below and hands it every other case
            # (not where a subclass overrides set_transform: its override is what runs).
            self._inserter = speedups.Inserter(
                self._caches, self._authority, self._lock, self._cache_ns,
                MethodType(FrameStore.set_transform, self),
            )  # fmt: skip
            self.__dict__["set_transform"] = self._inserter

    def _set_watchers(self, n: int) -> None:
        """How many threads or futures wait on inserts (they take the Python path then)."""
        self._watchers = n
        if self._inserter is not None:
            self._inserter.watchers = n

    # ------------------------------------------------------------------ inserting

    def set_transform(
        self, transform: TransformStamped, authority: str = "default_authority",
        *, strict: bool = False,
    ) -> bool:
        """Add one dynamic link sample ``header.frame_id → child_frame_id``.

        Applies tf2's checks: one leading '/' is stripped from both ids; a self link, an
        empty id, NaN/infinite values or a quaternion whose squared norm is off by 0.01 or
        more are refused, as is data older than the cache window (``TF_OLD_DATA``) and a
        link that would close a loop in the tree. Accepted quaternions are normalised.

        Args:
            transform: the link ``T_parent_child`` with its stamp.
            authority: who sent it (shown by `all_frames_as_yaml`).
            strict: raise instead of logging a warning and returning False.

        Returns:
            True if stored; False if refused (the reason is logged at WARNING).

        Raises:
            InvalidArgumentException: refused, and ``strict`` is set.
        """
        h = transform.header
        parent, child = h.frame_id, transform.child_frame_id
        if parent[:1] == "/":
            parent = parent[1:]
        if child[:1] == "/":
            child = child[1:]
        tr = transform.transform
        v, q = tr.translation, tr.rotation
        x, y, z, qx, qy, qz, qw = v.x, v.y, v.z, q.x, q.y, q.z, q.w
        n = qx * qx + qy * qy + qz * qz + qw * qw
        if (
            parent == child or not parent or not child
            or 0.0 * (x + y + z) != 0.0 or not -0.01 < n - 1.0 < 0.01
        ):  # fmt: skip
            val = (x, y, z, qx, qy, qz, qw)
            return self._refuse(insert_problems(parent, child, authority, val), strict)
        if not -1e-12 < n - 1.0 < 1e-12:
            s = 1.0 / sqrt(n)
            qx, qy, qz, qw = qx * s, qy * s, qz * s, qw * s
        st = h.stamp
        stamp = st.sec * 1_000_000_000 + st.nanosec
        val = (x, y, z, qx, qy, qz, qw)
        lock = self._lock
        lock.acquire()  # not `with`: acquire/release is ~90 ns cheaper per call on 3.11
        try:
            cache = self._caches.get(child)
            # Hot path, TimeCache.insert inlined: a newer sample for a link whose samples
            # all have this parent (so it is not empty and stays single-parent).
            if cache.__class__ is TimeCache and cache.parent == parent:
                stamps = cache.stamps
                if stamp > stamps[-1]:
                    stamps.append(stamp)
                    cache.vals.append(val)
                    cache.segs.append(None)
                    cache.parents.append(parent)
                    if stamps[cache.lo] < stamp - self._cache_ns:
                        cache.prune()
                    self._authority[child] = authority
                    if self._watchers:
                        self._wake()
                    return True
            return self._store(child, parent, stamp, val, authority, False, strict)
        finally:
            lock.release()

    def set_transform_static(
        self, transform: TransformStamped, authority: str = "default_authority",
        *, strict: bool = False,
    ) -> bool:
        """Add or replace a static link (valid at every time); same checks as `set_transform`."""
        h = transform.header
        parent, child = h.frame_id, transform.child_frame_id
        parent = parent[1:] if parent[:1] == "/" else parent
        child = child[1:] if child[:1] == "/" else child
        tr = transform.transform
        v, q = tr.translation, tr.rotation
        val = (v.x, v.y, v.z, q.x, q.y, q.z, q.w)
        problems = insert_problems(parent, child, authority, val)
        if problems:
            return self._refuse(problems, strict)
        n = sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w)
        val = (v.x, v.y, v.z, q.x / n, q.y / n, q.z / n, q.w / n)
        stamp = h.stamp.sec * NS + h.stamp.nanosec
        with self._lock:
            return self._store(child, parent, stamp, val, authority, True, strict)

    def _refuse(self, problems: list[str], strict: bool) -> bool:
        if strict:
            raise InvalidArgumentException("; ".join(problems))
        for p in problems:
            log.warning("%s", p)
        return False

    def _store(
        self, child: str, parent: str, stamp: int, val: Tf, authority: str,
        is_static: bool, strict: bool,
    ) -> bool:
        """The general insert (lock held): new links, re-parenting, statics, refusals."""
        cache = self._caches.get(child)
        if (
            (cache is None or cache.parent != parent)
            and child in self._frames  # a new frame is nobody's ancestor yet
            and self._closes_loop(child, parent, stamp)
        ):
            return self._refuse([(
                f'TF_LOOP: Ignoring transform {parent} -> {child} from authority "{authority}" '
                f"at time {format_ns(stamp)} because {parent} is already a descendant of "
                f"{child}; the tree would contain a loop"
            )], strict)  # fmt: skip
        self._frames[child] = None
        self._frames[parent] = None
        if cache is None or cache.is_static != is_static:  # ROS 2: a type change replaces
            cache = StaticCache(parent, val) if is_static else TimeCache(self._cache_ns)
            self._caches[child] = cache
            self._chains.clear()
        return self._stored(cache, cache.insert(stamp, parent, val), child, stamp, authority, strict)

    def _stored(
        self, cache: Cache, code: int, child: str, stamp: int, authority: str, strict: bool
    ) -> bool:
        """Finish an insert (lock held): refuse old data, drop stale chains, wake waiters."""
        if code == REJECTED:
            return self._refuse([(
                f"TF_OLD_DATA ignoring data from the past for frame {child} at time "
                f"{format_ns(stamp)} according to authority {authority}: the newest is at "
                f"{format_ns(cache.newest())} and the buffer keeps {self.cache_time:g} s"
            )], strict)  # fmt: skip
        if code == RESHAPED:
            self._chains.clear()
        self._authority[child] = authority
        if self._watchers:
            self._wake()
        return True

    def _closes_loop(self, child: str, parent: str, stamp: int) -> bool:
        """Whether ``child`` is an ancestor of ``parent`` at ``stamp`` (lock held)."""
        frame: str | None = parent
        for _ in range(len(self._frames) + 1):
            if frame == child:
                return True
            cache = self._caches.get(frame) if frame is not None else None
            if cache is None:
                return False
            frame = cache.parent_at(stamp)
        return False  # an older loop that does not go through child; walks report it

    def _wake(self) -> None:
        """Called (lock held) after each accepted insert while someone waits."""

    def _check(self, frame: str, arg: str) -> None:
        err = frame_error(frame, arg)
        if err is not None:
            raise err
        if frame not in self._frames:
            raise unknown_frame(frame, arg, self._frames)

    def _dump(self) -> str:
        return frames_as_string(self._caches)

    # ------------------------------------------------------------------ introspection

    def get_latest_common_time(self, target_frame: str, source_frame: str) -> Time:
        """The newest time at which the two frames can be related (0 if all links are static).

        Raises:
            LookupException, InvalidArgumentException: a bad or unknown frame.
            ConnectivityException: the frames are in different trees.
        """
        with self._lock:
            if target_frame != source_frame:
                self._check(target_frame, "getLatestCommonTime argument target_frame")
                self._check(source_frame, "getLatestCommonTime argument source_frame")
            return from_ns(latest_common_time(
                self._caches, target_frame, source_frame, len(self._frames), self._dump
            ))  # fmt: skip

    def frame_exists(self, frame_id: str) -> bool:
        """Whether ``frame_id`` was ever named in an accepted link (as child or parent)."""
        with self._lock:
            return frame_id in self._frames

    _frameExists = frame_exists  # tf2_py's name

    def get_frame_names(self) -> list[str]:
        """Every known frame id, in order of first appearance."""
        with self._lock:
            return list(self._frames)

    def get_parent(self, frame_id: str, time: TimeLike = 0) -> str | None:
        """The parent of ``frame_id`` at ``time`` (nearest sample), or None for a root."""
        t = to_ns(time)
        with self._lock:
            cache = self._caches.get(frame_id)
            return cache.parent_at(t) if cache is not None else None

    def all_frames_as_string(self) -> str:
        """``Frame X exists with parent Y.`` lines, as tf2."""
        with self._lock:
            return frames_as_string(self._caches)

    def all_frames_as_yaml(self, current_time: TimeLike = 0) -> str:
        """Per frame: parent, broadcaster, rate, newest/oldest stamp and buffer length (YAML)."""
        now = to_ns(current_time)
        with self._lock:
            return frames_as_yaml(self._caches, self._authority, now)

    def clear(self) -> None:
        """Drop every dynamic sample. Static links and frame names stay, as in tf2."""
        with self._lock:
            for cache in self._caches.values():
                cache.clear()
            self._chains.clear()
