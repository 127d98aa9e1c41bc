"""`Api`: the /api/v1 dispatcher: routes, token check, body limit and strict msgspec validation.

A small ASGI app instead of a Starlette router: one dict lookup per request (the API has
about 180 operations), and every error leaves as a docs/robot-api.md §1.2 JSON body with a 4xx code.
Handlers are plain ``async def handler(call: Call[Body, Query]) -> Answer`` functions: the
``Body`` and ``Query`` Structs in the annotation are what msgspec decodes the request's JSON body
and query string into (``None``: the operation takes none), so ``call.body.x`` is typed; the state
and the ports they work on are ``call.ctx`` (a `context.Context`, given to the `Api`); what they
return is encoded as JSON (a Starlette `Response` is sent as is).
"""

from __future__ import annotations

import logging
import re
from collections.abc import Awaitable, Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Final, Generic, get_args, get_type_hints
from urllib.parse import parse_qsl

import msgspec
from starlette.requests import Request
from starlette.responses import Response
from starlette.types import Receive, Scope, Send
from typing_extensions import TypeVar
from zenros.msgs.zenros_msgs.result import ResultCode

from ..errors import PortError
from ..state.tokens import TokenStore
from .spec_routes import SPEC_OPERATIONS

if TYPE_CHECKING:
    from .context import Context

__all__ = ["PREFIX", "PREFIX_KEY", "STATUS", "Answer", "Api", "ApiError", "Call", "Endpoint",
           "Handler", "api_error", "describe_invalid", "error_body", "send_json"]

PREFIX = "/api/v1"
PREFIX_KEY = "zenros.api_prefix"  # an ASGI scope key: where the operations' paths start
_ENC = msgspec.json.Encoder()
_JSON_HEADERS = [(b"content-type", b"application/json")]

Body = TypeVar("Body", default=Any)
"""The Struct an operation's JSON body decodes into (None: it takes no body)."""
Query = TypeVar("Query", default=Any)
"""The Struct an operation's query string decodes into (None: it takes no parameters)."""

Answer = Mapping[str, object] | Sequence[object] | msgspec.Struct | Response | None
"""What a handler returns: a JSON object, array or Struct (encoded by msgspec), or a Starlette
`Response` sent as is."""


class ApiError(Exception):
    """A request the API refuses: ``status_code`` and the §1.2 ``description``."""

    def __init__(self, status_code: int, description: str,
                 retry_after: int | None = None) -> None:
        super().__init__(description)
        self.status_code = status_code
        self.description = description
        self.retry_after = retry_after  # s: sent as Retry-After (a backend still starting)


# The one place a service's result code (a port error's, ..errors) gets its HTTP status:
# never from the wording of the service's message.
STATUS: Final[dict[ResultCode, int]] = {
    ResultCode.OK: 200,
    ResultCode.INVALID: 400,
    ResultCode.NOT_FOUND: 404,
    ResultCode.CONFLICT: 409,
    ResultCode.FAILED: 502,
    ResultCode.UNAVAILABLE: 503,
    ResultCode.TIMEOUT: 504,
}


def api_error(exc: PortError) -> ApiError:
    """The HTTP answer to a port error: its code's status, its detail and Retry-After."""
    return ApiError(STATUS[exc.code], exc.detail, exc.retry_after)


def error_body(description: str, result_style: bool = False) -> dict[str, Any]:
    """The §1.2 error body: ``{"status":"error",...}`` or ``{"result":false,...}``."""
    if result_style:
        return {"result": False, "description": description}
    return {"status": "error", "description": description}


@dataclass
class Call(Generic[Body, Query]):
    """One request as a handler sees it: the `Api` serving it, its validated ``body`` and
    ``query`` Structs (the types the handler's ``Call[Body, Query]`` names)."""

    api: Api
    query: Query
    body: Body
    token: str | None
    path: str = ""
    path_params: dict[str, str] = field(default_factory=dict)
    request: Request | None = None   # only for ``raw_body`` endpoints

    @property
    def ctx(self) -> Context:
        """The state and the ports the handler works on."""
        return self.api.ctx


Handler = Callable[[Call[Any, Any]], Awaitable[Answer]]


def _decoded_types(handler: Callable[..., object]) -> tuple[type[Any] | None, type[Any] | None]:
    """(body, query) from a handler's ``call: Call[Body, Query]`` annotation; (None, None) for
    a bare ``Call`` (then `Api.add`'s arguments say)."""
    try:
        hints = get_type_hints(handler, include_extras=True)  # Annotated limits kept
    except NameError as exc:  # a handler's annotation names what its module does not have
        raise ValueError(f"{handler.__qualname__}: {exc}") from exc
    hints.pop("return", None)
    args = get_args(next(iter(hints.values()), None))
    if len(args) != 2:
        return None, None
    body, query = (None if a is type(None) or a is Any else a for a in args)
    return body, query


@dataclass
class Endpoint:
    """One operation: method, path, handler and the structs its input must match."""

    method: str
    path: str
    handler: Handler
    query: type[Any] | None = None
    body: type[Any] | None = None
    result_style: bool = False
    public: bool = False
    implemented: bool = True
    media_type: str = "application/json"
    raw_body: bool = False   # the handler reads the body (a multipart upload) itself
    summary: str = ""
    description: str = ""


def describe_invalid(exc: msgspec.ValidationError, where: str) -> str:
    """A 400's text for a request that does not match its type, naming the field."""
    text = str(exc)
    # msgspec says "... - at `$.speed_x`"; name the field the way a client wrote it.
    text = re.sub(r"`\$\.?([^`]*)`", lambda m: f"`{m.group(1) or where}`", text)
    return f"invalid {where}: {text}"


class Api:
    """The /api/v1 operations. `add` them, then `finish()` routes the spec's remaining ones
    to 501. The object is an ASGI app for paths under ``/api/v1`` (or under the scope's
    `PREFIX_KEY`, e.g. ``/api/v1/robots/robot2`` in a fleet gateway)."""

    def __init__(self, ctx: Context, max_body: int = 64 * 1024,
                 logger: logging.Logger | None = None) -> None:
        self.ctx = ctx
        self.tokens: TokenStore = ctx.core.tokens
        self.openapi: dict[str, Any] = {}  # the OpenAPI document, built on its first request
        self.in_fleet = False  # one robot's of a `FleetApi`: the document has the fleet's paths
        self.max_body = max_body
        self.logger = logger or logging.getLogger("zenros.gateway.api")
        self.routes: dict[str, dict[str, Endpoint]] = {}
        self._templated: list[tuple[re.Pattern[str], dict[str, Endpoint]]] = []

    # ------------------------------------------------------------------ building

    def add(self, method: str, path: str, handler: Handler, **kw: Any) -> Endpoint:
        """Route ``method path`` to ``handler``; its body and query types come from its
        ``Call[Body, Query]`` annotation (``body=``/``query=`` may say them for a bare `Call`;
        both saying differently is a bug, a ValueError)."""
        for where, found in zip(("body", "query"), _decoded_types(handler), strict=True):
            given = kw.get(where)
            if given is not None and found is not None and given != found:
                raise ValueError(f"{method} {path}: {handler.__name__} takes a {where} of "
                                 f"{found.__name__}, routed with {given.__name__}")
            if found is not None:
                kw[where] = found
        doc = (handler.__doc__ or "").strip()
        summary, _, rest = doc.partition("\n")
        ep = Endpoint(method, path, handler, summary=kw.pop("summary", summary.strip()),
                      description=rest.strip(), **kw)
        table = self.routes.setdefault(path, {})
        if method in table:
            raise ValueError(f"{method} {path} is routed twice")
        table[method] = ep
        if "{" in path:
            pattern = re.compile("^" + re.sub(r"\{(\w+)\}", r"(?P<\1>[^/]+)", path) + "$")
            if not any(p.pattern == pattern.pattern for p, _ in self._templated):
                self._templated.append((pattern, table))
        return ep

    def route(self, method: str, path: str, **kw: Any) -> Callable[[Handler], Handler]:
        """Decorator form of `add`."""
        def deco(fn: Handler) -> Handler:
            self.add(method, path, fn, **kw)
            return fn
        return deco

    def finish(self) -> None:
        """Route every spec operation not added yet to a 501 ``not implemented`` answer."""
        for method, path in SPEC_OPERATIONS:
            if method in self.routes.get(path, {}):
                continue

            async def not_implemented(call: Call[None, None]) -> Answer:
                raise ApiError(501, f"not implemented: {call.path}")

            not_implemented.__doc__ = f"Not implemented yet (answers 501): {method} {path}."
            self.add(method, path, not_implemented, implemented=False, public=True)

    def endpoints(self) -> list[Endpoint]:
        return [ep for table in self.routes.values() for ep in table.values()]

    # ------------------------------------------------------------------ serving

    def _lookup(self, path: str) -> tuple[dict[str, Endpoint] | None, dict[str, str]]:
        table = self.routes.get(path)
        if table is not None:
            return table, {}
        for pattern, t in self._templated:
            m = pattern.match(path)
            if m:
                return t, m.groupdict()
        return None, {}

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        path = scope["path"][len(scope.get(PREFIX_KEY, PREFIX)):] or "/"
        if path != "/" and path.endswith("/") and path not in self.routes:
            path = path.rstrip("/")
        table, params = self._lookup(path)
        method = scope["method"]
        ep = None if table is None else table.get(method)
        try:
            if table is None:
                raise ApiError(404, f"no such endpoint: {scope['path']}")
            if ep is None:
                if method == "HEAD" and "GET" in table:
                    ep = table["GET"]
                else:
                    raise ApiError(405, f"{method} not allowed on {scope['path']}; "
                                        f"allowed: {', '.join(sorted(table))}")
            try:
                result = await self._serve(ep, scope, receive, params)
            except PortError as port:
                raise api_error(port) from port
        except ApiError as exc:
            style = ep.result_style if ep is not None else False
            extra = [] if exc.retry_after is None else [
                (b"retry-after", str(exc.retry_after).encode())]
            await send_json(send, exc.status_code, error_body(exc.description, style), extra)
            return
        except Exception as exc:  # a handler bug: a clear 500, logged, never a traceback out
            self.logger.exception("%s %s failed", method, scope["path"])
            style = ep.result_style if ep is not None else False
            await send_json(send, 500, error_body(f"internal error: {type(exc).__name__}: "
                                                   f"{exc}", style))
            return
        if isinstance(result, Response):
            await result(scope, receive, send)
            return
        await send_json(send, 200, result)

    async def _serve(self, ep: Endpoint, scope: Scope, receive: Receive,
                     params: dict[str, str]) -> Answer:
        raw_query = scope.get("query_string", b"").decode("latin-1")
        query: dict[str, Any] = dict(parse_qsl(raw_query, keep_blank_values=True))
        token = query.pop("token", None)
        body: dict[str, Any] | None = None
        if method_has_body(scope["method"]) and not ep.raw_body:
            body = await self._read_json(scope, receive)
            if body is not None and token is None and isinstance(body.get("token"), str):
                token = body["token"]
            if body is not None:
                body.pop("token", None)
        if not ep.public:
            problem = self.tokens.problem(token)
            if problem is not None:
                raise ApiError(401, problem)
        q = self._convert(query, ep.query, "query", strict=False)
        b = None
        if ep.body is not None:
            b = self._convert(body if body is not None else {}, ep.body, "body", strict=True)
        elif body and ep.implemented:
            raise ApiError(400, f"{ep.method} {ep.path} takes no body fields; "
                                f"got {', '.join(sorted(body))}")
        request = Request(scope, receive) if ep.raw_body else None
        return await ep.handler(Call(self, q, b, token, scope["path"], params, request))

    def _convert(self, data: dict[str, Any], tp: type[Any] | None, where: str,
                 strict: bool) -> Any:
        if tp is None:
            if data and where == "query":
                raise ApiError(400, f"unknown query parameter(s): {', '.join(sorted(data))}")
            return None
        try:
            return msgspec.convert(data, tp, strict=strict)
        except msgspec.ValidationError as exc:
            raise ApiError(400, describe_invalid(exc, where)) from exc

    async def _read_json(self, scope: Scope, receive: Receive) -> dict[str, Any] | None:
        for name, value in scope.get("headers", []):
            if name == b"content-length":
                try:
                    declared = int(value)
                except ValueError:
                    raise ApiError(400, "bad Content-Length header") from None
                if declared > self.max_body:
                    raise ApiError(413, f"body too large: {declared} bytes "
                                        f"(limit {self.max_body})")
        chunks: list[bytes] = []
        size = 0
        while True:
            message = await receive()
            if message["type"] == "http.disconnect":
                raise ApiError(400, "client disconnected")
            chunk = message.get("body", b"")
            size += len(chunk)
            if size > self.max_body:
                raise ApiError(413, f"body too large: over {self.max_body} bytes")
            chunks.append(chunk)
            if not message.get("more_body", False):
                break
        raw = b"".join(chunks)
        if not raw.strip():
            return None
        try:
            data = msgspec.json.decode(raw)
        except msgspec.DecodeError as exc:
            raise ApiError(400, f"malformed JSON body: {exc}") from exc
        except RecursionError as exc:
            raise ApiError(400, "malformed JSON body: nested too deep") from exc
        if not isinstance(data, dict):
            raise ApiError(400, f"the JSON body must be an object, got {type(data).__name__}")
        return data


def method_has_body(method: str) -> bool:
    return method in ("POST", "PUT", "PATCH")


async def send_json(send: Send, status: int, content: Any,
                     headers: list[tuple[bytes, bytes]] | None = None) -> None:
    body = _ENC.encode(content)
    await send({"type": "http.response.start", "status": status,
                "headers": [*_JSON_HEADERS, (b"content-length", str(len(body)).encode()),
                            *(headers or [])]})
    await send({"type": "http.response.body", "body": body})
