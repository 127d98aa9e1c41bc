"""`ActuatorLink`: actuator moves for the tasks service, over the chassis's
``actuators/move`` (zenros_msgs/MoveActuator) and followed on its ``actuators/state``.

A move is one service call that starts it; the axis's state then says where it is, whether it
still moves and whether it stopped on a fault (a limit reached in speed mode). Only states
stamped after the call's answer count: a state sent before the move started says nothing of
it. Cancelling stops the axis.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

from zenros.errors import ZenrosError
from zenros.msgs.zenros_msgs import ActuatorState, MoveActuator, MoveActuatorRequest
from zenros.node import Node

from .robot import Outcome
from .state_watch import Silent, StateWatch

__all__ = ["ActuatorLink"]

MODES: Final = {0: "home", 1: "run", 2: "stop", 3: "move"}


class ActuatorLink:
    """Moves one axis at a time per call; ``silence`` wall seconds without a state from the
    chassis end a move in error (the chassis is gone)."""

    def __init__(self, node: Node, call_timeout: float = 5.0, silence: float = 10.0) -> None:
        self.node = node
        self.call_timeout = call_timeout
        self.silence = silence
        self._client: Any = None  # made at the first move: most robots' tasks never move one
        self._watch: StateWatch[ActuatorState] = StateWatch(silence)
        self._sub: Any = None

    def move(self, axis: str, mode: int, target: float, speed: float, duration: float,
             progress: Callable[[float], None], cancelled: Callable[[], bool]) -> Outcome:
        """`Robot.move_axis`."""
        what = _describe(axis, mode, target, speed, duration)
        if self._sub is None:  # the state is published only while someone listens
            self._client = self.node.create_client(MoveActuator, "actuators/move")
            self._sub = self.node.create_subscription(ActuatorState, "actuators/state",
                                                      self._watch)
        req = MoveActuatorRequest(name=axis, mode=mode, position=target, speed=speed,
                                  duration=duration)
        try:
            res = self._client.call(req, timeout=self.call_timeout)
        except ZenrosError as exc:
            return Outcome("error", f"{what}: {exc}")
        if not res.success:
            return Outcome("error", f"{what}: {res.message}")
        if mode == MoveActuatorRequest.MODE_STOP:
            return Outcome("complete", f"{axis} {res.message}")
        i = res.state.name.index(axis)
        return self._follow(axis, i, mode, res.state, target, duration, progress, cancelled,
                            what)

    def _follow(self, axis: str, i: int, mode: int, start: ActuatorState, target: float,
                duration: float, progress: Callable[[float], None],
                cancelled: Callable[[], bool], what: str) -> Outcome:
        since = start.header.stamp
        begin = start.position[i]
        while True:
            try:
                state = self._watch.next_after(since, cancelled)
            except Silent:
                return Outcome("error", f"{what}: no actuators/state from the chassis for "
                                        f"{self.silence:g} s")
            if state is None:
                self._stop(axis)
                return Outcome("preempted")
            since = state.header.stamp
            pos = state.position[i]
            if mode == MoveActuatorRequest.MODE_SPEED:
                elapsed = since.to_sec() - start.header.stamp.to_sec()
                progress(elapsed / duration if duration > 0 else 1.0)
            else:
                goal = state.low[i] if mode == MoveActuatorRequest.MODE_HOME else target
                span = abs(goal - begin)
                progress(abs(pos - begin) / span if span > 1e-9 else 1.0)
            if state.moving[i]:
                continue
            if state.fault[i]:
                return Outcome("error", f"{what}: {state.fault[i]}")
            if mode == MoveActuatorRequest.MODE_HOME and state.zero_status[i] != 1:
                return Outcome("error", f"{what}: homing failed (zero_status "
                                        f"{state.zero_status[i]})")
            progress(1.0)
            return Outcome("complete", f"{axis} at {pos:.4g}")

    def _stop(self, axis: str) -> None:
        try:
            self._client.call(MoveActuatorRequest(name=axis, mode=MoveActuatorRequest.MODE_STOP),
                             timeout=self.call_timeout)
        except ZenrosError as exc:
            self.node.logger.warning("could not stop %s: %s", axis, exc)


def _describe(axis: str, mode: int, target: float, speed: float, duration: float) -> str:
    if mode == MoveActuatorRequest.MODE_POSITION:
        return f"{axis} to {target:g}" + (f" at {speed:g}" if speed else "")
    if mode == MoveActuatorRequest.MODE_SPEED:
        return f"{axis} at {speed:g} for {duration:g} s"
    return f"{axis} {MODES.get(mode, f'mode {mode}')}"
