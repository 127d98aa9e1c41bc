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
from typing import Any

from zenros.errors import ZenrosError

from .bridge import Bridge, BridgeError, Encode
from .convert import dumps
from .fragments import Defragmenter, FragmentError
from .frames import OpError, SubOptions
from .ops_actions import ActionOps
from .ops_services import ServiceOps
from .ops_topics import TopicOps
from .outbox import Outbox, Turnstile
from .served_action import ServedAction

__all__ = ["LEVELS", "ClientProtocol", "OpError"]

LEVELS = {"info": 0, "warning": 1, "warn": 1, "error": 2, "none": 3}

Send = Callable[[], None]


class ClientProtocol(TopicOps, ServiceOps, ActionOps):
    """The rosbridge session of one client.

    Args:
        bridge: the shared endpoints.
        client_id: a number for the logs.
        wake: called (on the loop) when the outbox has something to send.
        congested: tells whether the client's socket is backed up.
    """

    def __init__(self, bridge: Bridge, client_id: int, wake: Send,
                 congested: Callable[[], bool], logger: logging.Logger,
                 turnstile: Turnstile | None = None) -> None:
        self.bridge = bridge
        self.client_id = client_id
        self.outbox = Outbox(time.monotonic, turnstile)
        self._wake = wake
        self._congested = congested
        self._log = logger
        self.level = LEVELS["none"]
        self.subs: dict[str, dict[Any, SubOptions]] = {}
        self.compression: dict[str, str] = {}
        """Topics sent compressed (``png``, ``cbor`` or ``cbor-raw``), the others as JSON
        (encodings.py)."""
        self.advertised: set[str] = set()
        self.services: dict[str, Any] = {}
        self.pending: dict[str, tuple[concurrent.futures.Future[Any], str]] = {}
        self.goals: dict[Any, Any] = {}
        self.served_actions: dict[str, ServedAction] = {}
        self._tasks: set[asyncio.Task[Any]] = set()
        self._request_ids = itertools.count(1)
        self._rosapi_turn = asyncio.Lock()
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
        self._ops.update({
            "advertise_action": self.op_advertise_action,
            "unadvertise_action": self.op_unadvertise_action,
            "action_feedback": self.op_action_feedback,
            "action_result": self.op_action_result,
        })

    # ------------------------------------------------------------------ in and out

    def deliver(self, topic: str, encode: Encode) -> None:
        """A topic message from the bridge (on the loop), in the format this client takes."""
        fmt = self.format_of(topic)
        try:
            frame = encode(fmt)
        except (ValueError, TypeError, ZenrosError) as exc:
            self.report("error", f"{topic}: cannot encode as {fmt}: {exc}")
            return
        if self.outbox.publish(topic, frame, self._congested()):
            self._wake()

    def format_of(self, topic: str) -> str:
        return self.compression.get(topic, "json")

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
        except RecursionError:
            self.report("error", "Unable to parse JSON: nested too deep;"
                                 f" message was: {text[:200]}")
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

    # ------------------------------------------------------------------ misc

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
        for topic in [t for t, e in self.bridge.opaque.topics.items() if self in e.advertisers]:
            self.bridge.opaque.unadvertise(topic, self)
        for action in list(self.served_actions):
            self.stop_served_action(action)
        for service in list(self.services):
            self._stop_service(service)
        for task in list(self._tasks):
            task.cancel()
        loop = self.bridge.loop
        for handle in list(self.goals.values()):
            if not handle.done:  # a goal of a client that left is canceled, not orphaned
                loop.run_in_executor(None, handle.cancel)
        self.goals.clear()
