"""tf2_web_republisher, served by the bridge from the zenros TF buffer, for roslibjs's and
roslibpy's ``TFClient``.

A subscription names ``source_frames``, a ``target_frame``, ``angular_thres`` (rad),
``trans_thres`` (m) and a ``rate`` (Hz). At that rate each source frame is looked up in the
target frame (the latest transform), and a ``tf2_web_republisher/TFArray`` carries those
that moved more than a threshold since they were last sent (all of them the first time).
Two doors, as in the reference node:

* the service ``/republish_tfs`` (tf2_web_republisher/RepublishTFs) answers with a topic name
  (``/tf_repub_<n>``) that the TFArrays are then published on; it stops once nobody has
  subscribed to it for the request's ``timeout``;
* the ROS 1 action ``/tf2_web_republisher`` (TFSubscriptionAction) over its actionlib topics:
  a goal on ``/tf2_web_republisher/goal`` streams TFArrays as feedback on
  ``/tf2_web_republisher/feedback`` until it is canceled on ``/tf2_web_republisher/cancel``
  (or nobody listens to the feedback any more).

Those topics carry types zenros has no definition for, so they live among the bridge's
unchecked topics (opaque.py): rosbridge clients see them, zenros nodes do not.
"""

from __future__ import annotations

import asyncio
import itertools
import math
from collections.abc import Callable
from typing import Any

from zenros.tf import LATEST, Buffer, TransformException, TransformListener

from .convert import to_json
from .frames import OpError
from .host import BridgeHost

__all__ = ["ACTION", "SERVICE", "TFRepublisher"]

SERVICE = "/republish_tfs"
ACTION = "/tf2_web_republisher"
FEEDBACK_GRACE = 2.0  # s a goal streams with nobody on its feedback topic before it ends
Emit = Callable[[dict[str, Any]], None]


def _number(req: dict[str, Any], key: str, default: float) -> float:
    value = req.get(key, default)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise OpError(f"{key} must be a number, got {value!r}")
    return float(value)


def _seconds(value: Any) -> float:
    """A Duration in either spelling (``sec``/``nanosec`` or ROS 1's ``secs``/``nsecs``)."""
    if not isinstance(value, dict):
        return 0.0
    sec = value.get("sec", value.get("secs", 0)) or 0
    nsec = value.get("nanosec", value.get("nsecs", 0)) or 0
    return float(sec) + float(nsec) / 1e9


class Stream:
    """One subscription: looks its frames up at ``rate`` and emits what moved."""

    def __init__(self, buffer: Buffer, request: dict[str, Any], emit: Emit,
                 alive: Callable[[], bool], listeners: Callable[[], int]) -> None:
        frames = request.get("source_frames") or []
        if not isinstance(frames, list) or not all(isinstance(f, str) for f in frames):
            raise OpError("source_frames must be a list of frame names")
        target = request.get("target_frame")
        if not isinstance(target, str) or not target.strip("/"):
            raise OpError("target_frame must be a frame name")
        self.sources = [f.strip("/") for f in frames if f.strip("/")]
        self.target = target.strip("/")
        self.angular = _number(request, "angular_thres", 0.0)
        self.trans = _number(request, "trans_thres", 0.0)
        rate = _number(request, "rate", 10.0)
        self.period = 1.0 / rate if rate > 0 else 0.1
        self._buffer = buffer
        self._emit = emit
        self._alive = alive
        self._listeners = listeners
        self._last: dict[str, tuple[float, ...]] = {}
        self.task: asyncio.Task[None] | None = None

    def _moved(self, frame: str, r: tuple[float, ...]) -> bool:
        last = self._last.get(frame)
        if last is None:
            return True
        dist = math.dist(r[:3], last[:3])
        dot = min(1.0, abs(sum(a * b for a, b in zip(r[3:], last[3:], strict=True))))
        return dist > self.trans or 2.0 * math.acos(dot) > self.angular

    def step(self) -> None:
        out = []
        for frame in self.sources:
            try:
                t = self._buffer.lookup_transform(self.target, frame, LATEST)
            except TransformException:
                continue
            tr, q = t.transform.translation, t.transform.rotation
            r = (tr.x, tr.y, tr.z, q.x, q.y, q.z, q.w)
            if self._moved(frame, r):
                self._last[frame] = r
                out.append(to_json(t))
        if out:
            self._emit({"transforms": out})

    async def run(self) -> None:
        heard = 0
        while self._alive():
            n = self._listeners()
            if n > heard:  # a new listener gets every frame once, as the reference sends
                self._last.clear()
            heard = n
            if n:
                self.step()
            await asyncio.sleep(self.period)


class TFRepublisher:
    """The republisher of one bridge (on its loop): the service, the action, their streams."""

    def __init__(self, bridge: BridgeHost) -> None:
        self._bridge = bridge
        self._buffer: Buffer | None = None
        self._listener: TransformListener | None = None
        self._topics = itertools.count(1)
        self._streams: set[Stream] = set()
        self._goals: dict[str, Stream] = {}
        opaque = bridge.opaque
        opaque.hooks[ACTION + "/goal"] = self._on_goal
        opaque.hooks[ACTION + "/cancel"] = self._on_cancel

    @property
    def buffer(self) -> Buffer:
        if self._buffer is None:  # the TF topics are subscribed on first use only
            self._buffer = Buffer()
            self._listener = TransformListener(self._buffer, self._bridge.node)
        return self._buffer

    def _start(self, stream: Stream) -> None:
        self._streams.add(stream)
        stream.task = self._bridge.loop.create_task(stream.run())
        stream.task.add_done_callback(lambda _: self._streams.discard(stream))

    # ------------------------------------------------------------------ the service

    def republish_tfs(self, args: Any) -> dict[str, Any]:
        """``/republish_tfs``: a new topic that the requested frames are published on."""
        if not isinstance(args, dict):
            raise OpError("republish_tfs takes an object of named args")
        opaque = self._bridge.opaque
        topic = f"/tf_repub_{next(self._topics)}"
        timeout = max(_seconds(args.get("timeout")), 1.0)
        loop = self._bridge.loop
        seen = [loop.time()]

        def alive() -> bool:
            entry = opaque.topics.get(topic)
            if entry is not None and entry.sinks:
                seen[0] = loop.time()
            return loop.time() - seen[0] < timeout

        stream = Stream(self.buffer, args, lambda msg: opaque.publish(topic, msg), alive,
                        lambda: opaque.listeners(topic))
        opaque.advertise(topic, "tf2_web_republisher/TFArray", self)
        self._start(stream)
        assert stream.task is not None
        stream.task.add_done_callback(lambda _: opaque.unadvertise(topic, self))
        return {"topic_name": topic}

    # ------------------------------------------------------------------ the action

    def _on_goal(self, msg: Any) -> None:
        goal_id = (msg.get("goal_id") or {}).get("id") if isinstance(msg, dict) else None
        if not isinstance(goal_id, str):
            raise OpError(f"{ACTION}/goal: expected goal_id.id")
        goal = msg.get("goal") or {}
        opaque = self._bridge.opaque
        feedback_topic = ACTION + "/feedback"
        loop = self._bridge.loop
        seen = [loop.time()]

        def emit(tfs: dict[str, Any]) -> None:
            opaque.publish(feedback_topic, {
                "header": {"stamp": to_json(self._bridge.node.now()), "frame_id": ""},
                "status": {"goal_id": msg["goal_id"], "status": 1, "text": ""},
                "feedback": tfs})

        def alive() -> bool:
            if self._goals.get(goal_id) is not stream:
                return False
            entry = opaque.topics.get(feedback_topic)
            if entry is not None and entry.sinks:
                seen[0] = loop.time()
            return loop.time() - seen[0] < FEEDBACK_GRACE

        stream = Stream(self.buffer, goal, emit, alive, lambda: opaque.listeners(feedback_topic))
        old = self._goals.pop(goal_id, None)
        if old is not None and old.task is not None:
            old.task.cancel()
        self._goals[goal_id] = stream
        self._start(stream)
        assert stream.task is not None
        stream.task.add_done_callback(
            lambda _: self._goals.pop(goal_id, None) if self._goals.get(goal_id) is stream
            else None)

    def _on_cancel(self, msg: Any) -> None:
        goal_id = msg.get("id") if isinstance(msg, dict) else None
        for gid in [g for g in self._goals if not goal_id or g == goal_id]:
            stream = self._goals.pop(gid)
            if stream.task is not None:
                stream.task.cancel()

    def close(self) -> None:
        for stream in list(self._streams):
            if stream.task is not None:
                stream.task.cancel()
        self._goals.clear()
        if self._listener is not None:
            self._listener.unregister()
            self._listener = None
