"""`Container`: a state made of labelled child states, with its own userdata and listeners."""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ..errors import InvalidStateError, InvalidUserCodeError, SmachError, UserDataError
from .introspection import (
    ContainerEvent,
    ContainerStatus,
    EventKind,
    Listener,
    StateStructure,
    TransitionInfo,
)
from .listeners import ListenerSet
from .snapshot import status_of, structure_of
from .state import State, names
from .userdata import Remapper, UserData, UserDataAccess
from .wiring import Problem, check_child, key_problems, listing, raise_problems

if TYPE_CHECKING:
    from .execution import Execution

__all__ = ["Container"]


class Container(State):
    """Base of `StateMachine`, `Concurrence` and `Iterator`: a state holding labelled states.

    A container owns one `UserData`. On entry it copies its input keys in from the
    parent's userdata (or checks they are already set, at the root); on exit it copies
    its output keys back. Each child sees the container's userdata through a `Remapper`
    limited to the keys the child declared. Listeners added with `add_listener` hear the
    start, transition and termination events of this container and every nested one.
    """

    def __init__(
        self,
        outcomes: Sequence[str],
        input_keys: Sequence[str] = (),
        output_keys: Sequence[str] = (),
    ) -> None:
        super().__init__(outcomes, input_keys, output_keys)
        self.userdata = UserData(owner=lambda: f"container {self.path}")
        self._children: dict[str, State] = {}
        self._remappings: dict[str, dict[str, str]] = {}
        self._lock = threading.RLock()
        self._running = False
        self._listeners = ListenerSet()
        self._last_outcome: str | None = None
        self._pending_userdata: dict[str, Any] = {}

    # ------------------------------------------------------------------ children

    @property
    def children(self) -> dict[str, State]:
        """The child states by label, in the order they were added."""
        return dict(self._children)

    def __getitem__(self, label: str) -> State:
        try:
            return self._children[label]
        except KeyError:
            raise InvalidStateError(
                f"no state {label!r} in {self.path}; its states: {listing(self._children)}"
            ) from None

    def find(self, path: str) -> State:
        """The state at ``path`` below this container (``"NAV/GO"``; ``""`` is this one).

        Raises:
            InvalidStateError: A label on the way does not exist (the message lists the
                labels that do).
        """
        node: State = self
        for label in (p for p in path.strip("/").split("/") if p):
            if not isinstance(node, Container):
                raise InvalidStateError(f"{node.describe()} is not a container; cannot find {path!r}")
            node = node[label]
        return node

    def _add_child(self, label: str, state: State, remapping: Mapping[str, str] | None) -> None:
        if self._tree_running():
            raise SmachError(f"cannot add {label!r} to {self.path} while the machine is running")
        remap = check_child(self, label, state, remapping)
        state._attach(self, label)
        self._children[label] = state
        self._remappings[label] = remap

    def _tree_running(self) -> bool:
        node: State | None = self
        while node is not None:
            if isinstance(node, Container) and node._running:
                return True
            node = node.parent
        return False

    def remapping_of(self, label: str) -> dict[str, str]:
        """The key remapping of child ``label`` (its key -> this container's key)."""
        return dict(self._remappings[label])

    # ------------------------------------------------------------------ wiring checks

    def check(self) -> None:
        """Check the wiring of this container and every nested one, before anything runs.

        Raises:
            InvalidTransitionError: A transition names an unknown target, or an outcome is
                not connected (the message lists every problem and the valid choices).
            InvalidStateError: Any other problem: no states, or a key nothing provides.
        """
        raise_problems(self.describe(), self._problems())

    def _problems(self) -> list[Problem]:
        problems = self._wiring_problems()
        if not self._children:
            problems.append(Problem(False, f"{self.path} has no states; add at least one"))
        problems += key_problems(self, self._provided_keys())
        for child in self._children.values():
            if isinstance(child, Container):
                problems += child._problems()
        return problems

    def _wiring_problems(self) -> list[Problem]:
        """Container-specific problems (transitions, outcome maps); override."""
        return []

    def _provided_keys(self) -> set[str]:
        provided = {*self.input_keys, *self.userdata.keys()}
        for label, child in self._children.items():
            remap = self._remappings[label]
            provided |= {remap.get(k, k) for k in child.output_keys}
        return provided

    # ------------------------------------------------------------------ execution

    def execute(self, userdata: UserDataAccess | None = None) -> str:
        """Check the wiring, then run the container until it reaches one of its outcomes.

        Args:
            userdata: The parent's userdata; the input keys are copied in from it and the
                output keys copied back. None at the root: input keys must then already
                be set in `userdata` (the attribute), where output keys are left.

        Returns:
            One of the container's outcomes.

        Raises:
            InvalidTransitionError, InvalidStateError: The wiring check failed.
            UserDataError: An input key is missing, or a state broke its key declarations.
            InvalidUserCodeError: A state raised, or returned an undeclared outcome.
            SmachError: The container is already running.
        """
        self._claim()
        return self._run_claimed(userdata)

    def execute_in_thread(self, userdata: UserDataAccess | None = None) -> Execution:
        """Check the wiring here, then run `execute` on a background thread.

        Returns:
            An `Execution`: wait on it (``result()``, ``await``) or preempt it.
        """
        from .execution import Execution

        self.check()
        self._claim()
        try:
            return Execution(self, userdata)
        except BaseException:  # the thread never started: release the claim, then re-raise
            with self._lock:
                self._running = False
            raise

    @property
    def is_running(self) -> bool:
        """True while `execute` runs."""
        return self._running

    @property
    def last_outcome(self) -> str | None:
        """The outcome of the last run that ended normally (None before the first)."""
        return self._last_outcome

    def _claim(self) -> None:
        with self._lock:
            if self._running:
                raise SmachError(
                    f"{self.describe()} is already running; wait for it to end or preempt it"
                )
            self._running = True

    def _run_claimed(self, parent_ud: UserDataAccess | None) -> str:
        try:
            self.check()
            with self._lock:
                pending, self._pending_userdata = self._pending_userdata, {}
            self.userdata.update(pending)
            self._copy_inputs(parent_ud)
            self._emit("start", self.get_initial_states())
            try:
                outcome = self._execute_children()
            except Exception as exc:
                self._emit("termination", [], error=str(exc))
                raise
            if parent_ud is not None:
                for key in self.output_keys:
                    if key in self.userdata:
                        parent_ud[key] = self.userdata[key]
            self._last_outcome = outcome
            self._emit("termination", [], outcome=outcome)
            return outcome
        finally:
            with self._lock:
                self._running = False
                if self._parent is None:  # an unserviced request expires with its run
                    self.recall_preempt()

    def _copy_inputs(self, parent_ud: UserDataAccess | None) -> None:
        for key in self.input_keys:
            if parent_ud is None:
                if key not in self.userdata:
                    raise UserDataError(
                        f"{self.describe()} needs input key {key!r}: pass it in execute(userdata)"
                        f" or set it in .userdata first; set keys: {listing(self.userdata.keys())}"
                    )
            elif isinstance(parent_ud, Remapper) or key in parent_ud:
                self.userdata[key] = parent_ud[key]  # a Remapper explains a missing key itself
            else:
                raise UserDataError(
                    f"{self.describe()} needs input key {key!r}, which the userdata passed to"
                    f" execute() lacks; set keys: {listing(parent_ud.keys())}"
                )

    def _execute_children(self) -> str:
        """Run the children and return the container outcome; override."""
        raise NotImplementedError

    def _run_child(self, label: str) -> str:
        state = self._children[label]
        view = Remapper(
            self.userdata,
            state.describe(),
            state.input_keys,
            state.output_keys,
            self._remappings[label],
        )
        try:
            outcome = state.execute(view)
        except SmachError:
            raise
        except Exception as exc:
            raise InvalidUserCodeError(
                f"{state.describe()} raised {type(exc).__name__}: {exc}"
            ) from exc
        if outcome not in state.outcomes:
            raise InvalidUserCodeError(
                f"{state.describe()} returned {outcome!r}, which is not a declared outcome;"
                f" its outcomes: {listing(state.outcomes)}"
            )
        return outcome

    # ------------------------------------------------------------------ listeners

    def add_listener(self, listener: Listener) -> Callable[[], None]:
        """Call ``listener`` on every event of this container and of the containers inside it.

        Listeners run on the executing thread (a child's thread in a Concurrence); an
        exception in one is logged and does not stop the machine.

        Returns:
            A function that removes the listener.
        """
        return self._listeners.add(listener)

    def _emit(self, kind: EventKind, active: list[str], **fields: Any) -> None:
        self._dispatch(ContainerEvent(kind=kind, path=self.path, active_states=active, **fields))

    def _dispatch(self, event: ContainerEvent) -> None:
        self._listeners.dispatch(event)
        if isinstance(self._parent, Container):
            self._parent._dispatch(event)

    # ------------------------------------------------------------------ introspection

    def get_initial_states(self) -> list[str]:
        """The labels that run first; override."""
        raise NotImplementedError

    def get_active_states(self) -> list[str]:
        """The labels running now (empty when idle); override."""
        raise NotImplementedError

    def set_initial_state(
        self, labels: Sequence[str], userdata: Mapping[str, Any] | UserData | None = None
    ) -> None:
        """Choose where the next run starts, and seed the userdata (before `execute`).

        Args:
            labels: The initial child label(s); empty keeps the current choice.
            userdata: Keys to set in this container's userdata.

        Raises:
            InvalidStateError: A label is unknown or not valid for this container type.
            SmachError: The container is running.
        """
        chosen = names(labels, "initial states")
        with self._lock:
            if self._running:
                raise SmachError(f"cannot set the initial state of {self.path} while it runs")
            self._set_initial(chosen)
            if userdata is not None:
                self.userdata.update(userdata)

    def schedule_initial_state(
        self, labels: Sequence[str], userdata: Mapping[str, Any] | UserData | None = None
    ) -> bool:
        """`set_initial_state`, also accepted while the container runs (smach_ros's remote init).

        Idle, it is `set_initial_state`. Running, the labels are checked now and take effect
        at the next run (the current one has started already), and the userdata is set when
        that run starts, before its input keys are copied in.

        Returns:
            True if applied at once, False if deferred to the next run.

        Raises:
            InvalidStateError: A label is unknown or not valid for this container type.
        """
        chosen = names(labels, "initial states")
        values = userdata.snapshot() if isinstance(userdata, UserData) else dict(userdata or {})
        with self._lock:
            self._set_initial(chosen)  # checks; a run reads its initial state when it starts
            if not self._running:
                self.userdata.update(values)
                return True
            self._pending_userdata.update(values)
            return False

    def _set_initial(self, labels: tuple[str, ...]) -> None:
        raise NotImplementedError

    def _edges(self) -> list[TransitionInfo]:
        return []

    def _info(self) -> dict[str, Any]:
        return {}

    def get_transitions(self) -> list[TransitionInfo]:
        """The container's internal edges (for introspection; each container type has its
        own)."""
        return self._edges()

    def get_info(self) -> dict[str, Any]:
        """Container-type details for introspection (a sequence's order, an iterator's
        progress, ...)."""
        return self._info()

    def get_run_state(self) -> tuple[bool, list[str]]:
        """Whether it runs and its active children, read together (one consistent view)."""
        with self._lock:
            return self.is_running, self.get_active_states()

    def get_structure(self) -> StateStructure:
        """Outcomes, keys, transitions and children, recursively, as plain data."""
        return structure_of(self, State.get_structure(self))

    def get_status(self) -> ContainerStatus:
        """Active states, userdata snapshot and last outcome, for this and nested containers."""
        return status_of(self)
