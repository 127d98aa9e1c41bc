"""`StateMachine`: run one child at a time, choosing the next by the outcome of the last."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from ..errors import InvalidStateError, InvalidTransitionError
from .container import Container
from .introspection import TransitionInfo
from .state import State
from .wiring import Problem, listing

__all__ = ["StateMachine"]


class StateMachine(Container):
    """A finite state machine whose states may themselves be containers.

    Each state's outcomes map to the next state's label or to an outcome of the machine.
    An outcome left out of ``transitions`` falls through to the machine outcome of the
    same name (``"preempted"`` to ``"preempted"``); `check` reports it if there is none.
    The first state added is the initial state unless `set_initial_state` says otherwise.

    Example:
        >>> sm = StateMachine(outcomes=["done", "failed"])
        >>> sm.add("FOO", Foo(), transitions={"outcome1": "BAR", "outcome2": "done"})
        >>> sm.add("BAR", Bar(), transitions={"outcome1": "FOO"})
        >>> sm.execute()

    Args:
        outcomes: The machine's own outcomes.
        input_keys: Keys copied in from the parent's userdata on entry.
        output_keys: Keys copied back to the parent's userdata on exit.
    """

    def __init__(
        self,
        outcomes: Sequence[str],
        input_keys: Sequence[str] = (),
        output_keys: Sequence[str] = (),
    ) -> None:
        super().__init__(outcomes, input_keys, output_keys)
        self._transitions: dict[str, dict[str, str]] = {}
        self._initial: str | None = None
        self._current: str | None = None
        self._preempted_child: str | None = None

    def add(
        self,
        label: str,
        state: State,
        transitions: Mapping[str, str] | None = None,
        remapping: Mapping[str, str] | None = None,
    ) -> State:
        """Add ``state`` under ``label``.

        Args:
            label: Unique name of the state in this machine (no ``/``).
            state: The state (or container) to run.
            transitions: The state's outcome -> next state label or machine outcome.
            remapping: The state's key name -> this machine's userdata key.

        Returns:
            ``state``.

        Raises:
            InvalidStateError: Bad or duplicate label, label equal to a machine outcome,
                state already placed elsewhere, or remapping of undeclared keys.
            InvalidTransitionError: ``transitions`` names an outcome the state lacks.
        """
        if label in self.outcomes:
            raise InvalidStateError(
                f"label {label!r} in {self.path} is also an outcome of the machine, so a"
                f" transition to it would be ambiguous; outcomes: {listing(self.outcomes)}"
            )
        trans = dict(transitions or {})
        extra = [o for o in trans if o not in state.outcomes]
        if extra:
            raise InvalidTransitionError(
                f"transitions of {label!r} in {self.path} use outcomes {listing(extra)}, which"
                f" {type(state).__name__} does not declare; its outcomes: {listing(state.outcomes)}"
            )
        for outcome, target in trans.items():
            if not isinstance(target, str) or not target:
                raise InvalidTransitionError(
                    f"transition {label}.{outcome} in {self.path} must name a state or an"
                    f" outcome, got {target!r}"
                )
        self._add_child(label, state, remapping)
        self._transitions[label] = trans
        if self._initial is None:
            self._initial = label
        return state

    # ------------------------------------------------------------------ wiring

    def _target(self, label: str, outcome: str) -> str:
        return self._transitions[label].get(outcome, outcome)

    def _wiring_problems(self) -> list[Problem]:
        problems = []
        where = (f"available states: {listing(self._children)};"
                 f" container outcomes: {listing(self.outcomes)}")
        for label, state in self._children.items():
            for outcome in state.outcomes:
                target = self._transitions[label].get(outcome)
                if target is None and outcome not in self.outcomes:
                    problems.append(Problem(True, (
                        f"outcome {label}.{outcome} in {self.path} is not connected; {where}"
                    )))
                elif target is not None and target not in self._children \
                        and target not in self.outcomes:
                    problems.append(Problem(True, (
                        f"unknown state {target!r} in transition {label}.{outcome}"
                        f" of {self.path}; {where}"
                    )))
        return problems

    # ------------------------------------------------------------------ running

    def _execute_children(self) -> str:
        assert self._initial is not None  # check() guarantees at least one state
        label = self._initial
        try:
            while True:
                with self._lock:
                    self._current = label
                    self._pass_on_preempt(label)
                outcome = self._run_child(label)
                target = self._target(label, outcome)
                done = target not in self._children
                with self._lock:
                    if done:
                        self._settle_preempt()
                    # set before the event, so a listener reading the status sees the target
                    self._current = None if done else target
                self._emit("transition", [] if done else [target],
                           label=label, outcome=outcome, target=target)
                if done:
                    return target
                label = target
        finally:
            with self._lock:
                self._current = None
                if self._preempted_child is not None:
                    self._children[self._preempted_child].recall_preempt()
                    self._preempted_child = None

    def request_preempt(self) -> None:
        """Set this machine's preempt flag and pass the request to the running state."""
        with self._lock:
            super().request_preempt()
            if self._current is not None:
                self._preempt_child(self._current)

    def _preempt_child(self, label: str) -> None:
        previous = self._preempted_child
        if previous is not None and previous != label:
            self._children[previous].recall_preempt()
        self._preempted_child = label
        self._children[label].request_preempt()

    def _pass_on_preempt(self, label: str) -> None:
        """Before ``label`` runs: a standing request either was serviced or moves on to it."""
        if not self.preempt_requested():
            return
        previous = self._preempted_child
        if previous is not None and not self._children[previous].preempt_requested():
            self.service_preempt()  # the last state acted on it; the request is spent
            self._preempted_child = None
        else:
            self._preempt_child(label)

    def _settle_preempt(self) -> None:
        """On reaching a machine outcome: serviced below means serviced here."""
        previous, self._preempted_child = self._preempted_child, None
        if previous is None or not self.preempt_requested():
            return
        child = self._children[previous]
        if child.preempt_requested():
            child.recall_preempt()  # ignored below; the flag stays up for our parent
        else:
            self.service_preempt()

    # ------------------------------------------------------------------ introspection

    def get_initial_states(self) -> list[str]:
        """The label the next run starts in."""
        return [self._initial] if self._initial is not None else []

    def get_active_states(self) -> list[str]:
        """The running state's label (empty when idle)."""
        current = self._current
        return [current] if current is not None else []

    def _set_initial(self, labels: tuple[str, ...]) -> None:
        if not labels:
            return
        if len(labels) > 1:
            raise InvalidStateError(
                f"{self.path} is a {type(self).__name__} and starts in one state, got"
                f" {list(labels)}; its states: {listing(self._children)}"
            )
        if labels[0] not in self._children:
            raise InvalidStateError(
                f"unknown initial state {labels[0]!r} for {self.path};"
                f" available states: {listing(self._children)}"
            )
        self._initial = labels[0]

    def _edges(self) -> list[TransitionInfo]:
        edges = []
        for label, state in self._children.items():
            for outcome in state.outcomes:
                target = self._transitions[label].get(outcome)
                if target is not None:
                    edges.append(TransitionInfo(source=label, outcome=outcome, target=target))
                elif outcome in self.outcomes:
                    edges.append(TransitionInfo(
                        source=label, outcome=outcome, target=outcome, implicit=True))
        return edges
