"""`BridgeHost`: what the DDS bridge's routes and graph view (actions.py, graph.py, routes.py,
services.py) use of the `bridge.Ros2DdsBridge` that makes them, as a protocol, so they import
no module above them (as `zenros.action.host.ActionHost` does for the action server and
client)."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Protocol, TypeVar

from cyclonedds.domain import DomainParticipant
from zenros.executor import CallbackGroup
from zenros.log import LogOnce
from zenros.message import Message, ServiceType
from zenros.owner import Owner
from zenros.pubsub import Publisher
from zenros.qos import QoSProfile
from zenros.rpc import Service

__all__ = ["BridgeHost"]

M = TypeVar("M", bound=Message)


class BridgeHost(Owner, Protocol):
    """The DDS bridge node as its helpers see it: its participant, limits and endpoints."""

    participant: DomainParticipant
    guid: Any
    zid: str
    pool: ThreadPoolExecutor
    problems: LogOnce
    service_timeout: float
    result_timeout: float
    dds_topics: dict[tuple[str, str], Any]

    def bad_sample(self, topic: str, sender: str, exc: Exception) -> None: ...

    def writer_name(self, handle: int) -> str: ...

    def create_publisher(self, msg_type: type[M], topic: str,
                         qos: QoSProfile | int = 10) -> Publisher[M]: ...

    def create_service(self, srv_type: ServiceType, name: str, handler: Callable[..., Any], *,
                       callback_group: CallbackGroup | None = None) -> Service: ...

    def destroy(self, endpoint: Any) -> None: ...
