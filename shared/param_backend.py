"""`MasterBackend`: a node's parameters backed by the master, and its master-down behaviour."""

from __future__ import annotations

import functools
import os
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Protocol

from .errors import InvalidNameError, ParameterError, ServiceUnavailableError, ZenrosTimeout
from .names import Token
from .owner import Owner
from .param_client import ParameterClient
from .param_protocol import SET_PARAM, local_param_name, node_param_name

if TYPE_CHECKING:
    from .graph import Graph
    from .param_client import ParamEvent
    from .params import Parameters

__all__ = ["MASTER_GONE_GRACE", "MASTER_IN_LAUNCH", "MASTER_JOIN_WAIT", "MasterBackend",
           "ParameterOwner", "attach_parameter_backend"]

_UNREACHABLE = (ServiceUnavailableError, ZenrosTimeout)

MASTER_IN_LAUNCH = "ZENROS_MASTER_IN_LAUNCH"
"""Set by launch for the nodes it starts after a master of its own: master is up (launch
waited for it), and the node's fresh session only has to learn its services."""
MASTER_JOIN_WAIT = 3.0
"""How long such a node waits for master's services before its first parameter read."""
MASTER_GONE_GRACE = 3.0
"""Seconds master's services may be gone from the graph before a node reports master gone: a
link that dropped and was made again (a lease that ran out on a starved box) takes master's
tokens away and back within a second, and a healthy system must not report its master gone
(as an action client waits `zenros.action.client.LOST_TIMEOUT` for its goal's server)."""


class ParameterOwner(Owner, Protocol):
    """What the backend uses of its node (a `zenros.Node`; typed so, `node` imports this
    module and not the other way round)."""

    @property
    def graph(self) -> Graph: ...

    @property
    def parameters(self) -> Parameters: ...


class MasterBackend:
    """The `ParameterBackend` of one node: fetch from and store to the master.

    With master unreachable, `fetch` reports nothing stored (so declared defaults and
    overrides apply), `store` keeps the value to push later, and one warning is logged per
    outage: when an operation finds no master, or when master's services stay out of the
    graph for `MASTER_GONE_GRACE` seconds (a blip shorter than that is no outage). When a master's services appear in the graph, `resync` runs on a thread of its
    own: pending writes are pushed, every other declared parameter is fetched again.
    """

    def __init__(self, node: ParameterOwner, client: ParameterClient) -> None:
        self._node = node
        self._client = client
        self._lock = threading.Lock()
        self._pending: dict[str, Any] = {}
        self._down = False
        self._gone: threading.Timer | None = None  # master's tokens left: report after a grace
        self.closed = False
        self._sub = client.subscribe(node.fqn, self._on_event)
        graph = node.graph
        self._masters = {(t.zid, t.eid) for t in graph.servers(SET_PARAM)}
        graph.add_listener(self._on_graph)

    @property
    def reachable(self) -> bool:
        """False after an operation found no master, until one answers again."""
        return not self._down

    # ------------------------------------------------------------------ ParameterBackend

    def fetch(self, name: str) -> tuple[bool, Any]:
        """The stored value of the node's parameter ``name``: ``(found, value)``."""
        full = self._master_name(name)
        if full is None:
            return False, None
        try:
            found, value = self._client.lookup(full)
        except _UNREACHABLE as exc:
            self._mark_down(exc)
            return False, None
        except (ParameterError, InvalidNameError) as exc:
            self._node.logger.warning("cannot read parameter %s from master: %s", full, exc)
            return False, None
        self._mark_up()
        return found, value

    def store(self, name: str, value: Any) -> None:
        """Write the node's parameter through to master (kept for later if it is down)."""
        full = self._master_name(name)
        if full is None:
            return
        try:
            written = self._client.set(full, value)
        except _UNREACHABLE as exc:
            with self._lock:
                self._pending[name] = value
            self._mark_down(exc)
            return
        except (ParameterError, InvalidNameError) as exc:  # e.g. a dict key with a '.'
            self._node.logger.warning("parameter %s keeps its value locally; master refused"
                                      " it: %s", name, exc)
            return
        with self._lock:
            self._pending.pop(name, None)
        self._sub.note(written.name, (written.time, written.source))
        self._mark_up()

    # ------------------------------------------------------------------ resync

    def resync(self) -> None:
        """Push writes made while master was down, then fetch every declared parameter."""
        params = self._node.parameters
        for p in params.describe():
            if self.closed:
                return
            with self._lock:
                pending = p.name in self._pending
            if pending:
                self.store(p.name, params.get(p.name))
                continue
            found, value = self.fetch(p.name)
            if found:
                self._apply(p.name, value)

    def _apply(self, name: str, value: Any) -> None:
        try:
            self._node.parameters.apply_remote(name, value)
        except ParameterError as exc:
            self._node.logger.warning("ignoring the stored value of parameter %s: %s", name, exc)

    def _on_event(self, event: ParamEvent) -> None:
        if self.closed or event.deleted:
            return  # a deleted stored value leaves the node's current value in place
        local = local_param_name(self._node.fqn, event.name)
        if local is None:
            return
        params = self._node.parameters
        if params.has(local):
            self._apply(local, event.value)
            return
        parts = local.split(".")
        for i in range(len(parts) - 1, 0, -1):  # a leaf inside a declared dict parameter
            parent = ".".join(parts[:i])
            if params.has(parent) and isinstance(params.get(parent), dict):
                self._spawn(functools.partial(self._refetch, parent))
                return

    def _refetch(self, name: str) -> None:
        found, value = self.fetch(name)
        if found:
            self._apply(name, value)

    # ------------------------------------------------------------------ presence

    def _on_graph(self, event: str, tok: Token) -> None:
        if self.closed or tok.kind != "srv" or tok.name != SET_PARAM:
            return
        with self._lock:
            had = bool(self._masters)
            if event == "put":
                self._masters.add((tok.zid, tok.eid))
            else:
                self._masters.discard((tok.zid, tok.eid))
            has = bool(self._masters)
            if has and self._gone is not None:  # back within the grace: not reported gone
                self._gone.cancel()
                self._gone = None
            elif had and not has:
                self._gone = threading.Timer(MASTER_GONE_GRACE, self._confirm_gone)
                self._gone.daemon = True
                self._gone.start()
        if has and not had:
            self._spawn(self.resync)

    def _confirm_gone(self) -> None:
        """`MASTER_GONE_GRACE` s after master's services left the graph: still gone?"""
        with self._lock:
            gone = not self._masters and not self.closed
            self._gone = None
        if gone:
            self._mark_down(f"master left the graph {MASTER_GONE_GRACE:g} s ago")

    def _mark_down(self, why: object) -> None:
        with self._lock:
            if self._down:
                return
            self._down = True
        self._node.logger.warning(
            "parameter server unreachable (%s): using declared defaults and local values;"
            " stored values are picked up when master returns", why)

    def _mark_up(self) -> None:
        with self._lock:
            if not self._down:
                return
            self._down = False
        self._node.logger.info("parameter server reachable again")

    def _spawn(self, fn: Callable[[], None]) -> None:
        def run() -> None:
            try:
                fn()
            except Exception:  # a worker thread is a boundary; the session may be closing
                if not self.closed:
                    self._node.logger.exception("parameter resync failed")

        threading.Thread(target=run, name="zenros-param-resync", daemon=True).start()

    def _master_name(self, name: str) -> str | None:
        try:
            return node_param_name(self._node.fqn, name)
        except InvalidNameError:
            return None  # no master spelling (e.g. 'max-speed'): the parameter stays local

    def close(self) -> None:
        """Stop following master (the node is closing)."""
        if self.closed:
            return
        self.closed = True
        with self._lock:
            if self._gone is not None:
                self._gone.cancel()
        self._sub.close()
        if self._node.parameters.backend is self:
            self._node.parameters.backend = None


def attach_parameter_backend(node: ParameterOwner) -> MasterBackend:
    """Back ``node``'s parameters with the master; call it before parameters are declared.

    Sets ``node.parameters.backend``: a declared parameter takes its stored value from the
    master (under the node's name: ``costmap.inflation`` of ``/nav/planner`` is
    ``/nav/planner/costmap/inflation``) and ``set_parameter`` writes through. Remote changes
    reach the node's on-change callbacks. Parameters declared before the call are fetched
    now. With master down, declared values stay and a warning says so; when a master
    appears, stored values are picked up and writes made meanwhile are pushed.

    Returns:
        The backend (closed with the node).
    """
    client = ParameterClient(node.context, node=node.fqn)
    if os.environ.get(MASTER_IN_LAUNCH):
        client.wait_for_master(MASTER_JOIN_WAIT)  # at once when its services are known
    backend = MasterBackend(node, client)
    node.parameters.backend = backend
    node.add_waitable(backend)
    backend.resync()
    return backend
