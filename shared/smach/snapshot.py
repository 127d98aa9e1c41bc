"""Snapshots of a container for introspection: its structure tree and its status tree."""

from __future__ import annotations

from .introspection import ContainerEvent, ContainerStatus, StateStructure, snapshot_userdata
from .parent import Parent
from .state import join_path

__all__ = ["active_paths", "status_at_event", "status_of", "structure_of"]


def structure_of(container: Parent, own: StateStructure) -> StateStructure:
    """The container's declared interface (``own``: `State.get_structure` of it), its internal
    edges and its children, recursively."""
    children = []
    for label, child in container.children.items():
        node = child.get_structure()
        node.remapping = container.remapping_of(label)
        children.append(node)
    node = own
    node.is_container = True
    node.initial_states = container.get_initial_states()
    node.transitions = container.get_transitions()
    node.info = container.get_info()
    node.children = children
    return node


def status_of(container: Parent) -> ContainerStatus:
    """What the container and every container inside it are doing now."""
    running, active = container.get_run_state()
    plain, skipped = snapshot_userdata(container.userdata.snapshot())
    return ContainerStatus(
        path=container.path,
        type=type(container).__name__,
        running=running,
        initial_states=container.get_initial_states(),
        active_states=active,
        active_paths=active_paths(container, active),
        userdata=plain,
        unserializable=skipped,
        last_outcome=container.last_outcome,
        info=container.get_info(),
        children=[c.get_status() for c in container.children.values() if isinstance(c, Parent)],
    )


def active_paths(container: Parent, active: list[str]) -> list[str]:
    """The paths of the deepest active states below the ``active`` children of ``container``."""
    paths: list[str] = []
    children = container.children
    for label in active:
        child = children.get(label)
        if child is None:
            continue
        deeper = []
        if isinstance(child, Parent):
            deeper = active_paths(child, child.get_active_states())
        paths += deeper or [child.path]
    return paths


def status_at_event(root: Parent, event: ContainerEvent) -> ContainerStatus:
    """The status of ``root`` as a listener should report it when ``event`` fires.

    A container emits ``start`` before its first children begin and ``termination`` just
    before it clears its running flag, so the live status lags one step at those two
    events; here the emitting container shows the event's active states (and, at
    ``termination``, that it stopped). Every other event leaves the live status as it is.
    """
    status = status_of(root)
    if event.kind != "transition":
        _apply(status, event)
    return status


def _apply(status: ContainerStatus, event: ContainerEvent) -> bool:
    if status.path == event.path:
        status.active_states = list(event.active_states)
        if event.kind == "termination":
            status.running = False
    elif not any(_apply(child, event) for child in status.children):
        return False
    by_path = {child.path: child for child in status.children}
    paths: list[str] = []
    for label in status.active_states:
        path = join_path(status.path, label)
        child = by_path.get(path)
        paths += (child.active_paths if child is not None else []) or [path]
    status.active_paths = paths
    return True
