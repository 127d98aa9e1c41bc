"""`IntrospectionServer`: publish a machine's structure, status and events over Zenoh."""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING, Self

from ..errors import SmachError
from ..qos import QOS_LATCHED
from .container import Container
from .introspection import (
    ContainerEvent,
    ContainerStatus,
    SetInitialState,
    SetInitialStateRequest,
    SetInitialStateResponse,
    StateStructure,
)
from .snapshot import status_at_event

if TYPE_CHECKING:
    from ..node import Node

__all__ = ["IntrospectionServer"]


class IntrospectionServer:
    """Let tools watch and seed a running machine, as smach_ros's IntrospectionServer.

    Under ``name`` (default ``~/smach``, i.e. ``/<node>/smach``) it serves:

    - ``<name>/structure`` (`StateStructure`, latched): the whole tree, republished when an
      initial state changes;
    - ``<name>/status`` (`ContainerStatus`, latched): active states and userdata of every
      container, on each start, transition and termination and every ``period`` seconds;
    - ``<name>/events`` (`ContainerEvent`): each event as it happens;
    - ``<name>/set_initial_state`` (`SetInitialState` service): where the container at
      ``path`` starts and which userdata it gets, at once if it is idle, else at its next
      run (`Container.schedule_initial_state`).

    `zenros smach show` draws the tree from the first two. The server starts in the
    constructor; `close` (or closing the node) stops it.

    Args:
        node: The node that publishes.
        machine: The root container.
        name: The server's name (a topic namespace; resolved against the node).
        period: Seconds between status heartbeats.
    """

    def __init__(self, node: Node, machine: Container, name: str = "~/smach",
                 period: float = 1.0) -> None:
        if not isinstance(machine, Container):
            raise SmachError(
                f"IntrospectionServer serves a container, got {type(machine).__name__}")
        self.node = node
        self.machine = machine
        self.name = node.resolve_name(name)
        self._lock = threading.Lock()
        self.closed = False
        self._structure = node.create_publisher(StateStructure, f"{self.name}/structure",
                                                QOS_LATCHED)
        self._status = node.create_publisher(ContainerStatus, f"{self.name}/status", QOS_LATCHED)
        self._events = node.create_publisher(ContainerEvent, f"{self.name}/events", 100)
        self._service = node.create_service(SetInitialState, f"{self.name}/set_initial_state",
                                            self.handle_set_initial_state)
        self.publish_structure()
        self.publish_status()
        self._remove_listener = machine.add_listener(self._on_event)
        self._timer = node.create_timer(period, self.publish_status)
        node.add_waitable(self)

    def set_machine(self, machine: Container) -> None:
        """Watch ``machine`` from now on instead (a service that runs one machine after
        another, such as the tasks service, keeps one server): its structure and status are
        published at once."""
        if not isinstance(machine, Container):
            raise SmachError(
                f"IntrospectionServer serves a container, got {type(machine).__name__}")
        with self._lock:
            if self.closed:
                return
            self._remove_listener()
            self.machine = machine
            self._remove_listener = machine.add_listener(self._on_event)
        self.publish_structure()
        self.publish_status()

    def publish_structure(self) -> None:
        """Publish the machine's structure now."""
        with self._lock:
            if not self.closed:
                self._structure.publish(self.machine.get_structure())

    def publish_status(self) -> None:
        """Publish the machine's status now."""
        with self._lock:
            if not self.closed:
                self._status.publish(self.machine.get_status())

    def _on_event(self, event: ContainerEvent) -> None:
        with self._lock:  # one event at a time, so the last status published is the newest
            if self.closed:
                return
            self._events.publish(event)
            self._status.publish(status_at_event(self.machine, event))

    def handle_set_initial_state(self, request: SetInitialStateRequest) -> SetInitialStateResponse:
        """Serve ``set_initial_state``: refusals come back as ``success=False`` with the reason."""
        try:
            target = self.machine.find(request.path)
            if not isinstance(target, Container):
                raise SmachError(f"{target.describe()} is not a container; only containers"
                                 " have initial states")
            applied = target.schedule_initial_state(request.initial_states, request.userdata)
        except SmachError as exc:
            return SetInitialStateResponse(success=False, message=str(exc))
        self.publish_structure()
        self.publish_status()
        when = "now" if applied else f"when {target.path} next starts"
        return SetInitialStateResponse(success=True, applied=applied,
                                       message=f"initial state of {target.path} set; applies {when}")

    def close(self) -> None:
        """Stop publishing and serving; the machine keeps running."""
        with self._lock:
            if self.closed:
                return
            self.closed = True
        self._remove_listener()
        self._timer.cancel()
        for endpoint in (self._service, self._events, self._status, self._structure):
            self.node.destroy(endpoint)

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<IntrospectionServer {self.name} of {self.machine.describe()}>"
