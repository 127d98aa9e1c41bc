"""`ElevatorLink`: the building's elevators as the tasks service uses them (docs/building.md):
commands to a car's controller as this robot, and waits on the car's latched state."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Final, Literal

from zenros import Node
from zenros.building import Building
from zenros.errors import ZenrosError
from zenros.msgs.zenros_msgs import ElevatorCommand, ElevatorCommandRequest, ElevatorState
from zenros.qos import QOS_LATCHED

from .outcome import Outcome

__all__ = ["SILENCE", "ElevatorLink", "LbtRequest"]

SILENCE: Final = 10.0  # wall s without a car's state: its controller is gone
CALL_WAIT: Final = 10.0  # s for a command's answer
POLL: Final = 0.02


@dataclass(frozen=True)
class LbtRequest:
    """The last ``lbt_elevator_req_action`` that completed, waiting for its ack."""

    cmd: Literal["enter", "leave"]
    elevator: str
    from_level: int
    to_level: int


class ElevatorLink:
    def __init__(self, node: Node, building: Building) -> None:
        self.building = building
        self.me = node.namespace or "/"
        self._cond = threading.Condition()
        self._states: dict[str, tuple[ElevatorState, float]] = {}
        self._clients: dict[str, Any] = {}
        self.lbt: LbtRequest | None = None  # an lbt_elevator_req_action awaiting its ack
        for e in building.elevators:
            base = f"/building/elevators/{e.name}"
            self._clients[e.name] = node.create_client(ElevatorCommand, f"{base}/command")
            node.create_subscription(ElevatorState, f"{base}/state", self._on_state,
                                     QOS_LATCHED)

    def _on_state(self, msg: ElevatorState) -> None:
        with self._cond:
            self._states[msg.name] = (msg, time.monotonic())
            self._cond.notify_all()

    def state(self, name: str) -> ElevatorState | None:
        with self._cond:
            got = self._states.get(name)
        return None if got is None else got[0]

    def available(self, name: str, timeout: float = 5.0) -> bool:
        """Whether a controller serves car ``name``'s commands (waiting up to ``timeout``)."""
        client = self._clients.get(name)
        return client is not None and bool(client.wait_for_service(timeout))

    def command(self, name: str, command: str, level: int = 0) -> Outcome:
        """Send ``command`` (zenros_msgs/ElevatorCommand) to car ``name`` as this robot."""
        client = self._clients.get(name)
        if client is None:
            return Outcome("error", f"building {self.building.name!r} has no elevator {name!r}")
        try:
            req = ElevatorCommandRequest(command=command, robot=self.me,  # type: ignore[arg-type]
                                         level=level)
            res = client.call(req, timeout=CALL_WAIT)
        except ZenrosError as exc:
            return Outcome("error", f"elevator {name}: {command}: {exc}")
        if not res.success:
            return Outcome("error", f"elevator {name}: {command}: {res.message}")
        return Outcome("complete", res.message)

    def wait(self, name: str, until: Callable[[ElevatorState], bool], what: str,
             deadline: Callable[[], bool], cancelled: Callable[[], bool]) -> Outcome:
        """Wait until car ``name``'s state satisfies ``until``: complete; ``preempted`` once
        ``cancelled()``; error when ``deadline()`` says time is up or the car falls silent."""
        start = time.monotonic()
        with self._cond:
            while True:
                got = self._states.get(name)
                if got is not None and until(got[0]):
                    return Outcome("complete")
                if cancelled():
                    return Outcome("preempted", f"cancelled while waiting for {what}")
                if deadline():
                    return Outcome("error", f"timed out waiting for {what}")
                heard = got[1] if got is not None else start
                if time.monotonic() - max(heard, start) > SILENCE:
                    return Outcome("error", f"no word from elevator {name}'s controller for "
                                            f"{SILENCE:g} s while waiting for {what} (is the "
                                            "elevator service running?)")
                self._cond.wait(POLL)
