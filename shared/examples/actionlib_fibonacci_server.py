"""ROS 1's actionlib_tutorials ``fibonacci_server``, on rosbridge: the action ``/fibonacci``
as ROS 1 actionlib topics (``/fibonacci/goal``, ``cancel``, ``status``, ``feedback``,
``result``; ``actionlib_tutorials/FibonacciAction``), as roslibjs's examples expect it
(their ``setup_examples.launch`` runs this tutorial's node).

ROS 1 actionlib lives only on the rosbridge side of zenros (docs/rosbridge.md): this node is
a rosbridge client of the gateway, as a ROS 1 node is a client of its master: ``url``, or
else ws://127.0.0.1:<port>/ with the gateway's ``/gateway/rosbridge_port`` as stored on
master (what the gateway uses), else this node's ``rosbridge_port`` (9090). Its
answer is the ROS 1 tutorial's: ``order`` numbers appended to ``[0, 1]`` (order 7:
``[0, 1, 1, 2, 3, 5, 8, 13, 21]``), one every ``period`` seconds, each sent as feedback. The
ROS 2 action ``/fibonacci`` (example_interfaces, fibonacci_server.py) is another endpoint and
is untouched; while this node serves the ROS 1 topics, the bridge leaves them to it.
"""

from __future__ import annotations

import json
import threading
import time
from typing import Any

from websockets.exceptions import ConnectionClosed, InvalidHandshake, InvalidURI
from websockets.sync.client import ClientConnection, connect
from zenros import Node, run
from zenros.errors import ZenrosError
from zenros.param_client import ParameterClient

# actionlib_msgs/GoalStatus
PENDING, ACTIVE, PREEMPTED, SUCCEEDED, REJECTED = 0, 1, 2, 3, 5
MAX_ORDER = 10_000
PKG = "actionlib_tutorials/Fibonacci"


def _stamp() -> dict[str, int]:
    now = time.time()
    return {"secs": int(now), "nsecs": int((now % 1) * 1e9)}


class _Goal:
    def __init__(self, goal_id: dict[str, Any], order: int) -> None:
        self.goal_id = goal_id
        self.order = order
        self.status = PENDING
        self.text = ""
        self.cancel = threading.Event()
        self.ended: float | None = None


class ActionlibFibonacciServer(Node):
    """Serves ``name`` (``/fibonacci``) as ROS 1 actionlib topics through rosbridge."""

    node_name = "actionlib_fibonacci_server"

    def setup(self) -> None:
        self.url = str(self.declare_parameter("url", "")) or self._gateway_url(
            int(self.declare_parameter("rosbridge_port", 9090)))
        self.action = "/" + str(self.declare_parameter("name", "fibonacci")).strip("/")
        self.period = float(self.declare_parameter("period", 0.5))
        self.goals: dict[str, _Goal] = {}
        self._lock = threading.Lock()
        self._ws: ClientConnection | None = None
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._serve, name="actionlib-fibonacci",
                                        daemon=True)
        self._thread.start()

    def _gateway_url(self, port: int) -> str:
        try:
            port = int(ParameterClient(self.context, timeout=2.0).get("/gateway/rosbridge_port"))
        except (ZenrosError, TypeError, ValueError):
            pass  # not stored on master: the launch's value
        return f"ws://127.0.0.1:{port}/"

    # ------------------------------------------------------------------ rosbridge

    def _send(self, frame: dict[str, Any]) -> None:
        ws = self._ws
        if ws is None:
            return
        try:
            ws.send(json.dumps(frame))
        except (ConnectionClosed, OSError):
            pass

    def _publish(self, part: str, msg: dict[str, Any]) -> None:
        self._send({"op": "publish", "topic": f"{self.action}/{part}", "msg": msg})

    def _serve(self) -> None:
        """Connects (and reconnects when the gateway restarts) and serves."""
        while not self._stop.is_set():
            try:
                with connect(self.url, open_timeout=5, max_size=None) as ws:
                    self._ws = ws
                    self._advertise()
                    self.get_logger().info("serving %s (ROS 1 actionlib) on %s",
                                           self.action, self.url)
                    self._read(ws)
            except (OSError, ConnectionClosed, InvalidHandshake, InvalidURI, TimeoutError):
                pass
            self._ws = None
            self._stop.wait(0.5)

    def _advertise(self) -> None:
        a = self.action
        for part, typ in (("status", "actionlib_msgs/GoalStatusArray"),
                          ("feedback", f"{PKG}ActionFeedback"),
                          ("result", f"{PKG}ActionResult")):
            self._send({"op": "advertise", "topic": f"{a}/{part}", "type": typ})
        self._send({"op": "subscribe", "topic": f"{a}/goal", "type": f"{PKG}ActionGoal"})
        self._send({"op": "subscribe", "topic": f"{a}/cancel", "type": "actionlib_msgs/GoalID"})

    def _read(self, ws: ClientConnection) -> None:
        next_status = 0.0
        while not self._stop.is_set():
            now = time.monotonic()
            if now >= next_status:
                self._publish_status()
                busy = any(g.ended is None for g in self.goals.values())
                next_status = now + (0.2 if busy else 1.0)  # actionlib's 5 Hz while busy
            try:
                text = ws.recv(timeout=max(0.01, next_status - time.monotonic()))
            except TimeoutError:
                continue
            try:
                frame = json.loads(text)
            except ValueError:
                continue
            if frame.get("op") != "publish" or not isinstance(frame.get("msg"), dict):
                continue
            if frame.get("topic") == f"{self.action}/goal":
                self._on_goal(frame["msg"])
            elif frame.get("topic") == f"{self.action}/cancel":
                self._on_cancel(frame["msg"])

    # ------------------------------------------------------------------ actionlib

    def _publish_status(self) -> None:
        with self._lock:
            now = time.monotonic()
            for key in [k for k, g in self.goals.items() if g.ended and now - g.ended > 5.0]:
                del self.goals[key]
            status = [{"goal_id": g.goal_id, "status": g.status, "text": g.text}
                      for g in self.goals.values()]
        self._publish("status", {"header": {"stamp": _stamp(), "frame_id": ""},
                                 "status_list": status})

    def _on_goal(self, msg: dict[str, Any]) -> None:
        goal_id = msg.get("goal_id") or {}
        key = str(goal_id.get("id", ""))
        order = (msg.get("goal") or {}).get("order", 0)
        goal = _Goal({"stamp": goal_id.get("stamp") or _stamp(), "id": key},
                     order if isinstance(order, int) else -1)
        with self._lock:
            if key in self.goals:
                return  # a goal is sent once; a repeat is ignored, as actionlib does
            self.goals[key] = goal
        if not 0 <= goal.order <= MAX_ORDER:
            self._end(goal, REJECTED, f"order must be in [0, {MAX_ORDER}]", [])
            return
        threading.Thread(target=self._execute, args=(goal,), daemon=True).start()

    def _on_cancel(self, msg: dict[str, Any]) -> None:
        key = str(msg.get("id", "") or "")
        with self._lock:
            goals = [g for k, g in self.goals.items() if not key or k == key]
        for g in goals:
            g.cancel.set()

    def _execute(self, goal: _Goal) -> None:
        """actionlib_tutorials' fibonacci_server: ``order`` numbers after ``[0, 1]``."""
        goal.status = ACTIVE
        seq = [0, 1]
        for i in range(1, goal.order + 1):
            if goal.cancel.is_set() or self._stop.is_set():
                self._end(goal, PREEMPTED, "preempted", seq)
                return
            seq.append(seq[i] + seq[i - 1])
            self._publish("feedback", {"header": {"stamp": _stamp(), "frame_id": ""},
                                       "status": self._status_of(goal),
                                       "feedback": {"sequence": list(seq)}})
            goal.cancel.wait(self.period)
        self._end(goal, SUCCEEDED, "", seq)

    def _status_of(self, goal: _Goal) -> dict[str, Any]:
        return {"goal_id": goal.goal_id, "status": goal.status, "text": goal.text}

    def _end(self, goal: _Goal, status: int, text: str, seq: list[int]) -> None:
        goal.status, goal.text, goal.ended = status, text, time.monotonic()
        self._publish("result", {"header": {"stamp": _stamp(), "frame_id": ""},
                                 "status": self._status_of(goal),
                                 "result": {"sequence": seq}})
        self._publish_status()

    def close(self) -> None:
        self._stop.set()
        ws = self._ws
        if ws is not None:
            ws.close()
        self._thread.join(5)
        super().close()


if __name__ == "__main__":
    run(ActionlibFibonacciServer)
