"""`ws_app`: the docs/robot-api.md §11 topic WebSocket (``ws://host:3547/<topic>?token=``) as a
Starlette app."""

from __future__ import annotations

import asyncio
import json
from collections.abc import Callable

from starlette.applications import Starlette
from starlette.responses import JSONResponse
from starlette.routing import WebSocketRoute
from starlette.websockets import WebSocket, WebSocketDisconnect

from ..ports.topic_hub import Slot, TopicError, TopicHub
from ..state.tokens import TokenStore
from .api import error_body

__all__ = ["ws_app"]


def ws_app(default: TopicHub, tokens: TokenStore,
           select: Callable[[str], tuple[TopicHub, str]] | None = None) -> Starlette:
    """Each connection streams its topic as JSON text frames; frames it sends are published
    on that topic (type-checked; a bad one gets an error frame and the connection stays).

    ``select(path)`` picks the hub (a fleet gateway's robot) and the topic of a URL path,
    raising `TopicError` for a robot it does not serve; without it every path is
    ``default``'s topic.
    """

    async def endpoint(ws: WebSocket) -> None:
        problem = tokens.problem(ws.query_params.get("token"))
        if problem is not None:
            await ws.send_denial_response(JSONResponse(error_body(problem), 401))
            return
        path = ws.path_params["topic"]
        try:
            hub, name = select(path) if select is not None else (default, path)
        except TopicError as exc:
            await ws.send_denial_response(JSONResponse(error_body(str(exc)), 404))
            return
        try:
            topic = hub.resolve(name)
        except TopicError as exc:
            await ws.send_denial_response(JSONResponse(error_body(str(exc)), 400))
            return
        await ws.accept()
        slot = Slot(asyncio.get_running_loop())
        attached = False

        def attach() -> str | None:
            nonlocal attached
            if not attached:
                try:
                    hub.attach(topic, slot)
                    attached = True
                except TopicError as exc:
                    return str(exc)
            return None

        async def attach_when_listed() -> None:
            await hub.wait_listed(topic)
            problem = attach()
            if problem is not None:  # listed with a type this gateway cannot load
                await ws.send_text(json.dumps(error_body(problem)))

        watcher: asyncio.Task[None] | None = None
        problem = attach()
        if problem is not None:  # not streamable yet: attach when the graph lists it
            await ws.send_text(json.dumps(error_body(problem)))
            watcher = asyncio.create_task(attach_when_listed())
        sender = asyncio.create_task(_pump(ws, slot))
        try:
            while True:
                message = await ws.receive()
                if message["type"] == "websocket.disconnect":
                    break
                text = message.get("text")
                if text is None:
                    await ws.send_text(json.dumps(error_body(
                        "binary frames are not supported: send JSON text")))
                    continue
                try:
                    hub.publish_json(topic, text)
                except TopicError as exc:
                    await ws.send_text(json.dumps(error_body(str(exc))))
                    continue
                attach()  # publishing may have defined the topic
        except (WebSocketDisconnect, RuntimeError):
            pass
        finally:
            sender.cancel()
            if watcher is not None:
                watcher.cancel()
            if attached:
                hub.detach(topic, slot)

    return Starlette(routes=[WebSocketRoute("/{topic:path}", endpoint)])


async def _pump(ws: WebSocket, slot: Slot) -> None:
    try:
        while True:
            await ws.send_text(await slot.get())
    except (WebSocketDisconnect, RuntimeError, OSError):
        return
