"""Service introspection, as ROS 2 has it from Jazzy (`configure_introspection`): a service
server or client publishes each request and response it handles on ``<service>/
_service_event`` as ``<pkg>/srv/<Name>_Event`` (``info``: `ServiceEventInfo`; ``request`` and
``response``: at most one each), so ``zenros service echo`` (and ``ros2 service echo`` through
a bridge) shows a service's traffic without touching it.

States (`ServiceIntrospectionState`, rclpy's names): OFF (the default: nothing published),
METADATA (the info alone), CONTENTS (the request and response too). A server cannot tell
which client asked (a Zenoh query does not say), so its events carry a zero ``client_gid`` and
its own sequence numbers; a client's carry its session's id and its own numbering.
"""

from __future__ import annotations

import itertools
from enum import IntEnum
from functools import cache
from typing import TYPE_CHECKING, Any

import msgspec

from .message import Message, ServiceType
from .msgs.builtin_interfaces import Time
from .msgs.service_msgs import ServiceEventInfo
from .qos import QoSProfile

if TYPE_CHECKING:
    from .context import Context
    from .pubsub import Publisher

__all__ = ["EVENT_SUFFIX", "ServiceEvents", "ServiceIntrospectionState", "event_type_of"]

EVENT_SUFFIX = "/_service_event"
QOS_SERVICE_EVENTS = QoSProfile(depth=10)


class ServiceIntrospectionState(IntEnum):
    OFF = 0
    METADATA = 1
    CONTENTS = 2


@cache
def event_type_of(srv: ServiceType[Any, Any]) -> type[Message]:
    """The ``<pkg>/srv/<Name>_Event`` message of a service type (made once, registered as
    ``<pkg>/<Name>_Event``)."""
    short = srv.name.rpartition("/")[2]
    cls: type[Message] = msgspec.defstruct(
        f"{short}_Event",
        [("info", ServiceEventInfo, msgspec.field(default_factory=ServiceEventInfo)),
         ("request", list[srv.Request], msgspec.field(default_factory=list)),  # type: ignore[name-defined]
         ("response", list[srv.Response], msgspec.field(default_factory=list))],  # type: ignore[name-defined]
        bases=(Message,), kw_only=True, namespace={"__msgtype__": f"{srv.name}_Event"},
        module=__name__)
    return cls


def _gid(zid: str) -> list[int]:
    raw = bytes.fromhex(zid.rjust(32, "0")[-32:]) if zid else b""
    return list(raw.rjust(16, b"\0")[:16])


class ServiceEvents:
    """The events of one server or client: `configure` turns them on or off; ``request`` and
    ``response`` publish one each (nothing while OFF)."""

    def __init__(self, ctx: Context, node: str, srv: ServiceType[Any, Any], name: str,
                 client: bool) -> None:
        self._ctx, self._node, self._srv, self._name = ctx, node, srv, name
        self._client = client
        self._gid = _gid(ctx.zid) if client else [0] * 16
        self._seq = itertools.count(1)
        self._pub: Publisher[Any] | None = None
        self._clock: Any = None
        self.state = ServiceIntrospectionState.OFF

    def configure(self, clock: Any, qos: QoSProfile | None,
                  state: ServiceIntrospectionState) -> None:
        """rclpy's ``configure_introspection(clock, qos, state)``: events stamped by
        ``clock`` (anything with ``now()``), published with ``qos``."""
        from .pubsub import Publisher

        state = ServiceIntrospectionState(state)
        if self._pub is not None:
            self._pub.close()
            self._pub = None
        self.state, self._clock = state, clock
        if state is not ServiceIntrospectionState.OFF:
            self._pub = Publisher(self._ctx, self._node, event_type_of(self._srv),
                                  self._name + EVENT_SUFFIX, qos or QOS_SERVICE_EVENTS)

    def wait_for_subscribers(self, n: int = 1, timeout: float | None = None) -> bool:
        """Block until ``n`` subscriptions to the events are matched (False while OFF or on
        timeout): events published before are not received by them."""
        pub = self._pub
        return pub is not None and pub.wait_for_subscribers(n, timeout)

    def next_sequence(self) -> int:
        return next(self._seq)

    def _publish(self, kind: int, seq: int, request: Any = None, response: Any = None) -> None:
        pub = self._pub
        if pub is None:
            return
        stamp = self._clock.now() if self._clock is not None else Time()
        info = ServiceEventInfo(event_type=kind, stamp=stamp, client_gid=self._gid,
                                sequence_number=seq)
        contents = self.state is ServiceIntrospectionState.CONTENTS
        event = event_type_of(self._srv)(
            info=info, request=[request] if contents and request is not None else [],
            response=[response] if contents and response is not None else [])
        try:
            pub.publish(event)
        except Exception:  # noqa: BLE001, S110 - introspection never fails a call
            pass

    def request(self, seq: int, request: Any) -> None:
        self._publish(ServiceEventInfo.REQUEST_SENT if self._client
                      else ServiceEventInfo.REQUEST_RECEIVED, seq, request=request)

    def response(self, seq: int, response: Any) -> None:
        self._publish(ServiceEventInfo.RESPONSE_RECEIVED if self._client
                      else ServiceEventInfo.RESPONSE_SENT, seq, response=response)

    def close(self) -> None:
        if self._pub is not None:
            self._pub.close()
            self._pub = None
