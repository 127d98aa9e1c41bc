"""Runtime extras benchmark (issue 40): what rclpy offers beyond pub/sub, timed.

Prints one JSON line; each figure is one function returning its keys, merged at the end.

``lifecycle_transition_ms``: ten zenros LifecycleNodes in one process; a client in another
session calls each one's ``change_state`` (configure, then activate) in turn, as a lifecycle
manager does; the figure is the wall time per node (both calls and their answers, the
callbacks, the four transition events), the median of 5 rounds (target <= 50).
``lifecycle_transition_ms_rclpy``: the same with rclpy's LifecycleNode (ten in one process
spinning a multi-threaded executor) and an rclpy client in this process, measured in the same
run inside a network namespace (``unshare -n``, loopback with multicast: DDS discovery stays
on this machine), as bench/ros2.py does; null with a reason without root or the ``ros2``
extra.

``approx_sync_sets_per_s``: sets per second that zenros.message_filters'
ApproximateTimeSynchronizer emits from 3 topics of 30 Hz-like stamps with +-3 ms jitter (slop
20 ms, queue 10), fed in process (the algorithm's cost, no transport); the best of 5 runs of
20000 sets (target >= 10000). ``approx_sync_sets_per_s_rclpy``: the same with ROS 2's
message_filters (Python) where it is installed; it is not among the ROS 2 wheels on the
package index (no ``ros-message-filters``), so the key is null with the reason beside it.

``deadline_detect_ratio``: a publisher with a 0.1 s deadline publishes once; the delay from
that publish to its offered-deadline-missed event, over the deadline, median of 20 (target
<= 1.2). ``events_idle_ratio``: CPU time of a process with 20 publisher/subscription pairs at
rest for 3 s (one sample each first), with QoS events on (deadline 6 s, none due in the
window; matched and liveliness callbacks) over off, median of 3 (target <= 1.1);
``events_idle_cpu_ms`` the two; ``deadline_miss_cpu_us``: the CPU each deadline-missed event
costs (the same with a 1 s deadline: 40 endpoints missing every second). The
``*_rclpy`` keys: the same with rclpy in a network namespace (null with a reason without).

Run: ``python bench/runtime_extras.py`` (``--qos-events`` for the QoS figures alone).
"""

from __future__ import annotations

import os
import random
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from _harness import emit

HERE = Path(__file__).resolve()
NETNS = ("ip link set lo up && ip link set lo multicast on && "
         "ip route add 224.0.0.0/4 dev lo && exec \"$@\"")
N_NODES, ROUNDS = 10, 5


# ------------------------------------------------------------------ lifecycle_transition_ms

def _zenros_lifecycle_round() -> float:
    from zenros import Node
    from zenros.lifecycle import LifecycleNode
    from zenros.msgs.lifecycle_msgs import ChangeState, ChangeStateRequest, Transition
    from zenros.testing import linked_contexts, unique_prefix

    with linked_contexts(2, unique_prefix()) as (a, b):
        nodes = [LifecycleNode(f"lc{i}", context=a) for i in range(N_NODES)]
        client = Node("lc_bench_client", context=b)
        clients = [client.create_client(ChangeState, f"/lc{i}/change_state")
                   for i in range(N_NODES)]
        for c in clients:
            assert c.wait_for_service(30)
        t0 = time.perf_counter()
        for c in clients:
            for tid in (Transition.TRANSITION_CONFIGURE, Transition.TRANSITION_ACTIVATE):
                assert c.call(ChangeStateRequest(transition=Transition(id=tid)), timeout=10).success
        dt = time.perf_counter() - t0
        client.close()
        for n in nodes:
            n.close()
    return dt / N_NODES * 1000


def lifecycle_transition_ms() -> dict[str, Any]:
    _zenros_lifecycle_round()  # warm-up
    per_node = statistics.median(_zenros_lifecycle_round() for _ in range(ROUNDS))
    out: dict[str, Any] = {"lifecycle_transition_ms": round(per_node, 2)}
    ref, why = _rclpy_lifecycle()
    out["lifecycle_transition_ms_rclpy"] = None if ref is None else round(ref, 2)
    if why:
        out["lifecycle_transition_ms_rclpy_reason"] = why
    elif ref:
        out["lifecycle_transition_ratio"] = round(per_node / ref, 3)
    return out


def _rclpy_lifecycle() -> tuple[float | None, str | None]:
    """Re-run this file's rclpy part inside a network namespace; (ms per node, reason)."""
    try:
        import lifecycle_msgs.srv  # noqa: F401
        import rclpy.lifecycle  # noqa: F401
    except ModuleNotFoundError as e:
        return None, f"the ros2 extra is not installed ({e.name}): pip install -e '.[ros2]'"
    got, why = _rclpy_run("--rclpy-lifecycle")
    return (got[0] if got else None), why


def _rclpy_nodes() -> None:
    """Ten rclpy LifecycleNodes spinning until stdin closes."""
    import threading

    import rclpy
    from rclpy.executors import MultiThreadedExecutor
    from rclpy.lifecycle import LifecycleNode

    rclpy.init()
    ex = MultiThreadedExecutor(4)
    nodes = [LifecycleNode(f"lc{i}") for i in range(N_NODES)]
    for n in nodes:
        ex.add_node(n)
    threading.Thread(target=ex.spin, daemon=True).start()
    print("ready", flush=True)
    sys.stdin.read()
    ex.shutdown()
    rclpy.shutdown()


def _rclpy_round(node: Any, clients: list[Any]) -> float:
    import rclpy
    from lifecycle_msgs.msg import Transition
    from lifecycle_msgs.srv import ChangeState

    t0 = time.perf_counter()
    for c in clients:
        for tid in (Transition.TRANSITION_CONFIGURE, Transition.TRANSITION_ACTIVATE):
            req = ChangeState.Request()
            req.transition.id = tid
            fut = c.call_async(req)
            rclpy.spin_until_future_complete(node, fut, timeout_sec=10)
            assert fut.result() is not None and fut.result().success
    return (time.perf_counter() - t0) / N_NODES * 1000


def _rclpy_measure() -> None:
    import rclpy
    from lifecycle_msgs.srv import ChangeState

    per_round: list[float] = []
    for r in range(ROUNDS + 1):
        srv = subprocess.Popen([sys.executable, str(HERE), "--rclpy-nodes"],
                               stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        try:
            assert srv.stdout is not None and srv.stdout.readline().strip() == "ready"
            rclpy.init()
            node = rclpy.create_node(f"lc_bench_client{r}")
            clients = [node.create_client(ChangeState, f"/lc{i}/change_state")
                       for i in range(N_NODES)]
            for c in clients:
                assert c.wait_for_service(timeout_sec=30)
            ms = _rclpy_round(node, clients)
            if r:  # the first round warms up
                per_round.append(ms)
            node.destroy_node()
            rclpy.shutdown()
        finally:
            assert srv.stdin is not None
            srv.stdin.close()
            srv.wait(30)
    print(statistics.median(per_round), flush=True)


# ------------------------------------------------------------------ approx_sync_sets_per_s

SYNC_SETS, SYNC_TOPICS = 20_000, 3


def _sync_stream(n: int, seed: int = 1) -> list[tuple[int, Any]]:
    """(topic, message) in arrival order: topic i's k-th message near k/30 s."""
    from zenros.msgs.builtin_interfaces import Time
    from zenros.msgs.geometry_msgs import PointStamped
    from zenros.msgs.std_msgs import Header

    rng = random.Random(seed)
    return [(i, PointStamped(header=Header(stamp=Time.from_seconds(
        k / 30 + rng.uniform(-0.003, 0.003))))) for k in range(n) for i in range(SYNC_TOPICS)]


def _sets_per_s(sync_cls: Any, filter_cls: Any, msgs: list[tuple[int, Any]]) -> float:
    fs = [filter_cls() for _ in range(SYNC_TOPICS)]
    sync = sync_cls(fs, 10, 0.02)
    count = [0]

    def cb(*_: Any) -> None:
        count[0] += 1

    sync.registerCallback(cb)
    t0 = time.perf_counter()
    for i, m in msgs:
        fs[i].signalMessage(m)
    dt = time.perf_counter() - t0
    assert count[0] >= len(msgs) // SYNC_TOPICS - 2, count[0]
    return count[0] / dt


def approx_sync_sets_per_s() -> dict[str, Any]:
    from zenros.message_filters import ApproximateTimeSynchronizer, SimpleFilter

    msgs = _sync_stream(SYNC_SETS)
    _sets_per_s(ApproximateTimeSynchronizer, SimpleFilter, msgs[:3000])  # warm-up
    best = max(_sets_per_s(ApproximateTimeSynchronizer, SimpleFilter, msgs) for _ in range(5))
    out: dict[str, Any] = {"approx_sync_sets_per_s": round(best)}
    try:
        import message_filters  # type: ignore[import-not-found]
    except ModuleNotFoundError:
        out["approx_sync_sets_per_s_rclpy"] = None
        out["approx_sync_sets_per_s_rclpy_reason"] = (
            "ROS 2's message_filters is not installable here: no ros-message-filters wheel on "
            "the package index (the ros2 extra's wheels lack it)")
        return out
    ref = max(_sets_per_s(message_filters.ApproximateTimeSynchronizer,
                          message_filters.SimpleFilter, msgs) for _ in range(5))
    out["approx_sync_sets_per_s_rclpy"] = round(ref)
    return out


# ------------------------------------------------------------------ QoS events

DEADLINE, DEADLINE_ROUNDS = 0.1, 20
IDLE_ENDPOINTS, IDLE_S = 20, 3.0


def _zenros_deadline_ratio() -> float:
    """Median over rounds of (time from the last publish to the offered-deadline-missed
    event) / the deadline, for a publisher that publishes once and stops."""
    import threading

    from zenros import Node
    from zenros.msgs.std_msgs import String
    from zenros.qos import QoSProfile
    from zenros.qos_events import PublisherEventCallbacks
    from zenros.testing import linked_contexts, unique_prefix

    ratios = []
    with linked_contexts(1, unique_prefix()) as (ctx,):
        node = Node("deadline_bench", context=ctx)
        for r in range(DEADLINE_ROUNDS):
            fired = threading.Event()
            at: list[float] = []

            def on_miss(info: Any, at: list[float] = at, fired: threading.Event = fired) -> None:
                at.append(time.perf_counter())
                fired.set()

            pub = node.create_publisher(String, f"/deadline{r}", QoSProfile(deadline=DEADLINE),
                                        event_callbacks=PublisherEventCallbacks(deadline=on_miss))
            t0 = time.perf_counter()
            pub.publish(String(data="x"))
            assert fired.wait(5)
            ratios.append((at[0] - t0) / DEADLINE)
            node.destroy(pub)
        node.close()
    return statistics.median(ratios)


def _idle_cpu_s(events: bool, deadline: float = 2 * IDLE_S) -> float:
    """CPU seconds this process spends over IDLE_S with IDLE_ENDPOINTS publisher and
    subscription pairs at rest (one sample each first), with or without QoS events (a
    ``deadline`` longer than the window: none is due; 1 s: each endpoint misses every
    second, the cost of the events themselves)."""
    from zenros import Node
    from zenros.msgs.std_msgs import String
    from zenros.qos import QoSProfile
    from zenros.qos_events import PublisherEventCallbacks, SubscriptionEventCallbacks
    from zenros.testing import linked_contexts, unique_prefix, wait_for

    qos = QoSProfile(deadline=deadline) if events else QoSProfile()
    got = [0]
    with linked_contexts(2, unique_prefix()) as (a, b):
        pn, sn = Node("idle_pub", context=a), Node("idle_sub", context=b)
        pubs = []
        for i in range(IDLE_ENDPOINTS):
            def count(m: Any) -> None:
                got[0] += 1
            pcb = PublisherEventCallbacks(deadline=lambda i: None, matched=lambda i: None)
            scb = SubscriptionEventCallbacks(deadline=lambda i: None, liveliness=lambda i: None,
                                             matched=lambda i: None)
            sn.create_subscription(String, f"/idle{i}", count, qos,
                                   event_callbacks=scb if events else None)
            pubs.append(pn.create_publisher(String, f"/idle{i}", qos,
                                            event_callbacks=pcb if events else None))
        for p in pubs:
            assert p.wait_for_subscribers(1, 10)
            p.publish(String(data="once"))
        assert wait_for(lambda: got[0] >= IDLE_ENDPOINTS, 10)
        c0 = time.process_time()
        time.sleep(IDLE_S)  # the measured idle window
        cpu = time.process_time() - c0
        pn.close()
        sn.close()
    return cpu


def qos_events() -> dict[str, Any]:
    """``deadline_detect_ratio`` (<= 1.2) and ``events_idle_ratio`` (<= 1.1), zenros's and,
    in a network namespace, rclpy's (the wheels' default RMW)."""
    off = statistics.median(_idle_cpu_s(False) for _ in range(3))
    on = statistics.median(_idle_cpu_s(True) for _ in range(3))
    missing = statistics.median(_idle_cpu_s(True, 1.0) for _ in range(3))
    misses = 2 * IDLE_ENDPOINTS * IDLE_S  # a publisher's and a subscription's, each second
    out: dict[str, Any] = {"deadline_detect_ratio": round(_zenros_deadline_ratio(), 3),
                           "events_idle_ratio": round(on / off, 3) if off else None,
                           "events_idle_cpu_ms": [round(off * 1000, 1), round(on * 1000, 1)],
                           "deadline_miss_cpu_us": round((missing - on) / misses * 1e6, 1)}
    ref, why = _rclpy_run("--rclpy-qos-events")
    if ref is None:
        out["deadline_detect_ratio_rclpy"] = None
        out["deadline_detect_ratio_rclpy_reason"] = why
    else:
        out["deadline_detect_ratio_rclpy"] = round(ref[0], 3)
        out["events_idle_ratio_rclpy"] = round(ref[1], 3)
    return out


def _rclpy_run(flag: str) -> tuple[list[float] | None, str | None]:
    """This file's rclpy part ``flag`` inside a network namespace; (its numbers, reason)."""
    try:
        import rclpy  # noqa: F401
    except ModuleNotFoundError as e:
        return None, f"the ros2 extra is not installed ({e.name}): pip install -e '.[ros2]'"
    if os.geteuid() != 0:
        return None, "needs root for a network namespace (unshare -n), as bench/ros2.py"
    p = subprocess.run(["unshare", "-n", "sh", "-c", NETNS, "sh", sys.executable, str(HERE),
                        flag], capture_output=True, text=True, timeout=300, check=False)
    last = p.stdout.strip().splitlines()[-1:] or [""]
    try:
        return [float(v) for v in last[0].split()], None
    except ValueError:
        return None, f"the rclpy run failed: {(p.stderr or p.stdout).strip()[-300:]}"


def _rclpy_qos_events() -> None:
    """rclpy's deadline ratio and idle ratio, printed as two numbers."""
    import threading

    import rclpy
    from rclpy.duration import Duration
    from rclpy.event_handler import PublisherEventCallbacks, SubscriptionEventCallbacks
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import QoSProfile
    from std_msgs.msg import String

    rclpy.init()
    node = rclpy.create_node("deadline_bench")
    ex = SingleThreadedExecutor()
    ex.add_node(node)
    threading.Thread(target=ex.spin, daemon=True).start()
    ratios = []
    for r in range(DEADLINE_ROUNDS):
        fired = threading.Event()
        at: list[float] = []

        def on_miss(info: Any, at: list[float] = at, fired: threading.Event = fired) -> None:
            at.append(time.perf_counter())
            fired.set()

        qos = QoSProfile(depth=10, deadline=Duration(seconds=DEADLINE))
        pub = node.create_publisher(String, f"/deadline{r}", qos,
                                    event_callbacks=PublisherEventCallbacks(deadline=on_miss))
        t0 = time.perf_counter()
        pub.publish(String(data="x"))
        assert fired.wait(5)
        ratios.append((at[0] - t0) / DEADLINE)
        node.destroy_publisher(pub)

    def idle(events: bool) -> float:
        n = rclpy.create_node(f"idle_{int(events)}")
        ex.add_node(n)
        qos = QoSProfile(depth=10, deadline=Duration(seconds=2 * IDLE_S)) if events \
            else QoSProfile(depth=10)
        pubs = []
        for i in range(IDLE_ENDPOINTS):
            n.create_subscription(String, f"/idle{i}", lambda m: None, qos,
                                  event_callbacks=SubscriptionEventCallbacks(
                                      deadline=lambda i: None, liveliness=lambda i: None,
                                      matched=lambda i: None) if events else None)
            pubs.append(n.create_publisher(String, f"/idle{i}", qos,
                                           event_callbacks=PublisherEventCallbacks(
                                               deadline=lambda i: None, matched=lambda i: None)
                                           if events else None))
        time.sleep(1.0)  # discovery
        for p in pubs:
            p.publish(String(data="once"))
        c0 = time.process_time()
        time.sleep(IDLE_S)  # the measured idle window
        cpu = time.process_time() - c0
        ex.remove_node(n)
        n.destroy_node()
        return cpu

    off = statistics.median(idle(False) for _ in range(3))
    on = statistics.median(idle(True) for _ in range(3))
    print(statistics.median(ratios), on / off if off else float("nan"), flush=True)
    ex.shutdown()
    rclpy.shutdown()


# ------------------------------------------------------------------ main

FIGURES: list[Callable[[], dict[str, Any]]] = [lifecycle_transition_ms, approx_sync_sets_per_s,
                                               qos_events]


def main() -> None:
    if sys.argv[1:] == ["--rclpy-nodes"]:
        _rclpy_nodes()
        return
    if sys.argv[1:] == ["--rclpy-lifecycle"]:
        _rclpy_measure()
        return
    if sys.argv[1:] == ["--rclpy-qos-events"]:
        _rclpy_qos_events()
        return
    if sys.argv[1:] == ["--qos-events"]:
        emit("runtime_extras", qos_events())
        return
    metrics: dict[str, Any] = {}
    for figure in FIGURES:
        metrics.update(figure())
    emit("runtime_extras", metrics, targets={"lifecycle_transition_ms": "<= 50",
                                            "approx_sync_sets_per_s": ">= 10000",
                                            "deadline_detect_ratio": "<= 1.2",
                                            "events_idle_ratio": "<= 1.1"})


if __name__ == "__main__":
    main()
