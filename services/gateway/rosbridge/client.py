"""`ClientProtocol`: one rosbridge v2 connection: parses frames, hands each to the op's
handler, queues replies. A frame decodes in one step into its op's type (a `frames.Frame`
tagged by ``op``; a frame msgspec will not take, NaN in it say, is read as Python's json
reads it, then converted). The ops come from its capabilities (`CAPABILITIES`, each a
`capability.Capability` that registers its op codes, as rosbridge_suite's), besides the
session's own ``set_level``, ``fragment`` and ``auth``.

Errors follow the reference server: a failed ``call_service`` or ``send_action_goal`` is
answered (``result: false`` and the reason in ``values``, with the request's id); anything
else is logged on the server, and sent as a ``status`` frame only to a client that asked for
them with ``set_level`` (roslibpy raises on a status it did not ask for). The connection
always stays up.
"""

from __future__ import annotations

import asyncio
import json
import logging
import time
from collections.abc import Awaitable, Callable
from typing import Any

import msgspec
from zenros.errors import ZenrosError

from .bridge import Bridge, BridgeError, Encode
from .capability import Capability, OpHandler, Session
from .convert import dumps
from .fragments import Defragmenter, FragmentError
from .frames import Auth, Fragment, Frame, OpError, SetLevel, frame_decoder, op_of
from .ops_actions import ActionOps
from .ops_services import ServiceOps
from .ops_topics import TopicOps
from .outbox import Outbox, Turnstile

__all__ = ["CAPABILITIES", "LEVELS", "ClientProtocol", "OpError"]

LEVELS = {"info": 0, "warning": 1, "warn": 1, "error": 2, "none": 3}

Send = Callable[[], None]

CAPABILITIES: tuple[Callable[[Session], Capability], ...] = (TopicOps, ServiceOps, ActionOps)
"""The capabilities of every session, in order: they are closed in this order too."""


class ClientProtocol:
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
        self._tasks: set[asyncio.Task[Any]] = set()
        self._defrag = Defragmenter(time.monotonic)
        self.closed = False
        self._ops: dict[str, OpHandler] = {}
        self._frames: list[type[Frame]] = []
        self.register_operation(SetLevel, self.op_set_level)
        self.register_operation(Fragment, self.op_fragment)
        self.register_operation(Auth, lambda frame: None)  # rosauth is not supported
        self.capabilities = [make(self) for make in CAPABILITIES]
        for capability in self.capabilities:
            for kind, handler in capability.handlers().values():
                self.register_operation(kind, handler)
        self.topics = next(c for c in self.capabilities if isinstance(c, TopicOps))
        self._decoder = frame_decoder(tuple(self._frames))

    def register_operation(self, kind: type[Frame], handler: OpHandler) -> None:
        """Answer the op of frame type ``kind`` with ``handler`` (rosbridge_suite's
        ``register_operation``); an op registered twice is a bug."""
        op = op_of(kind)
        if op in self._ops:
            raise ValueError(f"rosbridge op {op!r} is registered twice")
        self._ops[op] = handler
        self._frames.append(kind)

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
        return self.topics.format_of(topic)

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
            frame: Frame | None = self._decoder.decode(text)
        except (msgspec.DecodeError, RecursionError):
            frame = self._leniently(text)
        if frame is not None:
            self.handle(frame)

    def _leniently(self, text: str) -> Frame | None:
        """A frame msgspec refused, read as Python's json reads it (NaN, say) and converted;
        None, once reported with the reference's words, if it still is not one."""
        try:
            obj = json.loads(text)
        except ValueError as exc:
            self.report("error", f"Unable to parse JSON: {exc}; message was: {text[:200]}")
            return None
        except RecursionError:
            self.report("error", "Unable to parse JSON: nested too deep;"
                                 f" message was: {text[:200]}")
            return None
        if not isinstance(obj, dict):
            self.report("error", f"Expected a JSON object, got {type(obj).__name__}")
            return None
        mid = obj.get("id")
        op = obj.get("op")
        if op is None:
            self.report("error", "Received a message without an op. All messages require 'op' "
                        f"field with value one of: {list(self._ops)}.", mid)
            return None
        if not isinstance(op, str) or op not in self._ops:
            self.report("error", f"Unknown operation: {op}. Allowed operations: "
                        f"{list(self._ops)}", mid)
            return None
        try:
            frame: Frame = msgspec.convert(obj, self._decoder.type)
        except (msgspec.ValidationError, RecursionError) as exc:
            self.report("error", f"{op}: {exc}", mid)
            return None
        return frame

    def handle(self, frame: Frame) -> None:
        """Run ``frame``'s op; an op that fails is reported with the frame's id."""
        mid = frame.id
        op = op_of(type(frame))
        handler = self._ops[op]
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

    def op_set_level(self, frame: SetLevel) -> None:
        level = frame.level
        if level not in LEVELS:
            raise OpError(f"level must be one of {', '.join(LEVELS)}, got {level!r}")
        self.level = LEVELS[str(level)]

    def op_fragment(self, frame: Fragment) -> None:
        try:
            text = self._defrag.add(msgspec.structs.asdict(frame))
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
        for capability in self.capabilities:
            capability.close()
        for task in list(self._tasks):
            task.cancel()
