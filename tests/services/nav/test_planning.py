"""GlobalPlanner: plans through several poses with leg lengths, plans out of the inflated
zone, error codes; PlanWorker serves the newest request on its thread."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from zenros.maps import GridMap
from zenros.msgs.nav2_msgs import ComputePathToPoseResult as Codes
from zenros.se2 import Pose2
from zenros.services.nav.costmap import CostmapParams
from zenros.services.nav.costmap.live import Costmaps
from zenros.services.nav.planning import PlannerParams
from zenros.services.nav.planning import errors
from zenros.services.nav.planning.global_planner import GlobalPlanner, PlanWorker
from zenros.services.nav.planning.wording import in_map_terms


def room(door: bool = True) -> Costmaps:
    """10 m x 6 m at 0.05 m, walled, with a wall at x = 5 and a door at y 4..5."""
    g = np.zeros((120, 200), dtype=np.int8)
    g[0, :] = g[-1, :] = g[:, 0] = g[:, -1] = 100
    g[:, 100] = 100
    if door:
        g[80:100, 100] = 0
    cm = Costmaps(CostmapParams(robot_radius=0.2, inflation_radius=0.5, cost_scaling_factor=3.0))
    cm.set_map(GridMap(g, 0.05, (0.0, 0.0, 0.0)))
    return cm


def test_plan_through_poses_reports_where_each_leg_ends() -> None:
    planner = GlobalPlanner(PlannerParams(), 0.2)
    snap = room().snapshot()
    out = planner.plan(snap, Pose2(1.0, 1.0), [Pose2(3.0, 1.0), Pose2(8.0, 1.0)])
    assert out.ok and out.error_code == 0
    assert out.xy is not None
    assert out.xy[0] == pytest.approx([1.0, 1.0]) and out.xy[-1] == pytest.approx([8.0, 1.0])
    length = float(np.sum(np.hypot(*np.diff(out.xy, axis=0).T)))
    assert out.leg_ends[-1] == pytest.approx(length)
    assert out.leg_ends[0] == pytest.approx(2.0, abs=0.1)
    assert np.max(out.xy[:, 1]) > 4.0  # through the door


def test_error_codes() -> None:
    planner = GlobalPlanner(PlannerParams(), 0.2, goal_tolerance=0.1)
    snap = room().snapshot()
    cases = [(Pose2(20.0, 1.0), Codes.GOAL_OUTSIDE_MAP), (Pose2(5.0, 1.0), Codes.GOAL_OCCUPIED)]
    for goal, code in cases:
        assert planner.plan(snap, Pose2(1.0, 1.0), [goal]).error_code == code
    assert planner.plan(snap, Pose2(-1.0, 1.0), [Pose2(2, 2)]).error_code == \
        Codes.START_OUTSIDE_MAP
    assert planner.plan(snap, Pose2(1.0, 1.0), []).error_code == Codes.UNKNOWN


def test_errors_say_where_in_the_map_not_which_cell() -> None:
    """Issue 37 item 3: a goal in a wall was "goal cell (100, 20) has cost 254"; the user
    gave metres in map, and the error says them back. The codes stay Nav2's."""
    planner = GlobalPlanner(PlannerParams(), 0.2, goal_tolerance=0.1)
    snap = room().snapshot()
    out = planner.plan(snap, Pose2(1.0, 1.0), [Pose2(5.02, 1.0)])
    assert (out.error_code, out.error_msg) == (Codes.GOAL_OCCUPIED,
                                               "goal (5.02, 1.00) is inside an obstacle")
    out = planner.plan(snap, Pose2(1.0, 1.0), [Pose2(3.0, 1.0), Pose2(5.0, 2.5)])
    assert (out.error_code, out.error_msg) == (
        Codes.GOAL_OCCUPIED, "leg 2 of 2: goal (5.00, 2.50) is inside an obstacle")
    out = planner.plan(room(door=False).snapshot(), Pose2(1.0, 1.0), [Pose2(8.0, 1.0)])
    assert (out.error_code, out.error_msg) == (
        Codes.NO_VALID_PATH, "no path from (1.00, 1.00) to (8.00, 1.00): every way there is "
                             "blocked")


@pytest.mark.parametrize(("error", "text"), [
    (errors.GoalOccupied, "goal (2.00, -3.25) is inside an obstacle"),
    (errors.StartOccupied, "start (1.00, 0.50) is inside an obstacle"),
    (errors.GoalOutsideMap, "goal (2.00, -3.25) is outside the map"),
    (errors.StartOutsideMap, "start (1.00, 0.50) is outside the map"),
    (errors.NoValidPath, "no path from (1.00, 0.50) to (2.00, -3.25): every way there is "
                         "blocked"),
    (errors.PlanningTimeout, "no path from (1.00, 0.50) to (2.00, -3.25) found within 1.5 s"),
    (errors.PlanningError, "cell (3, 4) went wrong"),  # no wording of its own: as raised
])
def test_every_planning_error_has_words_in_the_map_frame(error: type[errors.PlanningError],
                                                         text: str) -> None:
    exc = error("cell (3, 4) went wrong")
    assert in_map_terms(exc, Pose2(1.0, 0.5), Pose2(2.0, -3.25), 1.5) == text


def test_start_next_to_a_wall_is_planned_out_of() -> None:
    planner = GlobalPlanner(PlannerParams(), 0.2)
    snap = room().snapshot()
    start = Pose2(4.9, 1.0)  # 0.1 m from the wall: inscribed
    assert snap.costs[20, 98] >= 253
    out = planner.plan(snap, start, [Pose2(2.0, 1.0)])
    assert out.ok, out.error_msg


def test_worker_answers_the_newest_request() -> None:
    cm = room()
    worker = PlanWorker(GlobalPlanner(PlannerParams(), 0.2), cm.snapshot)
    try:
        tickets = [worker.submit(Pose2(1.0, 1.0), [Pose2(x, 1.0)]) for x in (2.0, 3.0, 8.0)]
        deadline = time.monotonic() + 10
        out = None
        while out is None and time.monotonic() < deadline:
            out = worker.poll(tickets[-1])
            time.sleep(0.005)
        assert out is not None and out.ok and out.xy is not None
        assert out.xy[-1] == pytest.approx([8.0, 1.0])
        assert math.isfinite(out.planning_time)
    finally:
        worker.close()


def test_unthreaded_worker_plans_in_the_caller_and_answers_at_the_next_poll() -> None:
    cm = room()
    worker = PlanWorker(GlobalPlanner(PlannerParams(), 0.2), cm.snapshot, threaded=False)
    try:
        assert worker._thread is None
        first = worker.submit(Pose2(1.0, 1.0), [Pose2(2.0, 1.0)])
        last = worker.submit(Pose2(1.0, 1.0), [Pose2(8.0, 1.0)])
        out = worker.poll(last)  # ready at once: no thread, no wait
        assert out is not None and out.ok and out.xy is not None
        assert out.xy[-1] == pytest.approx([8.0, 1.0])
        assert worker.poll(last) is None  # forgotten once polled
        earlier = worker.poll(first)
        assert earlier is not None and earlier.ok
        # a planner failure is an outcome, not an exception in the caller
        bad = PlanWorker(GlobalPlanner(PlannerParams(), 0.2), lambda: 1 / 0, threaded=False)
        out = bad.poll(bad.submit(Pose2(1.0, 1.0), [Pose2(2.0, 1.0)]))
        assert out is not None and not out.ok and "planner failed" in out.error_msg
        bad.close()
    finally:
        worker.close()
