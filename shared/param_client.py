"""`ParameterClient`: the master's parameter API over Zenoh, for nodes, tools and tests."""

from __future__ import annotations

import builtins
import json
import logging
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

import zenoh

from .errors import (
    InvalidNameError,
    InvalidParameterValueError,
    ParameterError,
    ParameterNotFoundError,
    ServiceUnavailableError,
    ZenrosTimeout,
)
from .message import Message, ServiceType
from .names import namespace_of, resolve
from .param_protocol import (
    DELETE_PARAM,
    DUMP_PARAMS,
    HAS_PARAM,
    LIST_PARAMS,
    LOAD_PARAMS,
    PARAM_SERVICES,
    SEARCH_PARAM,
    SET_PARAM,
    DeleteParam,
    DeleteParamRequest,
    DumpParams,
    DumpParamsRequest,
    HasParam,
    HasParamRequest,
    ListParams,
    ListParamsRequest,
    LoadParams,
    LoadParamsRequest,
    ParamResponse,
    SearchParam,
    SearchParamRequest,
    SetParam,
    SetParamRequest,
    decode_stamp,
    decode_value,
    param_key,
    param_name,
    raise_remote,
)
from .rpc import Client

if TYPE_CHECKING:
    from .context import Context

__all__ = ["ParamEvent", "ParamSubscription", "ParameterClient", "Written"]

_log = logging.getLogger("zenros.params")
_ERRORS: dict[str, type[Exception]] = {
    "InvalidNameError": InvalidNameError,
    "InvalidParameterValueError": InvalidParameterValueError,
}


class Written(NamedTuple):
    """An acknowledged write: the absolute name and the stamp the master gave it."""

    name: str
    time: int
    source: str


class ParamEvent(NamedTuple):
    """A change of one leaf: a new ``value``, or ``deleted``; ``time``/``source`` stamp it."""

    name: str
    value: Any
    deleted: bool
    time: int
    source: str


class ParamSubscription:
    """Change events under a prefix; older events than one already seen are dropped, so the
    duplicates that several master replicas send never move a value backwards."""

    def __init__(self, ctx: Context, prefix: str, callback: Callable[[ParamEvent], None]) -> None:
        self._keys = ctx.keys
        self._callback = callback
        self._lock = threading.Lock()
        self._newest: dict[str, tuple[int, str]] = {}
        key = param_key(ctx.keys, "/**" if prefix == "/" else prefix + "/**")
        self._sub = ctx.session.declare_subscriber(key, self._on_sample)
        self.closed = False

    def note(self, name: str, stamp: tuple[int, str]) -> None:
        """Record a stamp seen elsewhere (our own write): older events for ``name`` are stale."""
        with self._lock:
            if stamp > self._newest.get(name, (0, "")):
                self._newest[name] = stamp

    def _on_sample(self, sample: zenoh.Sample) -> None:
        try:
            name = param_name(self._keys, str(sample.key_expr))
            attachment = sample.attachment
            stamp = decode_stamp(attachment.to_bytes() if attachment is not None else None)
            with self._lock:
                if stamp != (0, "") and stamp <= self._newest.get(name, (0, "")):
                    return
                self._newest[name] = stamp
            if sample.kind == zenoh.SampleKind.DELETE:
                event = ParamEvent(name, None, True, *stamp)
            else:
                value = decode_value(sample.payload.to_bytes(), str(sample.encoding))
                event = ParamEvent(name, value, False, *stamp)
            self._callback(event)
        except Exception:  # noqa: BLE001 a subscriber callback is a boundary: log, go on
            _log.exception("parameter event on %s failed", sample.key_expr)

    def close(self) -> None:
        if not self.closed:
            self.closed = True
            self._sub.undeclare()  # type: ignore[no-untyped-call]


class ParameterClient:
    """Get, set, delete, has, search, list, subscribe, dump and load parameters on master.

    Names are resolved as ROS does against ``node`` (``~x`` is private to it, ``x`` is in its
    namespace, ``/x`` is global). Reads go straight to the parameter's key (one Zenoh get);
    writes go through the master's services and return once the write is on disk.

    Args:
        ctx: the context (session) to use.
        node: the caller's fully qualified node name, if any.
        timeout: seconds to wait for the master's answer.

    Raises (every method):
        ServiceUnavailableError: no master answered (none is running or reachable).
        ZenrosTimeout: a master exists but did not answer in time.
    """

    def __init__(self, ctx: Context, *, node: str | None = None, timeout: float = 3.0) -> None:
        self._ctx = ctx
        self._node = node
        self.timeout = timeout
        self._clients: dict[str, Client] = {}
        self._resolved: dict[str, str] = {}

    @property
    def node(self) -> str | None:
        """The caller's node FQN (names resolve against it)."""
        return self._node

    def resolve(self, name: str) -> str:
        """The absolute name of ``name`` as this client's node sees it."""
        found = self._resolved.get(name)
        if found is not None:
            return found
        given = name
        if name.startswith("~") and len(name) > 1 and name[1] != "/":
            name = "~/" + name[1:]
        ns = namespace_of(self.node) if self.node else "/"
        resolved: str = resolve(name, ns, self.node, "parameter")
        if len(self._resolved) < 1024:
            self._resolved[given] = resolved
        return resolved

    def _call(self, srv_type: ServiceType, service: str, request: Message) -> Any:
        client = self._clients.get(service)
        if client is None:
            client = self._clients[service] = Client(self._ctx, srv_type, service)
        response: ParamResponse = client.call(request, self.timeout)
        raise_remote(service, response)
        return response

    # ------------------------------------------------------------------ reads

    def lookup(self, name: str) -> tuple[bool, Any]:
        """``(True, value)``, or ``(False, None)`` when nothing is set at ``name``."""
        found, value, _ = self._read(self.resolve(name))
        return found, value

    def get(self, name: str) -> Any:
        """The value at ``name``, or the subtree under a namespace as a dict.

        Raises:
            ParameterNotFoundError: nothing is set at or under ``name``.
        """
        found, value, why = self._read(self.resolve(name))
        if not found:
            raise ParameterNotFoundError(why)
        return value

    def _read(self, full: str) -> tuple[bool, Any, str]:
        """One get on the parameter's key: (found, value, why not found)."""
        replies = self._ctx.session.get(param_key(self._ctx.keys, full), timeout=self.timeout,
                                        target=zenoh.QueryTarget.BEST_MATCHING)
        for reply in replies:
            ok = reply.ok
            if ok is not None:
                return True, decode_value(ok.payload.to_bytes(), str(ok.encoding)), ""
            err = reply.err
            assert err is not None
            data = err.payload.to_bytes()
            if data == b"Timeout":
                raise ZenrosTimeout(f"master did not answer for parameter {full} within "
                                    f"{self.timeout:.3g} s")
            kind, message = _parse_error(data)
            if kind == "ParameterNotFoundError":
                return False, None, message
            raise _ERRORS.get(kind, ParameterError)(message)
        raise ServiceUnavailableError(
            f"no parameter server answered for {full} (is master running with prefix "
            f"{self._ctx.keys.prefix!r}?)"
        )

    def has(self, name: str) -> bool:
        res = self._call(HasParam, HAS_PARAM, HasParamRequest(name=self.resolve(name),
                                                              caller=self.node or ""))
        return bool(res.has)

    def search(self, key: str) -> str | None:
        """ROS ``searchParam``: ``key`` in the nearest enclosing namespace of the caller."""
        res = self._call(SearchParam, SEARCH_PARAM,
                         SearchParamRequest(key=key, caller=self.node or "/"))
        return str(res.name) if res.found else None

    def list(self, prefix: str = "/") -> list[str]:
        """Every leaf name at or under ``prefix``, sorted."""
        res = self._call(ListParams, LIST_PARAMS, ListParamsRequest(prefix=self.resolve(prefix)))
        return list(res.names)

    def dump(self, prefix: str = "/") -> str:
        """The parameters at ``prefix`` as YAML in the ROS 2 params layout."""
        res = self._call(DumpParams, DUMP_PARAMS, DumpParamsRequest(prefix=self.resolve(prefix)))
        return str(res.yaml)

    # ------------------------------------------------------------------ writes

    def set(self, name: str, value: Any) -> Written:
        """Set a leaf, or replace the subtree at ``name`` with a dict; durable on return."""
        res = self._call(SetParam, SET_PARAM, SetParamRequest(
            name=self.resolve(name), value=value, caller=self.node or ""))
        return Written(res.name, res.time, res.source)

    def delete(self, name: str, *, namespace: bool = False) -> Written:
        """Delete a leaf, or (with ``namespace=True``) a whole subtree, the root included.

        Raises:
            ParameterNotFoundError: nothing is set at or under ``name``.
            ParameterError: ``name`` is a namespace and ``namespace`` is False.
            InvalidNameError: ``name`` is empty or invalid.
        """
        res = self._call(DeleteParam, DELETE_PARAM, DeleteParamRequest(
            name=self.resolve(name) if name else "", caller=self.node or "",
            namespace=namespace))
        return Written(res.name, res.time, res.source)

    def load(
        self, text: str, namespace: str = "/", source: str = "<string>"
    ) -> builtins.list[str]:
        """Set every parameter of a YAML document (ROS 2 or plain layout); returns the names."""
        res = self._call(LoadParams, LOAD_PARAMS, LoadParamsRequest(
            yaml=text, namespace=self.resolve(namespace), source=source))
        return list(res.names)

    # ------------------------------------------------------------------ events, presence

    def subscribe(self, prefix: str, callback: Callable[[ParamEvent], None]) -> ParamSubscription:
        """Call ``callback(event)`` for every change at or under ``prefix`` (on Zenoh's thread).

        Returns:
            The subscription; ``close()`` ends it.
        """
        return ParamSubscription(self._ctx, self.resolve(prefix), callback)

    def master_available(self) -> bool:
        """True if a master's parameter services are in the graph."""
        return bool(self._ctx.graph.servers(SET_PARAM))

    def wait_for_master(self, timeout: float | None = None) -> bool:
        """Block until a master is in the graph with every one of its parameter services (a
        master declares them one after the other); False on timeout."""
        services = self._ctx.graph.services
        return self._ctx.graph.wait_for(
            lambda: all(name in services() for name in PARAM_SERVICES), timeout)


def _parse_error(data: bytes) -> tuple[str, str]:
    try:
        body = json.loads(data)
        return str(body["error"]), str(body["message"])
    except (ValueError, KeyError, TypeError):
        return "", data.decode("utf-8", "replace")
