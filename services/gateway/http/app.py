"""`build_api` / `HttpApp`: the REST server's ASGI app: /api/v1 plus an optional fallback app."""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence

from starlette.types import ASGIApp, Receive, Scope, Send

from .api import PREFIX, Answer, Api, Call
from .context import Context
from .openapi import openapi_document
from .routes.actuators import add_actuator_routes
from .routes.asr import add_asr_routes
from .routes.blockly import add_blockly_routes
from .routes.calibration import add_calibration_routes
from .routes.connections import add_connection_routes
from .routes.coverage import add_coverage_routes
from .routes.elevators import add_elevator_routes
from .routes.extras import add_extra_routes
from .routes.fs import add_fs_routes
from .routes.goals import add_goal_routes
from .routes.host import add_host_routes, add_update_routes
from .routes.images import add_image_routes
from .routes.io import add_io_routes
from .routes.local_moves import add_local_move_routes
from .routes.map_transfer import add_map_transfer_routes
from .routes.mapping import add_mapping_routes
from .routes.nav import add_nav_routes
from .routes.onvif import add_onvif_routes
from .routes.people import add_people_routes
from .routes.records import add_record_routes
from .routes.system import add_system_routes
from .routes.tasks import add_task_routes
from .routes.tts import add_tts_routes
from .routes.videos import add_video_routes
from .routes.voices import add_voice_routes

__all__ = ["ROUTES", "HttpApp", "build_api"]

# every group of operations besides the system ones, in the order they are routed
ROUTES: tuple[Callable[[Api], None], ...] = (
    add_task_routes, add_nav_routes, add_goal_routes, add_local_move_routes, add_io_routes,
    add_record_routes, add_connection_routes, add_coverage_routes, add_extra_routes,
    add_fs_routes, add_tts_routes, add_mapping_routes, add_map_transfer_routes,
    add_image_routes, add_actuator_routes, add_host_routes, add_asr_routes,
    add_video_routes, add_voice_routes, add_update_routes, add_blockly_routes,
    add_onvif_routes, add_calibration_routes, add_people_routes, add_elevator_routes)


async def index(call: Call[None, None]) -> Answer:
    """The API's operations, split into ``implemented`` and ``not_implemented``."""
    done: list[str] = []
    todo: list[str] = []
    prefix = call.path.rstrip("/") or PREFIX  # /api/v1, or a fleet's /api/v1/robots/<name>
    for ep in sorted(call.api.endpoints(), key=lambda e: (e.path, e.method)):
        (done if ep.implemented else todo).append(f"{ep.method} {prefix}{ep.path}")
    return {"version": call.ctx.core.identity.version, "implemented": done,
            "not_implemented": todo}


async def openapi(call: Call[None, None]) -> Answer:
    """The OpenAPI document of this server."""
    if not call.api.openapi:
        call.api.openapi.update(openapi_document(call.api, "zenros robot API",
                                                 call.ctx.core.identity.version,
                                                 fleet=call.api.in_fleet))
    return call.api.openapi


def build_api(ctx: Context, max_body: int = 64 * 1024, logger: logging.Logger | None = None,
              adders: Sequence[Callable[[Api], None]] = ROUTES) -> Api:
    """The /api/v1 operations on ``ctx``: the system ones, those ``adders`` add (every
    group's by default), 501 for the rest."""
    api = Api(ctx, max_body=max_body, logger=logger)
    add_system_routes(api)
    for add in adders:
        add(api)
    api.finish()
    api.add("GET", "/", index, public=True)
    api.add("GET", "/openapi.json", openapi, public=True)
    return api


class HttpApp:
    """Routes ``/api/v1...`` to ``api`` (an `Api`, or a fleet's `FleetApi`); anything else to
    ``fallback`` (e.g. the dashboard), or a docs/robot-api.md §1.2 404."""

    def __init__(self, api: ASGIApp, fallback: ASGIApp | None = None) -> None:
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
