"""`Buffer`: tf2_ros's Python API: lookups, time travel, waiting, transforming messages.

Waiting is event-driven (see `Waiters`): a blocked ``lookup_transform(..., timeout=...)``
sleeps on a condition that every accepted insert notifies, and ``wait_for_transform``
futures are resolved from ``set_transform`` (any thread). Do not block with a timeout on
the thread that feeds the buffer: nothing would wake you.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Literal, TypeVar, overload

from ..errors import LookupException, TimeoutException
from ..msgs.builtin_interfaces import Duration, Time
from ..msgs.geometry_msgs import Quaternion, Transform, TransformStamped, Vector3
from ..msgs.std_msgs import Header
from .chain import Chain
from .convert import transform_stamped
from .core import DEFAULT_CACHE_TIME, BufferCore
from .report import frame_error
from .rigid import compose
from .stamped import do_transform, header_of
from .stamps import NS, TimeLike, format_ns, from_ns, seconds, to_ns
from .waiting import Waiters

M = TypeVar("M")
Timeout = float | Duration

__all__ = ["Buffer"]


class Buffer(BufferCore):
    """The TF buffer: stores links over time and answers frame queries (tf2_ros.Buffer).

    Times are `Time` messages or integer nanoseconds; 0 (``LATEST``) means the latest
    common time of the frames involved. Timeouts are float seconds or a `Duration`.

    Args:
        cache_time: seconds of history kept per dynamic link (default 10).
    """

    def __init__(self, cache_time: float | Duration = DEFAULT_CACHE_TIME) -> None:
        super().__init__(cache_time)
        self._waiters = Waiters(self._lock, self._set_watchers)

    # ------------------------------------------------------------------ lookups

    def lookup_transform(
        self, target_frame: str, source_frame: str, time: TimeLike, timeout: Timeout = 0.0
    ) -> TransformStamped:
        """``T_target_source``: the pose of ``source_frame`` expressed in ``target_frame``.

        Args:
            target_frame: the frame the result maps into (``header.frame_id``).
            source_frame: the frame it maps from (``child_frame_id``).
            time: when; 0 means the latest time all links on the path share.
            timeout: wait up to this long for the data to arrive.

        Returns:
            The transform, stamped with ``time`` (or the latest common time).

        Raises:
            LookupException: an unknown frame, or a loop in the tree.
            ConnectivityException: the frames are in different trees.
            ExtrapolationException: no data at ``time`` (Backward/Forward/NoData subclasses).
            InvalidArgumentException: an empty or '/'-prefixed frame id.
        """
        t = time.sec * NS + time.nanosec if time.__class__ is Time else to_ns(time)
        if timeout:
            self._block(lambda: self._can(target_frame, source_frame, t), timeout)
        lock = self._lock
        lock.acquire()  # not `with`: acquire/release is ~90 ns cheaper per call on 3.11
        try:
            ch = self._chains.get((target_frame, source_frame))
            r = ch.evaluate(t) if type(ch) is Chain and t else None
            tt = t
            if r is None:
                r, tt = self._lookup(target_frame, source_frame, t)
        finally:
            lock.release()
        return TransformStamped(  # _msg, inlined: this is the hot path
            header=Header(
                stamp=time if tt == t and time.__class__ is Time else from_ns(tt),
                frame_id=target_frame,
            ),
            child_frame_id=source_frame,
            transform=Transform(
                translation=Vector3(x=r[0], y=r[1], z=r[2]),
                rotation=Quaternion(x=r[3], y=r[4], z=r[5], w=r[6]),
            ),
        )

    def lookup_transform_full(
        self, target_frame: str, target_time: TimeLike, source_frame: str,
        source_time: TimeLike, fixed_frame: str, timeout: Timeout = 0.0,
    ) -> TransformStamped:
        """Time travel: ``source_frame`` at ``source_time`` seen from ``target_frame`` at
        ``target_time``, through ``fixed_frame`` (a frame that does not move, e.g. odom).

        Computed as ``T(target ← fixed @ target_time) · T(fixed ← source @ source_time)``,
        stamped with the target-side time.

        Raises:
            TransformException: as `lookup_transform`, for either leg.
        """
        tt, ts = to_ns(target_time), to_ns(source_time)
        if timeout:
            self._block(lambda: self._can_full(target_frame, tt, source_frame, ts, fixed_frame),
                        timeout)  # fmt: skip
        with self._lock:
            fn = "lookupTransform argument "
            for frame, arg in ((target_frame, "target_frame"), (source_frame, "source_frame"),
                               (fixed_frame, "fixed_frame")):  # fmt: skip
                self._check(frame, fn + arg)
            a, _ = self._lookup(fixed_frame, source_frame, ts)
            b, stamp = self._lookup(target_frame, fixed_frame, tt)
        return transform_stamped(target_frame, source_frame, compose(b, a), from_ns(stamp))

    @overload
    def can_transform(
        self, target_frame: str, source_frame: str, time: TimeLike, timeout: Timeout = ...,
        return_debug_tuple: Literal[False] = ...,
    ) -> bool: ...

    @overload
    def can_transform(
        self, target_frame: str, source_frame: str, time: TimeLike, timeout: Timeout = ...,
        *, return_debug_tuple: Literal[True],
    ) -> tuple[bool, str]: ...

    def can_transform(
        self, target_frame: str, source_frame: str, time: TimeLike, timeout: Timeout = 0.0,
        return_debug_tuple: bool = False,
    ) -> bool | tuple[bool, str]:
        """Whether `lookup_transform` would succeed; never raises for bad frames.

        Args:
            timeout: wait up to this long for it to become true.
            return_debug_tuple: also return tf2's explanation ("" when true).
        """
        t = time.sec * NS + time.nanosec if time.__class__ is Time else to_ns(time)
        if timeout:
            self._block(lambda: self._can(target_frame, source_frame, t), timeout)
        lock = self._lock
        lock.acquire()
        try:
            ok = self._can(target_frame, source_frame, t)
            if not return_debug_tuple:
                return ok
            return ok, ("" if ok else self._can_explain(target_frame, source_frame, t))
        finally:
            lock.release()

    @overload
    def can_transform_full(
        self, target_frame: str, target_time: TimeLike, source_frame: str,
        source_time: TimeLike, fixed_frame: str, timeout: Timeout = ...,
        return_debug_tuple: Literal[False] = ...,
    ) -> bool: ...

    @overload
    def can_transform_full(
        self, target_frame: str, target_time: TimeLike, source_frame: str,
        source_time: TimeLike, fixed_frame: str, timeout: Timeout = ...,
        *, return_debug_tuple: Literal[True],
    ) -> tuple[bool, str]: ...

    def can_transform_full(
        self, target_frame: str, target_time: TimeLike, source_frame: str,
        source_time: TimeLike, fixed_frame: str, timeout: Timeout = 0.0,
        return_debug_tuple: bool = False,
    ) -> bool | tuple[bool, str]:
        """Whether `lookup_transform_full` would succeed (both legs); never raises."""
        tt, ts = to_ns(target_time), to_ns(source_time)
        if timeout:
            self._block(lambda: self._can_full(target_frame, tt, source_frame, ts, fixed_frame),
                        timeout)  # fmt: skip
        with self._lock:
            ok = self._can_full(target_frame, tt, source_frame, ts, fixed_frame)
            if not return_debug_tuple:
                return ok
            if ok:
                return True, ""
            for frame, arg in ((target_frame, "target_frame"), (source_frame, "source_frame"),
                               (fixed_frame, "fixed_frame")):  # fmt: skip
                why = self._frame_problem(frame, "canTransform argument " + arg)
                if why:
                    return False, why
            why = self._can_explain(target_frame, fixed_frame, tt) or self._can_explain(
                fixed_frame, source_frame, ts
            )
            return False, why

    def _can_full(self, target: str, tt: int, source: str, ts: int, fixed: str) -> bool:
        for frame in (target, source, fixed):
            if frame_error(frame, "") or frame not in self._frames:
                return False
        return self._can(target, fixed, tt) and self._can(fixed, source, ts)

    # ------------------------------------------------------------------ transforming data

    def transform(self, obj: M, target_frame: str, timeout: Timeout = 0.0) -> M:
        """``obj`` (PointStamped, PoseStamped, Vector3Stamped, QuaternionStamped,
        PoseWithCovarianceStamped...) expressed in ``target_frame`` at its own stamp.

        Raises:
            TransformException: the lookup failed; InvalidArgumentException for other types.
        """
        h = header_of(obj)
        return do_transform(obj, self.lookup_transform(target_frame, h.frame_id, h.stamp, timeout))

    def transform_full(
        self, obj: M, target_frame: str, target_time: TimeLike, fixed_frame: str,
        timeout: Timeout = 0.0,
    ) -> M:
        """``obj`` seen from ``target_frame`` at ``target_time``, through ``fixed_frame``."""
        h = header_of(obj)
        t = self.lookup_transform_full(
            target_frame, target_time, h.frame_id, h.stamp, fixed_frame, timeout
        )
        return do_transform(obj, t)

    # ------------------------------------------------------------------ waiting

    def _block(self, ready: Callable[[], bool], timeout: Timeout) -> bool:
        return self._waiters.block(ready, seconds(timeout))

    def _wake(self) -> None:
        self._waiters.wake(self._can)

    def wait_for_transform_async(
        self, target_frame: str, source_frame: str, time: TimeLike
    ) -> asyncio.Future[bool]:
        """A future (of the running loop) that becomes True once `can_transform` holds.

        It fails at once with LookupException if ``time`` is already older than the
        window, so the data can never arrive (tf2's rule). Cancel it to stop waiting.
        """
        loop = asyncio.get_running_loop()
        fut: asyncio.Future[bool] = loop.create_future()
        t = to_ns(time)
        with self._lock:
            if self._can(target_frame, source_frame, t):
                fut.set_result(True)
                return fut
            if t and t + self._cache_ns < self._latest_or_zero(target_frame, source_frame):
                fut.set_exception(LookupException(
                    f"Failed to transform from {source_frame} to {target_frame}: time "
                    f"{format_ns(t)} is older than the {self.cache_time:g} s the buffer keeps"
                ))  # fmt: skip
                return fut
            self._waiters.add(target_frame, source_frame, t, fut)
        return fut

    async def wait_for_transform(
        self, target_frame: str, source_frame: str, time: TimeLike,
        timeout: Timeout | None = None,
    ) -> None:
        """Wait until `can_transform` holds.

        Raises:
            TimeoutException: ``timeout`` passed first.
            LookupException: ``time`` is older than the buffer window.
        """
        fut = self.wait_for_transform_async(target_frame, source_frame, time)
        if timeout is None:
            await fut
            return
        limit = seconds(timeout)
        try:
            await asyncio.wait_for(fut, limit)
        except TimeoutError:
            raise TimeoutException(
                f"Timed out waiting for transform from {source_frame} to {target_frame} at "
                f"time {format_ns(to_ns(time))} after {limit:g} s"
            ) from None

    async def lookup_transform_async(
        self, target_frame: str, source_frame: str, time: TimeLike,
        timeout: Timeout | None = None,
    ) -> TransformStamped:
        """Wait for the transform (see `wait_for_transform`), then look it up."""
        await self.wait_for_transform(target_frame, source_frame, time, timeout)
        return self.lookup_transform(target_frame, source_frame, time)
