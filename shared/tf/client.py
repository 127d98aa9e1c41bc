"""`BufferClient`: lookups answered by the tf service instead of a local buffer (tf2_ros's
BufferClient), for thin clients that should not listen to ``/tf`` themselves."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..msgs.builtin_interfaces import Duration, Time
from ..msgs.geometry_msgs import TransformStamped
from ..msgs.tf_srvs import (
    CanTransform,
    CanTransformRequest,
    LookupTransform,
    LookupTransformRequest,
    LookupTransformResponse,
)
from .codes import exception_from_error
from .stamps import TimeLike, from_ns, seconds, to_ns

if TYPE_CHECKING:
    from ..node import Node
    from ..rpc import Client

__all__ = ["DEFAULT_SERVER", "BufferClient"]

DEFAULT_SERVER = "/tf"
"""The tf service's node name; its services are ``<server>/lookup_transform`` etc."""


def _time(t: TimeLike) -> Time:
    return t if isinstance(t, Time) else from_ns(to_ns(t))


class BufferClient:
    """Asks the tf service (``server``) for transforms; raises tf2's exceptions.

    Args:
        node: the node whose session makes the calls.
        server: the tf service node's name (default ``/tf``).
        timeout_padding: seconds added to each lookup's timeout for the round trip.
    """

    def __init__(self, node: Node, server: str = DEFAULT_SERVER,
                 timeout_padding: float = 2.0) -> None:
        base = server.rstrip("/") or ""
        self._lookup: Client = node.create_client(LookupTransform, f"{base}/lookup_transform")
        self._can: Client = node.create_client(CanTransform, f"{base}/can_transform")
        self._padding = timeout_padding

    def wait_for_server(self, timeout: float | None = None) -> bool:
        """Block until the tf service is up; False on timeout."""
        return self._lookup.wait_for_service(timeout)

    def lookup_transform(self, target_frame: str, source_frame: str, time: TimeLike,
                         timeout: float | Duration = 0.0) -> TransformStamped:
        """As `Buffer.lookup_transform`, answered by the server.

        Raises:
            TransformException: the server's tf2 error (Lookup, Connectivity, ...).
            ServiceError, ServiceUnavailableError, ZenrosTimeout: the call itself failed.
        """
        req = LookupTransformRequest(target_frame=target_frame, source_frame=source_frame,
                                     source_time=_time(time), timeout=_duration(timeout))
        return self._result(self._lookup.call(req, seconds(timeout) + self._padding))

    def lookup_transform_full(
        self, target_frame: str, target_time: TimeLike, source_frame: str,
        source_time: TimeLike, fixed_frame: str, timeout: float | Duration = 0.0,
    ) -> TransformStamped:
        """As `Buffer.lookup_transform_full` (time travel), answered by the server."""
        req = LookupTransformRequest(
            target_frame=target_frame, source_frame=source_frame,
            source_time=_time(source_time), timeout=_duration(timeout),
            target_time=_time(target_time), fixed_frame=fixed_frame, advanced=True,
        )
        return self._result(self._lookup.call(req, seconds(timeout) + self._padding))

    async def lookup_transform_async(
        self, target_frame: str, source_frame: str, time: TimeLike,
        timeout: float | Duration = 0.0,
    ) -> TransformStamped:
        """Awaitable `lookup_transform`."""
        req = LookupTransformRequest(target_frame=target_frame, source_frame=source_frame,
                                     source_time=_time(time), timeout=_duration(timeout))
        res = await self._lookup.call_async(req, seconds(timeout) + self._padding)
        return self._result(res)

    def can_transform(self, target_frame: str, source_frame: str, time: TimeLike,
                      timeout: float | Duration = 0.0) -> bool:
        """Whether the server can relate the frames (waiting up to ``timeout``)."""
        req = CanTransformRequest(target_frame=target_frame, source_frame=source_frame,
                                  source_time=_time(time), timeout=_duration(timeout))
        return bool(self._can.call(req, seconds(timeout) + self._padding).can_transform)

    @staticmethod
    def _result(res: LookupTransformResponse) -> TransformStamped:
        exc = exception_from_error(res.error)
        if exc is not None:
            raise exc
        return res.transform


def _duration(timeout: float | Duration) -> Duration:
    return timeout if isinstance(timeout, Duration) else Duration.from_seconds(seconds(timeout))
