"""`Parent`: what the container helpers (wiring checks, snapshots, executions) use of a container.

They are typed against this protocol, not against `Container`, so the imports point one way:
state -> wiring, snapshot, execution -> container. `Container` satisfies it (nothing else
does), and ``isinstance(state, Parent)`` tells a container from a leaf state.
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

from .introspection import ContainerStatus, TransitionInfo
from .state import State
from .userdata import UserData, UserDataAccess

__all__ = ["Parent"]


@runtime_checkable
class Parent(Protocol):
    """A state holding labelled child states (see `zenros.smach.Container`)."""

    @property
    def path(self) -> str: ...

    @property
    def parent(self) -> State | None: ...

    @property
    def children(self) -> dict[str, State]: ...

    @property
    def output_keys(self) -> tuple[str, ...]: ...

    @property
    def userdata(self) -> UserData: ...

    @property
    def is_running(self) -> bool: ...

    @property
    def last_outcome(self) -> str | None: ...

    def describe(self) -> str: ...

    def remapping_of(self, label: str) -> dict[str, str]: ...

    def get_initial_states(self) -> list[str]: ...

    def get_active_states(self) -> list[str]: ...

    def get_status(self) -> ContainerStatus: ...

    def request_preempt(self) -> None: ...

    def _run_claimed(self, parent_ud: UserDataAccess | None) -> str: ...

    def get_transitions(self) -> list[TransitionInfo]: ...

    def get_info(self) -> dict[str, Any]: ...

    def get_run_state(self) -> tuple[bool, list[str]]: ...
