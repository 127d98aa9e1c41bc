"""`RosState`: the base of states that talk to a `zenros.Node`; waits that a preempt cuts short."""

from __future__ import annotations

import threading
import weakref
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import msgspec

from ..errors import InvalidStateError, InvalidUserCodeError
from .state import State, interface_of, names
from .userdata import UserDataAccess

if TYPE_CHECKING:
    from ..node import Node

__all__ = ["RosState", "build_message", "check_slots", "fill_slots", "read_slots", "slot_keys"]


class RosState(State):
    """A state bound to a node, whose waits end on a condition, a preempt or a graph change.

    Subclasses block in `wait_until` instead of sleeping: it wakes when `notify` is called
    (by a callback that changed what the predicate reads) and when a preempt is requested;
    `wait_for_graph` also wakes on every change of the computation graph (so "is the server
    there yet?" needs no polling).

    Args:
        node: The node whose endpoints the state uses.
        outcomes, input_keys, output_keys: As for `State`.
        callbacks: User callbacks whose `cb_interface` declarations (outcomes and keys)
            are merged in.
    """

    def __init__(
        self,
        node: Node,
        outcomes: Sequence[str],
        input_keys: Sequence[str] = (),
        output_keys: Sequence[str] = (),
        callbacks: Sequence[Callable[..., Any] | None] = (),
    ) -> None:
        outs, ins, writes = list(names(outcomes, "outcomes")), list(input_keys), list(output_keys)
        for cb in callbacks:
            if cb is None:
                continue
            if not callable(cb):
                raise InvalidStateError(
                    f"{type(self).__name__}: callbacks must be callable, got {type(cb).__name__}")
            o, i, w = interface_of(cb)
            outs, ins, writes = [*outs, *o], [*ins, *i], [*writes, *w]
        super().__init__(outs, ins, writes)
        self.node = node
        self._cond = threading.Condition()
        self._watching_graph = False

    def notify(self) -> None:
        """Wake `wait_until` to re-check its predicate (thread-safe)."""
        with self._cond:
            self._cond.notify_all()

    def request_preempt(self) -> None:
        """Set the preempt flag and wake the waiting `execute`."""
        super().request_preempt()
        self.notify()

    def wait_until(self, done: Callable[[], bool], timeout: float | None = None, *,
                   preemptible: bool = True) -> bool:
        """Block until ``done()`` or (if ``preemptible``) a preempt request, at most ``timeout`` s.

        Returns:
            ``done()`` at the end (False on a timeout or a preempt before it held).
        """
        if preemptible:
            def ready() -> bool:
                return done() or self.preempt_requested()
        else:
            ready = done
        with self._cond:
            self._cond.wait_for(ready, timeout)
            return done()

    def wait_for_graph(self, ready: Callable[[], bool], timeout: float | None) -> bool:
        """`wait_until` for a graph condition ("a server is there"): also woken by graph changes.

        The first wait that has to block registers a listener on the node's graph for the
        life of the state (a weak reference: it does not keep the state alive).
        """
        if ready():
            return True
        with self._cond:
            register, self._watching_graph = not self._watching_graph, True
        if register:
            ref = weakref.ref(self)
            self.node.graph.add_listener(lambda _event, _token: _wake(ref))
        return self.wait_until(ready, timeout)

    def await_server(self, ready: Callable[[], bool], what: str,
                     timeout: float | None) -> str | None:
        """Wait for a server (``what``: "service /x", "action /y"): None when it is there,
        else the outcome to return ("preempted", or "aborted" with a warning)."""
        if self.wait_for_graph(ready, timeout):
            return None
        if self.take_preempt():
            return "preempted"
        self.node.logger.warning("%s: no server for %s within %g s", self.describe(), what,
                                 timeout)
        return "aborted"

    def take_preempt(self) -> bool:
        """If a preempt is requested, service it and return True (then return "preempted")."""
        if self.preempt_requested():
            self.service_preempt()
            return True
        return False


def _wake(ref: weakref.ReferenceType[RosState]) -> None:
    state = ref()
    if state is not None:
        state.notify()


def fill_slots(state: State, message: Any, userdata: UserDataAccess, slots: Sequence[str],
               key: str | None = None) -> Any:
    """``message`` (or ``userdata[key]``) with each slot field replaced by ``userdata[slot]``."""
    if key is not None:
        message = userdata[key]
    if not slots:
        return message
    values = {slot: userdata[slot] for slot in slots}
    try:
        return msgspec.structs.replace(message, **values)
    except (TypeError, AttributeError) as exc:
        raise InvalidUserCodeError(
            f"{state.describe()} cannot set slots {list(slots)} on {type(message).__name__}:"
            f" {exc}; its fields: {', '.join(getattr(message, '__struct_fields__', ()))}"
        ) from exc


def build_message(
    state: State, template: Any, msg_type: type[Any], userdata: UserDataAccess,
    slots: Sequence[str], key: str | None, cb: Callable[..., Any] | None, noun: str, target: str,
) -> Any:
    """The message a state sends (a goal, a request): a copy of ``template`` (else a default
    ``msg_type``) or ``userdata[key]``, its slots filled from userdata, then ``cb(userdata,
    msg)`` may edit it or return a replacement. Raises `InvalidUserCodeError` naming the
    ``noun`` and ``target`` ("request", "service /x") if the result has the wrong type."""
    base = template if template is not None else msg_type()
    msg = fill_slots(state, base, userdata, slots, key)
    if template is not None and msg is template:  # a callback may mutate it: copy
        msg = msgspec.structs.replace(template)
    if cb is not None:
        made = cb(userdata, msg)
        msg = made if made is not None else msg
    if type(msg) is not msg_type:
        raise InvalidUserCodeError(
            f"{state.describe()} built a {type(msg).__name__} {noun}; {target}"
            f" takes {msg_type.__name__}")
    return msg


def read_slots(message: Any, userdata: UserDataAccess, slots: Sequence[str],
               key: str | None = None) -> None:
    """Store ``message`` under ``key`` and each slot field under its own name."""
    if key is not None:
        userdata[key] = message
    for slot in slots:
        userdata[slot] = getattr(message, slot)


def slot_keys(slots: Sequence[str], key: str | None, extra: Sequence[str]) -> list[str]:
    """The userdata keys a state declares for ``slots``, an optional ``key`` and ``extra``."""
    return [*names(slots, "slots"), *([key] if key else []), *names(extra, "keys")]


def check_slots(state_type: str, message_type: type[Any], slots: Sequence[str], what: str) -> None:
    """Raise `InvalidStateError` if a slot is not a field of ``message_type``."""
    fields: Mapping[str, Any] | Sequence[str] = getattr(message_type, "__struct_fields__", ())
    unknown = [s for s in slots if s not in fields]
    if unknown:
        raise InvalidStateError(
            f"{state_type}: {what} {unknown} are not fields of {message_type.__name__};"
            f" its fields: {', '.join(fields) or '(none)'}"
        )
