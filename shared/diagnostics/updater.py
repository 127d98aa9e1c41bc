"""`Updater`: a node's diagnostic tasks, run on a timer and published on ``/diagnostics``."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from ..msgs.diagnostic_msgs import DiagnosticArray, DiagnosticStatus
from .status import ERROR, OK, DiagnosticStatusWrapper, plain

__all__ = ["CompositeDiagnosticTask", "DiagnosticTask", "FunctionDiagnosticTask", "Updater"]

TaskFn = Callable[[DiagnosticStatusWrapper], Any]
TOPIC = "/diagnostics"


class DiagnosticTask:
    """A named check: ``run(stat)`` fills ``stat`` (summary, values) and returns it."""

    def __init__(self, name: str) -> None:
        self.name = name

    def getName(self) -> str:
        return self.name

    def run(self, stat: DiagnosticStatusWrapper) -> DiagnosticStatusWrapper:
        return stat


class FunctionDiagnosticTask(DiagnosticTask):
    """A task from a function ``fn(stat)``."""

    def __init__(self, name: str, fn: TaskFn) -> None:
        super().__init__(name)
        self.fn = fn

    def run(self, stat: DiagnosticStatusWrapper) -> DiagnosticStatusWrapper:
        out = self.fn(stat)
        return out if isinstance(out, DiagnosticStatusWrapper) else stat


class CompositeDiagnosticTask(DiagnosticTask):
    """Several tasks as one status: each sees the summary passed in, adds its values, and
    the summaries are merged (the worst level, the messages of that kind joined)."""

    def __init__(self, name: str) -> None:
        super().__init__(name)
        self.tasks: list[DiagnosticTask] = []

    def addTask(self, task: DiagnosticTask) -> None:
        self.tasks.append(task)

    add_task = addTask

    def run(self, stat: DiagnosticStatusWrapper) -> DiagnosticStatusWrapper:
        combined = DiagnosticStatusWrapper()
        original = (stat.level, stat.message)
        for task in self.tasks:
            stat.summary(*original)
            stat = task.run(stat)
            combined.merge_summary(stat)
        stat.summary(combined)
        return stat


class Updater:
    """rclpy diagnostic_updater's ``Updater(node, period=1.0)``.

    ``add(task)`` or ``add(name, fn)`` adds a task (and sends it once as OK "Node starting
    up"); every ``period`` s (parameter ``diagnostic_updater.period``) each task runs on a
    fresh status (ERROR "No message was set" until it says otherwise) and the statuses go
    out in one DiagnosticArray on ``/diagnostics``, named ``<node>: <task>`` (the node's
    full name with parameter ``diagnostic_updater.use_fqn``). ``hardware_id`` is set on
    each; ``force_update()`` publishes now; ``broadcast(level, message)`` sends that
    summary for every task. A task that raises reports ERROR with the exception."""

    def __init__(self, node: Any, period: float = 1.0) -> None:
        self.node = node
        self.hardware_id = ""
        self.verbose = False
        self._tasks: list[DiagnosticTask] = []
        self._lock = threading.RLock()
        self.period = float(node.declare_parameter("diagnostic_updater.period", float(period)))
        if not self.period > 0:
            raise ValueError(f"diagnostic_updater.period must be > 0 s, got {self.period}")
        use_fqn = bool(node.declare_parameter("diagnostic_updater.use_fqn", False))
        self._prefix = f"{node.fqn if use_fqn else node.name}: "
        self._pub = node.create_publisher(DiagnosticArray, TOPIC, 10)
        self._timer = node.create_timer(self.period, self.update)

    @property
    def tasks(self) -> list[DiagnosticTask]:
        with self._lock:
            return list(self._tasks)

    def setHardwareID(self, hwid: str) -> None:
        self.hardware_id = hwid

    def add(self, task: DiagnosticTask | str, fn: TaskFn | None = None) -> DiagnosticTask:
        """Add ``task``, or a task named ``task`` calling ``fn(stat)``; returns it."""
        if isinstance(task, str):
            if fn is None:
                raise TypeError("add(name, fn): a task function is needed")
            task = FunctionDiagnosticTask(task, fn)
        with self._lock:
            self._tasks.append(task)
        stat = DiagnosticStatusWrapper(name=task.name, hardware_id=self.hardware_id)
        stat.summary(OK, "Node starting up")
        self._publish([stat])
        return task

    def removeByName(self, name: str) -> bool:
        with self._lock:
            for k, t in enumerate(self._tasks):
                if t.name == name:
                    del self._tasks[k]
                    return True
        return False

    remove_by_name = removeByName

    def update(self) -> None:
        """Run every task and publish their statuses (the timer's tick)."""
        out = []
        for task in self.tasks:
            stat = DiagnosticStatusWrapper(name=task.name, level=ERROR,
                                           message="No message was set",
                                           hardware_id=self.hardware_id)
            try:
                stat = task.run(stat)
            except Exception as e:  # noqa: BLE001 - a failing check is a status, not a crash
                stat.summary(ERROR, f"task raised {type(e).__name__}: {e}")
            stat.name = task.name
            out.append(stat)
            if self.verbose and stat.level:
                self.node.get_logger().warning(f"Non-zero diagnostic status. Name: "
                                               f"{stat.name}, status {stat.level}: {stat.message}")
        self._publish(out)

    force_update = update

    def broadcast(self, level: int, message: str) -> None:
        """Send ``(level, message)`` as every task's status (a device gone, say)."""
        out = []
        for task in self.tasks:
            stat = DiagnosticStatusWrapper(name=task.name, hardware_id=self.hardware_id)
            stat.summary(level, message)
            out.append(stat)
        self._publish(out)

    def _publish(self, statuses: list[DiagnosticStatusWrapper]) -> None:
        msg = DiagnosticArray(status=[_named(plain(s), self._prefix) for s in statuses])
        msg.header.stamp = self.node.now()
        self._pub.publish(msg)


def _named(s: DiagnosticStatus, prefix: str) -> DiagnosticStatus:
    s.name = prefix + s.name
    return s
