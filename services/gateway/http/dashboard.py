"""`dashboard_app`: the web dashboard's static files and its ``config.json`` (the rosbridge port,
the robot's namespace, a fleet's robots and schedule server), served at ``/`` next to the REST API."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import JSONResponse
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

__all__ = ["STATIC_DIR", "dashboard_app"]

STATIC_DIR = Path(__file__).parents[1] / "static"


def dashboard_app(rosbridge_port: int, namespace: str = "", title: str = "",
                  robots: Callable[[], list[str]] | None = None,
                  schedule_server: str = "") -> Starlette:
    """The dashboard (``/``, ``/js/...``, ``/style.css``) and ``/config.json``.

    Args:
        rosbridge_port: where the page's rosbridge connection goes (on the page's host).
        namespace: the robot's namespace; the page prefixes its topics with it.
        title: the name shown in the page's header (default: the namespace).
        robots: a fleet gateway's robots now (names); ``namespace`` is then the default
            one's. ``config.json`` lists them as ``robots`` and the page shows the fleet view.
        schedule_server: a fleet's schedule server (``schedule_server`` in ``config.json``):
            the fleet view draws its traffic reservations.
    """
    config: dict[str, Any] = {"rosbridge_port": rosbridge_port,
                              "namespace": "" if namespace == "/" else namespace.rstrip("/"),
                              "title": title}

    async def config_json(request: Request) -> JSONResponse:
        extra = {} if robots is None else {"robots": robots(),
                                           "schedule_server": schedule_server}
        return JSONResponse(config | extra, headers={"Cache-Control": "no-store"})

    return Starlette(routes=[
        Route("/config.json", config_json),
        Mount("/", StaticFiles(directory=STATIC_DIR, html=True)),
    ])
