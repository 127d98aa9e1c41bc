"""Snapshots of a container for introspection: its structure tree and its status tree."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .introspection import ContainerStatus, StateStructure, snapshot_userdata
from .state import State

if TYPE_CHECKING:
    from .container import Container

__all__ = ["active_paths", "status_of", "structure_of"]


def structure_of(container: Container) -> StateStructure:
    """The container's declared interface, internal edges and children, recursively."""
    children = []
    for label, child in container.children.items():
        node = child.get_structure()
        node.remapping = container.remapping_of(label)
        children.append(node)
    node = State.get_structure(container)
    node.is_container = True
    node.initial_states = container.get_initial_states()
    node.transitions = container._edges()
    node.info = container._info()
    node.children = children
    return node


def status_of(container: Container) -> ContainerStatus:
    """What the container and every container inside it are doing now."""
    from .container import Container

    with container._lock:
        running = container.is_running
        active = container.get_active_states()
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
        info=container._info(),
        children=[c.get_status() for c in container.children.values() if isinstance(c, Container)],
    )


def active_paths(container: Container, active: list[str]) -> list[str]:
    """The paths of the deepest active states below the ``active`` children of ``container``."""
    from .container import Container

    paths: list[str] = []
    children = container.children
    for label in active:
        child = children.get(label)
        if child is None:
            continue
        deeper = []
        if isinstance(child, Container):
            deeper = active_paths(child, child.get_active_states())
        paths += deeper or [child.path]
    return paths
