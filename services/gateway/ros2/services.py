"""A ROS 2 service (a server on DDS elsewhere) offered as a zenros service of the same name.

The server's request reader (``rq/<name>Request``, type ``pkg::srv::dds_::X_Request_``) makes
the route: a DDS writer of requests, a DDS reader of replies (``rr/<name>Reply``) and a zenros
service whose handler writes the request as CDR and waits for the reply (`Requester`, which
the action routes use for their three services as well).

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
from collections.abc import Callable
from typing import Any

from cyclonedds._clayer import ddspy_write
from cyclonedds.core import Listener, Policy, Qos
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from zenros.errors import CodecError, ZenrosTimeout
from zenros.message import Message, ServiceType
from zenros.ros2.cdr import cdr_codec
from zenros.ros2.registry import ros_name_of
from zenros.ros2.typehash import type_hash

from .ddstypes import dds_type
from .host import BridgeHost
from .routes import take_valid

__all__ = ["Requester", "ServiceRoute", "service_qos"]

def service_qos(ros_type: str) -> Qos:
    """rmw's default service QoS (reliable, volatile, keep-last 10), with the type hash."""
    return Qos(Policy.Reliability.Reliable(100_000_000), Policy.Durability.Volatile,
               Policy.History.KeepLast(10), Policy.IgnoreLocal.Participant,
               Policy.Userdata(f"typehash={type_hash(ros_type)};".encode()))


class Requester:
    """Requests written on ``rq/<name>Request``, replies read on ``rr/<name>Reply``, one
    request in flight: the next reply is the one in flight's. ``call`` blocks."""

    def __init__(self, bridge: BridgeHost, name: str, req_type: str, resp_type: str) -> None:
        self.bridge = bridge
        self.name = name
        p = bridge.participant
        self.writer = DataWriter(p, Topic(p, f"rq{name}Request", dds_type(req_type)),
                                 qos=service_qos(req_type))
        self._replies: queue.Queue[bytes | None] = queue.Queue()
        self.reader = DataReader(p, Topic(p, f"rr{name}Reply", dds_type(resp_type)),
                                 qos=service_qos(resp_type),
                                 listener=Listener(on_data_available=self._on_data))  # type: ignore[no-untyped-call]
        self._lock = threading.Lock()
        self._closed = False

    def _on_data(self, reader: Any) -> None:
        for data, _info in take_valid(reader):
            self._replies.put(bytes(data))

    def matched(self) -> bool:
        return bool(self.writer.get_matched_subscriptions()
                    and self.reader.get_matched_publications())

    def call(self, data: bytes, timeout: float, accept: Callable[[bytes], Any]) -> Any:
        """Write ``data`` (CDR) as a request and return ``accept(reply)`` of the first reply
        that ``accept`` takes (a reply it refuses with `zenros.errors.CodecError` is counted
        as a bad sample and the wait goes on); `ZenrosTimeout` after ``timeout`` s."""
        with self._lock:  # one request in flight: the next reply is this request's
            deadline = time.monotonic() + timeout
            while not self.matched():  # a request written before the match would be lost
                if time.monotonic() > deadline:
                    raise ZenrosTimeout(f"ROS 2 service {self.name}: its DDS endpoints did "
                                        f"not match in {timeout:g} s")
                time.sleep(0.01)
            while not self._replies.empty():  # late replies of a request that timed out
                self._replies.get_nowait()
            if self._closed:
                raise ZenrosTimeout(f"ROS 2 service {self.name}: the route closed")
            ddspy_write(self.writer._ref, data + bytes(-len(data) & 3))
            while True:
                try:
                    raw = self._replies.get(timeout=max(0.0, deadline - time.monotonic()))
                except queue.Empty:
                    raise ZenrosTimeout(f"ROS 2 service {self.name} did not reply in "
                                        f"{timeout:g} s") from None
                if raw is None or self._closed:
                    raise ZenrosTimeout(f"ROS 2 service {self.name}: the route closed")
                try:
                    return accept(raw)
                except CodecError as exc:
                    self.bridge.bad_sample(f"rr{self.name}Reply", "its server", exc)

    def close(self) -> None:
        self.reader.set_listener(None)
        self._closed = True
        self._replies.put(None)  # a caller waiting for a reply gives up now
        self.reader.__del__()
        self.writer.__del__()


class ServiceRoute:
    """zenros clients -> a ROS 2 service on DDS, one request in flight at a time."""

    def __init__(self, bridge: BridgeHost, name: str, srv: ServiceType,
                 timeout: float) -> None:
        self.bridge = bridge
        self.name = name
        self.timeout = timeout
        self.req = cdr_codec(srv.Request)
        self.resp = cdr_codec(srv.Response)
        self.requester = Requester(bridge, name, ros_name_of(srv.Request),
                                   ros_name_of(srv.Response))
        self.calls = 0
        self.service = bridge.create_service(srv, name, self._call)

    def _call(self, request: Message) -> Any:
        reply = self.requester.call(self.req.encode(request), self.timeout, self.resp.decode)
        self.calls += 1
        return reply

    def close(self) -> None:
        self.bridge.destroy(self.service)
        self.requester.close()
