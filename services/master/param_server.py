"""The parameter server on Zenoh: gets on ``<prefix>/param/**``, typed write services, events.

- A plain Zenoh ``get`` on a parameter's key returns its value (a namespace's key returns the
  subtree as a dict); a wildcard ``get`` returns one reply per leaf. Values are JSON, so
  ``z_get -s 'zenros/param/**'`` prints them, unless they hold bytes or a non-finite float
  (then MessagePack).
- Every change of a leaf is published on the leaf's key: a PUT with the new value, or a
  DELETE; the attachment carries the write's stamp. ``z_sub -k 'zenros/param/**'`` watches.
- Operations that take a caller (private and relative names), and all writes, are services
  under ``/master/...`` (see `zenros.param_protocol`); a write is answered once it is on disk.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import Any

import zenoh
from zenros.errors import InvalidNameError, ParameterError, ParameterNotFoundError
from zenros.log import ErrorLog
from zenros.node import Node
from zenros.param_protocol import (
    DELETE_PARAM,
    DUMP_PARAMS,
    GET_PARAM,
    HAS_PARAM,
    JSON_ENCODING,
    LIST_PARAMS,
    LOAD_PARAMS,
    MSGPACK_ENCODING,
    SEARCH_PARAM,
    SET_PARAM,
    DeleteParam,
    DeleteParamRequest,
    DeleteParamResponse,
    DumpParams,
    DumpParamsRequest,
    DumpParamsResponse,
    GetParam,
    GetParamRequest,
    GetParamResponse,
    HasParam,
    HasParamRequest,
    HasParamResponse,
    ListParams,
    ListParamsRequest,
    ListParamsResponse,
    LoadParams,
    LoadParamsRequest,
    LoadParamsResponse,
    ParamResponse,
    SearchParam,
    SearchParamRequest,
    SearchParamResponse,
    SetParam,
    SetParamRequest,
    SetParamResponse,
    encode_stamp,
    encode_value,
    error_fields,
    param_key,
    param_name,
)
from zenros.rpc import error_payload

from .param_store import ParamStore
from .param_tree import Change
from .param_value import resolve_param_name

__all__ = ["ParamServer", "hlc_time"]

_FAILURES = (ParameterError, InvalidNameError)
_CACHE_SIZE = 4096
_ENCODINGS = {JSON_ENCODING: zenoh.Encoding(JSON_ENCODING),
              MSGPACK_ENCODING: zenoh.Encoding(MSGPACK_ENCODING)}


def _encoded(value: Any) -> tuple[bytes, zenoh.Encoding]:
    data, mime = encode_value(value)
    return data, _ENCODINGS[mime]


def hlc_time(ts: zenoh.Timestamp) -> int:
    """A Zenoh timestamp's time as the store's NTP64 integer (HLC counter bits included)."""
    ntp = ts.get_time_as_ntp64()
    text = str(ntp)  # zenoh-python prints NTP64 as its raw 64-bit value
    if text.isdigit():
        return int(text)
    return (int(ntp.as_secs()) << 32) | ((int(ntp.subsec_nanos()) << 32) // 1_000_000_000)


def _resolve(name: str, caller: str) -> str:
    return resolve_param_name(name or "/", node=caller or None)


def _guard(response_type: type[ParamResponse], fn: Callable[[Any], ParamResponse]
           ) -> Callable[[Any], ParamResponse]:
    """A handler whose expected failures (bad name, missing parameter) become response data."""

    def handler(req: Any) -> ParamResponse:
        try:
            return fn(req)
        except _FAILURES as exc:
            return response_type(**error_fields(exc))

    return handler


class ParamServer:
    """Serves one `ParamStore` on the node's session."""

    def __init__(self, node: Node, store: ParamStore) -> None:
        self._node = node
        self._store = store
        ctx = node.context
        self._session = ctx.session
        self._keys = ctx.keys
        # Encoded answers of plain gets by key; cleared on every change. A reader caches
        # only if no change happened since it began (the generation), so a stale answer
        # can never be stored.
        self._cache: dict[str, tuple[bytes, zenoh.Encoding]] = {}
        self._cache_lock = threading.Lock()
        self._generation = 0
        self._errors = ErrorLog(node.logger)
        self._queryable = self._session.declare_queryable(
            param_key(ctx.keys, "/**"), self._on_get, complete=True
        )
        self._remove_listener = store.add_listener(self._on_change)
        services: list[tuple[Any, str, type[ParamResponse], Callable[[Any], ParamResponse]]] = [
            (SetParam, SET_PARAM, SetParamResponse, self.handle_set),
            (GetParam, GET_PARAM, GetParamResponse, self.handle_get),
            (DeleteParam, DELETE_PARAM, DeleteParamResponse, self.handle_delete),
            (HasParam, HAS_PARAM, HasParamResponse, self.handle_has),
            (SearchParam, SEARCH_PARAM, SearchParamResponse, self.handle_search),
            (ListParams, LIST_PARAMS, ListParamsResponse, self.handle_list),
            (DumpParams, DUMP_PARAMS, DumpParamsResponse, self.handle_dump),
            (LoadParams, LOAD_PARAMS, LoadParamsResponse, self.handle_load),
        ]
        for srv_type, name, response, fn in services:
            node.create_service(srv_type, name, _guard(response, fn))

    # ------------------------------------------------------------------ plain gets

    def _on_get(self, query: zenoh.Query) -> None:
        with query:
            try:
                self._answer_get(query)
            except Exception as exc:  # noqa: BLE001 nothing a read does stops the server
                self._errors.report(type(exc).__name__, logging.ERROR,
                                    "parameter read failed: %s: %s", type(exc).__name__, exc,
                                    exc_info=exc)
                try:
                    query.reply_err(error_payload("InternalError", f"{type(exc).__name__}: {exc}"))
                except zenoh.ZError:
                    pass

    def _answer_get(self, query: zenoh.Query) -> None:
        key = str(query.key_expr)
        hit = self._cache.get(key)
        if hit is None:
            if any(c in key for c in "*$"):
                self._reply_leaves(query)
                return
            generation = self._generation
            try:
                value = self._store.get(param_name(self._keys, key))
            except _FAILURES as exc:
                query.reply_err(error_payload(type(exc).__name__, str(exc)))
                return
            hit = _encoded(value)
            with self._cache_lock:
                if generation == self._generation and len(self._cache) < _CACHE_SIZE:
                    self._cache[key] = hit
        query.reply(query.key_expr, hit[0], encoding=hit[1])

    def _reply_leaves(self, query: zenoh.Query) -> None:
        wanted = query.key_expr
        for name in self._store.names():
            key = param_key(self._keys, name)
            if not zenoh.KeyExpr(key).intersects(wanted):
                continue
            try:
                value = self._store.get(name)
            except ParameterNotFoundError:  # deleted meanwhile
                continue
            data, encoding = _encoded(value)
            query.reply(key, data, encoding=encoding)

    # ------------------------------------------------------------------ events

    def _on_change(self, change: Change) -> None:
        with self._cache_lock:  # a cached subtree may hold this leaf: forget them all
            self._generation += 1
            self._cache.clear()
        key = param_key(self._keys, change.name)
        stamp = encode_stamp(*change.stamp)
        if change.deleted:
            self._session.delete(key, attachment=stamp)
            return
        data, encoding = _encoded(change.value)
        self._session.put(key, data, encoding=encoding, attachment=stamp)

    # ------------------------------------------------------------------ services

    def _now(self) -> int:
        """The session's HLC time (NTP64): the physical part of the write's stamp."""
        return hlc_time(self._session.new_timestamp())

    def handle_set(self, req: SetParamRequest) -> SetParamResponse:
        name = _resolve(req.name, req.caller)
        stamp = self._store.set(name, req.value, now=self._now())
        return SetParamResponse(name=name, time=stamp.time, source=stamp.source)

    def handle_get(self, req: GetParamRequest) -> GetParamResponse:
        name = _resolve(req.name, req.caller)
        return GetParamResponse(name=name, value=self._store.get(name))

    def handle_delete(self, req: DeleteParamRequest) -> DeleteParamResponse:
        if not req.name:
            raise InvalidNameError("delete_param needs a name (an empty one is not the root: "
                                   "to delete every parameter, name / with namespace: true)")
        name = _resolve(req.name, req.caller)
        if not req.namespace:
            held = self._store.names(name)
            if name == "/" or (held and held != [name]):
                raise ParameterError(
                    f"{name} is a namespace holding {len(held)} parameter(s); deleting it "
                    f"needs namespace: true (zenros param delete --namespace {name})")
        stamp = self._store.delete(name, now=self._now())
        return DeleteParamResponse(name=name, time=stamp.time, source=stamp.source)

    def handle_has(self, req: HasParamRequest) -> HasParamResponse:
        name = _resolve(req.name, req.caller)
        return HasParamResponse(name=name, has=self._store.has(name))

    def handle_search(self, req: SearchParamRequest) -> SearchParamResponse:
        found = self._store.search(req.caller or "/", req.key)
        return SearchParamResponse(found=found is not None, name=found or "")

    def handle_list(self, req: ListParamsRequest) -> ListParamsResponse:
        return ListParamsResponse(names=self._store.names(_resolve(req.prefix, req.caller)))

    def handle_dump(self, req: DumpParamsRequest) -> DumpParamsResponse:
        return DumpParamsResponse(yaml=self._store.dump_yaml(_resolve(req.prefix, req.caller)))

    def handle_load(self, req: LoadParamsRequest) -> LoadParamsResponse:
        names = self._store.load_yaml(req.yaml, req.namespace or "/", req.source,
                                      now=self._now())
        return LoadParamsResponse(names=names)

    def close(self) -> None:
        """Stop serving gets and events (the node closes the services)."""
        self._remove_listener()
        self._queryable.undeclare()  # type: ignore[no-untyped-call]
