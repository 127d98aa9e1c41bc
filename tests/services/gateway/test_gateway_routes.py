"""REST handlers as plain functions over an explicit `Context`: the /api/v1 app built on
stand-in ports and driven in process (AsgiClient: no socket, no Zenoh session), and the
one table that turns port errors into HTTP answers."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path
from typing import Any, cast, get_args, get_type_hints

import msgspec
import numpy as np
import pytest
from zenros.maps import GridMap
from zenros.msgs.nav_msgs import OccupancyGrid
from zenros.msgs.zenros_msgs.chassis import IoState
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.task_docs import Task
from zenros.services.gateway.errors import (
    Conflict,
    Failed,
    NoAnswer,
    NotFound,
    PortError,
    Refused,
    Unavailable,
    port_error,
)
from zenros.services.gateway.http.api import STATUS, Answer, Call, api_error
from zenros.services.gateway.http.app import HttpApp, build_api
from zenros.services.gateway.http.context import Context
from zenros.services.gateway.http.fleet import FleetApi
from zenros.services.gateway.ports.nav_actions import NavActions
from zenros.services.gateway.ports.tasks_link import TasksLink
from zenros.services.gateway.state.config import GatewayConfig
from zenros.services.gateway.state.core import Core, make_identity
from zenros.services.gateway.state.settings import Settings
from zenros.services.gateway.testing import AsgiClient


class FakeTasks:
    """The tasks service's typed calls (`TasksLink`): records each call, raises the port
    error in ``errors`` when set for it, else answers the task ``ident`` named ``call``."""

    def __init__(self) -> None:
        self.calls: list[tuple[str, str, object]] = []
        self.errors: dict[str, PortError] = {}

    def _answer(self, name: str, ident: str, arg: object = None) -> Task:
        self.calls.append((name, ident, arg))
        if name in self.errors:
            raise self.errors[name]
        return Task(id=ident, name=name)

    async def tasks(self, ident: str = "") -> list[Task]:
        return [self._answer("get", ident)]

    async def get(self, ident: str) -> Task:
        return self._answer("get", ident)

    async def step(self, name: str, ident: str = "") -> Task:
        return self._answer(name, ident)

    async def loop(self, ident: str, flag: bool) -> Task:
        return self._answer("loop", ident, flag)

    async def create(self, task: Task) -> Task:
        return self._answer("create", task.name, task)

    run_task = TasksLink.run_task  # the real policy, over these calls


class FakeIo:
    """The chassis IO port: raises ``error`` when set, else keeps the level."""

    def __init__(self) -> None:
        self.error: PortError | None = None
        self.state = IoState(outputs=[0, 1, 0])

    def current(self) -> IoState:
        if self.error is not None:
            raise self.error
        return self.state

    async def set(self, board: str, port: int, level: int) -> IoState:
        if self.error is not None:
            raise self.error
        self.state.outputs[port - 1] = level
        return self.state


class FakeNav:
    """What the loop and goal routes use of the nav actions port (`NavActions`)."""

    loop_task_id = ""
    path_name = ""
    same_map = NavActions.same_map


class FakeMapLink:
    """nav's map as a goal on the current map reads it (`NavServices`): the map's name and
    its grid."""

    def __init__(self, grid: OccupancyGrid) -> None:
        self.grid = grid

    async def current_map(self) -> str:
        return "office"


class Rig:
    def __init__(self, tmp: Path) -> None:
        self.core = Core(GatewayConfig(no_token_check=True), Settings(tmp / "settings.json"),
                         make_identity("/r", "6.6.8", 0))
        self.tasks, self.io, self.nav = FakeTasks(), FakeIo(), FakeNav()
        none = cast(Any, None)  # ports these tests do not reach
        tasks = cast(Any, self.tasks)
        self.ctx = Context(core=self.core, tasks=tasks, nav_actions=cast(Any, self.nav),
                           nav_services=none, io=cast(Any, self.io), topics=none, hub=none,
                           params=none, files=none, speech=none, audio=none, coverage=none)
        self.http = AsgiClient(build_api(self.ctx), "/api/v1")


@pytest.fixture
def rig(tmp_path: Path) -> Rig:
    return Rig(tmp_path)


def test_task_routes_forward_to_the_tasks_port(rig: Rig) -> None:
    r = rig.http.get("/task/start", params={"id": "t7"})
    assert r.status_code == 200
    assert (r.json()["id"], r.json()["name"]) == ("t7", "start")
    assert rig.tasks.calls == [("start", "t7", None)]
    r = rig.http.get("/task/loop", params={"id": "t7", "loop_flag": "true"})
    assert rig.tasks.calls[-1] == ("loop", "t7", True)
    rig.tasks.errors["get"] = port_error(ResultCode.NOT_FOUND, "no task 'x'")
    r = rig.http.get("/task", params={"id": "x"})
    assert r.status_code == 404 and r.json() == {"status": "error", "description": "no task 'x'"}


def test_a_starting_backend_is_a_503_with_retry_after(rig: Rig) -> None:
    rig.tasks.errors["get"] = port_error(ResultCode.UNAVAILABLE, "tasks is starting", 2)
    r = rig.http.get("/task")
    assert r.status_code == 503 and r.headers["retry-after"] == "2"


@pytest.mark.parametrize(("error", "status"), [
    (Unavailable("the chassis is not running"), 503), (NoAnswer("no answer"), 504),
    (Failed("it broke"), 502), (Refused("bad level"), 400), (NotFound("no port"), 404),
    (Conflict("no extension board"), 409)])
def test_port_errors_leave_as_their_http_status(rig: Rig, error: PortError,
                                                status: int) -> None:
    rig.io.error = error
    r = rig.http.post("/system/io", json={"port": "1", "level": "1"})
    assert r.status_code == status
    assert r.json() == {"status": "error", "description": error.detail}


def test_io_routes_work_on_the_io_port(rig: Rig) -> None:
    assert rig.http.get("/system/io").json() == {"status": "ok", "out1": "0", "out2": "1",
                                                 "out3": "0"}
    assert rig.http.post("/system/io", json={"port": "3", "level": "1"}).json() == {
        "status": "ok"}
    assert rig.io.state.outputs == [0, 1, 1]


def test_the_loop_task_is_navs_loop_task(rig: Rig) -> None:
    """GET and DELETE /navigation/loop_task act on the nav actions port's loop task id (kept
    by it, cleared when the task ends), not on a list of their own."""
    assert rig.http.get("/navigation/loop_task").status_code == 404
    assert rig.http.delete("/navigation/loop_task").status_code == 404
    rig.nav.loop_task_id = "loop1"
    rig.core.state.looping = True
    assert rig.http.get("/navigation/loop_task").json()["id"] == "loop1"
    stopped = rig.http.delete("/navigation/loop_task").json()
    assert (stopped["id"], stopped["name"]) == ("loop1", "stop")
    assert rig.nav.loop_task_id == "" and rig.core.state.looping is False
    assert rig.http.get("/navigation/loop_task").status_code == 404


def test_a_goal_inside_an_obstacle_is_refused_at_once(rig: Rig) -> None:
    """Issue 37 item 3: ``start_nav_task`` into an obstacle of the map answered 200 and
    the task failed later at planning; the gateway holds the map and refuses it (400, the
    §1.2 body, nav's wording), making no task. A free goal still starts one."""
    cells = np.zeros((40, 60), dtype=np.int8)
    cells[20:30, 30:40] = 100  # a block: x 0.50..1.00, y 0.00..0.50
    cells[0, 0] = -1           # unknown space is not an obstacle to nav
    rig.ctx = replace(rig.ctx, nav_services=cast(Any, FakeMapLink(
        GridMap(cells, 0.05, (-1.0, -1.0, 0.0)).to_msg())))
    rig.http = AsgiClient(build_api(rig.ctx), "/api/v1")
    r = rig.http.post("/navigation/start_nav_task", json={"x": 0.75, "y": 0.25})
    assert r.status_code == 400, r.text
    assert r.json() == {"status": "error",
                        "description": "goal (0.75, 0.25) is inside an obstacle"}
    assert rig.tasks.calls == []
    for x, y in ((0.25, 0.25), (-0.99, -0.99), (40.0, 0.0)):  # free, unknown, off the map
        r = rig.http.post("/navigation/start_nav_task", json={"x": x, "y": y})
        assert r.status_code == 200, r.text
    assert [c[0] for c in rig.tasks.calls] == ["create", "start"] * 3


def test_one_table_maps_every_port_error() -> None:
    for cls in (Unavailable, NoAnswer, Failed, Refused, NotFound, Conflict):
        assert api_error(cls("x")).status_code == STATUS[cls.code]
    err = api_error(port_error(ResultCode.INVALID, "bad sub_tasks"))
    assert (err.status_code, err.description, err.retry_after) == (400, "bad sub_tasks", None)
    assert api_error(Unavailable("starting", retry_after=2)).retry_after == 2


def test_handlers_are_plain_functions() -> None:
    """Every /api/v1 handler is a module-level function: nothing captured in a closure."""
    rig_api = build_api(_bare_context())
    for ep in rig_api.endpoints():
        if not ep.implemented:
            continue
        fn = ep.handler
        assert "<locals>" not in fn.__qualname__, (ep.method, ep.path, fn.__qualname__)
        assert not getattr(fn, "__closure__", None), (ep.method, ep.path)


def _bare_context() -> Context:
    core = Core(GatewayConfig(no_token_check=True), Settings(None),
                make_identity("/r", "6.6.8", 0))
    none = cast(Any, None)
    return Context(core=core, tasks=none, nav_actions=none, nav_services=none, io=none,
                   topics=none, hub=none, params=none, files=none, speech=none, audio=none,
                   coverage=none)


def _doc_operations(marker: str) -> set[tuple[str, str]]:
    """The operations docs/robot-api.md lists in its paragraph opened by ``marker`` alone."""
    text = (Path(__file__).resolve().parents[3] / "docs" / "robot-api.md").read_text()
    paragraph = text.split(f"\n{marker}\n", 1)[1].split("\n\n", 1)[0]
    return set(re.findall(r"`(GET|POST|PUT|DELETE) (/[^`]*)`", paragraph))


def test_the_api_reference_lists_what_is_implemented_and_what_answers_501() -> None:
    """docs/robot-api.md §19's two lists are the route table's split, operation for operation."""
    api = build_api(_bare_context())
    ours = {("GET", "/"), ("GET", "/openapi.json")}
    done = {(e.method, e.path) for e in api.endpoints() if e.implemented} - ours
    todo = {(e.method, e.path) for e in api.endpoints() if not e.implemented}
    listed_done, listed_todo = _doc_operations("Implemented:"), _doc_operations("501:")
    assert not listed_done & listed_todo, sorted(listed_done & listed_todo)
    assert listed_done == done, (sorted(done - listed_done), sorted(listed_done - done))
    assert listed_todo == todo, (sorted(todo - listed_todo), sorted(listed_todo - todo))


def test_a_fleet_gateways_openapi_lists_every_robots_paths() -> None:
    """A fleet gateway's openapi.json has GET /api/v1/robots and each operation again under
    /api/v1/robots/{robot}: the same operations the robot's index lists under its prefix."""
    class Topics:  # what the list reads of a robot's topics
        def fresh(self, what: str) -> bool:
            return True

    robots = {name: build_api(replace(_bare_context(), topics=cast(Any, Topics())))
              for name in ("robot1", "robot2")}
    fleet = FleetApi(robots["robot1"].tokens, "robot1")
    for name, api in robots.items():
        fleet.add(name, api)
    http = AsgiClient(HttpApp(fleet), "/api/v1")
    doc = http.get("/openapi.json").json()
    assert http.get("/robots/robot2/openapi.json").json() == doc
    single = {p: item for p, item in doc["paths"].items() if not p.startswith("/api/v1/robots")}
    per_robot = {p: item for p, item in doc["paths"].items()
                 if p.startswith("/api/v1/robots/{robot}")}
    assert set(per_robot) == {p.replace("/api/v1", "/api/v1/robots/{robot}", 1) for p in single}
    index = http.get("/robots/robot2/").json()
    ops = {f"{m.upper()} {p.replace('{robot}', 'robot2')}" for p, item in per_robot.items()
           for m in item}
    assert ops == set(index["implemented"]) | set(index["not_implemented"])
    status = per_robot["/api/v1/robots/{robot}/system/status"]["get"]
    assert status["parameters"][0] == {**status["parameters"][0], "name": "robot", "in": "path",
                                       "required": True}
    assert "404" in status["responses"] and status["operationId"] == "robot_get_system_status"
    listed = doc["paths"]["/api/v1/robots"]["get"]
    assert {"200", "401"} <= set(listed["responses"])
    listing = http.get("/robots").json()
    schema = listed["responses"]["200"]["content"]["application/json"]["schema"]
    assert set(listing) == set(schema["properties"])
    assert set(listing["robots"][0]) == set(schema["properties"]["robots"]["items"]["properties"])
    # a single robot's gateway documents its own paths only
    alone = AsgiClient(build_api(_bare_context()), "/api/v1").get("/openapi.json").json()
    assert set(alone["paths"]) == set(single)


class _Point(msgspec.Struct, forbid_unknown_fields=True):
    x: float


async def _moved(call: Call[_Point, None]) -> Answer:
    """Echo the body's ``x`` (typed: ``call.body`` is a `_Point`)."""
    return {"x": call.body.x}


def test_a_handlers_call_annotation_is_what_the_request_decodes_into() -> None:
    """``Call[Body, Query]`` in a handler's signature is the one place its input is typed:
    `Api.add` takes the body and query types from it (a request that does not fit is a 400
    naming the field), and a route that says otherwise is refused when it is added."""
    api = build_api(_bare_context())
    ep = api.add("POST", "/test/moved", _moved)
    assert (ep.body, ep.query) == (_Point, None)
    http = AsgiClient(api, "/api/v1")
    assert http.post("/test/moved", json={"x": 1.5}).json() == {"x": 1.5}
    bad = http.post("/test/moved", json={"x": "far"})
    assert bad.status_code == 400 and "`x`" in bad.json()["description"]
    with pytest.raises(ValueError, match="takes a body of _Point"):
        api.add("PUT", "/test/moved", _moved, body=Task)
    for e in build_api(_bare_context()).endpoints():  # every route agrees with its handler
        hinted = get_type_hints(e.handler, include_extras=True)
        args = get_args(next(v for k, v in hinted.items() if k != "return"))
        if args and args[0] is not Any:
            assert e.body == (None if args[0] is type(None) else args[0]), e.path
        if args:
            assert e.query == (None if args[1] is type(None) else args[1]), e.path
