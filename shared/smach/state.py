"""`State`: the unit of a state machine, with declared outcomes, userdata keys and preemption."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

from ..errors import InvalidStateError
from .introspection import StateStructure
from .userdata import UserDataAccess

__all__ = ["CBState", "State", "cb_interface", "interface_of", "names"]

F = TypeVar("F", bound=Callable[..., Any])


def names(values: Iterable[str] | str, what: str) -> tuple[str, ...]:
    """Validate a list of outcome or key names; return them deduplicated, in declared order.

    Raises:
        InvalidStateError: ``values`` is a bare string, or holds a non-string or empty name.
    """
    if isinstance(values, str):
        raise InvalidStateError(
            f"{what} must be a list of names, got the string {values!r}; write [{values!r}]"
        )
    out: list[str] = []
    for value in values:
        if not isinstance(value, str) or not value:
            raise InvalidStateError(f"{what} must be non-empty strings, got {value!r}")
        if value not in out:
            out.append(value)
    return tuple(out)


def join_path(parent: str, label: str) -> str:
    """The path of child ``label`` under the container at ``parent`` (``/`` is the root)."""
    return f"{parent.rstrip('/')}/{label}"


class State:
    """Base class of every state and container.

    A state talks to its container in two ways only: the outcome that `execute` returns,
    and the userdata keys it reads and writes. Both are declared here, before anything
    runs, so containers can check the wiring at construction.

    Preemption is cooperative: `request_preempt` sets a flag that a long-running
    `execute` polls with `preempt_requested` (or waits on with `wait_for_preempt`); when
    it stops early it calls `service_preempt` and returns ``"preempted"``.

    Args:
        outcomes: The outcomes `execute` may return.
        input_keys: Userdata keys the state reads.
        output_keys: Userdata keys the state writes.
        io_keys: Keys both read and written (added to both lists).

    Raises:
        InvalidStateError: No outcome, or a name list is malformed.
    """

    def __init__(
        self,
        outcomes: Sequence[str] = (),
        input_keys: Sequence[str] = (),
        output_keys: Sequence[str] = (),
        io_keys: Sequence[str] = (),
    ) -> None:
        self._outcomes = names(outcomes, "outcomes")
        if not self._outcomes:
            raise InvalidStateError(
                f"{type(self).__name__} declares no outcome; a state needs at least one"
            )
        io = names(io_keys, "io_keys")
        self._input_keys = names((*names(input_keys, "input_keys"), *io), "input_keys")
        self._output_keys = names((*names(output_keys, "output_keys"), *io), "output_keys")
        self._preempt = threading.Event()
        self._parent: State | None = None  # the container holding it
        self._label: str | None = None

    # ------------------------------------------------------------------ contract

    def execute(self, userdata: UserDataAccess) -> str:
        """Do the state's work; block until done and return one of the declared outcomes.

        Args:
            userdata: A view of the container's userdata restricted to the declared keys.

        Returns:
            One of `outcomes`.
        """
        raise NotImplementedError(f"{type(self).__name__} must implement execute(userdata)")

    @property
    def outcomes(self) -> tuple[str, ...]:
        """The declared outcomes, in declaration order."""
        return self._outcomes

    @property
    def input_keys(self) -> tuple[str, ...]:
        """The userdata keys this state may read."""
        return self._input_keys

    @property
    def output_keys(self) -> tuple[str, ...]:
        """The userdata keys this state may write."""
        return self._output_keys

    # ------------------------------------------------------------------ place in the tree

    @property
    def label(self) -> str | None:
        """The label under which this state was added to its container (None at the root)."""
        return self._label

    @property
    def parent(self) -> State | None:
        """The container holding this state (None at the root)."""
        return self._parent

    @property
    def path(self) -> str:
        """Where the state sits: ``/`` for a root, ``/NAV/GO`` for a nested one."""
        if self._parent is None or self._label is None:
            return "/"
        return join_path(self._parent.path, self._label)

    def describe(self) -> str:
        """Path and type, as error messages name a state: ``/NAV/GO (GoTo)``."""
        return f"{self.path} ({type(self).__name__})"

    def get_structure(self) -> StateStructure:
        """The state's declared interface as plain data (containers add their children)."""
        return StateStructure(
            path=self.path,
            label=self._label or "",
            type=type(self).__name__,
            outcomes=list(self._outcomes),
            input_keys=list(self._input_keys),
            output_keys=list(self._output_keys),
        )

    def _attach(self, parent: State, label: str) -> None:
        if self._parent is not None:
            raise InvalidStateError(
                f"cannot add {type(self).__name__} as {label!r} to {parent.path}: this instance"
                f" is already {self.path}; create a new instance for each place it runs"
            )
        self._parent, self._label = parent, label

    # ------------------------------------------------------------------ preemption

    def request_preempt(self) -> None:
        """Ask the state to stop early (thread-safe); it decides when, at its next check."""
        self._preempt.set()

    def service_preempt(self) -> None:
        """Acknowledge a preempt: the state is acting on it. A new request may follow."""
        self._preempt.clear()

    def recall_preempt(self) -> None:
        """Withdraw a preempt request that was not acted on."""
        self._preempt.clear()

    def preempt_requested(self) -> bool:
        """True while a preempt is requested and not yet serviced or recalled."""
        return self._preempt.is_set()

    def wait_for_preempt(self, timeout: float | None = None) -> bool:
        """Block until a preempt is requested or ``timeout`` seconds pass.

        Returns:
            True if a preempt is requested (use it instead of ``sleep`` in ``execute``).
        """
        return self._preempt.wait(timeout)

    def __repr__(self) -> str:
        return f"<{self.describe()} outcomes={list(self._outcomes)}>"


@dataclass(frozen=True)
class _Interface:
    outcomes: tuple[str, ...]
    input_keys: tuple[str, ...]
    output_keys: tuple[str, ...]


_INTERFACE_ATTR = "__smach_interface__"


def cb_interface(
    outcomes: Sequence[str] = (),
    input_keys: Sequence[str] = (),
    output_keys: Sequence[str] = (),
    io_keys: Sequence[str] = (),
) -> Callable[[F], F]:
    """Decorate a callback with the outcomes and keys a `CBState` built from it declares.

    Example:
        >>> @cb_interface(outcomes=["done"], input_keys=["n"])
        ... def check(userdata): return "done"
    """
    io = names(io_keys, "io_keys")
    spec = _Interface(
        names(outcomes, "outcomes"),
        names((*names(input_keys, "input_keys"), *io), "input_keys"),
        names((*names(output_keys, "output_keys"), *io), "output_keys"),
    )

    def decorate(fn: F) -> F:
        setattr(fn, _INTERFACE_ATTR, spec)
        return fn

    return decorate


def interface_of(cb: Callable[..., Any]) -> tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
    """The ``(outcomes, input_keys, output_keys)`` that `cb_interface` declared on ``cb``.

    All three are empty for a callback without a declaration.
    """
    spec = getattr(cb, _INTERFACE_ATTR, _Interface((), (), ()))
    return spec.outcomes, spec.input_keys, spec.output_keys


class CBState(State):
    """A state that calls one function: ``cb(userdata, *args, **kwargs) -> outcome``.

    Outcomes and keys come from the constructor, merged with those declared on the
    callback by `cb_interface`.

    Args:
        cb: The callback; it receives the userdata view first.
        args: Extra positional arguments for ``cb``.
        kwargs: Extra keyword arguments for ``cb``.
        outcomes: Outcomes, in addition to the callback's declared ones.
        input_keys: Keys read, in addition to the callback's.
        output_keys: Keys written, in addition to the callback's.
        io_keys: Keys read and written.
    """

    def __init__(
        self,
        cb: Callable[..., str],
        args: Sequence[Any] = (),
        kwargs: Mapping[str, Any] | None = None,
        outcomes: Sequence[str] = (),
        input_keys: Sequence[str] = (),
        output_keys: Sequence[str] = (),
        io_keys: Sequence[str] = (),
    ) -> None:
        if not callable(cb):
            raise InvalidStateError(f"CBState needs a callable, got {type(cb).__name__}")
        cb_outcomes, cb_inputs, cb_outputs = interface_of(cb)
        super().__init__(
            (*names(outcomes, "outcomes"), *cb_outcomes),
            (*names(input_keys, "input_keys"), *cb_inputs),
            (*names(output_keys, "output_keys"), *cb_outputs),
            io_keys,
        )
        self._cb = cb
        self._args = tuple(args)
        self._kwargs = dict(kwargs or {})

    def execute(self, userdata: UserDataAccess) -> str:
        """Call the callback and return its outcome."""
        return self._cb(userdata, *self._args, **self._kwargs)
