"""The diagnostic aggregator's core, as ROS's diagnostic_aggregator: statuses sorted into a
tree by analyzers (GenericAnalyzer, and "Other" for what none claims), with no I/O.

The service (``python -m zenros.services.diagnostics``) feeds it ``/diagnostics`` and
publishes its `Aggregator.report` on ``/diagnostics_agg`` and ``/diagnostics_toplevel_state``.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from ..errors import ConfigError
from ..msgs.diagnostic_msgs import DiagnosticStatus, KeyValue
from .status import ERROR, LEVEL_NAMES, OK, STALE

__all__ = ["Aggregator", "GenericAnalyzer", "OtherAnalyzer", "analyzers_from_params",
           "output_name", "remove_leading_chaff", "toplevel_state"]

_NS = 1_000_000_000


def output_name(name: str) -> str:
    """An item's name in the tree: its slashes become spaces."""
    return name.replace("/", " ")


def remove_leading_chaff(full: str, chaff: str) -> str:
    """``/Path/prefix: Name`` → ``/Path/Name``: drop ``chaff`` at the start of the last
    segment, then a ``:`` and the spaces that follow (ROS's removeLeadingNameChaff)."""
    if not chaff:
        return full
    cut = full.rfind("/")
    head, tail = full[:cut + 1], full[cut + 1:]
    tail = tail.removeprefix(chaff)
    tail = tail.removeprefix(":")
    return head + tail.lstrip(" ")


def _join(path: str, name: str) -> str:
    return "/" + name if path in ("", "/") else f"{path}/{name}"


@dataclass
class StatusItem:
    """The last status of one name, and when it came."""

    name: str
    level: int = STALE
    message: str = "Missing"
    hardware_id: str = ""
    values: list[KeyValue] = field(default_factory=list)
    updated_ns: int = 0

    def to_status(self, path: str, stale: bool) -> DiagnosticStatus:
        return DiagnosticStatus(level=STALE if stale else self.level,
                                name=_join(path, output_name(self.name)),
                                message=self.message, hardware_id=self.hardware_id,
                                values=list(self.values))


class _AnalyzerBase:
    """Items by name under one header ``path``; `report` as GenericAnalyzerBase's."""

    def __init__(self, path: str, *, timeout: float = 5.0, num_items: int = -1,
                 discard_stale: bool = False) -> None:
        self.path = path
        self.timeout = timeout
        self.num_items = num_items
        self.discard_stale = discard_stale
        self.items: dict[str, StatusItem] = {}

    def analyze(self, s: DiagnosticStatus, now_ns: int) -> None:
        self.items[s.name] = StatusItem(s.name, min(max(int(s.level), OK), STALE), s.message,
                                        s.hardware_id, list(s.values), now_ns)

    def report(self, now_ns: int) -> list[DiagnosticStatus]:
        header = DiagnosticStatus(level=OK, name=self.path, message="OK")
        out = [header]
        all_stale = True
        for name, item in list(self.items.items()):
            stale = self.timeout > 0 and (now_ns - item.updated_ns) / _NS > self.timeout
            if stale and self.discard_stale:
                del self.items[name]
                continue
            header.level = max(header.level, item.level)
            header.values.append(KeyValue(key=name, value=item.message))
            all_stale = all_stale and (item.level == STALE or stale)
            out.append(item.to_status(self.path, stale))
            if stale:
                header.level = STALE
        if all_stale:
            header.level = OK if self.discard_stale else STALE
        elif header.level == STALE:
            header.level = ERROR  # some stale, not all
        header.message = LEVEL_NAMES[header.level]
        if self.num_items == 0 and not self.items:
            header.level, header.message = OK, "OK"
        elif self.num_items > 0 and len(self.items) != self.num_items:
            header.level = max(ERROR, header.level)
            header.message = (f"Expected {self.num_items}, found {len(self.items)}"
                              if self.items else f"No items found, expected {self.num_items}")
        return out


class GenericAnalyzer(_AnalyzerBase):
    """diagnostic_aggregator's GenericAnalyzer: claims the statuses whose name matches a
    ``regex`` (whole name), is ``expected``, ``startswith`` or ``contains`` one of the given
    strings; shows them under ``<base>/<path>``, less a ``remove_prefix`` (and
    ``find_and_remove_prefix``, which also claims by it). ``expected`` names that never
    came show as STALE "Missing" and make the header ERROR; ``timeout`` (s, 0: never)
    makes silent items STALE; ``num_items`` checks their count; ``discard_stale`` drops
    timed-out items instead."""

    def __init__(self, path: str, *, base_path: str = "", startswith: Sequence[str] = (),
                 contains: Sequence[str] = (), expected: Sequence[str] = (),
                 regex: Sequence[str] = (), remove_prefix: Sequence[str] = (),
                 find_and_remove_prefix: Sequence[str] = (), timeout: float = 5.0,
                 num_items: int = -1, discard_stale: bool = False, now_ns: int = 0) -> None:
        if not path:
            raise ConfigError("an analyzer needs a path (the name of its branch)")
        super().__init__(_join(base_path, path), timeout=timeout, num_items=num_items,
                         discard_stale=discard_stale)
        self.nice_name = path
        self.startswith = list(startswith) + list(find_and_remove_prefix)
        self.contains = list(contains)
        self.expected = list(expected)
        try:
            self.regex = [re.compile(r) for r in regex]
        except re.error as e:
            raise ConfigError(f"analyzer {path!r}: bad regex: {e}") from None
        self.chaff = [output_name(c) for c in list(remove_prefix) + list(find_and_remove_prefix)]
        if not (self.startswith or self.contains or self.expected or self.regex):
            raise ConfigError(f"analyzer {path!r} has no way of matching statuses: give "
                             "startswith, contains, expected or regex")
        for name in self.expected:
            self.items[name] = StatusItem(name, updated_ns=now_ns)

    def match(self, name: str) -> bool:
        return (any(r.fullmatch(name) for r in self.regex) or name in self.expected
                or any(name.startswith(s) for s in self.startswith)
                or any(c in name for c in self.contains))

    def report(self, now_ns: int) -> list[DiagnosticStatus]:
        """The header, then the items; an expected item not yet heard from is STALE
        "Missing", which makes the header ERROR (STALE if nothing else came either)."""
        out = super().report(now_ns)
        for s in out:
            for c in self.chaff:
                s.name = remove_leading_chaff(s.name, c)
        return out


class OtherAnalyzer(_AnalyzerBase):
    """What no analyzer claims, under ``<base>/Other`` (items go after 5 s of silence);
    nothing is shown while it is empty. ``other_as_errors``: its header is ERROR."""

    def __init__(self, base_path: str = "", other_as_errors: bool = False) -> None:
        super().__init__(_join(base_path, "Other"), timeout=5.0, discard_stale=True)
        self.other_as_errors = other_as_errors

    def report(self, now_ns: int) -> list[DiagnosticStatus]:
        out = super().report(now_ns)
        if len(out) == 1:
            return []
        if self.other_as_errors:
            out[0].level, out[0].message = ERROR, 'Unanalyzed items found in "Other"'
        return out


class Aggregator:
    """Statuses in (`add`), the tree out (`report`): each status goes to every analyzer that
    matches its name, or to "Other"."""

    def __init__(self, analyzers: Iterable[GenericAnalyzer], *, base_path: str = "",
                 other_as_errors: bool = False) -> None:
        self.analyzers = list(analyzers)
        self.other = OtherAnalyzer(base_path, other_as_errors)
        self._routes: dict[str, list[_AnalyzerBase]] = {}

    def add(self, statuses: Iterable[DiagnosticStatus], now_ns: int) -> int:
        """Take in ``statuses``; returns the highest level one of them raised an item to
        (-1 if none rose), which a ``critical`` aggregator publishes at once for."""
        raised = -1
        for s in statuses:
            routes = self._routes.get(s.name)
            if routes is None:
                routes = [a for a in self.analyzers if a.match(s.name)] or [self.other]
                self._routes[s.name] = routes
            for a in routes:
                before = a.items.get(s.name)
                a.analyze(s, now_ns)
                if before is None or s.level > before.level:
                    raised = max(raised, s.level)
        return raised

    def report(self, now_ns: int) -> tuple[list[DiagnosticStatus], DiagnosticStatus]:
        """The tree (each analyzer's header, then its items; "Other" last) and the top-level
        state: the worst level, ERROR if there is nothing or some (not all) are stale."""
        out: list[DiagnosticStatus] = []
        for a in self.analyzers:
            out += a.report(now_ns)
        out += self.other.report(now_ns)
        return out, toplevel_state(out)


def toplevel_state(tree: Sequence[DiagnosticStatus]) -> DiagnosticStatus:
    """The robot's state from its tree: the worst level; ERROR if the tree is empty or some
    (not all) of it is STALE."""
    levels = [s.level for s in tree]
    top = DiagnosticStatus(name="toplevel_state", level=max(levels, default=-1))
    if not levels or (max(levels) > ERROR and min(levels) <= ERROR):
        top.level = ERROR
    top.message = LEVEL_NAMES[top.level]
    return top


_KEYS: dict[str, type] = {"type": str, "path": str, "startswith": list, "contains": list,
                          "expected": list, "regex": list, "remove_prefix": list,
                          "find_and_remove_prefix": list, "timeout": float, "num_items": int,
                          "discard_stale": bool, "name": list}
_TYPES = ("diagnostic_aggregator/GenericAnalyzer", "GenericAnalyzer")


def analyzers_from_params(params: dict[str, Any], base_path: str = "",
                          now_ns: int = 0) -> list[GenericAnalyzer]:
    """GenericAnalyzers from flat parameters as diagnostic_aggregator's YAML gives them:
    ``analyzers.<ns>.type``, ``analyzers.<ns>.path`` and the analyzer's own keys
    (``startswith``, ``contains``, ``expected``, ``regex``, ``remove_prefix``,
    ``find_and_remove_prefix``, ``timeout``, ``num_items``, ``discard_stale``); a string
    where a list is expected is a list of one. `ConfigError` names what is wrong."""
    groups: dict[str, dict[str, Any]] = {}
    for key, value in params.items():
        if not key.startswith("analyzers."):
            continue
        ns, _, k = key[len("analyzers."):].rpartition(".")
        if not ns or k not in _KEYS:
            raise ConfigError(f"parameter {key!r}: analyzers.<name>.<key>, key one of "
                             f"{', '.join(sorted(_KEYS))}")
        want = _KEYS[k]
        if want is list:
            value = [value] if isinstance(value, str) else value
            if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                raise ConfigError(f"parameter {key!r}: a list of strings, got {value!r}")
        elif want is float and isinstance(value, int) and not isinstance(value, bool):
            value = float(value)
        elif not isinstance(value, want) or (want is int and isinstance(value, bool)):
            raise ConfigError(f"parameter {key!r}: a {want.__name__}, got {value!r}")
        groups.setdefault(ns, {})[k] = value
    out = []
    for ns in sorted(groups):
        g = groups[ns]
        if g.get("type") not in _TYPES:
            raise ConfigError(f"analyzers.{ns}.type: {g.get('type')!r} is not supported; "
                             f"this aggregator runs {_TYPES[0]}")
        if not g.get("path"):
            raise ConfigError(f"analyzers.{ns}.path is missing")
        expected = list(g.get("expected", [])) + list(g.get("name", []))
        out.append(GenericAnalyzer(
            g["path"], base_path=base_path, startswith=g.get("startswith", ()),
            contains=g.get("contains", ()), expected=expected, regex=g.get("regex", ()),
            remove_prefix=g.get("remove_prefix", ()),
            find_and_remove_prefix=g.get("find_and_remove_prefix", ()),
            timeout=g.get("timeout", 5.0), num_items=g.get("num_items", -1),
            discard_stale=g.get("discard_stale", False), now_ns=now_ns))
    return out
