"""The parameter tree: stamped writes per name, last-writer-wins merge, and the visible view.

The tree keeps one row per name: the newest write there, a value or a tombstone, with its
stamp. Which leaves are *visible* follows from the rows alone:

    a live row at N is visible iff no row at an ancestor or a descendant of N is newer.

A write at N thereby replaces the subtree at N (older rows below are hidden) and turns an
older leaf above N into a namespace; a tombstone at N deletes the subtree. Setting a dict at
N writes a tombstone at N plus one row per leaf, all with the same stamp. Because the view is a
function of the rows and merging keeps the newest row per name, merge is commutative,
associative and idempotent: replicas that saw the same writes, in any order, agree.
"""

from __future__ import annotations

import bisect
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import Any, NamedTuple

import msgspec
from zenros.errors import InvalidNameError, InvalidParameterValueError, ParameterNotFoundError
from zenros.names import join, namespace_of, validate_name

from .param_value import (
    Value,
    ancestors,
    canonical,
    check_size,
    check_value,
    copy_value,
    flatten,
)

__all__ = [
    "ZERO",
    "Change",
    "Entry",
    "ParamTree",
    "Stamp",
    "decode_entries",
    "encode_entries",
    "ntp64",
]


class Stamp(NamedTuple):
    """A totally ordered write time: an NTP64 time (Zenoh HLC), then the writer's id."""

    time: int
    source: str


ZERO = Stamp(0, "")


class Entry(msgspec.Struct, frozen=True, array_like=True):
    """One row: the newest write at one name (a value or a tombstone), as replicas exchange it."""

    name: str
    time: int
    source: str
    deleted: bool = False
    value: Any = None

    @property
    def stamp(self) -> Stamp:
        return Stamp(self.time, self.source)


@dataclass(frozen=True)
class Change:
    """A change of one visible leaf, as listeners receive it (``deleted`` or a new ``value``)."""

    name: str
    value: Value
    deleted: bool
    stamp: Stamp


_ENCODER = msgspec.msgpack.Encoder(order="deterministic")


def ntp64(ns: int) -> int:
    """NTP64 time (32.32 fixed-point seconds since the UNIX epoch, as Zenoh's HLC) from ns."""
    sec, rem = divmod(ns, 1_000_000_000)
    return (sec << 32) | ((rem << 32) // 1_000_000_000)


def encode_entries(entries: Iterable[Entry]) -> bytes:
    """Entries as MessagePack (dict keys sorted, so equal rows encode equally)."""
    return _ENCODER.encode(list(entries))


def decode_entries(data: bytes) -> list[Entry]:
    """Entries back from `encode_entries`.

    Raises:
        msgspec.DecodeError: the payload is not a list of entries.
    """
    return msgspec.msgpack.decode(data, type=list[Entry])


def _order(e: Entry) -> tuple[int, str, bool, bytes]:
    """Total order of rows: stamp, then a deterministic tie-break on the content."""
    return (e.time, e.source, e.deleted, _ENCODER.encode(e.value))


def _range(names: list[str], prefix: str) -> tuple[int, int]:
    """Index range of ``prefix`` and its descendants in a sorted name list.

    '/' sorts before every character allowed in a name, so a subtree is contiguous.
    """
    if prefix == "/":
        return 0, len(names)
    return bisect.bisect_left(names, prefix), bisect.bisect_left(names, prefix + "0")


def _insort(names: list[str], name: str) -> None:
    i = bisect.bisect_left(names, name)
    if i == len(names) or names[i] != name:
        names.insert(i, name)


class ParamTree:
    """The in-memory rows and their visible view; no I/O, not thread-safe."""

    def __init__(self, entries: Iterable[Entry] = ()) -> None:
        self._rows: dict[str, Entry] = {}
        self._row_names: list[str] = []
        self._newest_below: dict[str, Stamp] = {}
        self._visible: dict[str, Entry] = {}
        self._visible_names: list[str] = []
        self.apply(self.winners(entries))

    # ------------------------------------------------------------------ reads

    def get(self, name: str) -> Value:
        """The value of a leaf, or the subtree under a namespace as a nested dict.

        Raises:
            ParameterNotFoundError: nothing is set at or under ``name``.
        """
        name = canonical(name)
        leaf = self._visible.get(name)
        if leaf is not None:
            return copy_value(leaf.value)
        lo, hi = _range(self._visible_names, name)
        if lo == hi:
            if name == "/":
                return {}
            raise ParameterNotFoundError(self._not_found(name))
        out: dict[str, Value] = {}
        cut = 1 if name == "/" else len(name) + 1
        for full in self._visible_names[lo:hi]:
            *path, last = full[cut:].split("/")
            node = out
            for part in path:
                node = node.setdefault(part, {})
            node[last] = copy_value(self._visible[full].value)
        return out

    def has(self, name: str) -> bool:
        """True if a leaf or a non-empty namespace exists at ``name``."""
        name = canonical(name)
        lo, hi = _range(self._visible_names, name)
        return lo < hi

    def names(self, prefix: str = "/") -> list[str]:
        """Every visible leaf name at or under ``prefix``, sorted."""
        lo, hi = _range(self._visible_names, canonical(prefix))
        return self._visible_names[lo:hi]

    def search(self, namespace: str, key: str) -> str | None:
        """ROS ``searchParam``: the full name ``key`` has in the nearest enclosing namespace.

        Starting at ``namespace`` (the caller's node name in ROS 1, so its private namespace
        comes first) and walking up to ``/``, the first namespace in which the first segment
        of ``key`` exists wins; the rest of ``key`` is appended whether or not it exists yet.

        Args:
            namespace: absolute namespace to start from, usually the caller's node FQN.
            key: a relative name such as ``robot_description`` or ``robot_description/arm``.

        Returns:
            The absolute name found, or None.

        Raises:
            InvalidNameError: ``key`` is empty, global or private, or a name is malformed.
        """
        if not key or key[0] in "/~":
            raise InvalidNameError(
                f"cannot search for parameter {key!r}: the key must be a relative name"
                " (global and private names need no search)"
            )
        validate_name(key, "parameter")
        parts = [p for p in canonical(namespace or "/").split("/") if p]
        first = key.split("/", 1)[0]
        for i in range(len(parts), -1, -1):
            base = "/" + "/".join(parts[:i])
            if self.has(join(base, first)):
                found: str = join(base, key)
                return found
        return None

    def entries(self) -> list[Entry]:
        """Every row, tombstones included, sorted by name."""
        return [self._rows[n] for n in self._row_names]

    def since(self, stamp: Stamp) -> list[Entry]:
        """Rows written after ``stamp``, oldest first."""
        return sorted((e for e in self._rows.values() if e.stamp > stamp), key=_order)

    def newest(self) -> Stamp:
        """The newest stamp of any row (ZERO when empty)."""
        return max((e.stamp for e in self._rows.values()), default=ZERO)

    # ------------------------------------------------------------------ writes

    def plan_set(self, name: str, value: Value, stamp: Stamp) -> list[Entry]:
        """The rows that setting ``name`` to ``value`` writes (a dict replaces the subtree).

        Raises:
            InvalidNameError, InvalidParameterValueError: bad name, key or value.
        """
        name = canonical(name)
        value = check_value(value, name)
        check_size(value, name)
        t, src = stamp
        if not isinstance(value, dict):
            if name == "/":
                raise InvalidParameterValueError(
                    f"the root namespace / can only be set to a dict, got {type(value).__name__}"
                )
            return [Entry(name, t, src, False, value)]
        if not value and name != "/":
            return [Entry(name, t, src, False, {})]
        rows = [Entry(name, t, src, True)]
        rows += [Entry(canonical(leaf), t, src, False, v) for leaf, v in flatten(name, value)]
        return rows

    def plan_delete(self, name: str, stamp: Stamp) -> list[Entry]:
        """The rows that deleting the leaf or subtree at ``name`` writes.

        Raises:
            ParameterNotFoundError: nothing is set at or under ``name``.
        """
        if not self.has(name):
            raise ParameterNotFoundError(self._not_found(name))
        return [Entry(name, stamp.time, stamp.source, True)]

    def winners(self, entries: Iterable[Entry]) -> list[Entry]:
        """The entries that are newer than the rows they would replace (newest per name)."""
        best: dict[str, Entry] = {}
        for e in entries:
            old = best.get(e.name) or self._rows.get(e.name)
            if old is None or _order(e) > _order(old):
                best[e.name] = e
        return [e for e in best.values() if self._rows.get(e.name) is not e]

    def apply(self, winners: list[Entry]) -> list[Change]:
        """Store rows (from `winners`) and return the changes of the visible view.

        Deletions come first, so a listener mirroring the tree never sees a leaf and a
        namespace at one name at the same time.
        """
        affected: set[str] = set()
        for e in winners:
            self._rows[e.name] = e
            _insort(self._row_names, e.name)
            affected.add(e.name)
            for up in ancestors(e.name):
                affected.add(up)
                if self._newest_below.get(up, ZERO) < e.stamp:
                    self._newest_below[up] = e.stamp
            lo, hi = _range(self._row_names, e.name)
            affected.update(self._row_names[lo:hi])
        changes: list[Change] = []
        newest = max((e.stamp for e in winners), default=ZERO)
        for name in sorted(affected):
            row = self._rows.get(name)
            before = self._visible.get(name)
            now = row if row is not None and self._is_visible(row) else None
            if now is before:
                continue
            if now is None:
                assert before is not None
                del self._visible[name]
                self._visible_names.remove(name)
                changes.append(Change(name, None, True, newest))
            else:
                if before is None:
                    _insort(self._visible_names, name)
                self._visible[name] = now
                changes.append(Change(name, copy_value(now.value), False, now.stamp))
        changes.sort(key=lambda c: not c.deleted)  # deletions first, each group by name
        return changes

    # ------------------------------------------------------------------ internals

    def _is_visible(self, row: Entry) -> bool:
        if row.deleted:
            return False
        stamp = row.stamp
        if self._newest_below.get(row.name, ZERO) > stamp:
            return False
        for up in ancestors(row.name):
            above = self._rows.get(up)
            if above is not None and above.stamp > stamp:
                return False
        return True

    def _not_found(self, name: str) -> str:
        parent = namespace_of(name)
        cut = 1 if parent == "/" else len(parent) + 1
        near = sorted({n[cut:].split("/", 1)[0] for n in self.names(parent) if n != parent})
        hint = f"; {parent} holds: {', '.join(near[:10])}" if near else ""
        return f"parameter {name} is not set{hint}"

    def __iter__(self) -> Iterator[str]:
        return iter(self._visible_names)

    def __len__(self) -> int:
        return len(self._visible_names)
