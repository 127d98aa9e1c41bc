"""`Concurrence`: run every child at once, each on its own thread, and join their outcomes."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any

from ..errors import InvalidStateError, InvalidUserCodeError
from .container import Container
from .introspection import TransitionInfo
from .state import State
from .wiring import Problem, listing

__all__ = ["ChildOutcomes", "Concurrence"]

ChildOutcomes = dict[str, str | None]
"""Child label -> its outcome, or None while it runs (or if it raised)."""


class Concurrence(Container):
    """Split-join concurrency: all children start together; the container ends when all end.

    The outcome is chosen, first match wins: ``outcome_cb(child_outcomes)`` if it returns
    an outcome; else the ``outcome_map`` entry whose conditions all hold (the one with
    the most conditions if several do, then the first declared); else ``"preempted"`` if
    the container itself was preempted and declares that outcome; else
    ``default_outcome``.

    ``child_termination_cb(child_outcomes)`` runs each time a child ends and may end the
    others early: True preempts every child still running, a list of labels preempts
    those, False (or None) lets them run. It runs on the ending child's thread with the
    container's lock held, so it must be quick and must not wait on other threads.

    Example:
        >>> cc = Concurrence(outcomes=["arrived", "blocked"], default_outcome="blocked",
        ...                  outcome_map={"arrived": {"NAV": "succeeded"}},
        ...                  child_termination_cb=lambda outcomes: True)
        >>> cc.add("NAV", GoTo())
        >>> cc.add("WATCH", WatchBumper())

    Args:
        outcomes: The container's outcomes.
        default_outcome: The outcome when nothing else decides.
        input_keys: Keys copied in from the parent's userdata on entry.
        output_keys: Keys copied back to the parent's userdata on exit.
        outcome_map: Container outcome -> {child label: child outcome} conditions.
        outcome_cb: Decides the outcome from the child outcomes (None: no decision).
        child_termination_cb: Called as each child ends; says whom to preempt.

    Raises:
        InvalidStateError: ``default_outcome`` or an ``outcome_map`` key is not an outcome,
            or a callback is not callable.
    """

    def __init__(
        self,
        outcomes: Sequence[str],
        default_outcome: str,
        input_keys: Sequence[str] = (),
        output_keys: Sequence[str] = (),
        outcome_map: Mapping[str, Mapping[str, str]] | None = None,
        outcome_cb: Callable[[ChildOutcomes], str | None] | None = None,
        child_termination_cb: Callable[[ChildOutcomes], bool | Iterable[str] | None]
        | None = None,
    ) -> None:
        super().__init__(outcomes, input_keys, output_keys)
        omap = {k: dict(v) for k, v in (outcome_map or {}).items()}
        errors = []
        if default_outcome not in self.outcomes:
            errors.append(f"default outcome {default_outcome!r} is not an outcome")
        errors += [f"outcome_map key {k!r} is not an outcome" for k in omap if k not in self.outcomes]
        errors += [f"outcome_map[{k!r}] has no conditions" for k, v in omap.items() if not v]
        for name, cb in (("outcome_cb", outcome_cb), ("child_termination_cb", child_termination_cb)):
            if cb is not None and not callable(cb):
                errors.append(f"{name} must be callable, got {type(cb).__name__}")
        if errors:
            raise InvalidStateError(
                f"Concurrence: {'; '.join(errors)}; outcomes: {listing(self.outcomes)}"
            )
        self._default = default_outcome
        self._outcome_map = omap
        self._outcome_cb = outcome_cb
        self._termination_cb = child_termination_cb
        self._cond = threading.Condition(self._lock)
        self._child_outcomes: ChildOutcomes = {}
        self._pending: set[str] = set()  # children whose thread has not finished
        self._asked: set[str] = set()  # children this container asked to preempt
        self._error: Exception | None = None

    def add(self, label: str, state: State, remapping: Mapping[str, str] | None = None) -> State:
        """Add a child that runs concurrently with the others.

        Returns:
            ``state``.
        """
        self._add_child(label, state, remapping)
        return state

    def _wiring_problems(self) -> list[Problem]:
        problems = []
        for outcome, conditions in self._outcome_map.items():
            for label, child_outcome in conditions.items():
                child = self._children.get(label)
                if child is None:
                    problems.append(Problem(True, (
                        f"outcome_map[{outcome!r}] of {self.path} names unknown state {label!r};"
                        f" available states: {listing(self._children)}"
                    )))
                elif child_outcome not in child.outcomes:
                    problems.append(Problem(True, (
                        f"outcome_map[{outcome!r}] of {self.path} expects {label}.{child_outcome},"
                        f" which {label} does not declare; its outcomes: {listing(child.outcomes)}"
                    )))
        return problems

    # ------------------------------------------------------------------ running

    def _execute_children(self) -> str:
        labels = list(self._children)
        with self._cond:
            self._child_outcomes = dict.fromkeys(labels)
            self._pending = set(labels)
            self._asked = set()
            self._error = None
            if self.preempt_requested():
                self._preempt_running(labels)
        threads = [
            threading.Thread(target=self._child_runner, args=(label,),
                             name=f"smach:{self._children[label].path}", daemon=True)
            for label in labels
        ]
        for thread in threads:
            thread.start()
        with self._cond:
            self._cond.wait_for(lambda: not self._pending)
        for thread in threads:
            thread.join()
        with self._cond:
            outcomes = dict(self._child_outcomes)
            error, self._error = self._error, None
            preempted = self.preempt_requested()
            ignored = [lb for lb in self._asked if self._children[lb].preempt_requested()]
            for label in ignored:
                self._children[label].recall_preempt()
            if preempted and self._asked and not ignored:
                self.service_preempt()
            self._asked = set()
        if error is not None:
            raise error
        return self._decide(outcomes, preempted)

    def _child_runner(self, label: str) -> None:
        outcome: str | None = None
        try:
            outcome = self._run_child(label)
        except Exception as exc:  # noqa: BLE001  (re-raised by the container's thread)
            with self._cond:
                if self._error is None:
                    self._error = exc
                self._preempt_running(list(self._children))
        finally:
            with self._cond:
                self._child_outcomes[label] = outcome
                if outcome is not None:
                    self._on_child_end()
                active = self.get_active_states()
        try:
            if outcome is not None:
                self._emit("transition", active, label=label, outcome=outcome)
        finally:
            with self._cond:
                self._pending.discard(label)
                self._cond.notify_all()

    def _on_child_end(self) -> None:
        """Ask the termination callback whom to preempt (called with the lock held)."""
        if self._termination_cb is None:
            return
        try:
            verdict = self._termination_cb(dict(self._child_outcomes))
        except Exception as exc:  # noqa: BLE001  (user callback: re-raised after the join)
            if self._error is None:
                self._error = InvalidUserCodeError(
                    f"child_termination_cb of {self.path} raised {type(exc).__name__}: {exc}")
                self._error.__cause__ = exc
            verdict = True
        if verdict is True:
            self._preempt_running(list(self._children))
        elif verdict is False or verdict is None:
            return
        elif isinstance(verdict, Iterable) and not isinstance(verdict, str):
            chosen = list(verdict)
            unknown = [lb for lb in chosen if lb not in self._children]
            if unknown:
                self._error = self._error or InvalidUserCodeError(
                    f"child_termination_cb of {self.path} asked to preempt unknown states"
                    f" {listing(unknown)}; available states: {listing(self._children)}")
                chosen = list(self._children)
            self._preempt_running(chosen)
        else:
            self._error = self._error or InvalidUserCodeError(
                f"child_termination_cb of {self.path} must return a bool or a list of labels,"
                f" got {verdict!r}")
            self._preempt_running(list(self._children))

    def _preempt_running(self, labels: Iterable[str]) -> None:
        for label in labels:
            if label in self._pending and self._child_outcomes.get(label) is None:
                self._asked.add(label)
                self._children[label].request_preempt()

    def request_preempt(self) -> None:
        """Set this container's preempt flag and preempt every child still running."""
        with self._cond:
            super().request_preempt()
            self._preempt_running(list(self._children))

    def _decide(self, outcomes: ChildOutcomes, preempted: bool) -> str:
        if self._outcome_cb is not None:
            try:
                chosen = self._outcome_cb(dict(outcomes))
            except Exception as exc:  # user callback
                raise InvalidUserCodeError(
                    f"outcome_cb of {self.path} raised {type(exc).__name__}: {exc}") from exc
            if chosen is not None:
                if chosen not in self.outcomes:
                    raise InvalidUserCodeError(
                        f"outcome_cb of {self.path} returned {chosen!r}, which is not an"
                        f" outcome; outcomes: {listing(self.outcomes)}")
                return chosen
        best: tuple[int, str] | None = None
        for outcome, conditions in self._outcome_map.items():
            holds = all(outcomes.get(lb) == o for lb, o in conditions.items())
            if holds and (best is None or len(conditions) > best[0]):
                best = (len(conditions), outcome)
        if best is not None:
            return best[1]
        if preempted and "preempted" in self.outcomes:
            return "preempted"
        return self._default

    # ------------------------------------------------------------------ introspection

    def get_initial_states(self) -> list[str]:
        """Every child: a Concurrence starts them all."""
        return list(self._children)

    def get_active_states(self) -> list[str]:
        """The children still running."""
        with self._lock:
            return [lb for lb in self._children
                    if lb in self._pending and self._child_outcomes.get(lb) is None]

    def _set_initial(self, labels: tuple[str, ...]) -> None:
        if labels and set(labels) != set(self._children):
            raise InvalidStateError(
                f"{self.path} is a Concurrence and always starts all its states"
                f" ({listing(self._children)}); got {list(labels)}"
            )

    def _edges(self) -> list[TransitionInfo]:
        return [
            TransitionInfo(source=label, outcome=child_outcome, target=outcome)
            for outcome, conditions in self._outcome_map.items()
            for label, child_outcome in conditions.items()
        ]

    def _info(self) -> dict[str, Any]:
        return {
            "default_outcome": self._default,
            "outcome_cb": self._outcome_cb is not None,
            "child_termination_cb": self._termination_cb is not None,
        }
