"""`TfServer`: the buffer server's logic: feeds a `Buffer` and a `FrameMonitor` from TF
messages and answers lookup, can_transform and frames requests. No Zenoh here."""

from __future__ import annotations

import asyncio
import logging
import time
from collections.abc import Callable
from typing import TypeAlias

from zenros.clock import Clock
from zenros.errors import TimeoutException, TransformException
from zenros.msgs.tf2_msgs import TFMessage
from zenros.msgs.tf_srvs import (
    CanTransformRequest,
    CanTransformResponse,
    FramesRequest,
    FramesResponse,
    LookupTransformRequest,
    LookupTransformResponse,
)
from zenros.tf import Buffer, ClockJumpGuard, error_msg

from .monitor import FrameMonitor

__all__ = ["TfServer"]

NS = 1_000_000_000
Request: TypeAlias = LookupTransformRequest | CanTransformRequest


class TfServer:
    """Stores what arrives on ``/tf`` and ``/tf_static`` and answers thin clients.

    A lookup that fails comes back with ``error`` set (tf2's code and message), never as
    an exception. A request with a timeout waits (event-driven) up to that long for the
    data, then answers as a plain lookup would: with the underlying error, as tf2 does.

    Args:
        buffer: where links are stored.
        monitor: where per-frame statistics are kept.
        clock: the node's clock (sim time aware): stamps delays, detects backward jumps.
        logger: for clock-jump warnings.
        monotonic: seconds for rates (``time.monotonic``; tests pass their own).
        resolve: maps a recorded authority to the one to report (the tap's ``session
            <zid>`` placeholders to node names, once the graph knows them).
    """

    def __init__(self, buffer: Buffer, monitor: FrameMonitor, clock: Clock,
                 logger: logging.Logger, *,
                 monotonic: Callable[[], float] = time.monotonic,
                 resolve: Callable[[str], str] = str) -> None:
        self.buffer = buffer
        self.monitor = monitor
        self.resolve = resolve
        self._clock = clock
        self._monotonic = monotonic
        self.guard = ClockJumpGuard(buffer, clock, logger)
        # a real clock's nanoseconds, read straight (no Time made for every message)
        self._clock_ns: Callable[[], int] | None = getattr(clock, "ns", None)

    def on_message(self, msg: TFMessage, is_static: bool, authority: str) -> None:
        """Store every link of one message; count the accepted ones."""
        guard = self.guard
        if not is_static and guard.active:
            guard.check()
        if self._clock_ns is not None:
            now_ns = self._clock_ns()
        else:
            now = self._clock.now()
            now_ns = now.sec * NS + now.nanosec
        arrival = self._monotonic()
        insert = self.buffer.set_transform_static if is_static else self.buffer.set_transform
        record = self.monitor.record
        for t in msg.transforms:
            if insert(t, authority):
                h = t.header
                record(t.child_frame_id.removeprefix("/"), h.frame_id.removeprefix("/"),
                       authority, h.stamp.sec * NS + h.stamp.nanosec, static=is_static,
                       now_ns=now_ns, arrival=arrival)  # fmt: skip

    async def lookup_transform(self, req: LookupTransformRequest) -> LookupTransformResponse:
        """The transform asked for, or the tf2 error."""
        b = self.buffer
        try:
            await self._wait(req)
            if req.advanced:
                t = b.lookup_transform_full(req.target_frame, req.target_time, req.source_frame,
                                            req.source_time, req.fixed_frame)
            else:
                t = b.lookup_transform(req.target_frame, req.source_frame, req.source_time)
        except TransformException as exc:
            return LookupTransformResponse(error=error_msg(exc))
        return LookupTransformResponse(transform=t)

    async def can_transform(self, req: CanTransformRequest) -> CanTransformResponse:
        """Whether the lookup would succeed, and tf2's explanation if not."""
        b = self.buffer
        try:
            await self._wait(req)
        except TransformException as exc:
            return CanTransformResponse(can_transform=False, error_string=str(exc))
        if req.advanced:
            ok, why = b.can_transform_full(req.target_frame, req.target_time, req.source_frame,
                                           req.source_time, req.fixed_frame,
                                           return_debug_tuple=True)
        else:
            ok, why = b.can_transform(req.target_frame, req.source_frame, req.source_time,
                                      return_debug_tuple=True)
        return CanTransformResponse(can_transform=ok, error_string=why)

    def frames(self, req: FramesRequest | None = None) -> FramesResponse:
        """Every child frame with its statistics, and tf2's YAML dump."""
        now = self._clock.now()
        frames = self.monitor.frames(self._monotonic())
        for f in frames:
            f.authority = self.resolve(f.authority)
        return FramesResponse(frames=frames, stamp=now, yaml=self.buffer.all_frames_as_yaml(now))

    async def _wait(self, req: Request) -> None:
        """Wait up to the request's timeout for every leg to become available.

        Raises:
            LookupException: a time older than the buffer keeps (it can never arrive).
        """
        timeout = req.timeout.nanoseconds / NS
        if not timeout > 0:
            return
        if req.advanced:
            legs = [(req.target_frame, req.fixed_frame, req.target_time),
                    (req.fixed_frame, req.source_frame, req.source_time)]
        else:
            legs = [(req.target_frame, req.source_frame, req.source_time)]
        loop = asyncio.get_running_loop()
        deadline = loop.time() + timeout
        for target, source, t in legs:
            if target == source:
                continue
            if _invalid(target) or _invalid(source):
                return  # can never become valid: the lookup reports it at once
            try:
                await self.buffer.wait_for_transform(
                    target, source, t, max(0.0, deadline - loop.time())
                )
            except TimeoutException:
                return  # the lookup that follows reports the underlying error


def _invalid(frame: str) -> bool:
    return not frame or frame[0] == "/"

