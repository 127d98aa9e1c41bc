"""A ROS 2 service (a server on DDS elsewhere) offered as a zenros service of the same name.

The server's request reader (``rq/<name>Request``, type ``pkg::srv::dds_::X_Request_``) makes
the route: a DDS writer of requests, a DDS reader of replies (``rr/<name>Reply``) and a zenros
service whose handler writes the request as CDR and waits for the reply.

Fast DDS (rmw_fastrtps) carries a request's identity out of band, in the RTPS inline QoS of the
DATA submessage (the related-sample identity); cyclonedds neither writes it nor shows it to its
reader. A Fast DDS server answers a request without one (it replies with the request's own
sample identity) but the bridge cannot tell which request a reply is for, so it keeps one
request in flight per service and takes the next reply as that request's. A reply to another
ROS 2 client's call of the same service at the same time would be taken as the bridge's: the
route is exact only while the bridge is the service's only concurrent caller (docs/ros2.md).
"""

from __future__ import annotations

import queue
import threading
import time
from typing import TYPE_CHECKING, Any

from cyclonedds._clayer import ddspy_take, ddspy_write
from cyclonedds.core import InstanceState, Listener, Policy, Qos, SampleState, ViewState
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

from zenros.errors import CodecError, ZenrosTimeout
from zenros.message import Message, ServiceType
from zenros.ros2.cdr import cdr_codec
from zenros.ros2.registry import ros_name_of
from zenros.ros2.typehash import type_hash

from .ddstypes import dds_type

if TYPE_CHECKING:
    from .bridge import Ros2DdsBridge

__all__ = ["ServiceRoute"]

_ANY = SampleState.Any | ViewState.Any | InstanceState.Any


def _qos(ros_type: str) -> Qos:
    """rmw's default service QoS (reliable, volatile, keep-last 10), with the type hash."""
    return Qos(Policy.Reliability.Reliable(100_000_000), Policy.Durability.Volatile,
               Policy.History.KeepLast(10), Policy.IgnoreLocal.Participant,
               Policy.Userdata(f"typehash={type_hash(ros_type)};".encode()))


class ServiceRoute:
    """zenros clients -> a ROS 2 service on DDS, one request in flight at a time."""

    def __init__(self, bridge: Ros2DdsBridge, name: str, srv: ServiceType,
                 timeout: float) -> None:
        self.bridge = bridge
        self.name = name
        self.timeout = timeout
        self.req = cdr_codec(srv.Request)
        self.resp = cdr_codec(srv.Response)
        req_type, resp_type = ros_name_of(srv.Request), ros_name_of(srv.Response)
        p = bridge.participant
        self.writer = DataWriter(p, Topic(p, f"rq{name}Request", dds_type(req_type)),
                                 qos=_qos(req_type))
        self._replies: queue.Queue[bytes] = queue.Queue()
        self.reader = DataReader(p, Topic(p, f"rr{name}Reply", dds_type(resp_type)),
                                 qos=_qos(resp_type),
                                 listener=Listener(on_data_available=self._on_data))  # type: ignore[no-untyped-call]
        self._lock = threading.Lock()
        self.calls = 0
        self.service = bridge.create_service(srv, name, self._call)

    def _on_data(self, reader: Any) -> None:
        try:
            batch = ddspy_take(reader._ref, _ANY, 16)
        except Exception:  # noqa: BLE001 the reader is being deleted
            return
        if isinstance(batch, int):
            return
        for data, info in batch:
            if info.valid_data:
                self._replies.put(bytes(data))

    def _matched(self) -> bool:
        return bool(self.writer.get_matched_subscriptions()
                    and self.reader.get_matched_publications())

    def _call(self, request: Message) -> Any:
        data = self.req.encode(request)
        with self._lock:  # one request in flight: the next reply is this request's
            deadline = time.monotonic() + self.timeout
            while not self._matched():  # a request written before the match would be lost
                if time.monotonic() > deadline:
                    raise ZenrosTimeout(f"ROS 2 service {self.name}: its DDS endpoints did "
                                        f"not match in {self.timeout} s")
                time.sleep(0.01)
            while not self._replies.empty():  # late replies of a request that timed out
                self._replies.get_nowait()
            ddspy_write(self.writer._ref, data + bytes(-len(data) & 3))
            while True:
                try:
                    raw = self._replies.get(timeout=max(0.0, deadline - time.monotonic()))
                except queue.Empty:
                    raise ZenrosTimeout(f"ROS 2 service {self.name} did not reply in "
                                        f"{self.timeout} s") from None
                try:
                    reply = self.resp.decode(raw)
                except CodecError as exc:
                    self.bridge.bad_sample(f"rr{self.name}Reply", "its server", exc)
                    continue
                self.calls += 1
                return reply

    def close(self) -> None:
        self.bridge.destroy(self.service)
        self.reader.set_listener(None)
        self.reader.__del__()
        self.writer.__del__()
