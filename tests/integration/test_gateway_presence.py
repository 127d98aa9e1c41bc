"""A backend the gateway calls (nav, tasks) that is still starting answers 503 "starting"
with Retry-After, distinct from one that went away (issue 21 item 6: right after launch,
``/navigation/start`` said "the nav service is not running" while nav was starting)."""

from __future__ import annotations

import time
from pathlib import Path

import httpx
from zenros.action import ServerGoalHandle
from zenros.context import Context
from zenros.msgs.nav2_msgs import NavigateToPose, NavigateToPoseResult
from zenros.msgs.zenros_msgs.tasks import GetTasks, GetTasksRequest, GetTasksResponse
from zenros.node import Node
from zenros.services.gateway.state.presence import RETRY_AFTER
from zenros.services.gateway.testing import running_gateway
from zenros.testing import wait_for


def _navigate(gh: ServerGoalHandle) -> NavigateToPoseResult:
    gh.succeed()
    return NavigateToPoseResult()


def _tasks_get(req: GetTasksRequest) -> GetTasksResponse:
    return GetTasksResponse(tasks=[])


def test_starting_then_up_then_gone(ctx_pair: list[Context], tmp_path: Path) -> None:
    with running_gateway(ctx_pair[0], tmp_path, no_token_check=True) as gw, \
            httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=20) as h:
        # starting: nothing seen yet, within the grace
        for path in ("/navigation/start", "/task"):
            r = h.get(path)
            assert r.status_code == 503, r.text
            assert r.headers["retry-after"] == str(RETRY_AFTER), (path, r.headers)
            assert "is starting" in r.text, r.text
        # the services come up: a client that retries gets through
        backend = Node("fake_backend", context=ctx_pair[1])
        try:
            nav = backend.create_action_server(NavigateToPose, "navigate_to_pose", _navigate)
            tasks = backend.create_service(GetTasks, "tasks/get", _tasks_get)
            assert wait_for(lambda: h.get("/navigation/start").status_code == 200, 10)
            assert wait_for(lambda: h.get("/task").status_code == 200, 10)
            assert h.get("/task").json() == []
            # and go away: 503 saying so, without Retry-After
            nav.close()
            tasks.close()
            assert wait_for(lambda: h.get("/navigation/start").status_code == 503, 10)
            assert wait_for(lambda: h.get("/task").status_code == 503, 10)
            for path in ("/navigation/start", "/task"):
                r = h.get(path)
                assert "went away" in r.text and "retry-after" not in r.headers, r.text
        finally:
            backend.close()


def test_never_seen_after_the_grace_is_not_running(ctx_pair: list[Context],
                                                   tmp_path: Path) -> None:
    with running_gateway(ctx_pair[0], tmp_path, no_token_check=True, startup_grace=0.5) as gw, \
            httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=20) as h:
        start = time.monotonic()
        assert wait_for(lambda: time.monotonic() - start > 0.6, 2)
        r = h.get("/navigation/start")
        assert r.status_code == 503 and "retry-after" not in r.headers
        assert "the nav service is not running" in r.text, r.text
