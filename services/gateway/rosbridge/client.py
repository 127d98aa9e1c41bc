"""`ClientProtocol`: one rosbridge v2 connection: parses frames, runs the ops, queues replies.

Errors follow the reference server: a failed ``call_service`` or ``send_action_goal`` is
answered (``result: false`` and the reason in ``values``, with the request's id); anything
else is logged on the server, and sent as a ``status`` frame only to a client that asked for
them with ``set_level`` (roslibpy raises on a status it did not ask for). The connection
always stays up.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import itertools
import json
import logging
import time
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any

from zenros.errors import ServiceError, UnknownTypeError, ZenrosError, ZenrosTimeout
from zenros.message import Message, ServiceType, lookup_action, lookup_service
from zenros.names import validate_name

from .bridge import Bridge, BridgeError
from .convert import dumps, message_from_json, request_args, to_json
from .fragments import Defragmenter, FragmentError
from .outbox import Outbox
from .rosapi import Rosapi, RosapiError

__all__ = ["LEVELS", "ClientProtocol", "OpError"]

LEVELS = {"info": 0, "warning": 1, "warn": 1, "error": 2, "none": 3}
DEFAULT_SERVICE_TIMEOUT = 10.0  # seconds, when call_service carries no timeout
CLIENT_SERVICE_TIMEOUT = 10.0  # seconds a browser has to answer a forwarded call

Send = Callable[[], None]


class OpError(ValueError):
    """An op that cannot be carried out; reported with the request's id."""


@dataclass
class SubOptions:
    """One subscription id's options; several ids on one topic are merged."""

    throttle_rate: float = 0
    queue_length: int = 0
    fragment_size: int = 0


def _name(frame: dict[str, Any], key: str) -> str:
    value = frame.get(key)
    if not isinstance(value, str) or not value:
        raise OpError(f"Expected a key '{key}' with a non-empty string in message")
    name = value if value.startswith("/") else "/" + value
    name = name.split("#", 1)[0]  # the legacy form carries the call id after '#'
    try:
        validate_name(name, key)
    except ValueError as exc:
        raise OpError(str(exc)) from None
    return name


def _legacy_id(frame: dict[str, Any], key: str) -> Any:
    """The interaction id: the ``id`` field, else what follows ``#`` in the name."""
    if "id" in frame:
        return frame["id"]
    value = frame.get(key)
    if isinstance(value, str) and "#" in value:
        return value.split("#", 1)[1]
    return None


def _int(frame: dict[str, Any], key: str, default: int = 0) -> int:
    value = frame.get(key, default)
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise OpError(f"Expected '{key}' to be a number, got {type(value).__name__}")
    return int(value)


class ClientProtocol:
    """The rosbridge session of one client.

    Args:
        bridge: the shared endpoints.
        client_id: a number for the logs.
        wake: called (on the loop) when the outbox has something to send.
        congested: tells whether the client's socket is backed up.
    """

    def __init__(self, bridge: Bridge, client_id: int, wake: Send,
                 congested: Callable[[], bool], logger: logging.Logger) -> None:
        self.bridge = bridge
        self.client_id = client_id
        self.outbox = Outbox(time.monotonic)
        self._wake = wake
        self._congested = congested
        self._log = logger
        self.level = LEVELS["none"]
        self.subs: dict[str, dict[Any, SubOptions]] = {}
        self.advertised: set[str] = set()
        self.services: dict[str, Any] = {}
        self.pending: dict[str, tuple[concurrent.futures.Future[Any], str]] = {}
        self.goals: dict[Any, Any] = {}
        self._tasks: set[asyncio.Task[Any]] = set()
        self._request_ids = itertools.count(1)
        self._defrag = Defragmenter(time.monotonic)
        self.closed = False
        self._ops: dict[str, Callable[[dict[str, Any]], None]] = {
            "advertise": self.op_advertise,
            "unadvertise": self.op_unadvertise,
            "publish": self.op_publish,
            "subscribe": self.op_subscribe,
            "unsubscribe": self.op_unsubscribe,
            "call_service": self.op_call_service,
            "service_response": self.op_service_response,
            "advertise_service": self.op_advertise_service,
            "unadvertise_service": self.op_unadvertise_service,
            "send_action_goal": self.op_send_action_goal,
            "cancel_action_goal": self.op_cancel_action_goal,
            "set_level": self.op_set_level,
            "fragment": self.op_fragment,
            "auth": lambda frame: None,  # accepted silently: rosauth is not supported
        }
        for op in ("advertise_action", "unadvertise_action", "action_feedback",
                   "action_result"):
            self._ops[op] = self.op_not_implemented

    # ------------------------------------------------------------------ in and out

    def deliver(self, topic: str, frame: bytes) -> None:
        """A topic frame from the bridge (on the loop)."""
        if self.outbox.publish(topic, frame, self._congested()):
            self._wake()

    def send(self, obj: dict[str, Any], fragment_size: int = 0) -> None:
        """Queue a reply frame (never dropped)."""
        if self.closed:
            return
        self.outbox.reply(dumps(obj), fragment_size)
        self._wake()

    def report(self, level: str, message: str, mid: Any = None) -> None:
        """Log on the server; also send a ``status`` frame if the client asked for them."""
        text = f"[Client {self.client_id}] " + (f"[id: {mid}] " if mid is not None else "") + message
        self._log.log(logging.ERROR if level == "error" else
                      logging.WARNING if level == "warning" else logging.INFO, "%s", text)
        if LEVELS.get(level, 0) >= self.level:
            status: dict[str, Any] = {"op": "status", "level": level, "msg": message}
            if mid is not None:
                status["id"] = mid
            self.send(status)

    def incoming(self, text: str | bytes) -> None:
        """Handle one WebSocket message."""
        if isinstance(text, bytes):
            self.report("error", "binary frames are not supported: send JSON text frames")
            return
        try:
            frame = json.loads(text)
        except ValueError as exc:
            self.report("error", f"Unable to parse JSON: {exc}; message was: {text[:200]}")
            return
        if not isinstance(frame, dict):
            self.report("error", f"Expected a JSON object, got {type(frame).__name__}")
            return
        self.handle(frame)

    def handle(self, frame: dict[str, Any]) -> None:
        mid = frame.get("id")
        op = frame.get("op")
        if op is None:
            self.report("error", "Received a message without an op. All messages require 'op' "
                        f"field with value one of: {list(self._ops)}.", mid)
            return
        handler = self._ops.get(op) if isinstance(op, str) else None
        if handler is None:
            self.report("error", f"Unknown operation: {op}. Allowed operations: "
                        f"{list(self._ops)}", mid)
            return
        try:
            handler(frame)
        except (OpError, BridgeError, ZenrosError, ValueError, TypeError) as exc:
            self.report("error", f"{op}: {exc}", mid)
        except Exception as exc:  # noqa: BLE001 a client's frame must never end the server
            self._log.exception("[Client %s] %s failed", self.client_id, op)
            self.report("error", f"{op}: {type(exc).__name__}: {exc}", mid)

    def spawn(self, coro: Awaitable[Any]) -> None:
        task: asyncio.Task[Any] = asyncio.ensure_future(coro)
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    # ------------------------------------------------------------------ topics

    def op_advertise(self, frame: dict[str, Any]) -> None:
        topic = _name(frame, "topic")
        type_name = frame.get("type")
        if not isinstance(type_name, str) or not type_name:
            raise OpError("Expected a key 'type' with a non-empty string in message")
        msg_type = self.bridge.topic_type(topic, type_name)
        if topic in self.advertised and self.bridge.publishers[topic][0].msg_type is msg_type:
            return  # a replay after reconnect, or a second advertise: nothing to do
        self.bridge.advertise(topic, msg_type, self, bool(frame.get("latch", False)),
                              _int(frame, "queue_size", 100))
        self.advertised.add(topic)

    def op_unadvertise(self, frame: dict[str, Any]) -> None:
        topic = _name(frame, "topic")
        if topic in self.advertised:
            self.advertised.discard(topic)
            self.bridge.unadvertise(topic, self)

    def op_publish(self, frame: dict[str, Any]) -> None:
        topic = _name(frame, "topic")
        if topic not in self.advertised:
            entry = self.bridge.publishers.get(topic)
            known = self.bridge.node.graph.topics().get(topic)
            if entry is None and not known:
                raise OpError(f"Cannot infer topic type for topic {topic} as it is not yet "
                              "advertised")
            msg_type = entry[0].msg_type if entry else self.bridge.topic_type(topic, None)
            self.bridge.advertise(topic, msg_type, self, bool(frame.get("latch", False)), 100)
            self.advertised.add(topic)
        pub = self.bridge.publishers[topic][0]
        msg = message_from_json(frame.get("msg"), pub.msg_type, self.bridge.node.now())
        pub.publish(msg)

    def op_subscribe(self, frame: dict[str, Any]) -> None:
        topic = _name(frame, "topic")
        type_name = frame.get("type")
        if type_name is not None and not isinstance(type_name, str):
            raise OpError("Expected 'type' to be a string")
        opts = SubOptions(throttle_rate=_int(frame, "throttle_rate"),
                          queue_length=_int(frame, "queue_length"),
                          fragment_size=_int(frame, "fragment_size"))
        if topic not in self.subs:
            msg_type = self.bridge.topic_type(topic, type_name or None)
            self.bridge.attach(topic, msg_type, self)
            self.subs[topic] = {}
        elif type_name:
            feed = self.bridge.feeds[topic]
            if self.bridge.topic_type(topic, type_name) is not feed.msg_type:
                raise OpError(f"{topic} is already subscribed with type {feed.type_name}")
        self.subs[topic][frame.get("id")] = opts
        self._configure(topic)

    def _configure(self, topic: str) -> None:
        opts = list(self.subs[topic].values())
        fragments = [o.fragment_size for o in opts if o.fragment_size > 0]
        self.outbox.configure(topic, min(o.throttle_rate for o in opts),
                              max(o.queue_length for o in opts),
                              min(fragments) if fragments else 0)

    def op_unsubscribe(self, frame: dict[str, Any]) -> None:
        topic = _name(frame, "topic")
        ids = self.subs.get(topic)
        if ids is None:
            return
        mid = frame.get("id")
        if mid is not None and mid in ids and len(ids) > 1:
            del ids[mid]
            self._configure(topic)
            return
        if mid is not None and mid not in ids:
            return
        self._drop_subscription(topic)

    def _drop_subscription(self, topic: str) -> None:
        self.subs.pop(topic, None)
        self.outbox.remove(topic)
        self.bridge.detach(topic, self)

    # ------------------------------------------------------------------ calling services

    def op_call_service(self, frame: dict[str, Any]) -> None:
        mid = _legacy_id(frame, "service")
        given = frame.get("service")
        try:
            service = _name(frame, "service")
        except OpError as exc:
            if isinstance(given, str):
                self._service_failed(given, mid, str(exc))
                return
            raise
        self.spawn(self._call_service(service, str(given), mid, frame))

    def _service_failed(self, service: str, mid: Any, reason: str) -> None:
        self.report("error", f"call_service {service}: {reason}", mid)
        reply: dict[str, Any] = {"op": "service_response", "service": service,
                                 "values": reason, "result": False}
        if mid is not None:
            reply["id"] = mid
        self.send(reply)

    async def _call_service(self, service: str, given: str, mid: Any,
                            frame: dict[str, Any]) -> None:
        args = frame.get("args") or {}
        try:
            if Rosapi.handles(service):
                if not isinstance(args, dict):
                    raise OpError("rosapi services take an object of named args")
                values = await asyncio.to_thread(self.bridge.rosapi.call, service, args)
            else:
                values = await self._call_zenros(service, args, frame)
        except (OpError, BridgeError, RosapiError, ZenrosError, ValueError, TypeError) as exc:
            self._service_failed(given, mid, str(exc) if not isinstance(exc, ServiceError)
                                 else exc.reason)
            return
        reply: dict[str, Any] = {"op": "service_response", "service": given, "values": values,
                                 "result": True}
        if mid is not None:
            reply["id"] = mid
        self.send(reply, _int(frame, "fragment_size"))

    async def _call_zenros(self, service: str, args: Any, frame: dict[str, Any]) -> Any:
        type_name = self.bridge.service_type_of(service)
        if type_name is None:
            raise OpError(f"Service {service} does not exist")
        try:
            srv_type = lookup_service(type_name)
        except UnknownTypeError as exc:
            raise OpError(str(exc)) from None
        request = message_from_json(request_args(args, srv_type.Request), srv_type.Request)
        timeout = frame.get("timeout")
        if not isinstance(timeout, (int, float)) or isinstance(timeout, bool) or timeout <= 0:
            timeout = DEFAULT_SERVICE_TIMEOUT
        try:
            response = await self.bridge.client(srv_type, service).call_async(request, timeout)
        except ZenrosTimeout:
            raise OpError(f"Service {service} timed out after {timeout:g} s") from None
        return to_json(response)

    # ------------------------------------------------------------------ serving services

    def op_advertise_service(self, frame: dict[str, Any]) -> None:
        service = _name(frame, "service")
        type_name = frame.get("type")
        if not isinstance(type_name, str) or not type_name:
            raise OpError("Expected a key 'type' with a non-empty string in message")
        try:
            srv_type = lookup_service(type_name)
        except UnknownTypeError as exc:
            raise OpError(str(exc)) from None
        old = self.services.get(service)
        if old is not None:
            if old.srv_type is srv_type:
                return  # a replay after reconnect
            self._stop_service(service)
        self.services[service] = self.bridge.serve(srv_type, service,
                                                   self._forwarder(service, srv_type))

    def _forwarder(self, service: str, srv_type: ServiceType) -> Callable[..., Any]:
        loop = self.bridge.loop

        async def forward(request: Message) -> Message:  # on the node's executor loop
            cid = f"service_request:{service}:{next(self._request_ids)}"
            fut: concurrent.futures.Future[Any] = concurrent.futures.Future()
            self.pending[cid] = (fut, service)
            loop.call_soon_threadsafe(self.send, {"op": "call_service", "id": cid,
                                                  "service": service, "args": to_json(request)})
            try:
                values = await asyncio.wait_for(asyncio.wrap_future(fut), CLIENT_SERVICE_TIMEOUT)
            except TimeoutError:
                raise ServiceError(service, f"the rosbridge client did not answer within "
                                   f"{CLIENT_SERVICE_TIMEOUT:g} s") from None
            finally:
                self.pending.pop(cid, None)
            return message_from_json(values, srv_type.Response)

        return forward

    def op_service_response(self, frame: dict[str, Any]) -> None:
        mid = frame.get("id")
        entry = self.pending.get(mid) if isinstance(mid, str) else None
        if entry is None:
            raise OpError(f"no pending service call with id {mid!r}")
        fut, service = entry
        if fut.done():
            return
        if frame.get("result", True) is False:
            values = frame.get("values")
            fut.set_exception(ServiceError(service, values if isinstance(values, str)
                                           else "the rosbridge client's handler failed"))
        else:
            fut.set_result(frame.get("values") or {})

    def op_unadvertise_service(self, frame: dict[str, Any]) -> None:
        self._stop_service(_name(frame, "service"))

    def _stop_service(self, service: str) -> None:
        srv = self.services.pop(service, None)
        if srv is None:
            return
        self.bridge.release(srv)
        for cid, (fut, name) in list(self.pending.items()):
            if name == service and not fut.done():
                fut.set_exception(ServiceError(service, "the service was unadvertised"))
                self.pending.pop(cid, None)

    # ------------------------------------------------------------------ actions

    def op_send_action_goal(self, frame: dict[str, Any]) -> None:
        mid = _legacy_id(frame, "action")
        action = frame.get("action")
        if not isinstance(action, str):
            raise OpError("Expected a key 'action' with a string in message")
        self.spawn(self._send_goal(action, mid, frame))

    async def _send_goal(self, given: str, mid: Any, frame: dict[str, Any]) -> None:
        def reply(values: Any, status: int, ok: bool) -> None:
            out: dict[str, Any] = {"op": "action_result", "action": given, "values": values,
                                   "status": status, "result": ok}
            if mid is not None:
                out["id"] = mid
            self.send(out, _int(frame, "fragment_size"))

        try:
            action = _name(frame, "action")
            type_name = frame.get("action_type")
            if not isinstance(type_name, str) or not type_name:
                raise OpError("Expected a key 'action_type' with a non-empty string in message")
            try:
                action_type = lookup_action(type_name)
            except UnknownTypeError as exc:
                raise OpError(str(exc)) from None
            goal = message_from_json(frame.get("args") or {}, action_type.Goal)
            client = self.bridge.action_client(action_type, action)
            on_feedback = self._feedback_sender(given, mid) if frame.get("feedback") else None
            handle = client.send_goal_async(goal, on_feedback)
            if mid is not None:
                self.goals[mid] = handle
            try:
                result = await handle.result_async()
            finally:
                if mid is not None:
                    self.goals.pop(mid, None)
        except (OpError, BridgeError, ZenrosError, ValueError, TypeError) as exc:
            self.report("error", f"send_action_goal {type(exc).__name__}: {exc}", mid)
            reply(str(exc), 0, False)
            return
        status = int(result.status) if result.status <= 6 else 0
        if result.reason and status == 0:
            reply(result.reason, 0, False)
            return
        reply(to_json(result.result), status, True)

    def _feedback_sender(self, action: str, mid: Any) -> Callable[[Any], None]:
        loop = self.bridge.loop

        def on_feedback(msg: Any) -> None:  # on the action client's feedback thread
            out: dict[str, Any] = {"op": "action_feedback", "action": action,
                                   "values": to_json(msg.feedback)}
            if mid is not None:
                out["id"] = mid
            loop.call_soon_threadsafe(self.send, out)

        return on_feedback

    def op_cancel_action_goal(self, frame: dict[str, Any]) -> None:
        mid = _legacy_id(frame, "action")
        handle = self.goals.get(mid)
        if handle is None:
            raise OpError(f"no goal in progress with id {mid!r}")
        self.spawn(asyncio.to_thread(handle.cancel))

    # ------------------------------------------------------------------ misc

    def op_not_implemented(self, frame: dict[str, Any]) -> None:
        raise OpError(f"not implemented: {frame.get('op')} (client-side action servers are "
                      "not supported)")

    def op_set_level(self, frame: dict[str, Any]) -> None:
        level = frame.get("level")
        if level not in LEVELS:
            raise OpError(f"level must be one of {', '.join(LEVELS)}, got {level!r}")
        self.level = LEVELS[str(level)]

    def op_fragment(self, frame: dict[str, Any]) -> None:
        try:
            text = self._defrag.add(frame)
        except FragmentError as exc:
            raise OpError(str(exc)) from None
        if text is not None:
            self.incoming(text)

    # ------------------------------------------------------------------ end

    def close(self) -> None:
        """Release everything this client owns (on disconnect)."""
        if self.closed:
            return
        self.closed = True
        for topic in list(self.subs):
            self._drop_subscription(topic)
        for topic in list(self.advertised):
            self.bridge.unadvertise(topic, self)
        self.advertised.clear()
        for service in list(self.services):
            self._stop_service(service)
        for task in list(self._tasks):
            task.cancel()
        loop = self.bridge.loop
        for handle in list(self.goals.values()):
            if not handle.done:  # a goal of a client that left is canceled, not orphaned
                loop.run_in_executor(None, handle.cancel)
        self.goals.clear()
