"""`Sequence`: a state machine whose states run in the order they were added."""

from __future__ import annotations

from collections.abc import Mapping
from collections.abc import Sequence as Seq
from typing import Any

from ..errors import InvalidStateError
from .state import State
from .state_machine import StateMachine
from .wiring import listing

__all__ = ["Sequence"]


class Sequence(StateMachine):
    """A `StateMachine` that links each state's ``connector_outcome`` to the next state added.

    The last state's connector outcome falls through to the container outcome of the same
    name, unless given explicitly. Other outcomes are wired as in a `StateMachine`, and an
    explicit transition for the connector outcome overrides the automatic link.

    Example:
        >>> seq = Sequence(outcomes=["succeeded", "aborted"], connector_outcome="succeeded")
        >>> seq.add("UNDOCK", Undock())
        >>> seq.add("GO", GoTo(), transitions={"aborted": "aborted"})

    Args:
        outcomes: The sequence's own outcomes.
        connector_outcome: The outcome that leads from one state to the next.
        input_keys: Keys copied in from the parent's userdata on entry.
        output_keys: Keys copied back to the parent's userdata on exit.
    """

    def __init__(
        self,
        outcomes: Seq[str],
        connector_outcome: str,
        input_keys: Seq[str] = (),
        output_keys: Seq[str] = (),
    ) -> None:
        super().__init__(outcomes, input_keys, output_keys)
        if not isinstance(connector_outcome, str) or not connector_outcome:
            raise InvalidStateError(
                f"connector_outcome must be an outcome name, got {connector_outcome!r}"
            )
        self._connector = connector_outcome
        self._last: str | None = None

    @property
    def connector_outcome(self) -> str:
        """The outcome that leads to the next state."""
        return self._connector

    def add(
        self,
        label: str,
        state: State,
        transitions: Mapping[str, str] | None = None,
        remapping: Mapping[str, str] | None = None,
    ) -> State:
        """Append ``state``; the previous state's connector outcome now leads to it.

        Raises:
            InvalidStateError: ``state`` does not declare the connector outcome (and the
                reasons of `StateMachine.add`).
        """
        if self._connector not in state.outcomes:
            raise InvalidStateError(
                f"{label!r} cannot join sequence {self.path}: it lacks the connector outcome"
                f" {self._connector!r}; its outcomes: {listing(state.outcomes)}"
            )
        added = super().add(label, state, transitions, remapping)
        if self._last is not None:
            self._transitions[self._last].setdefault(self._connector, label)
        self._last = label
        return added

    def _info(self) -> dict[str, Any]:
        return {"connector_outcome": self._connector}
