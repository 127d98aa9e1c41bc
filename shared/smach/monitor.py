"""`MonitorState`: subscribe to a topic while active and judge each message with a condition."""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Generic, TypeVar

from ..errors import InvalidStateError, InvalidUserCodeError
from ..message import Message
from ..qos import QoSProfile
from .ros_state import RosState
from .userdata import UserDataAccess

if TYPE_CHECKING:
    from ..node import Node

__all__ = ["MonitorState"]

M = TypeVar("M", bound=Message)


class MonitorState(RosState, Generic[M]):
    """Watch ``topic`` and end when ``cond_cb`` turns False, as smach_ros's MonitorState.

    On entry the state subscribes to ``topic``; each message is passed to
    ``cond_cb(userdata, msg)``. The first False ends the state with ``"invalid"``;
    ``max_checks`` True answers in a row end it with ``"valid"`` (``-1``: never, so the
    state monitors until the condition fails or a preempt comes). A preempt ends it at once
    with ``"preempted"``, and so does a preempt requested before it started. ``timeout``
    seconds without a verdict give ``"invalid"``. The subscription is dropped on exit.

    The condition runs on the thread that delivered the message (one message at a time);
    it may write the state's output keys (``userdata.last = msg``). If it raises, the
    state raises `InvalidUserCodeError` from ``execute``.

    Example:
        >>> MonitorState(node, "battery", BatteryState,
        ...              lambda ud, msg: msg.percentage > 0.2)   # "invalid" when low

    Args:
        node: The node that subscribes.
        topic: The topic name (resolved against the node).
        msg_type: The message type.
        cond_cb: ``cond_cb(userdata, msg) -> bool``; may carry a `cb_interface`.
        max_checks: True answers that make the outcome ``"valid"``; -1: no limit.
        timeout: Seconds to wait for a verdict; None: no limit.
        input_keys: Keys the condition reads.
        output_keys: Keys the condition writes.
        qos: The subscription's QoS (a latched topic needs a latched profile).
    """

    def __init__(
        self,
        node: Node,
        topic: str,
        msg_type: type[M],
        cond_cb: Callable[[UserDataAccess, M], bool],
        max_checks: int = -1,
        timeout: float | None = None,
        input_keys: Sequence[str] = (),
        output_keys: Sequence[str] = (),
        qos: QoSProfile | int = 10,
    ) -> None:
        if not callable(cond_cb):
            raise InvalidStateError(f"cond_cb must be callable, got {type(cond_cb).__name__}")
        if max_checks == 0 or max_checks < -1:
            raise InvalidStateError(f"max_checks must be >= 1, or -1 for ever; got {max_checks}")
        if timeout is not None and timeout < 0:
            raise InvalidStateError(f"timeout must be >= 0 or None, got {timeout}")
        super().__init__(node, ("valid", "invalid", "preempted"), input_keys, output_keys,
                         callbacks=(cond_cb,))
        self.topic = node.resolve_name(topic)
        self.msg_type = msg_type
        self._cond_cb = cond_cb
        self._max_checks = max_checks
        self._timeout = timeout
        self._qos = qos
        self._cb_lock = threading.Lock()  # one condition call at a time
        self._userdata: UserDataAccess | None = None
        self._verdict: str | None = None
        self._error: Exception | None = None
        self.checks = 0
        """Messages judged in the current (or last) run."""

    def execute(self, userdata: UserDataAccess) -> str:
        """Subscribe, wait for a verdict, a timeout or a preempt; see the class docstring."""
        if self.take_preempt():
            return "preempted"
        with self._cb_lock:
            self.checks, self._verdict, self._error = 0, None, None
            self._userdata = userdata
        sub = self.node.create_subscription(self.msg_type, self.topic, self._on_message,
                                            self._qos)
        try:
            self.wait_until(lambda: self._verdict is not None, self._timeout)
        finally:
            with self._cb_lock:
                self._userdata = None
            self.node.destroy(sub)
        if self._error is not None:
            raise InvalidUserCodeError(
                f"cond_cb of {self.describe()} raised {type(self._error).__name__}:"
                f" {self._error}") from self._error
        if self.take_preempt():
            return "preempted"
        return self._verdict or "invalid"

    def _on_message(self, msg: M) -> None:
        with self._cb_lock:
            userdata = self._userdata
            if userdata is None or self._verdict is not None:
                return  # not running, or already decided: a late message
            self.checks += 1
            try:
                ok = bool(self._cond_cb(userdata, msg))
            except Exception as exc:  # noqa: BLE001  (user code: re-raised by execute)
                self._error, self._verdict = exc, "invalid"
            else:
                if not ok:
                    self._verdict = "invalid"
                elif self._max_checks != -1 and self.checks >= self._max_checks:
                    self._verdict = "valid"
            decided = self._verdict is not None
        if decided:
            self.notify()

    def __repr__(self) -> str:
        return f"<{self.describe()} topic={self.topic} type={self.msg_type.__name__}>"
