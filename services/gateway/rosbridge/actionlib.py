"""ROS 1 actionlib over topics (``<name>/goal``, ``cancel``, ``status``, ``feedback``,
``result``), bridged onto zenros actions both ways.

* **A ROS 1 client of a zenros action** (roslibpy ``actionlib.ActionClient``, roslibjs
  ``ActionClient``): once a client advertises ``<name>/goal`` with a ``<pkg>/<Name>ActionGoal``
  type and a zenros action ``<name>`` exists whose Goal, Result and Feedback field layouts
  agree with the ROS 1 type's, each goal published there is sent to the zenros action; the
  bridge publishes ``<name>/status`` (an ``actionlib_msgs/GoalStatusArray`` every 0.2 s while
  goals are alive, every second while idle, so a client sees the server), ``<name>/feedback``
  and ``<name>/result`` with the goal's id, and maps ``<name>/cancel`` to a zenros cancel.
* **A ROS 1 server becomes a zenros action** (roslibpy ``SimpleActionServer``): once a client
  subscribes ``<name>/goal`` with a ``<pkg>/<Name>ActionGoal`` type that maps to a zenros
  action type (`zenros_action_type`) and no zenros action ``<name>`` exists, the bridge
  serves a zenros action ``<name>``: each zenros goal is published on ``<name>/goal``, the
  client's ``<name>/feedback`` becomes the goal's feedback, its ``<name>/result`` ends it,
  and a zenros cancel is published on ``<name>/cancel``.

Everything else on those topics still crosses between rosbridge clients unchecked
(opaque.py). Status codes map as in `ros1_status` / `ros2_outcome`.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import itertools
import time
from dataclasses import dataclass, field
from typing import Any

import msgspec
from zenros.action import GoalStatus
from zenros.errors import UnknownTypeError, ZenrosError
from zenros.message import ActionType, Message, normalize_type_name
from zenros.registry import lookup_action

from .convert import message_from_json, to_json
from .frames import OpError
from .host import BridgeHost
from .opaque import ROS1_DEFAULTS

__all__ = ["ActionlibBridge", "actionlib_topics", "ros1_action_name", "ros1_status",
           "ros2_outcome", "zenros_action_type"]

# actionlib_msgs/GoalStatus
PENDING, ACTIVE, PREEMPTED, SUCCEEDED, ABORTED, REJECTED = 0, 1, 2, 3, 4, 5
PREEMPTING, RECALLING, RECALLED, LOST = 6, 7, 8, 9

STATUS_PERIOD_BUSY = 0.2  # s between status arrays while goals are alive (actionlib: 5 Hz)
STATUS_PERIOD_IDLE = 1.0
KEEP_ENDED = 5.0  # s an ended goal stays in the status list (actionlib's status_list_timeout)

ROS1_EQUIVALENTS = {"actionlib_tutorials/Fibonacci": "example_interfaces/Fibonacci"}
"""ROS 1 action types whose ROS 2 counterpart lives in another package (besides the same
``<pkg>/<Name>``); each is used only if the field layouts agree."""


def ros1_action_name(action_type: ActionType) -> str | None:
    """The ROS 1 action ``pkg/Name`` a ROS 1 client would use for a zenros action type: its
    counterpart in ROS1_EQUIVALENTS, else the same name; None if their layouts disagree."""
    ours = normalize_type_name(action_type.name)
    for ros1, zenros in ROS1_EQUIVALENTS.items():
        if zenros == ours and layouts_agree(ros1, action_type):
            return ros1
    return ours if layouts_agree(ours, action_type) else None


def actionlib_topics(name: str, ros1: str) -> dict[str, str]:
    """The topics an actionlib server of ROS 1 action ``ros1`` (``pkg/Name``) on ``name``
    publishes, with their types (long form, as rosapi lists them): ``status``, ``feedback``
    and ``result``, from its start."""
    pkg, _, short = ros1.partition("/")
    return {f"{name}/status": "actionlib_msgs/msg/GoalStatusArray",
            f"{name}/feedback": f"{pkg}/msg/{short}ActionFeedback",
            f"{name}/result": f"{pkg}/msg/{short}ActionResult"}


def ros1_status(status: GoalStatus, was_active: bool) -> int:
    """A zenros goal state as actionlib's GoalStatus (``was_active``: it ran before it ended)."""
    if status in (GoalStatus.UNKNOWN, GoalStatus.ACCEPTED):
        return PENDING
    if status is GoalStatus.EXECUTING:
        return ACTIVE
    if status is GoalStatus.CANCELING:
        return PREEMPTING if was_active else RECALLING
    if status is GoalStatus.SUCCEEDED:
        return SUCCEEDED
    if status is GoalStatus.CANCELED:
        return PREEMPTED if was_active else RECALLED
    if status is GoalStatus.ABORTED:
        return ABORTED
    if status is GoalStatus.REJECTED:
        return REJECTED
    return LOST


def ros2_outcome(status: Any, cancel_requested: bool) -> GoalStatus:
    """How a zenros goal ends when its ROS 1 server reports ``status`` in a result."""
    if status == SUCCEEDED:
        return GoalStatus.SUCCEEDED
    if status in (PREEMPTED, RECALLED) and cancel_requested:
        return GoalStatus.CANCELED
    return GoalStatus.ABORTED


def _base(type_name: str, suffix: str) -> str | None:
    """``pkg/NameActionGoal`` → ``pkg/Name`` (None if ``type_name`` is not such a type)."""
    name: str = normalize_type_name(type_name)
    tail = "Action" + suffix
    if "/" not in name or not name.endswith(tail) or len(name.split("/", 1)[1]) <= len(tail):
        return None
    return name[: -len(tail)]


def _layout(msg_type: type[Message]) -> set[str]:
    return {f.name for f in msgspec.structs.fields(msg_type)}


def layouts_agree(ros1: str, action_type: ActionType) -> bool:
    """Whether the ROS 1 action ``pkg/Name`` has the zenros type's Goal, Result and Feedback
    fields (checked when the bridge knows the ROS 1 layout, opaque.ROS1_DEFAULTS; else left to
    each message, which fails on a field the zenros type lacks)."""
    parts = {"Goal": ("goal", action_type.Goal), "Result": ("result", action_type.Result),
             "Feedback": ("feedback", action_type.Feedback)}
    for suffix, (inner, msg_type) in parts.items():
        defaults = ROS1_DEFAULTS.get(f"{ros1}Action{suffix}")
        if defaults is not None and set(defaults[inner]) != _layout(msg_type):
            return False
    return True


def zenros_action_type(ros1: str) -> ActionType | None:
    """The zenros action type a ROS 1 action ``pkg/Name`` maps to: the same name, or its
    counterpart in ROS1_EQUIVALENTS, if the field layouts agree."""
    for name in (ros1, ROS1_EQUIVALENTS.get(ros1)):
        if name is None:
            continue
        try:
            action_type = lookup_action(name)
        except UnknownTypeError:
            continue
        if layouts_agree(ros1, action_type):
            return action_type
    return None


def _stamp(seconds: float | None = None) -> dict[str, int]:
    t = time.time() if seconds is None else seconds
    secs = int(t)
    return {"secs": secs, "nsecs": int((t - secs) * 1e9)}


def _header() -> dict[str, Any]:
    return {"seq": 0, "stamp": _stamp(), "frame_id": ""}


def _seconds(stamp: Any) -> float:
    if not isinstance(stamp, dict):
        return 0.0
    sec = stamp.get("secs", stamp.get("sec", 0)) or 0
    nsec = stamp.get("nsecs", stamp.get("nanosec", 0)) or 0
    return float(sec) + float(nsec) / 1e9


@dataclass
class _ClientGoal:
    """One ROS 1 goal sent to a zenros action."""

    goal_id: dict[str, Any]
    accepted_at: float
    handle: Any = None
    status: int = PENDING
    text: str = ""
    was_active: bool = False
    ended_at: float | None = None

    def refresh(self) -> None:
        if self.handle is None or self.ended_at is not None:
            return
        st = self.handle.status
        self.was_active = self.was_active or st is GoalStatus.EXECUTING
        self.status = ros1_status(st, self.was_active)


@dataclass
class ActionProxy:
    """A zenros action seen by ROS 1 clients as actionlib topics."""

    bridge: BridgeHost
    name: str
    action_type: ActionType
    goals: dict[str, _ClientGoal] = field(default_factory=dict)
    task: asyncio.Task[None] | None = None
    _ids: itertools.count[int] = field(default_factory=lambda: itertools.count(1))

    def publish(self, part: str, msg: dict[str, Any]) -> None:
        self.bridge.opaque.publish(f"{self.name}/{part}", msg)

    def status_msg(self, entry: _ClientGoal) -> dict[str, Any]:
        return {"goal_id": entry.goal_id, "status": entry.status, "text": entry.text}

    def publish_status(self) -> None:
        now = time.monotonic()
        for gid in [g for g, e in self.goals.items()
                    if e.ended_at is not None and now - e.ended_at > KEEP_ENDED]:
            del self.goals[gid]
        for entry in self.goals.values():
            entry.refresh()
        self.publish("status", {"header": _header(),
                                "status_list": [self.status_msg(e) for e in self.goals.values()]})

    def on_goal(self, msg: Any) -> None:
        """A client's ``<name>/goal`` (on the bridge's loop)."""
        if not isinstance(msg, dict):
            raise OpError(f"{self.name}/goal: expected an object")
        given = msg.get("goal_id")
        goal_id: dict[str, Any] = given if isinstance(given, dict) else {}
        gid = goal_id.get("id")
        stamp = goal_id.get("stamp")
        if not isinstance(gid, str) or not gid:  # actionlib makes one up, so does the bridge
            gid = f"{self.name}-{next(self._ids)}-{time.time():.3f}"
        if not _seconds(stamp):
            stamp = _stamp()
        entry = _ClientGoal({"stamp": stamp, "id": gid}, _seconds(stamp))
        self.goals[gid] = entry
        try:
            goal = message_from_json(msg.get("goal") or {}, self.action_type.Goal)
        except (ValueError, TypeError) as exc:
            self._end(entry, REJECTED, f"goal does not fit {self.action_type.name}: {exc}",
                      to_json(self.action_type.Result()))
            raise OpError(f"{self.name}/goal: {exc}") from None
        client = self.bridge.action_client(self.action_type, self.name)
        loop = self.bridge.loop

        def on_feedback(fb: Any) -> None:  # on the action client's feedback thread
            loop.call_soon_threadsafe(self._feedback, entry, to_json(fb.feedback))

        try:
            entry.handle = client.send_goal_async(goal, on_feedback)
        except (ZenrosError, ValueError, TypeError) as exc:
            self._end(entry, REJECTED, str(exc), to_json(self.action_type.Result()))
            raise OpError(f"{self.name}/goal: {exc}") from None
        self.publish_status()
        task = loop.create_task(self._await_result(entry))
        self.bridge.background.add(task)
        task.add_done_callback(self.bridge.background.discard)

    def _feedback(self, entry: _ClientGoal, feedback: Any) -> None:
        if entry.ended_at is not None:
            return
        entry.was_active = True
        entry.refresh()
        if entry.status == PENDING:
            entry.status = ACTIVE
        self.publish("feedback", {"header": _header(), "status": self.status_msg(entry),
                                  "feedback": feedback})

    async def _await_result(self, entry: _ClientGoal) -> None:
        try:
            result = await entry.handle.result_async()
        except (ZenrosError, RuntimeError) as exc:
            self._end(entry, LOST, str(exc), to_json(self.action_type.Result()))
            return
        entry.refresh()
        self._end(entry, ros1_status(result.status, entry.was_active), result.reason,
                  to_json(result.result))

    def _end(self, entry: _ClientGoal, status: int, text: str, result: Any) -> None:
        entry.status, entry.text, entry.ended_at = status, text, time.monotonic()
        self.publish("result", {"header": _header(), "status": self.status_msg(entry),
                                "result": result})
        self.publish_status()

    def on_cancel(self, msg: Any) -> None:
        """A client's ``<name>/cancel`` (an actionlib_msgs/GoalID): an id cancels that goal, a
        stamp every goal sent at or before it, neither of them every goal."""
        msg = msg if isinstance(msg, dict) else {}
        gid = msg.get("id") or ""
        before = _seconds(msg.get("stamp"))
        for key, entry in list(self.goals.items()):
            if entry.ended_at is not None or entry.handle is None:
                continue
            hit = (not gid and not before) or key == gid or (before and entry.accepted_at <= before)
            if hit:
                entry.status = PREEMPTING if entry.was_active else RECALLING
                task = asyncio.ensure_future(asyncio.to_thread(entry.handle.cancel))
                self.bridge.background.add(task)
                task.add_done_callback(self.bridge.background.discard)
        self.publish_status()

    def alive(self) -> bool:
        entry = self.bridge.opaque.topics.get(f"{self.name}/goal")
        live = any(e.ended_at is None for e in self.goals.values())
        return live or (entry is not None and bool(entry.advertisers))

    async def run(self) -> None:
        while self.alive():
            self.publish_status()
            busy = any(e.ended_at is None for e in self.goals.values())
            await asyncio.sleep(STATUS_PERIOD_BUSY if busy else STATUS_PERIOD_IDLE)


@dataclass
class _ServedGoal:
    handle: Any
    future: concurrent.futures.Future[tuple[int, Any]]


class Ros1Server:
    """A ROS 1 action server of a rosbridge client (roslibpy ``SimpleActionServer``), served
    as a zenros action."""

    def __init__(self, bridge: BridgeHost, name: str,
                 action_type: ActionType[Message, Message, Message], owner: Any) -> None:
        self.bridge = bridge
        self.name = name
        self.action_type = action_type
        self.owner = owner
        self.goals: dict[str, _ServedGoal] = {}
        self._ids = itertools.count(1)
        self.server = bridge.node.create_action_server(
            action_type, name, self.execute, cancel_callback=self.on_cancel, policy="parallel")
        self.task: asyncio.Task[None] | None = None

    def _publish(self, part: str, msg: dict[str, Any]) -> None:  # from any thread
        self.bridge.loop.call_soon_threadsafe(
            self.bridge.opaque.publish, f"{self.name}/{part}", msg)

    async def execute(self, handle: Any) -> Message:
        """The zenros server's execute callback (on the node's event loop)."""
        gid = f"zenros-{self.name}-{next(self._ids)}-{time.time():.3f}"
        fut: concurrent.futures.Future[tuple[int, Any]] = concurrent.futures.Future()
        self.goals[gid] = _ServedGoal(handle, fut)
        self._publish("goal", {"header": _header(), "goal_id": {"stamp": _stamp(), "id": gid},
                               "goal": to_json(handle.request)})
        try:
            status, values = await asyncio.wrap_future(fut)
        except RuntimeError:
            handle.abort()
            return self.action_type.Result()
        finally:
            self.goals.pop(gid, None)
        try:
            result = message_from_json(values or {}, self.action_type.Result)
        except (ValueError, TypeError):
            handle.abort()
            return self.action_type.Result()
        outcome = ros2_outcome(status, handle.is_cancel_requested)
        if outcome is GoalStatus.SUCCEEDED:
            handle.succeed()
        elif outcome is GoalStatus.CANCELED:
            handle.canceled()
        else:
            handle.abort()
        return result

    def on_cancel(self, handle: Any) -> bool:
        for gid, goal in list(self.goals.items()):
            if goal.handle is handle:
                self._publish("cancel", {"stamp": {"secs": 0, "nsecs": 0}, "id": gid})
        return True

    def _goal_of(self, msg: Any) -> tuple[str, _ServedGoal] | None:
        status = msg.get("status") if isinstance(msg, dict) else None
        goal_id = status.get("goal_id") if isinstance(status, dict) else None
        gid = goal_id.get("id") if isinstance(goal_id, dict) else None
        goal = self.goals.get(gid) if isinstance(gid, str) else None
        return None if goal is None or gid is None else (gid, goal)

    def on_feedback(self, msg: Any) -> None:
        """The client's ``<name>/feedback`` (on the bridge's loop)."""
        found = self._goal_of(msg)
        if found is None:
            return  # a goal of another rosbridge client, not of a zenros one
        feedback = message_from_json(msg.get("feedback") or {}, self.action_type.Feedback)
        found[1].handle.publish_feedback(feedback)

    def on_result(self, msg: Any) -> None:
        found = self._goal_of(msg)
        if found is None or found[1].future.done():
            return
        found[1].future.set_result((msg["status"].get("status"), msg.get("result")))

    def alive(self) -> bool:
        entry = self.bridge.opaque.topics.get(f"{self.name}/goal")
        return entry is not None and self.owner in entry.sinks and not self.owner.closed

    async def run(self) -> None:
        while self.alive():
            await asyncio.sleep(0.5)

    def close(self) -> None:
        for goal in list(self.goals.values()):
            if not goal.future.done():
                goal.future.set_exception(RuntimeError(f"{self.name}: its server left"))
        self.bridge.loop.run_in_executor(None, self.server.close)


class ActionlibBridge:
    """The actionlib proxies and served actions of one bridge (on its loop)."""

    def __init__(self, bridge: BridgeHost) -> None:
        self.bridge = bridge
        self.proxies: dict[str, ActionProxy] = {}
        self.served: dict[str, Ros1Server] = {}

    def advertised(self, topic: str, type_name: str) -> None:
        """A client advertised ``topic`` with an unregistered type: a ROS 1 action client of a
        zenros action?"""
        ros1 = _base(type_name, "Goal")
        if ros1 is None or not topic.endswith("/goal"):
            return
        name = topic[: -len("/goal")]
        if name in self.proxies or name in self.served:
            return  # already bridged, or served by a rosbridge client: it stays between clients
        entry = self.bridge.opaque.topics.get(topic)
        if entry is not None and entry.sinks:
            return  # a rosbridge client serves it (it reads the goals): between clients
        types = self.bridge.node.graph.actions().get(name)
        if not types:
            return
        try:
            action_type = lookup_action(types[0])
        except UnknownTypeError:
            return
        if not layouts_agree(ros1, action_type):
            return
        proxy = self.proxies[name] = ActionProxy(self.bridge, name, action_type)
        hooks = self.bridge.opaque.hooks
        hooks[topic] = proxy.on_goal
        hooks[name + "/cancel"] = proxy.on_cancel
        proxy.task = self.bridge.loop.create_task(proxy.run())
        proxy.task.add_done_callback(lambda _: self._drop_proxy(name, proxy))

    def offered_topics(self) -> dict[str, str]:
        """The actionlib topics of every zenros action a ROS 1 client can use through the
        bridge (`advertised`), with their ROS 1 types: what a ROS 1 master lists of an
        actionlib server from its start (rosapi ``topics``), before any client sends a goal."""
        out: dict[str, str] = {}
        for name, types in self.bridge.node.graph.actions().items():
            try:
                action_type = lookup_action(types[0]) if types else None
            except UnknownTypeError:
                continue
            ros1 = None if action_type is None else ros1_action_name(action_type)
            if ros1 is not None:
                out.update(actionlib_topics(name, ros1))
        return out

    def _drop_proxy(self, name: str, proxy: ActionProxy) -> None:
        if self.proxies.get(name) is proxy:
            del self.proxies[name]
            for part in ("/goal", "/cancel"):
                self.bridge.opaque.hooks.pop(name + part, None)

    def subscribed(self, topic: str, type_name: str, owner: Any) -> None:
        """A client subscribed ``topic`` with an unregistered type: a ROS 1 action server
        that can be served as a zenros action?"""
        ros1 = _base(type_name, "Goal")
        if ros1 is None or not topic.endswith("/goal"):
            return
        name = topic[: -len("/goal")]
        if name in self.served or name in self.proxies or self.bridge.node.graph.actions().get(name):
            return
        action_type = zenros_action_type(ros1)
        if action_type is None:
            return
        served = self.served[name] = Ros1Server(self.bridge, name, action_type, owner)
        hooks = self.bridge.opaque.hooks
        hooks[name + "/feedback"] = served.on_feedback
        hooks[name + "/result"] = served.on_result
        served.task = self.bridge.loop.create_task(served.run())
        served.task.add_done_callback(lambda _: self._drop_served(name, served))

    def _drop_served(self, name: str, served: Ros1Server) -> None:
        if self.served.get(name) is served:
            del self.served[name]
            for part in ("/feedback", "/result"):
                self.bridge.opaque.hooks.pop(name + part, None)
        served.close()

    def close(self) -> None:
        for proxy in list(self.proxies.values()):
            if proxy.task is not None:
                proxy.task.cancel()
        for served in list(self.served.values()):
            if served.task is not None:
                served.task.cancel()
