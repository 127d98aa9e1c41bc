"""`zenros launch fleet.yaml robots:=10`: ten simulated robots in one world on this box, each
one process (its services composed), isolated from the others: a goal, an e-stop and a TF tree
reach only their own robot."""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import pytest
from zenros.action import ActionClient
from zenros.context import Context
from zenros.msgs.geometry_msgs import PoseStamped
from zenros.msgs.nav2_msgs import NavigateToPose, NavigateToPoseGoal
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.std_msgs import Header
from zenros.msgs.std_srvs import SetBool, SetBoolRequest
from zenros.msgs.zenros_msgs import ChassisState
from zenros.node import Node
from zenros.session import SessionOptions
from zenros.testing import Proc, free_port, unique_prefix, wait_for
from zenros.tf import Buffer, TransformListener

pytestmark = [pytest.mark.system, pytest.mark.xdist_group("sim"), pytest.mark.timeout(900)]

ROOT = Path(__file__).resolve().parents[2]
ROBOTS = 10
SPACING = 2.5  # fleet.yaml: robot k starts at ((k - 1) * 2.5, 0, 0)
AHEAD = 1.2  # each robot's goal: this far ahead of where it starts
SERVICES = ("chassis", "nav", "slam", "tf", "tasks")


@dataclass
class Fleet:
    proc: Proc
    ctx: Context
    node: Node
    env: dict[str, str]  # what a fresh CLI process needs to join the fleet
    rest_port: int  # the fleet gateway's REST API


@pytest.fixture(scope="module")
def fleet(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Fleet]:
    home = tmp_path_factory.mktemp("fleet")
    prefix, endpoint = unique_prefix(), f"tcp/127.0.0.1:{free_port()}"
    env = {"ZENROS_HOME": str(home), "ZENROS_PREFIX": prefix, "ZENROS_CONNECT": endpoint}
    ports = {name: free_port() for name in ("rest_port", "ws_port", "rosbridge_port",
                                            "modbus_port")}
    proc = Proc([sys.executable, "-m", "zenros.cli", "launch",
                 str(ROOT / "deploy" / "launch" / "fleet.yaml"), f"robots:={ROBOTS}",
                 f"data:={home}", *(f"{k}:={v}" for k, v in ports.items())], env=env)
    ctx: Context | None = None
    try:
        for k in range(1, ROBOTS + 1):
            assert proc.wait_line(f"robot{k}/robot is ready", 240), proc.output
        # The test's own session is a client of the launch's router: what it observes then
        # comes through the router's links, which each robot made to a configured endpoint and
        # makes again if they drop. As a peer it linked to each robot by gossip, and a link of
        # those whose lease ran out alone on the starved box never came back (docs/zenoh-
        # config.md, "Known limit"): one robot's ground truth unheard for the rest of the
        # module in a full suite run (2026-12-06). Fresh CLI processes, below, stay peers.
        ctx = Context(SessionOptions(mode="client", connect=[endpoint]), prefix=prefix)
        node = Node("fleet_test", context=ctx)
        yield Fleet(proc, ctx, node, env, ports["rest_port"])
        node.close()
    finally:
        if ctx is not None:
            ctx.close()
        proc.stop(timeout=60)


def keep(into: dict[int, Any], k: int, field: Callable[[Any], Any]) -> Callable[[Any], None]:
    """A callback that keeps ``field(msg)`` of robot ``k``'s latest message in ``into``."""
    return lambda msg: into.__setitem__(k, field(msg))


def truth(fleet: Fleet) -> dict[int, Any]:
    """Each robot's latest ground truth (sim/ground_truth), by robot number."""
    latest: dict[int, Any] = {}
    for k in range(1, ROBOTS + 1):
        fleet.node.create_subscription(Odometry, f"/robot{k}/sim/ground_truth",
                                       keep(latest, k, lambda m: m.pose.pose.position))
    assert wait_for(lambda: len(latest) == ROBOTS, 30), sorted(latest)
    return latest


def robot_pids(fleet: Fleet) -> dict[str, int]:
    """The pid of every robot service's node, once the graph lists them all."""
    g = fleet.ctx.graph
    want = {f"/robot{k}/{s}" for k in range(1, ROBOTS + 1) for s in SERVICES}
    assert g.wait_for(lambda: want <= set(g.node_names()), 30), want - set(g.node_names())
    return {n.name: n.pid for n in g.nodes() if n.name in want}


def test_every_robot_is_one_process_in_the_graph(fleet: Fleet) -> None:
    pids = robot_pids(fleet)
    for k in range(1, ROBOTS + 1):
        assert len({pids[f"/robot{k}/{s}"] for s in SERVICES}) == 1  # composed
    assert len(set(pids.values())) == ROBOTS


def test_one_gateway_serves_every_robot(fleet: Fleet) -> None:
    # issue 37.7: the gateway, a peer, missed a robot for good when their gossip-found link
    # was lost while ten processes started; the launch now links its peers by configured
    # endpoints, which Zenoh makes again (docs/launch.md, "Endpoints")
    g = fleet.ctx.graph
    pids = robot_pids(fleet)
    # one gateway serves them all, as it says (GET /api/v1/robots) ...
    base = f"http://127.0.0.1:{fleet.rest_port}/api/v1"
    with httpx.Client(base_url=base, timeout=20) as http:
        token = http.get("/token", params={"username": "admin",
                                           "password": "admin"}).json()["token"]

        def served() -> set[str]:
            return {r["name"] for r in http.get("/robots", params={"token": token})
                    .json()["robots"]}

        want_served = {f"robot{k}" for k in range(1, ROBOTS + 1)}
        assert wait_for(lambda: served() == want_served, 60), \
            f"{served()}\n{_lines(fleet.proc.output, ('gateway',))}"
    # ... with a node per robot (/robot<k>/gateway), all in its one process: the views this
    # session's graph shows (a token may reach it late on a loaded box: issue 37.7)
    views = {"/gateway", *(f"/robot{k}/gateway" for k in range(1, ROBOTS + 1))}
    assert g.wait_for(lambda: "/gateway" in g.node_names()
                      and len(views & set(g.node_names())) > 1, 60), g.node_names()
    gateway = {n.pid for n in g.nodes() if n.name in views}
    assert len(gateway) == 1 and not gateway & set(pids.values())


def test_goals_estop_and_tf_reach_only_their_own_robot(fleet: Fleet) -> None:
    where = truth(fleet)
    starts = {k: (where[k].x, where[k].y) for k in where}
    for k, (x, y) in starts.items():
        assert (x, y) == pytest.approx(((k - 1) * SPACING, 0.0), abs=0.05)
    stopped = 3
    estop = fleet.node.create_client(SetBool, f"/robot{stopped}/chassis/set_estop")
    # asked again while the graph lists it (grace): beside a CPU hog a robot's link to the
    # router may be made again just now, and the query finds no route for a moment
    assert estop.call(SetBoolRequest(data=True), timeout=20, grace=20).success
    states: dict[int, bool] = {}
    for k in range(1, ROBOTS + 1):
        fleet.node.create_subscription(ChassisState, f"/robot{k}/chassis/state",
                                       keep(states, k, lambda m: m.estop))
    assert wait_for(lambda: states == {k: k == stopped for k in range(1, ROBOTS + 1)}, 30), \
        states
    # every robot but the stopped one drives AHEAD metres; each gets its own goal
    goals = {}
    for k in range(1, ROBOTS + 1):
        if k == stopped:
            continue
        # reach_grace, as the estop call's grace above: a listed server's queryable may reach
        # this session a while after its token on a loaded box (CI once saw robot5's goal end
        # unanswered after the default 1 s); at most 90 % of send_timeout
        client = ActionClient(fleet.node, NavigateToPose, f"/robot{k}/navigate_to_pose",
                              send_timeout=30, reach_grace=20)
        assert client.wait_for_server(30)
        target = PoseStamped(header=Header(frame_id="map"))
        target.pose.position.x = starts[k][0] + AHEAD
        target.pose.orientation.w = 1.0
        goals[k] = client.send_goal_async(NavigateToPoseGoal(pose=target))
    results = {k: h.result(180) for k, h in goals.items()}
    failed = {k: (r.status.name, r.reason) for k, r in results.items() if not r.succeeded}
    assert not failed, f"{failed}\n{_robot_lines(fleet.proc.output, failed)}"
    assert wait_for(lambda: all(
        math.hypot(where[k].x - starts[k][0] - AHEAD, where[k].y) < 0.25 for k in goals), 10), \
        {k: (where[k].x - starts[k][0], where[k].y) for k in goals}
    assert math.hypot(where[stopped].x - starts[stopped][0],
                      where[stopped].y - starts[stopped][1]) < 0.02
    # each robot's TF tree (/robot<k>/tf) puts its base_link where that robot is
    for k in (1, stopped, ROBOTS):
        tf_node = Node(f"tf_reader{k}", context=fleet.ctx,
                       remappings=[f"/tf:=/robot{k}/tf", f"/tf_static:=/robot{k}/tf_static"])
        try:
            buffer = Buffer()
            TransformListener(buffer, tf_node)
            assert wait_for(lambda b=buffer: b.can_transform("map", "base_link", 0), 20)
            t = buffer.lookup_transform("map", "base_link", 0).transform.translation
            assert (t.x, t.y) == pytest.approx((where[k].x, where[k].y), abs=0.1)
        finally:
            tf_node.close()


def _robot_lines(output: str, robots: Iterable[int]) -> str:
    """The launch's lines of these robots (their warnings and errors), the last 40."""
    return _lines(output, tuple(f"robot{k}/" for k in robots))


def _lines(output: str, tags: tuple[str, ...]) -> str:
    """The launch's lines that name one of ``tags``, the last 40."""
    return "\n".join([ln for ln in output.splitlines() if any(t in ln for t in tags)][-40:])


def test_goals_from_fresh_cli_processes_reach_every_robot(fleet: Fleet) -> None:
    # issue 37.4: `zenros action send_goal /robot9/navigate_to_pose ...` from a new shell
    # found no server while robot9 was up. Here ten fresh CLI processes at once, one goal
    # each (the robot's own pose: nav accepts it and ends at once), and every one is taken.
    where = truth(fleet)
    estop = fleet.node.create_client(SetBool, "/robot3/chassis/set_estop")
    assert estop.call(SetBoolRequest(data=False), timeout=20, grace=20).success
    clis = {}
    try:
        for k in range(1, ROBOTS + 1):
            goal = (f"{{pose: {{header: {{frame_id: map}}, pose: {{position: "
                    f"{{x: {where[k].x:.3f}, y: {where[k].y:.3f}}}, orientation: {{w: 1.0}}}}}}}}")
            clis[k] = Proc([sys.executable, "-m", "zenros.cli", "action", "send_goal",
                            f"/robot{k}/navigate_to_pose", "nav2_msgs/action/NavigateToPose",
                            goal, "--server-timeout", "60"], env=fleet.env)
        for k, cli in clis.items():
            assert cli.wait(120) == 0, f"robot{k}: {cli.output}"
            assert "Goal accepted with ID" in cli.output, f"robot{k}: {cli.output}"
            assert "Goal finished with status: SUCCEEDED" in cli.output, f"robot{k}: {cli.output}"
    finally:
        for cli in clis.values():
            cli.stop(10)


def test_each_robot_has_its_own_diagnostics_tree(fleet: Fleet) -> None:
    # robot.yaml's aggregator in each robot's namespace: its chassis and nav, nobody else's
    from zenros.msgs.diagnostic_msgs import DiagnosticArray

    trees: dict[int, Any] = {}
    for k in (1, ROBOTS):
        fleet.node.create_subscription(DiagnosticArray, f"/robot{k}/diagnostics_agg",
                                       keep(trees, k, lambda m: m))
    # 60 s: on a loaded box a new subscription reaches a robot of the composed process late
    # (issue 37.4's family; 30 s was exceeded twice in suites run beside other tests)
    assert wait_for(lambda: len(trees) == 2, 60), sorted(trees)
    for k, tree in trees.items():
        names = {s.name for s in tree.status}
        assert {"/Chassis/motors", "/Chassis/battery", "/Navigation/localization"} <= names, \
            (k, names)
        # the fleet gateway reports at the root: its items never land in a robot's tree (whose
        # Gateway branch is for a station's gateway of that robot, station.yaml)
        assert not any(n.startswith("/Gateway/") for n in names), (k, names)
