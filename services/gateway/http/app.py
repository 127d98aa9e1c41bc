"""`build_api` / `HttpApp`: the REST server's ASGI app: /api/v1 plus an optional fallback app."""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from typing import Any

from starlette.types import ASGIApp, Receive, Scope, Send

from ..state.core import Core
from .api import PREFIX, Api, Call
from .openapi import openapi_document
from .routes.system import add_system_routes

__all__ = ["HttpApp", "build_api"]


def build_api(core: Core, max_body: int = 64 * 1024, logger: logging.Logger | None = None,
              adders: Sequence[Callable[[Api], None]] = ()) -> Api:
    """The /api/v1 operations: the system ones, those ``adders`` add, 501 for the rest."""
    api = Api(core.tokens, max_body=max_body, logger=logger)
    add_system_routes(api, core)
    for add in adders:
        add(api)
    api.finish()
    schema: dict[str, Any] = {}

    async def index(call: Call) -> Any:
        """The API's operations, split into ``implemented`` and ``not_implemented``."""
        done: list[str] = []
        todo: list[str] = []
        for ep in sorted(api.endpoints(), key=lambda e: (e.path, e.method)):
            (done if ep.implemented else todo).append(f"{ep.method} {PREFIX}{ep.path}")
        return {"version": core.identity.version, "implemented": done, "not_implemented": todo}

    async def openapi(call: Call) -> Any:
        """The OpenAPI document of this server."""
        if not schema:
            schema.update(openapi_document(api, "zenros robot API", core.identity.version))
        return schema

    api.add("GET", "/", index, public=True)
    api.add("GET", "/openapi.json", openapi, public=True)
    return api


class HttpApp:
    """Routes ``/api/v1...`` to the `Api`; anything else to ``fallback`` (e.g. the dashboard),
    or a §1.2 404."""

    def __init__(self, api: Api, fallback: ASGIApp | None = None) -> None:
        self.api = api
        self.fallback = fallback

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http" and (scope["path"] == PREFIX
                                        or scope["path"].startswith(PREFIX + "/")):
            await self.api(scope, receive, send)
            return
        if self.fallback is not None:
            await self.fallback(scope, receive, send)
            return
        if scope["type"] == "lifespan":
            while True:
                msg = await receive()
                if msg["type"] == "lifespan.startup":
                    await send({"type": "lifespan.startup.complete"})
                elif msg["type"] == "lifespan.shutdown":
                    await send({"type": "lifespan.shutdown.complete"})
                    return
        if scope["type"] == "http":
            await self.api(scope, receive, send)  # answers 404 with the §1.2 body
