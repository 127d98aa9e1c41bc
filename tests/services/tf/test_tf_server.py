"""The buffer server's logic without a network: feeding, statistics, lookups, waiting."""

from __future__ import annotations

import asyncio
import logging

import pytest
from zenros.clock import ManualClock
from zenros.msgs.builtin_interfaces import Duration, Time
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.msgs.tf2_msgs import TFMessage
from zenros.msgs.tf_srvs import (
    CanTransformRequest,
    LookupTransformRequest,
    TF2Error,
)
from zenros.services.tf.monitor import FrameMonitor
from zenros.services.tf.server import TfServer
from zenros.tf import Buffer, transform_stamped

log = logging.getLogger("test.tf")


def link(parent: str, child: str, x: float, sec: int) -> TransformStamped:
    return transform_stamped(parent, child, (x, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0), Time(sec=sec))


def make(sim: bool = True) -> tuple[TfServer, ManualClock, list[float]]:
    clock = ManualClock(Time(sec=100))
    mono = [0.0]
    if not sim:
        clock.kind = "system"  # type: ignore[misc]
    server = TfServer(Buffer(), FrameMonitor(), clock, log, monotonic=lambda: mono[0],
                      resolve=lambda a: a.replace("session 1", "/chassis"))
    return server, clock, mono


def test_feeding_stores_links_and_counts_only_the_accepted_ones(
    caplog: pytest.LogCaptureFixture,
) -> None:
    server, _, mono = make()
    server.on_message(TFMessage(transforms=[link("odom", "base_link", 1.0, 99),
                                            link("a", "a", 1.0, 99)]), False, "session 1")
    mono[0] = 0.1
    server.on_message(TFMessage(transforms=[link("/odom", "/base_link", 2.0, 100)]), False,
                      "session 1")  # fmt: skip
    server.on_message(TFMessage(transforms=[link("base_link", "laser", 0.1, 0)]), True, "/tf")
    assert "TF_SELF_TRANSFORM" in caplog.text
    res = server.frames()
    assert [f.frame_id for f in res.frames] == ["base_link", "laser"]
    base, laser = res.frames
    assert (base.parent, base.authority, base.count) == ("odom", "/chassis", 2)
    assert base.rate == pytest.approx(10.0) and base.delay == pytest.approx(0.5)
    assert laser.static and laser.authority == "/tf"
    assert res.stamp == Time(sec=100) and "'base_link':" in res.yaml


async def test_lookup_answers_with_the_transform_or_a_tf2_error() -> None:
    server, _, _ = make()
    server.on_message(TFMessage(transforms=[link("odom", "base_link", 1.0, 99),
                                            link("odom", "base_link", 2.0, 100)]), False, "x")
    ok = await server.lookup_transform(LookupTransformRequest(
        target_frame="odom", source_frame="base_link", source_time=Time(sec=99, nanosec=5 * 10**8)))
    assert ok.error.error == TF2Error.NO_ERROR
    assert ok.transform.transform.translation.x == pytest.approx(1.5)
    bad = await server.lookup_transform(LookupTransformRequest(
        target_frame="odom", source_frame="base_link", source_time=Time(sec=101)))
    assert bad.error.error == TF2Error.EXTRAPOLATION_ERROR
    assert "extrapolation into the future" in bad.error.error_string
    travel = await server.lookup_transform(LookupTransformRequest(
        target_frame="base_link", target_time=Time(sec=100), source_frame="base_link",
        source_time=Time(sec=99), fixed_frame="odom", advanced=True))
    assert travel.transform.transform.translation.x == pytest.approx(-1.0)
    can = await server.can_transform(CanTransformRequest(
        target_frame="odom", source_frame="nowhere"))
    assert not can.can_transform and "frame does not exist" in can.error_string


async def test_a_timeout_waits_for_data_then_reports_the_underlying_error() -> None:
    server, _, _ = make()
    req = LookupTransformRequest(target_frame="odom", source_frame="base_link",
                                 source_time=Time(sec=100), timeout=Duration(sec=5))
    pending = asyncio.ensure_future(server.lookup_transform(req))
    await asyncio.sleep(0)  # the request is now waiting
    assert not pending.done()
    server.on_message(TFMessage(transforms=[link("odom", "base_link", 3.0, 100)]), False, "x")
    res = await asyncio.wait_for(pending, 5)
    assert res.error.error == 0 and res.transform.transform.translation.x == 3.0
    short = LookupTransformRequest(target_frame="odom", source_frame="nowhere",
                                   timeout=Duration(nanosec=50_000_000))
    res = await server.lookup_transform(short)
    assert res.error.error == TF2Error.LOOKUP_ERROR  # not TIMEOUT_ERROR, as tf2
    invalid = LookupTransformRequest(target_frame="/odom", source_frame="base_link",
                                     timeout=Duration(sec=30))
    res = await asyncio.wait_for(server.lookup_transform(invalid), 2)  # no wait at all
    assert res.error.error == TF2Error.INVALID_ARGUMENT_ERROR
    can = await server.can_transform(CanTransformRequest(
        target_frame="odom", source_frame="base_link", timeout=Duration(sec=1),
        target_time=Time(sec=100), fixed_frame="odom", advanced=True,
        source_time=Time(sec=100)))
    assert can.can_transform


def test_a_backward_sim_clock_jump_clears_the_dynamic_links() -> None:
    server, clock, _ = make()
    server.on_message(TFMessage(transforms=[link("odom", "base_link", 1.0, 100)]), False, "x")
    server.on_message(TFMessage(transforms=[link("base_link", "laser", 0.1, 0)]), True, "x")
    clock.set(Time(sec=3))
    server.on_message(TFMessage(transforms=[link("odom", "base_link", 2.0, 3)]), False, "x")
    assert server.guard.jumps == 1
    assert server.buffer.can_transform("odom", "laser", Time(sec=3))
    assert not server.buffer.can_transform("odom", "laser", Time(sec=100))


def test_on_wall_time_a_clock_step_back_changes_nothing() -> None:
    server, clock, _ = make(sim=False)
    server.on_message(TFMessage(transforms=[link("odom", "base_link", 1.0, 100)]), False, "x")
    clock.set(Time(sec=3))
    server.on_message(TFMessage(transforms=[link("odom", "base_link", 2.0, 101)]), False, "x")
    assert server.guard.jumps == 0 and server.buffer.can_transform("odom", "base_link",
                                                                    Time(sec=100))
