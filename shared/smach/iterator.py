"""`Iterator`: run one contained state once per item of an iterable."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Generator, Iterable, Mapping, Sequence
from typing import Any

from ..errors import InvalidStateError, InvalidTransitionError, InvalidUserCodeError
from .container import Container
from .introspection import TransitionInfo
from .state import State, names
from .wiring import Problem, listing

__all__ = ["Iterator"]

_END = object()


class Iterator(Container):
    """Loop over items: before each run of the contained state, the item goes in userdata.

    A loop outcome of the contained state moves on to the next item; a break outcome ends
    the container with that outcome, or with ``final_outcome_map[outcome]``. When the items
    run out the container ends with ``exhausted_outcome`` (added to ``outcomes`` if absent).

    ``it`` is an iterable, or a function returning one; a function is called at every
    `execute`, so a generator function gives fresh items each run, where a generator
    object would be used up after the first.

    Example:
        >>> loop = Iterator(outcomes=["done", "aborted"], it=lambda: [p1, p2, p3],
        ...                 it_label="waypoint", exhausted_outcome="done")
        >>> loop.set_contained_state("GO", GoTo(), loop_outcomes=["succeeded"],
        ...                          remapping={"target": "waypoint"})

    Args:
        outcomes: The container's outcomes.
        it: The items, or a function returning them.
        it_label: The userdata key each item is stored under.
        exhausted_outcome: The outcome once every item has been visited.
        input_keys: Keys copied in from the parent's userdata on entry.
        output_keys: Keys copied back to the parent's userdata on exit.
    """

    def __init__(
        self,
        outcomes: Sequence[str],
        it: Iterable[Any] | Callable[[], Iterable[Any]],
        it_label: str = "it_data",
        exhausted_outcome: str = "exhausted",
        input_keys: Sequence[str] = (),
        output_keys: Sequence[str] = (),
    ) -> None:
        declared = names(outcomes, "outcomes")
        super().__init__((*declared, exhausted_outcome), input_keys, output_keys)
        if not callable(it) and not isinstance(it, Iterable):
            raise InvalidStateError(
                f"Iterator needs an iterable or a function returning one, got {type(it).__name__}"
            )
        if not isinstance(it_label, str) or not it_label:
            raise InvalidStateError(f"it_label must be a userdata key name, got {it_label!r}")
        self._items = it
        self._it_label = it_label
        self._exhausted = exhausted_outcome
        self._loop: tuple[str, ...] = ()
        self._break: tuple[str, ...] = ()
        self._final: dict[str, str] = {}
        self._current: str | None = None
        self._index: int | None = None
        self._asked = False

    def set_contained_state(
        self,
        label: str,
        state: State,
        loop_outcomes: Sequence[str] = (),
        break_outcomes: Sequence[str] = (),
        final_outcome_map: Mapping[str, str] | None = None,
        remapping: Mapping[str, str] | None = None,
    ) -> State:
        """Set the state run for each item.

        Give ``loop_outcomes`` (every other outcome breaks) or ``break_outcomes`` (every
        other outcome loops), or both if together they cover the state's outcomes exactly.

        Args:
            label: The state's label.
            state: The state to run per item.
            loop_outcomes: Outcomes that move on to the next item.
            break_outcomes: Outcomes that end the container.
            final_outcome_map: Break outcome -> container outcome (default: same name).
            remapping: The state's key name -> this container's userdata key.

        Returns:
            ``state``.

        Raises:
            InvalidStateError: A state is already set, or neither list is given.
            InvalidTransitionError: A list or the map names an outcome the state lacks, or
                maps to something that is not a container outcome.
        """
        if self._children:
            raise InvalidStateError(
                f"{self.path} already iterates {listing(self._children)}; an Iterator holds"
                " one state (use a StateMachine for more)"
            )
        loop, brk = names(loop_outcomes, "loop_outcomes"), names(break_outcomes, "break_outcomes")
        final = dict(final_outcome_map or {})
        own = listing(state.outcomes)
        unknown = [o for o in (*loop, *brk, *final) if o not in state.outcomes]
        if unknown:
            raise InvalidTransitionError(
                f"{label!r} in {self.path} has no outcomes {listing(unknown)}; its outcomes: {own}"
            )
        if not loop and not brk:
            raise InvalidStateError(
                f"give {label!r} in {self.path} loop_outcomes or break_outcomes; its outcomes: {own}"
            )
        if loop and brk and (set(loop) & set(brk) or set(loop) | set(brk) != set(state.outcomes)):
            raise InvalidStateError(
                f"loop_outcomes and break_outcomes of {label!r} in {self.path} must split its"
                f" outcomes ({own}) in two; got loop {list(loop)}, break {list(brk)}"
            )
        bad = {o: t for o, t in final.items() if t not in self.outcomes}
        if bad:
            raise InvalidTransitionError(
                f"final_outcome_map of {self.path} maps to {listing(bad.values())}, which are not"
                f" container outcomes; outcomes: {listing(self.outcomes)}"
            )
        self._add_child(label, state, remapping)
        self._loop = loop or tuple(o for o in state.outcomes if o not in brk)
        self._break = brk or tuple(o for o in state.outcomes if o not in loop)
        self._final = final
        return state

    def _provided_keys(self) -> set[str]:
        return super()._provided_keys() | {self._it_label}

    def _wiring_problems(self) -> list[Problem]:
        problems = []
        for label in self._children:
            for outcome in self._break:
                target = self._final.get(outcome, outcome)
                if target not in self.outcomes:
                    problems.append(Problem(True, (
                        f"break outcome {label}.{outcome} of {self.path} is not a container"
                        f" outcome; map it in final_outcome_map to one of {listing(self.outcomes)}"
                    )))
        return problems

    # ------------------------------------------------------------------ running

    def _execute_children(self) -> str:
        label = next(iter(self._children))
        child = self._children[label]
        items = self._iterate()
        try:
            for index in itertools.count():
                with self._lock:
                    if self.preempt_requested() and "preempted" in self.outcomes:
                        self.service_preempt()
                        return "preempted"
                item = next(items, _END)
                if item is _END:
                    return self._exhausted
                with self._lock:
                    self._current, self._index = label, index
                    if self.preempt_requested():
                        self._asked = True
                        child.request_preempt()
                self.userdata[self._it_label] = item
                outcome = self._run_child(label)
                with self._lock:
                    self._current = None
                    was_preempted = self.preempt_requested()
                    self._settle_preempt(child)
                if outcome in self._break:
                    target = self._final.get(outcome, outcome)
                elif was_preempted and "preempted" in self.outcomes:
                    self.service_preempt()
                    target = "preempted"
                else:
                    self._emit("transition", [label], label=label, outcome=outcome, target=label)
                    continue
                self._emit("transition", [], label=label, outcome=outcome, target=target)
                return target
            raise AssertionError("unreachable")  # itertools.count() never ends
        finally:
            with self._lock:
                self._current = None
                self._settle_preempt(child)

    def _iterate(self) -> Generator[Any, None, None]:
        """The items, with errors raised by user code wrapped in `InvalidUserCodeError`."""
        try:
            items = iter(self._items() if callable(self._items) else self._items)
        except Exception as exc:  # user code: the items function or __iter__
            raise InvalidUserCodeError(
                f"the items of {self.path} could not be iterated: {type(exc).__name__}: {exc}"
            ) from exc
        while True:
            try:
                item = next(items)
            except StopIteration:
                return
            except Exception as exc:  # user code: the generator
                raise InvalidUserCodeError(
                    f"the items of {self.path} raised {type(exc).__name__}: {exc}"
                ) from exc
            yield item

    def _settle_preempt(self, child: State) -> None:
        if not self._asked:
            return
        self._asked = False
        if child.preempt_requested():
            child.recall_preempt()  # ignored: our own flag stays up
        elif self.preempt_requested():
            self.service_preempt()

    def request_preempt(self) -> None:
        """Set this container's preempt flag and pass it to the running contained state."""
        with self._lock:
            super().request_preempt()
            if self._current is not None:
                self._asked = True
                self._children[self._current].request_preempt()

    # ------------------------------------------------------------------ introspection

    def get_initial_states(self) -> list[str]:
        """The contained state's label."""
        return list(self._children)

    def get_active_states(self) -> list[str]:
        """The contained state's label while it runs."""
        current = self._current
        return [current] if current is not None else []

    def _set_initial(self, labels: tuple[str, ...]) -> None:
        if labels and list(labels) != list(self._children):
            raise InvalidStateError(
                f"{self.path} is an Iterator; its only state is {listing(self._children)},"
                f" got {list(labels)}"
            )

    def _edges(self) -> list[TransitionInfo]:
        edges = []
        for label in self._children:
            edges += [TransitionInfo(source=label, outcome=o, target=label) for o in self._loop]
            edges += [
                TransitionInfo(source=label, outcome=o, target=self._final.get(o, o),
                               implicit=o not in self._final)
                for o in self._break
            ]
        return edges

    def _info(self) -> dict[str, Any]:
        return {
            "it_label": self._it_label,
            "exhausted_outcome": self._exhausted,
            "loop_outcomes": list(self._loop),
            "break_outcomes": list(self._break),
            "index": self._index,
        }
