"""Userdata: a container's thread-safe key/value store, and the key-restricted view states get."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterable, Iterator, Mapping
from typing import Any, Protocol

from ..errors import UserDataError

__all__ = ["Remapper", "UserData", "UserDataAccess"]


def _listing(keys: Iterable[object]) -> str:
    items = sorted(str(k) for k in keys)
    return ", ".join(items) if items else "(none)"


class UserDataAccess(Protocol):
    """What a state's ``execute`` receives: item and attribute access to userdata keys."""

    def __getitem__(self, key: str) -> Any: ...

    def __setitem__(self, key: str, value: Any) -> None: ...

    def __contains__(self, key: object) -> bool: ...

    def __getattr__(self, name: str) -> Any: ...

    def __setattr__(self, name: str, value: Any) -> None: ...

    def keys(self) -> list[str]: ...

    def get(self, key: str, default: Any = None) -> Any: ...


class UserData:
    """A flat, thread-safe store of named values owned by one container.

    Keys are read and written as items (``ud["goal"]``) or attributes (``ud.goal``).
    Values are stored by reference, as in smach.

    Args:
        data: Initial keys and values.
        owner: Who owns it, for error messages: a name, or a function returning one
            (a container passes its path, which changes when it is nested).
    """

    _lock: threading.RLock
    _data: dict[str, Any]
    _owner: str | Callable[[], str]

    def __init__(
        self, data: Mapping[str, Any] | None = None, owner: str | Callable[[], str] = "userdata"
    ) -> None:
        object.__setattr__(self, "_lock", threading.RLock())
        object.__setattr__(self, "_data", dict(data or {}))
        object.__setattr__(self, "_owner", owner)

    def _owner_name(self) -> str:
        owner = self._owner
        return owner() if callable(owner) else str(owner)

    def __getitem__(self, key: str) -> Any:
        with self._lock:
            try:
                return self._data[key]
            except KeyError:
                raise UserDataError(
                    f"{self._owner_name()} has no userdata key {key!r}; set keys: {_listing(self._data)}"
                ) from None

    def __setitem__(self, key: str, value: Any) -> None:
        if not isinstance(key, str) or not key:
            raise UserDataError(f"userdata keys are non-empty strings, got {key!r}")
        with self._lock:
            self._data[key] = value

    def __delitem__(self, key: str) -> None:
        with self._lock:
            if key not in self._data:
                raise UserDataError(
                    f"{self._owner_name()} has no userdata key {key!r}; set keys: {_listing(self._data)}"
                )
            del self._data[key]

    def __contains__(self, key: object) -> bool:
        with self._lock:
            return key in self._data

    def __len__(self) -> int:
        with self._lock:
            return len(self._data)

    def __iter__(self) -> Iterator[str]:
        return iter(self.keys())

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        return self[name]

    def __setattr__(self, name: str, value: Any) -> None:
        if name.startswith("_") or hasattr(type(self), name):
            raise UserDataError(
                f"{name!r} cannot be set as an attribute of userdata; use ud[{name!r}] = ..."
            )
        self[name] = value

    def keys(self) -> list[str]:
        """The set keys, in insertion order."""
        with self._lock:
            return list(self._data)

    def get(self, key: str, default: Any = None) -> Any:
        """The value of ``key``, or ``default`` if it is not set."""
        with self._lock:
            return self._data.get(key, default)

    def update(self, other: Mapping[str, Any] | UserData) -> None:
        """Set every key of ``other``, overwriting existing ones."""
        items = other.snapshot() if isinstance(other, UserData) else dict(other)
        for key, value in items.items():
            self[key] = value

    def snapshot(self) -> dict[str, Any]:
        """A shallow copy of all keys and values, taken under the lock."""
        with self._lock:
            return dict(self._data)

    def __repr__(self) -> str:
        return f"UserData({self.snapshot()!r})"


class Remapper:
    """A state's view of its container's userdata: declared keys only, names remapped.

    Reading a key that is not an input key, or writing one that is not an output key,
    raises `UserDataError` naming the state and the key. ``remapping`` maps the state's
    own key names onto the container's (``{"foo_in": "counter"}``).

    Args:
        userdata: The container's userdata.
        state: Who is reading (``/SM/FOO (Foo)``), for error messages.
        input_keys: Keys the state may read.
        output_keys: Keys the state may write.
        remapping: State key -> container key.
    """

    _ud: UserDataAccess
    _state: str
    _inputs: tuple[str, ...]
    _outputs: tuple[str, ...]
    _map: dict[str, str]

    def __init__(
        self,
        userdata: UserDataAccess,
        state: str,
        input_keys: tuple[str, ...],
        output_keys: tuple[str, ...],
        remapping: Mapping[str, str] | None = None,
    ) -> None:
        object.__setattr__(self, "_ud", userdata)
        object.__setattr__(self, "_state", state)
        object.__setattr__(self, "_inputs", input_keys)
        object.__setattr__(self, "_outputs", output_keys)
        object.__setattr__(self, "_map", dict(remapping or {}))

    def _remap(self, key: str) -> str:
        return self._map.get(key, key)

    def _check_read(self, key: str) -> str:
        if key not in self._inputs:
            raise UserDataError(
                f"state {self._state} read userdata key {key!r}, which it did not declare as an"
                f" input key; its input keys: {_listing(self._inputs)}"
            )
        return self._remap(key)

    def __getitem__(self, key: str) -> Any:
        target = self._check_read(key)
        if target not in self._ud:
            via = f" (remapped to {target!r})" if target != key else ""
            raise UserDataError(
                f"state {self._state} read input key {key!r}{via}, which is not set;"
                f" set keys: {_listing(self._ud.keys())}"
            )
        return self._ud[target]

    def __setitem__(self, key: str, value: Any) -> None:
        if key not in self._outputs:
            raise UserDataError(
                f"state {self._state} wrote userdata key {key!r}, which it did not declare as an"
                f" output key; its output keys: {_listing(self._outputs)}"
            )
        self._ud[self._remap(key)] = value

    def __contains__(self, key: object) -> bool:
        return isinstance(key, str) and key in self._inputs and self._remap(key) in self._ud

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        return self[name]

    def __setattr__(self, name: str, value: Any) -> None:
        if name.startswith("_") or hasattr(type(self), name):
            raise UserDataError(
                f"state {self._state}: {name!r} cannot be set as an attribute of userdata;"
                f" use userdata[{name!r}] = ..."
            )
        self[name] = value

    def keys(self) -> list[str]:
        """The input keys that are currently set, under the state's own names."""
        return [k for k in self._inputs if self._remap(k) in self._ud]

    def get(self, key: str, default: Any = None) -> Any:
        """The value of input key ``key``, or ``default`` if it is declared but not set."""
        target = self._check_read(key)
        return self._ud.get(target, default)

    def __repr__(self) -> str:
        return f"Remapper({self._state}, inputs={list(self._inputs)}, outputs={list(self._outputs)})"
