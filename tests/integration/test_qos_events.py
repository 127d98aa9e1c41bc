"""QoS events over real Zenoh, with rclpy's callback API (`zenros.qos_events`): matched,
incompatible QoS, deadline missed (offered and requested), liveliness (automatic: a frozen
publisher process; manual by topic: a publisher that stops asserting), and message lost
past a publisher's lifespan."""

from __future__ import annotations

import signal
import sys
import time
from typing import Any

import pytest
from zenros.context import Context
from zenros.msgs.std_msgs import String
from zenros.node import Node
from zenros.qos import Durability, Liveliness, QoSProfile, Reliability
from zenros.qos_events import (
    PublisherEventCallbacks,
    QoSPolicyKind,
    SubscriptionEventCallbacks,
    incompatible_policy,
)
from zenros.testing import Collector, Proc, wait_for

TOPIC = "/qos_topic"


def test_policy_rules_are_ros2s_request_offered() -> None:
    rel, be = QoSProfile(), QoSProfile(reliability=Reliability.BEST_EFFORT)
    assert incompatible_policy(be, rel) is QoSPolicyKind.RELIABILITY
    assert incompatible_policy(rel, be) is None
    latched = QoSProfile(durability=Durability.TRANSIENT_LOCAL)
    assert incompatible_policy(rel, latched) is QoSPolicyKind.DURABILITY
    assert incompatible_policy(latched, rel) is None
    assert incompatible_policy(rel, QoSProfile(deadline=1.0)) is QoSPolicyKind.DEADLINE
    assert incompatible_policy(QoSProfile(deadline=2.0), QoSProfile(deadline=1.0)) \
        is QoSPolicyKind.DEADLINE
    assert incompatible_policy(QoSProfile(deadline=0.5), QoSProfile(deadline=1.0)) is None
    manual = QoSProfile(liveliness=Liveliness.MANUAL_BY_TOPIC)
    assert incompatible_policy(rel, manual) is QoSPolicyKind.LIVELINESS
    assert incompatible_policy(manual, rel) is None
    assert incompatible_policy(rel, QoSProfile(liveliness_lease_duration=1.0)) \
        is QoSPolicyKind.LIVELINESS_LEASE_DURATION


def test_profile_policies_travel_in_the_token_tag() -> None:
    q = QoSProfile(depth=3, deadline=0.25, lifespan=2, liveliness=Liveliness.MANUAL_BY_TOPIC,
                   liveliness_lease_duration=1.5)
    assert q.tag == "rel+3+d0.25+ls2+m+lease1.5"
    assert QoSProfile.from_tag(q.tag) == q
    assert QoSProfile.from_tag("be+tl+1") == QoSProfile(
        depth=1, reliability=Reliability.BEST_EFFORT, durability=Durability.TRANSIENT_LOCAL)
    assert QoSProfile.from_tag("rel+10+dnope+zz") == QoSProfile()  # lenient
    with pytest.raises(ValueError, match="deadline"):
        QoSProfile(deadline=-1.0)
    with pytest.raises(TypeError, match="lifespan"):
        QoSProfile(lifespan="soon")  # type: ignore[arg-type]


def test_matched_counts_subscriptions_joining_and_leaving(make_node: Any) -> None:
    matched: Collector[Any] = Collector()
    pub = make_node("talker", 0).create_publisher(
        String, TOPIC, event_callbacks=PublisherEventCallbacks(matched=matched))
    listener = make_node("listener", 1)
    sub = listener.create_subscription(String, TOPIC, lambda m: None)
    assert matched.wait(1, 10)
    first = matched.items[0]
    assert (first.total_count, first.current_count, first.current_count_change) == (1, 1, 1)
    listener.destroy(sub)
    assert matched.wait(2, 10)
    assert (matched.items[1].total_count, matched.items[1].current_count,
            matched.items[1].current_count_change) == (1, 0, -1)
    assert pub.events.matched_total == 1


def test_incompatible_qos_is_told_to_both_sides_and_warned_by_default(
        make_node: Any, caplog: pytest.LogCaptureFixture) -> None:
    offered: Collector[Any] = Collector()
    requested: Collector[Any] = Collector()
    make_node("talker", 0).create_publisher(
        String, TOPIC, QoSProfile(reliability=Reliability.BEST_EFFORT),
        event_callbacks=PublisherEventCallbacks(incompatible_qos=offered))
    make_node("listener", 1).create_subscription(
        String, TOPIC, lambda m: None, QoSProfile(deadline=1.0),
        event_callbacks=SubscriptionEventCallbacks(incompatible_qos=requested))
    assert offered.wait(1, 10) and requested.wait(1, 10)
    assert offered.items[0].last_policy_kind is QoSPolicyKind.RELIABILITY
    assert requested.items[0].last_policy_kind is QoSPolicyKind.RELIABILITY
    assert offered.items[0].total_count == 1
    make_node("other", 1).create_subscription(
        String, TOPIC, lambda m: None, QoSProfile(durability=Durability.TRANSIENT_LOCAL),
        event_callbacks=SubscriptionEventCallbacks())  # no callback: rclpy's default warns
    assert wait_for(lambda: "requesting incompatible QoS" not in caplog.text
                    and "offering incompatible QoS (policy RELIABILITY)" in caplog.text, 10)


def test_offered_deadline_counts_each_period_without_a_publish(make_node: Any) -> None:
    missed: Collector[Any] = Collector()
    pub = make_node("talker", 0).create_publisher(
        String, TOPIC, QoSProfile(deadline=0.2),
        event_callbacks=PublisherEventCallbacks(deadline=missed))
    for _ in range(6):  # every 0.05 s: within the deadline
        pub.publish(String(data="x"))
        time.sleep(0.05)  # the publisher's own pacing
    assert missed.items == []
    assert missed.wait(3, 5)  # then silence: one miss per 0.2 s
    assert [m.total_count for m in missed.items[:3]] == [1, 2, 3]
    assert all(m.total_count_change == 1 for m in missed.items)


def test_manual_liveliness_is_lost_unless_asserted_and_seen_by_subscribers(
        make_node: Any) -> None:
    lost: Collector[Any] = Collector()
    changed: Collector[Any] = Collector()
    manual = QoSProfile(liveliness=Liveliness.MANUAL_BY_TOPIC, liveliness_lease_duration=0.3)
    make_node("listener", 1).create_subscription(
        String, TOPIC, lambda m: None, manual,
        event_callbacks=SubscriptionEventCallbacks(liveliness=changed))
    pub = make_node("talker", 0).create_publisher(
        String, TOPIC, manual, event_callbacks=PublisherEventCallbacks(liveliness=lost))
    assert changed.wait(1, 10) and changed.items[0].alive_count == 1
    for _ in range(8):  # asserted every 0.1 s, without publishing: not lost
        pub.assert_liveliness()
        time.sleep(0.1)  # the publisher's own pacing
    assert lost.items == []
    assert lost.wait(1, 5) and lost.items[0].total_count == 1  # then it lapses
    # the subscriber saw no sample in its lease: not alive; the next sample: alive again
    assert wait_for(lambda: changed.items[-1].not_alive_count == 1, 5), changed.items
    assert changed.items[-1].alive_count == 0
    pub.publish(String(data="here"))
    assert wait_for(lambda: changed.items[-1].alive_count == 1, 5), changed.items
    assert changed.items[-1].not_alive_count == 0


def test_a_latched_sample_past_its_lifespan_is_lost_to_a_late_subscriber(
        make_node: Any) -> None:
    latched = QoSProfile(depth=1, durability=Durability.TRANSIENT_LOCAL, lifespan=0.3)
    pub = make_node("talker", 0).create_publisher(String, TOPIC, latched)
    pub.publish(String(data="fresh a moment ago"))
    stamp = time.monotonic()
    assert wait_for(lambda: time.monotonic() - stamp > 0.5, 5)  # the sample ages past 0.3 s
    got: Collector[Any] = Collector()
    lost: Collector[Any] = Collector()
    sub = make_node("late", 1).create_subscription(
        String, TOPIC, got, QoSProfile(depth=1, durability=Durability.TRANSIENT_LOCAL),
        event_callbacks=SubscriptionEventCallbacks(message_lost=lost))
    assert lost.wait(1, 10) and lost.items[0].total_count == 1
    assert got.items == [] and sub.events.lost_total == 1
    pub.publish(String(data="new"))
    assert got.wait(1, 10) and got.items[0].data == "new"


@pytest.mark.system
def test_a_frozen_publisher_process_misses_the_deadline_and_leaves_alive_count(
        router: str, prefix: str, observer: Context, procs: list[Proc]) -> None:
    """ROS 2's deadline and liveliness against a real process: the talker at 20 Hz, frozen
    with SIGSTOP (deadline missed at once, then not alive after its Zenoh lease), thawed
    (alive again, samples within the deadline)."""
    talker = Proc([sys.executable, "-m", "zenros.examples.talker", "-e", router, "--prefix",
                   prefix, "-p", "rate:=20.0"])
    procs.append(talker)
    missed: Collector[Any] = Collector()
    changed: Collector[Any] = Collector()
    got: Collector[Any] = Collector()
    node = Node("watcher", context=observer)
    try:
        node.create_subscription(String, "/chatter", got, QoSProfile(deadline=0.5),
                                 event_callbacks=SubscriptionEventCallbacks(
                                     deadline=missed, liveliness=changed))
        assert got.wait(5, 15), talker.output
        assert wait_for(lambda: changed.items and changed.items[-1].alive_count == 1, 5)
        assert missed.items == []
        talker.signal(signal.SIGSTOP)
        try:
            assert missed.wait(1, 5)
            assert wait_for(lambda: changed.items[-1].alive_count == 0, 10), changed.items
        finally:
            talker.signal(signal.SIGCONT)
        assert wait_for(lambda: changed.items[-1].alive_count == 1, 15), changed.items
        n = len(got.items)
        assert got.wait(n + 10, 10)
    finally:
        node.close()
