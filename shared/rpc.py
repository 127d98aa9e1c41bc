"""`Service` (a Zenoh queryable) and `Client` (a Zenoh get), typed by a `ServiceType`."""

from __future__ import annotations

import asyncio
import inspect
import json
import logging
import threading
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Generic, NoReturn

import zenoh

from .codec import codec_for, split_encoding
from .context import is_session_failure
from .errors import (
    CodecError,
    DecodeError,
    EncodeError,
    RefusedError,
    ServiceError,
    ServiceUnavailableError,
    TypeMismatchError,
    ZenrosTimeout,
)
from .executor import CallbackGroup
from .gate import DeliveryGate
from .log import ErrorLog
from .message import Message, Q, S, ServiceType, normalize_type_name
from .qos import QoSProfile
from .reach import REACH_GRACE, Reach, ask_while_listed, ask_while_listed_async
from .service_events import ServiceEvents, ServiceIntrospectionState

if TYPE_CHECKING:
    from .context import Context

__all__ = ["REACH_GRACE", "Client", "Service", "ask_while_listed", "error_payload",
           "wildcard_refusal"]

QUERY_QUEUE = 256  # queries a service buffers before Zenoh pushes back (its default channel)


def error_payload(kind: str, message: str, code: int | None = None) -> bytes:
    """The JSON body of a ``reply_err``: ``{"error": kind, "message": ...}``, plus the
    result ``code`` of a `RefusedError`."""
    body: dict[str, Any] = {"error": kind, "message": message}
    if code is not None:
        body["code"] = code
    return json.dumps(body).encode()


def wildcard_refusal(what: str, key: str, query: zenoh.Query) -> str:
    """Why a query on a key expression other than ``key`` itself is refused."""
    return (f"{what} answers only queries on its own key {key}, not {query.key_expr}: "
            "a wildcard query must not call every service or action it matches")


def _reply_err(query: zenoh.Query, kind: str, message: str, code: int | None = None) -> None:
    """Answer ``query`` with an error; a query already answered or finalized is left alone."""
    try:
        query.reply_err(error_payload(kind, message, code))
    except zenoh.ZError:
        pass


def _parse_error(data: bytes) -> tuple[str, int | None]:
    """(reason, result code or None) of an error reply."""
    try:
        body = json.loads(data)
        code = body.get("code")
        return (f"{body['error']}: {body['message']}",
                code if isinstance(code, int) and not isinstance(code, bool) else None)
    except (ValueError, KeyError, TypeError, AttributeError):
        return data.decode("utf-8", "replace"), None


class Service:
    """Serves one service: decodes the request, calls the handler, replies.

    The handler is ``handler(request) -> response`` or rclpy's
    ``handler(request, response) -> response``, sync or ``async def``. A bad request and a
    handler exception are answered with ``reply_err`` (the caller gets `ServiceError`) and
    the service keeps serving.
    """

    def __init__(
        self,
        ctx: Context,
        node: str,
        srv_type: ServiceType,
        name: str,
        handler: Callable[..., Any],
        logger: logging.Logger,
        group: CallbackGroup | None = None,
        gate: DeliveryGate | None = None,
    ) -> None:
        self.srv_type = srv_type
        self.name = name
        self.key = ctx.keys.service(name)
        self._key_expr = zenoh.KeyExpr(self.key)
        self._ctx = ctx
        self._logger = logger
        self._group = group
        self._gate = gate
        self._req = codec_for(srv_type.Request)
        self._res = codec_for(srv_type.Response)
        self._res_encoding = zenoh.Encoding(self._res.mime).with_schema(self._res.type_name)
        self._req_encoding = zenoh.Encoding(self._req.mime).with_schema(self._req.type_name)
        self._handler = handler
        self._errors = ErrorLog(logger)
        self._is_async = inspect.iscoroutinefunction(handler)
        try:
            self._two_args = len(inspect.signature(handler).parameters) >= 2
        except (TypeError, ValueError):
            self._two_args = False
        # Zenoh queues queries in a channel (its default FIFO of QUERY_QUEUE, pushing back
        # when full) without taking the GIL, and one thread of zenoh-python's serves them
        # (an indirect callback). That thread waits for a query without waking: a thread
        # reading a zenoh-python channel itself wakes ten times a second to check for signals,
        # which in a robot's process of some 60 services and actions was a fifth of its CPU
        # at rest (docs/fleet.md, "Work skipped at rest").
        self._serving: threading.Thread | None = None
        self._served = threading.Event()  # the callback's thread has ended (undeclared)
        self._queryable = ctx.session.declare_queryable(
            self.key, zenoh.handlers.Callback(self._serve_one, self._served.set),
            complete=True)
        self._token = ctx.session.liveliness().declare_token(
            ctx.keys.entity_token("srv", node, name, srv_type.name, "", ctx.zid, ctx.next_eid())
        )
        self._unserve = ctx.serve_here(self.key)
        self.events = ServiceEvents(ctx, node, srv_type, name, client=False)
        """Its introspection events (`zenros.service_events`), off until configured."""
        self.closed = False

    def configure_introspection(self, clock: Any, qos: QoSProfile | None,
                                state: ServiceIntrospectionState) -> None:
        """rclpy's: publish each request and response on ``<name>/_service_event``
        (METADATA: the info alone; CONTENTS: the messages too; OFF: nothing)."""
        self.events.configure(clock, qos, state)

    def _serve_one(self, query: zenoh.Query) -> None:
        """One query, on the callback's thread (requests wait in Zenoh's queue until the
        node's setup() returned)."""
        if self._serving is None:
            self._serving = threading.current_thread()
            self._serving.name = f"zenros-srv:{self.name}"
        gate = self._gate
        if gate is not None and not gate.is_open:
            gate.wait()
        if gate is not None and gate.abandoned:
            return
        try:
            self._on_query(query)
        except Exception as exc:  # noqa: BLE001 nothing a request does stops the service
            self._internal_error(query, exc)
        except BaseException as exc:
            if not is_session_failure(exc):
                raise
            self._ctx.fail(exc)  # the process exits (runtime) so supervision can restart it

    def _on_query(self, query: zenoh.Query) -> None:
        key = query.key_expr
        if key != self._key_expr:  # a wildcard get must not call every service
            with query:
                self._errors.report("Wildcard", logging.WARNING, "service %s: refused a "
                                    "query on %s", self.name, key)
                _reply_err(query, "BadRequest", wildcard_refusal(f"service {self.name}",
                                                                 self.key, query))
            return
        if self._is_async:
            self._ctx.executor.submit(self._serve_async(query))
            return
        with query:  # finalizes the query when done, whatever references linger
            req = self._request(query)
            if req is None:
                return
            seq = self._event_request(req)
            try:
                res = self._group.run(self._call, req) if self._group else self._call(req)
            except Exception as exc:  # noqa: BLE001 (the handler's error goes to the caller)
                self._fail(query, exc)
                return
            self._reply(query, res)
            if seq:
                self.events.response(seq, res)

    def _event_request(self, req: Message) -> int:
        """The request's sequence number for the introspection events (0 while off)."""
        if self.events.state is ServiceIntrospectionState.OFF:
            return 0
        seq = self.events.next_sequence()
        self.events.request(seq, req)
        return seq

    @property
    def errors(self) -> int:
        """Requests answered with an error: bad requests, handler exceptions, bad responses."""
        return self._errors.count

    def _request(self, query: zenoh.Query) -> Message | None:
        payload = query.payload
        try:
            enc = query.encoding
            if enc is not None and enc != self._req_encoding:
                self._check_schema(str(enc))
            msg: Message = self._req.decode(payload.to_bytes() if payload is not None else b"{}")
            return msg
        except CodecError as exc:
            reason = str(exc)
        self._errors.report("BadRequest", logging.WARNING, "service %s: bad request: %s",
                            self.name, reason)
        _reply_err(query, "BadRequest", reason)
        return None

    def _check_schema(self, encoding: str) -> None:
        """Refuse a request whose encoding names another type (`TypeMismatchError`); a bare
        MIME type (``z_get`` sends ``zenoh/bytes``) is accepted and the payload decides."""
        schema = split_encoding(encoding)[1]
        if schema and normalize_type_name(schema) != self._req.type_name:
            raise TypeMismatchError(f"type mismatch: service {self.name} takes "
                                    f"{self._req.type_name}, got {schema}")

    def _call(self, req: Message) -> Any:
        if self._two_args:
            return self._handler(req, self.srv_type.Response())
        return self._handler(req)

    async def _serve_async(self, query: zenoh.Query) -> None:
        try:
            with query:
                req = self._request(query)
                if req is None:
                    return
                seq = self._event_request(req)
                try:
                    if self._two_args:
                        res = await self._handler(req, self.srv_type.Response())
                    else:
                        res = await self._handler(req)
                except Exception as exc:  # noqa: BLE001 (the handler's error goes to the caller)
                    self._fail(query, exc)
                    return
                self._reply(query, res)
                if seq:
                    self.events.response(seq, res)
        except Exception as exc:  # noqa: BLE001 nothing a request does stops the service
            self._internal_error(query, exc)
        except BaseException as exc:
            if not is_session_failure(exc):
                raise
            self._ctx.fail(exc)
        finally:
            self._ctx.executor.mark_work()

    def _fail(self, query: zenoh.Query, exc: Exception) -> None:
        self._errors.report(type(exc).__name__, logging.ERROR, "service %s: handler raised %s: %s",
                            self.name, type(exc).__name__, exc, exc_info=exc)
        if isinstance(exc, RefusedError):
            _reply_err(query, exc.kind, str(exc), exc.code)
        else:
            _reply_err(query, type(exc).__name__, str(exc))

    def _internal_error(self, query: zenoh.Query, exc: Exception) -> None:
        """Something other than the handler failed on a request (a bug, or a reply Zenoh
        refused): answer if the query is still open, count, log, and go on serving."""
        self._errors.report("InternalError", logging.ERROR, "service %s: request failed: %s: %s",
                            self.name, type(exc).__name__, exc, exc_info=exc)
        _reply_err(query, "InternalError", f"{type(exc).__name__}: {exc}")

    def _reply(self, query: zenoh.Query, res: Any) -> None:
        try:
            data = self._res.encode(res)
        except EncodeError as exc:
            self._errors.report("BadResponse", logging.ERROR,
                                "service %s: handler returned a bad response: %s", self.name, exc)
            _reply_err(query, "BadResponse", str(exc))
            return
        query.reply(query.key_expr, data, encoding=self._res_encoding)

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        self.events.close()
        self._unserve()
        self._token.undeclare()  # type: ignore[no-untyped-call]
        self._queryable.undeclare()  # type: ignore[no-untyped-call]
        if self._serving is not threading.current_thread():
            self._served.wait(2.0)  # a query being served finishes first


class Client(Generic[Q, S]):
    """Calls one service. `call` blocks; `call_async` is awaitable from any event loop.
    Typed by its `ServiceType`: a `Client[Req, Res]` takes a ``Req`` and answers a ``Res``."""

    def __init__(self, ctx: Context, srv_type: ServiceType[Q, S], name: str,
                 node: str = "") -> None:
        self.srv_type = srv_type
        self.name = name
        self.key = ctx.keys.service(name)
        self._ctx = ctx
        self._req = codec_for(srv_type.Request)
        self._res = codec_for(srv_type.Response)
        self._req_encoding = zenoh.Encoding(self._req.mime).with_schema(self._req.type_name)
        self._token: Any = None
        if node:  # a node's client is in the graph (as `ros2 node info` lists them)
            self._token = ctx.session.liveliness().declare_token(
                ctx.keys.entity_token("cli", node, name, srv_type.name, "", ctx.zid,
                                      ctx.next_eid())
            )  # fmt: skip
        self.events = ServiceEvents(ctx, node, srv_type, name, client=True)
        """Its introspection events (`zenros.service_events`), off until configured."""
        self.closed = False

    def configure_introspection(self, clock: Any, qos: QoSProfile | None,
                                state: ServiceIntrospectionState) -> None:
        """rclpy's: publish each request sent and response received on
        ``<name>/_service_event``."""
        self.events.configure(clock, qos, state)

    def _sent(self, request: Q) -> int:
        if self.events.state is ServiceIntrospectionState.OFF:
            return 0
        seq = self.events.next_sequence()
        self.events.request(seq, request)
        return seq

    def _received(self, seq: int, response: S) -> S:
        if seq:
            self.events.response(seq, response)
        return response

    def _encode(self, request: Q) -> bytes:
        if type(request) is not self.srv_type.Request:
            raise EncodeError(
                f"service {self.name} takes {self._req.type_name}, got {type(request).__name__}"
            )
        return self._req.encode(request)

    def _result(self, reply: zenoh.Reply, timeout: float) -> S:
        ok = reply.ok
        if ok is not None:
            try:
                res: S = self._res.decode(ok.payload.to_bytes())
                return res
            except DecodeError as exc:
                raise ServiceError(self.name, f"bad response: {exc}") from exc
        err = reply.err
        assert err is not None
        data = err.payload.to_bytes()
        if data == b"Timeout":  # zenoh's own error reply when the get times out
            raise ZenrosTimeout(f"service {self.name} did not answer within {timeout:.3g} s")
        raise ServiceError(self.name, *_parse_error(data))

    def call(self, request: Q, timeout: float = 5.0,
             grace: float = REACH_GRACE) -> S:
        """Call the service and return its response.

        A query that ends with no reply while the graph lists a server is sent again, for
        ``grace`` s at most (`zenros.reach`: a session can list a server a moment before a
        query can reach it).

        Raises:
            ServiceError: the handler failed or rejected the request (carries the reason).
            ServiceUnavailableError: no server answered.
            ZenrosTimeout: a server exists but did not answer within ``timeout`` seconds.
        """
        data = self._encode(request)
        seq = self._sent(request)
        start = time.monotonic()
        reply = self._ask(data, timeout)
        if reply is None:  # asked again while the graph lists a server (`zenros.reach`)
            reach = Reach(self.service_is_ready, timeout, grace, start=start)
            pause = reach.again()
            if pause is not None:
                time.sleep(pause)
                reply = reach.ask(lambda left: self._ask(data, left))
        if reply is None:
            return self._no_reply(timeout, time.monotonic() - start)
        return self._received(seq, self._result(reply, timeout))

    def _ask(self, data: bytes, timeout: float) -> zenoh.Reply | None:
        """One query: its first reply, None when it ended with none."""
        for reply in self._ctx.session.get(
                self.key, payload=data, encoding=self._req_encoding, timeout=timeout,
                target=zenoh.QueryTarget.BEST_MATCHING,
                allowed_destination=self._ctx.destination(self.key)):
            return reply
        return None

    def _no_reply(self, timeout: float, elapsed: float) -> NoReturn:
        if elapsed < timeout * 0.9:
            raise ServiceUnavailableError(f"no server for service {self.name}")
        raise ZenrosTimeout(f"service {self.name} did not answer within {timeout:.3g} s")

    async def call_async(self, request: Q, timeout: float = 5.0,
                         grace: float = REACH_GRACE) -> S:
        """Awaitable `call` (the same asking again, `zenros.reach`); the reply is delivered to
        the awaiting loop."""
        data = self._encode(request)
        seq = self._sent(request)
        loop = asyncio.get_running_loop()
        start = time.monotonic()

        async def ask(left: float) -> zenoh.Reply | None:
            fut: asyncio.Future[zenoh.Reply | None] = loop.create_future()

            def settle(reply: zenoh.Reply | None) -> None:
                if not fut.done():
                    fut.set_result(reply)

            def on_reply(reply: zenoh.Reply) -> None:
                loop.call_soon_threadsafe(settle, reply)

            def on_done() -> None:
                loop.call_soon_threadsafe(settle, None)

            self._ctx.session.get(
                self.key, zenoh.handlers.Callback(on_reply, on_done), payload=data,
                encoding=self._req_encoding, timeout=left,
                target=zenoh.QueryTarget.BEST_MATCHING,
                allowed_destination=self._ctx.destination(self.key),
            )
            return await fut

        reply = await ask_while_listed_async(ask, self.service_is_ready, timeout, grace)
        if reply is None:
            return self._no_reply(timeout, time.monotonic() - start)
        return self._received(seq, self._result(reply, timeout))

    def service_is_ready(self) -> bool:
        return bool(self._ctx.graph.servers(self.name))

    def wait_for_service(self, timeout: float | None = None) -> bool:
        """Block until a server for this service is in the graph; False on timeout."""
        return self._ctx.graph.wait_for_service(self.name, timeout)

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        self.events.close()
        if self._token is not None:
            self._token.undeclare()
