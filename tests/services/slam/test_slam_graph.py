"""The optimiser closes a synthetic loop; the loop closer takes a real closure and refuses a
false one in a featureless corridor; the pose graph file round-trips."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from slam_worlds import ROOM, cast, corridor
from zenros.se2 import Pose2
from zenros.services.slam.graph import PoseGraph, relative
from zenros.services.slam.loop import LoopCloser
from zenros.services.slam.optimizer import optimize
from zenros.services.slam.params import SlamParameters
from zenros.services.slam.store import check_name, load_graph, save_graph


def _square(n_side: int = 10, step: float = 0.5) -> list[Pose2]:
    poses = [Pose2()]
    for k in range(4 * n_side):
        turn = math.pi / 2 if (k + 1) % n_side == 0 else 0.0
        poses.append(poses[-1] * Pose2(step, 0.0, turn))
    return poses


def test_optimiser_closes_a_drifted_loop() -> None:
    truth = _square()
    rng = np.random.default_rng(1)
    graph = PoseGraph()
    odo_cov = np.diag([0.01 ** 2, 0.01 ** 2, 0.01 ** 2])
    est = [Pose2()]
    for a, b in zip(truth, truth[1:]):
        z = relative(a, b)
        z = Pose2(z.x + rng.normal(0, 0.01), z.y + rng.normal(0, 0.01),
                  z.theta + 0.02 + rng.normal(0, 0.005))  # a heading bias: the loop drifts
        est.append(est[-1] * z)
    for k, p in enumerate(est):
        graph.add_node(p, p, float(k), cast(ROOM, Pose2(5, 3, 0), beams=8))
    for k in range(len(est) - 1):
        graph.add_edge(k, k + 1, relative(est[k], est[k + 1]), odo_cov)
    end = len(est) - 1
    drift = truth[end].distance(est[end])
    assert drift > 0.5
    graph.add_edge(0, end, relative(truth[0], truth[end]), np.diag([1e-4, 1e-4, 1e-4]), "loop")
    res = optimize(graph.poses(), graph.edges)
    assert res.final_cost < res.initial_cost / 4
    x = res.poses
    assert np.allclose(x[0], 0.0)  # the first node holds the map frame
    err = max(math.hypot(x[k, 0] - t.x, x[k, 1] - t.y) for k, t in enumerate(truth))
    assert err < drift / 3


def test_huber_keeps_a_bad_loop_edge_from_folding_the_map() -> None:
    truth = [Pose2(0.5 * k, 0.0, 0.0) for k in range(30)]
    graph = PoseGraph()
    cov = np.diag([0.01 ** 2, 0.01 ** 2, 0.005 ** 2])
    for k, p in enumerate(truth):
        graph.add_node(p, p, float(k), cast(ROOM, Pose2(5, 3, 0), beams=8))
    for k in range(len(truth) - 1):
        graph.add_edge(k, k + 1, relative(truth[k], truth[k + 1]), cov)
    graph.add_edge(0, 29, Pose2(2.0, 1.0, 0.0), np.diag([1e-4, 1e-4, 1e-4]), "loop")  # wrong
    x = optimize(graph.poses(), graph.edges, huber=3.0).poses
    assert abs(x[29, 0] - truth[29].x) < 3.0  # pulled, but not onto the false place (2, 1)
    assert x[29, 0] > 8.0


def _walk(world: list, poses: list[Pose2]) -> PoseGraph:
    graph = PoseGraph()
    for k, p in enumerate(poses):
        graph.add_node(p, p, float(k), cast(world, p, noise=0.01, seed=k))
    return graph


def test_loop_closer_accepts_a_true_closure_in_a_room() -> None:
    params = SlamParameters()
    # out along the room and back past the start: the last node sees the first ones again
    out = [Pose2(1.5 + 0.4 * k, 1.0, 0.0) for k in range(18)]
    back = [Pose2(8.3 - 0.4 * k, 5.0, math.pi) for k in range(18)]
    graph = _walk(ROOM, out + back + [Pose2(1.7, 1.2, 0.1)])
    node = graph.nodes[-1]
    # the graph drifted: the new node is believed 0.6 m and 3 degrees from where it is
    true_pose = node.pose
    node.pose = Pose2(true_pose.x + 0.6, true_pose.y - 0.4, true_pose.theta + 0.05)
    found = LoopCloser(params).try_close(graph, node)
    assert found is not None and found.accepted, found
    got = found.result.pose
    assert math.hypot(got.x - true_pose.x, got.y - true_pose.y) < 0.05
    assert abs(got.theta - true_pose.theta) < 0.01


def test_loop_closer_rejects_a_false_match_in_a_corridor() -> None:
    params = SlamParameters()
    world = corridor()
    out = [Pose2(-15 + 0.4 * k, 0.0, 0.0) for k in range(40)]
    graph = _walk(world, out + [Pose2(-14.0, 0.1, 0.0)])
    node = graph.nodes[-1]
    node.pose = Pose2(-12.5, 0.1, 0.0)  # 1.5 m off along the corridor: nothing shows it
    found = LoopCloser(params).try_close(graph, node)
    assert found is not None and not found.accepted
    assert "ambiguous" in found.reason


def test_pose_graph_file_round_trips(tmp_path: Path) -> None:
    graph = _walk(ROOM, [Pose2(2, 1, 0), Pose2(2.5, 1, 0.2), Pose2(3, 1.2, 0.4)])
    graph.add_edge(0, 1, Pose2(0.5, 0, 0.2), np.diag([1e-3, 2e-3, 3e-3]))
    graph.add_edge(0, 2, Pose2(1.0, 0.2, 0.4), np.diag([1e-3, 1e-3, 1e-3]), "loop")
    path = tmp_path / "site.posegraph"
    save_graph(path, graph, Pose2(0.1, -0.2, 0.03), 0.05)
    back, m2o, res = load_graph(path)
    assert m2o == Pose2(0.1, -0.2, 0.03) and res == 0.05
    assert [n.pose for n in back.nodes] == [n.pose for n in graph.nodes]
    assert np.array_equal(back.nodes[1].scan.ranges, graph.nodes[1].scan.ranges)
    assert [(e.i, e.j, e.kind) for e in back.edges] == [(0, 1, "odom"), (0, 2, "loop")]
    assert np.allclose(back.edges[0].information, graph.edges[0].information)
    assert back.loop_closures == 1


def test_a_file_that_is_not_a_pose_graph_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "x.posegraph"
    path.write_bytes(b"\x93\x01\x02\x03not a graph")
    with pytest.raises(ValueError, match="not a pose graph"):
        load_graph(path)


@pytest.mark.parametrize("name", ["", "../etc", "a/b", ".hidden", "-x", "x" * 65])
def test_map_names_that_are_paths_are_refused(name: str) -> None:
    with pytest.raises(ValueError, match="invalid map name"):
        check_name(name)
