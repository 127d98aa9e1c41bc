"""`ElevatorLink`: the building's elevator controller for the doors (docs/building.md): each
car's latched ``/building/elevators/<name>/state`` (zenros_msgs/ElevatorState) and its
``/building/elevators/<name>/command`` service.

The keys are absolute, outside the robot's namespace: every robot of a fleet gateway reaches
the same cars. The elevators are those whose command service is in the graph; the default
one (no name given) is the first by name. Subscriptions and clients are made at first use,
one per elevator asked about.
"""

from __future__ import annotations

import asyncio
import re
import threading

from zenros.msgs.zenros_msgs.elevator import (
    ElevatorCommand,
    ElevatorCommandRequest,
    ElevatorCommandResponse,
    ElevatorState,
)
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.rpc import Client

from ..errors import NotFound, PortError, Refused, Unavailable
from .calls import call_port

__all__ = ["NO_CONTROLLER", "ElevatorLink"]

NO_CONTROLLER = ("no building/elevator controller: launch with building:=PATH (a building "
                 "YAML; docs/building.md)")
_COMMAND = re.compile(r"^/building/elevators/([^/]+)/command$")


class _Car:
    """One elevator's latest state and its command client."""

    def __init__(self, node: Node, name: str) -> None:
        self.state: ElevatorState | None = None
        self.heard = threading.Event()
        node.create_subscription(ElevatorState, f"/building/elevators/{name}/state",
                                 self._on_state, QOS_LATCHED)
        self.client: Client[ElevatorCommandRequest, ElevatorCommandResponse] = (
            node.create_client(ElevatorCommand, f"/building/elevators/{name}/command"))

    def _on_state(self, msg: ElevatorState) -> None:
        self.state = msg
        self.heard.set()


class ElevatorLink:
    """The building's elevators as the controller in the graph serves them."""

    def __init__(self, node: Node, timeout: float = 5.0, first_state: float = 3.0) -> None:
        self.node = node
        self.timeout = timeout
        self.first_state = first_state
        self._cars: dict[str, _Car] = {}
        self._lock = threading.Lock()

    def names(self) -> list[str]:
        """The elevators whose command service is in the graph now, by name."""
        found = (_COMMAND.match(s) for s in self.node.context.graph.services())
        return sorted(m.group(1) for m in found if m)

    def resolve(self, name: str) -> str:
        """``name``, or the default elevator for ""; `Unavailable` with no controller,
        `NotFound` for an elevator the building does not have."""
        names = self.names()
        if not names:
            raise Unavailable(NO_CONTROLLER)
        if not name:
            return names[0]
        if name not in names:
            raise NotFound(f"unknown elevator {name!r} (elevators: {', '.join(names)})")
        return name

    def _car(self, name: str) -> _Car:
        with self._lock:
            car = self._cars.get(name)
            if car is None:
                car = self._cars[name] = _Car(self.node, name)
            return car

    async def state(self, name: str = "") -> ElevatorState:
        """Elevator ``name``'s state (its latched state; the first ask waits
        ``first_state`` s for it)."""
        car = self._car(self.resolve(name))
        if car.state is None:
            await asyncio.to_thread(car.heard.wait, self.first_state)
        if car.state is None:
            raise Unavailable(f"{NO_CONTROLLER}; elevator {name or 'default'!r} published "
                              f"no state within {self.first_state:g} s")
        return car.state

    async def command(self, name: str, req: ElevatorCommandRequest) -> str:
        """Send ``req`` to elevator ``name`` ("": the default); what it did, or `Refused`
        with the controller's reason."""
        car = self._car(self.resolve(name))

        def absent() -> PortError:
            return Unavailable(NO_CONTROLLER)

        res: ElevatorCommandResponse = await call_port(car.client, req, self.timeout, absent,
                                                      "the elevator controller")
        if not res.success:
            raise Refused(res.message)
        return str(res.message)
