"""Wiring checks: the construction mistakes a container can hold, and the error listing them."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import NamedTuple

from ..errors import InvalidStateError, InvalidTransitionError
from .parent import Parent
from .state import State

__all__ = ["Problem", "check_child", "key_problems", "listing", "raise_problems"]


class Problem(NamedTuple):
    """One wiring mistake; ``transition`` marks the kind `InvalidTransitionError` reports."""

    transition: bool
    text: str


def listing(items: Iterable[object]) -> str:
    """Sorted, comma-separated names for error messages (``(none)`` when empty)."""
    out = sorted(str(i) for i in items)
    return ", ".join(out) if out else "(none)"


def key_problems(container: Parent, provided: set[str]) -> list[Problem]:
    """Input keys of children, and output keys of the container, that nothing provides.

    Args:
        container: The container to check.
        provided: The keys available inside it: its input keys, the keys already set in
            its userdata and the keys its children write.
    """
    problems = []
    for label, child in container.children.items():
        for key in child.input_keys:
            target = container.remapping_of(label).get(key, key)
            if target not in provided:
                via = f" (remapped to {target!r})" if target != key else ""
                problems.append(Problem(False, (
                    f"{child.describe()} reads key {key!r}{via}, which nothing in"
                    f" {container.path} provides; available keys: {listing(provided)}"
                )))
    for key in container.output_keys:
        if key not in provided:
            problems.append(Problem(False, (
                f"output key {key!r} of {container.path} is never written by its states;"
                f" available keys: {listing(provided)}"
            )))
    return problems


def raise_problems(where: str, problems: list[Problem]) -> None:
    """Raise one error listing every problem, if there are any.

    Raises:
        InvalidTransitionError: At least one problem is about transitions.
        InvalidStateError: All problems are of other kinds (no states, missing keys).
    """
    if not problems:
        return
    error = InvalidTransitionError if any(p.transition for p in problems) else InvalidStateError
    text = "\n  ".join(p.text for p in problems)
    raise error(f"{where} is wired wrongly:\n  {text}")


def check_child(
    container: Parent, label: str, state: State, remapping: Mapping[str, str] | None
) -> dict[str, str]:
    """Check what can be checked when ``state`` is added: label, type, place, remapping.

    Returns:
        The remapping as a new dict.

    Raises:
        InvalidStateError: Bad or duplicate label, not a State, the container itself or
            one of its ancestors, or a remapping of keys the state does not declare.
    """
    if not isinstance(label, str) or not label or "/" in label:
        raise InvalidStateError(f"a state label is a non-empty string without '/', got {label!r}")
    if not isinstance(state, State):
        raise InvalidStateError(
            f"cannot add {label!r} to {container.path}: expected a State,"
            f" got {type(state).__name__}"
        )
    if label in container.children:
        raise InvalidStateError(
            f"duplicate label {label!r} in {container.path};"
            f" labels in use: {listing(container.children)}"
        )
    node: State | Parent | None = container
    while node is not None:
        if node is state:
            raise InvalidStateError(f"cannot add {container.path} inside itself as {label!r}")
        node = node.parent
    remap = dict(remapping or {})
    declared = {*state.input_keys, *state.output_keys}
    unknown = [k for k in remap if k not in declared]
    if unknown:
        raise InvalidStateError(
            f"remapping of {label!r} in {container.path} names keys the state does not declare:"
            f" {listing(unknown)}; its keys: {listing(declared)}"
        )
    return remap
