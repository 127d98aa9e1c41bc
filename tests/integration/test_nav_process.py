"""The nav service as processes (chassis and nav at 10x, each its own process, through a
router): maps listed and a goal under way over the wire, SIGINT ends nav cleanly with the
robot stopped; a bad start map is a startup failure (exit code 3) naming file and field."""

from __future__ import annotations

import signal
import sys
from pathlib import Path

import pytest
from zenros.action import ActionClient
from zenros.context import Context
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import PoseWithCovarianceStamped
from zenros.msgs.nav2_msgs import NavigateToPose, NavigateToPoseGoal
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.zenros_msgs import ListMaps, ListMapsRequest
from zenros.node import Node
from zenros.se2 import Pose2
from zenros.services.nav.actions.convert import pose_stamped
from zenros.testing import Proc, wait_for

pytestmark = pytest.mark.system


def start(router: str, prefix: str, module: str, *params: str) -> Proc:
    args = [sys.executable, "-m", module, "-e", router, "--prefix", prefix]
    for p in params:
        args += ["-p", p]
    return Proc(args)


def test_nav_and_chassis_processes(router: str, prefix: str, observer: Context,
                                   procs: list[Proc], tmp_path: Path) -> None:
    chassis = start(router, prefix, "zenros.services.chassis", "speed:=10", "seed:=1")
    procs.append(chassis)
    nav = start(router, prefix, "zenros.services.nav", "use_sim_time:=true",
                f"maps_dir:={tmp_path}")
    procs.append(nav)
    assert nav.wait_line("started", 40), nav.output
    user = Node("user", context=observer)
    try:
        maps = user.create_client(ListMaps, "map_server/list_maps")
        assert maps.wait_for_service(10)
        assert [m.name for m in maps.call(ListMapsRequest(), timeout=10).maps] == ["office"]
        assert (tmp_path / "office" / "office.yaml").is_file()
        truth: list[Odometry] = []
        user.create_subscription(Odometry, "sim/ground_truth", truth.append)
        # as a Nav2 client waits for amcl_pose: nav knows where the robot is (else a goal
        # is aborted, the pose unknown for localization_timeout: 0.5 s of wall time at 10x)
        poses: list[PoseWithCovarianceStamped] = []
        user.create_subscription(PoseWithCovarianceStamped, "robot_pose", poses.append)
        assert wait_for(lambda: bool(poses), 20), nav.output
        client = ActionClient(user, NavigateToPose, "navigate_to_pose")
        assert client.wait_for_server(20)
        # a goal under way, then nav is stopped: it leaves the robot standing
        handle = client.send_goal_async(NavigateToPoseGoal(
            pose=pose_stamped(Pose2(20.0, 0.0), Time())))
        assert handle.wait_accepted(10)
        moving = wait_for(lambda: bool(truth) and abs(truth[-1].twist.twist.linear.x) > 0.3, 20)
        assert moving, (
            f"goal {handle.status.name} {handle.reason!r}, result "
            f"{handle.result(1).result if handle.done else None}, last twist "
            f"{truth[-1].twist.twist if truth else None}\nnav:\n{nav.output[-3000:]}"
            f"\nchassis:\n{chassis.output[-2000:]}")
        nav.signal(signal.SIGINT)
        assert nav.wait(15) == 0, nav.output
        assert wait_for(lambda: abs(truth[-1].twist.twist.linear.x) < 1e-6, 5)
    finally:
        user.close()


def test_a_bad_map_fails_startup(router: str, prefix: str, procs: list[Proc],
                                 tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("image: nowhere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"
                   "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n")
    nav = start(router, prefix, "zenros.services.nav", f"map:={bad}",
                f"maps_dir:={tmp_path / 'maps'}")
    procs.append(nav)
    assert nav.wait(30) == 3, nav.output
    assert "startup failed" in nav.output and "bad.yaml" in nav.output
    assert "'image'" in nav.output
