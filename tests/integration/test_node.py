"""The Node API: names and remapping, parameters, sim time, timers, rosout, lifecycle."""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Any

import pytest
from zenros import InvalidNameError, InvalidParameterValueError, Node, ParameterNotDeclaredError
from zenros.clock import ManualClock, Time
from zenros.errors import NodeClosedError
from zenros.msgs.rcl_interfaces import Log
from zenros.msgs.rosgraph_msgs import Clock
from zenros.msgs.std_msgs import String
from zenros.params import SetParametersResult
from zenros.testing import Collector, wait_for


class Teleop(Node):
    def setup(self) -> None:
        self.speed = self.declare_parameter("speed", 0.5)
        self.pub = self.create_publisher(String, "cmd")
        self.private = self.create_publisher(String, "~/status")
        self.absolute = self.create_publisher(String, "/global_topic")


def test_names_resolve_with_namespace_private_and_global(make_node: Any) -> None:
    n = make_node("teleop", 0, cls=Teleop, namespace="/robot1")
    assert n.fqn == "/robot1/teleop"
    assert n.pub.topic == "/robot1/cmd"
    assert n.private.topic == "/robot1/teleop/status"
    assert n.absolute.topic == "/global_topic"


def test_default_name_comes_from_the_class(ctx_pair: Any) -> None:
    class BatteryMonitorNode(Node):
        pass

    with BatteryMonitorNode(context=ctx_pair[0]) as n:
        assert n.name == "battery_monitor"


def test_remapping_and_special_rules(make_node: Any) -> None:
    n = make_node("teleop", 0, cls=Teleop,
                  remappings=["cmd:=/base/cmd_vel", "__ns:=/r2", "__node:=driver"])
    assert n.fqn == "/r2/driver"
    assert n.pub.topic == "/base/cmd_vel"
    assert n.private.topic == "/r2/driver/status"


@pytest.mark.parametrize("bad", ["1robot", "my node", "a*b", ""])
def test_invalid_node_names_fail_clearly(ctx_pair: Any, bad: str) -> None:
    with pytest.raises(InvalidNameError, match="invalid node name"):
        Node(bad, context=ctx_pair[0])


def test_invalid_topic_name_fails_and_points_at_it(make_node: Any) -> None:
    n = make_node("a", 0)
    with pytest.raises(InvalidNameError, match=r"(?s)'\$'.*\^"):
        n.create_publisher(String, "cmd$vel")


def test_parameters_from_overrides_file_and_code(make_node: Any, tmp_path: Path) -> None:
    f = tmp_path / "params.yaml"
    f.write_text("/**:\n  ros__parameters:\n    speed: 0.7\n    mode: fast\n"
                 "teleop:\n  ros__parameters:\n    limits:\n      max: 2.0\n")
    n = make_node("teleop", 0, cls=Teleop, params_files=[str(f)],
                  parameter_overrides={"mode": "slow"})
    assert n.speed == 0.7
    assert n.declare_parameter("mode", "normal") == "slow"  # -p wins over the file
    assert n.declare_parameter("limits.max", 1.0) == 2.0
    seen: list[Any] = []
    n.on_parameter_change(lambda p: seen.append((p.name, p.value)), "speed")
    n.set_parameter("speed", 1)  # int accepted for a float parameter
    assert n.get_parameter("speed") == 1.0 and seen == [("speed", 1.0)]
    with pytest.raises(InvalidParameterValueError, match="'speed' is float, got string"):
        n.set_parameter("speed", "fast")
    with pytest.raises(ParameterNotDeclaredError, match="declared: limits.max"):
        n.get_parameter("nope")


def test_wrong_override_type_fails_at_construction(ctx_pair: Any) -> None:
    with pytest.raises(InvalidParameterValueError, match="speed"):
        Teleop("teleop", context=ctx_pair[0], parameter_overrides={"speed": "abc"})


def test_validator_can_refuse_a_change(make_node: Any) -> None:
    n = make_node("teleop", 0, cls=Teleop)
    n.add_on_set_parameters_callback(
        lambda ps: SetParametersResult(all(p.value <= 1.0 for p in ps), "too fast"))
    with pytest.raises(InvalidParameterValueError, match="too fast"):
        n.set_parameter("speed", 3.0)
    assert n.get_parameter("speed") == 0.5


def test_a_timer_made_without_autostart_waits_for_its_reset(make_node: Any) -> None:
    """rclpy's ``autostart=False``: the timer is made canceled and ticks once reset (in
    wall time: a plain callback on the node's real clock, the loop's own timer)."""
    n = make_node("waiting", 0)
    early, ticks = n.create_timer(0.01, lambda: None), threading.Semaphore(0)
    timer = n.create_timer(0.01, ticks.release, autostart=False)
    assert timer.is_canceled()
    assert wait_for(lambda: early.calls >= 5, 5)
    assert timer.calls == 0
    timer.reset()
    assert ticks.acquire(timeout=5) and ticks.acquire(timeout=5) and not timer.is_canceled()


def test_timers_follow_sim_time_from_clock_topic(make_node: Any) -> None:
    sim = make_node("sim", 0)
    clock_pub = sim.create_publisher(Clock, "/clock")
    n = make_node("worker", 1, parameter_overrides={"use_sim_time": True})
    assert isinstance(n.get_clock(), ManualClock)
    assert clock_pub.wait_for_subscribers(1, 5)
    ticks: list[Time] = []
    # The timer's first deadline is one period after its creation, however late the busy
    # executor gets to it: hold the executor while /clock moves half a period on.
    held, release = threading.Event(), threading.Event()
    n.context.executor.call_soon(lambda: (held.set(), release.wait(5)))
    assert held.wait(5)
    n.create_timer(1.0, lambda: ticks.append(n.now()))
    clock_pub.publish(Clock(clock=Time.from_seconds(0.5)))
    assert wait_for(lambda: n.now() == Time.from_seconds(0.5), 5)
    release.set()
    # 10 simulated seconds in 0.1 s steps, as fast as the timer keeps up: 10 ticks, each at
    # a whole simulated second (a clock that leaps several periods ticks once, as in ROS 2).
    for sec in range(1, 11):
        for step in range(1, 11):
            if (sec, step) <= (1, 5):
                continue  # sent above
            clock_pub.publish(Clock(clock=Time.from_seconds(sec - 1 + step / 10)))
        assert wait_for(lambda n=sec: len(ticks) == n, 5), ticks
    # the clock stops at each whole second until the tick: every tick sees exactly it
    assert ticks == [Time(sec=s) for s in range(1, 11)]


def test_rate_follows_sim_time(make_node: Any) -> None:
    n = make_node("worker", 0, parameter_overrides={"use_sim_time": True})
    clock = n.get_clock()
    assert isinstance(clock, ManualClock)
    clock.set(Time(sec=100))
    rate = n.create_rate(2.0)
    woke = threading.Event()

    def sleeper() -> None:
        rate.sleep()
        woke.set()

    threading.Thread(target=sleeper, daemon=True).start()
    assert not woke.wait(0.05)
    clock.set(Time(sec=100, nanosec=500_000_000))
    assert woke.wait(2)


def test_logs_go_to_rosout(make_node: Any) -> None:
    got: Collector[Log] = Collector()
    make_node("console", 1).create_subscription(Log, "/rosout", got, 100)
    n = make_node("talker", 0, namespace="/robot1")
    assert n._rosout.wait_for_subscribers(1, 5)
    n.get_logger().warning("battery low: %d%%", 15)
    assert got.wait(1, timeout=2)
    rec = next(m for m in got.items if "battery" in m.msg)
    assert rec.name == "/robot1/talker" and rec.level == Log.WARN and rec.msg == "battery low: 15%"


def test_close_is_idempotent_and_blocks_new_endpoints(make_node: Any) -> None:
    n = make_node("a", 0)
    n.close()
    n.close()
    with pytest.raises(RuntimeError, match="closed"):
        n.create_publisher(String, "x")


def test_setup_failure_closes_the_node(ctx_pair: Any) -> None:
    class Broken(Node):
        def setup(self) -> None:
            self.create_publisher(String, "ok")
            raise RuntimeError("setup failed")

    with pytest.raises(RuntimeError, match="setup failed"):
        Broken("broken", context=ctx_pair[0])
    g = ctx_pair[1].graph
    assert g.wait_for(lambda: "/broken" not in g.node_names(), 5)


def test_a_node_owns_what_is_added_as_a_waitable(make_node: Any) -> None:
    class Part:
        def __init__(self) -> None:
            self.closed = 0

        def close(self) -> None:
            self.closed += 1

    node = make_node("owner", 0)
    kept, dropped = Part(), Part()
    assert node.add_waitable(kept) is kept
    node.add_waitable(dropped)
    node.remove_waitable(dropped)
    node.close()
    assert kept.closed == 1 and dropped.closed == 0
    late = Part()
    with pytest.raises(NodeClosedError, match="node /owner is closed"):
        node.add_waitable(late)
    assert late.closed == 1
    with pytest.raises(NodeClosedError):
        node.create_publisher(String, "chatter")
