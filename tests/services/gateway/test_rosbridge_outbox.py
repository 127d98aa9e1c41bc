"""rosbridge `Outbox`: replies never drop, throttle spaces frames, congestion keeps the newest."""

from __future__ import annotations

from zenros.services.gateway.rosbridge.outbox import BURST_LIMIT, Outbox


class Clock:
    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


def frames(out: list[tuple[bytes, int]]) -> list[bytes]:
    return [f for f, _ in out]


def test_replies_and_unthrottled_topics_all_go_out() -> None:
    box = Outbox(Clock())
    box.configure("/a", 0, 0)
    box.reply(b"r1")
    for i in range(5):
        assert box.publish("/a", b"%d" % i, congested=False)
    out, wake = box.take()
    assert frames(out) == [b"r1", b"0", b"1", b"2", b"3", b"4"] and wake is None
    assert box.take() == ([], None)


def test_unsubscribed_topic_is_refused() -> None:
    box = Outbox(Clock())
    assert not box.publish("/b", b"x", congested=False)


def test_congestion_keeps_the_newest_queue_length_frames() -> None:
    box = Outbox(Clock())
    box.configure("/a", 0, 3)
    box.configure("/b", 0, 0)
    for i in range(10):
        box.publish("/a", b"a%d" % i, congested=True)
        box.publish("/b", b"b%d" % i, congested=True)
    out, _ = box.take()
    assert frames(out) == [b"a7", b"a8", b"a9", b"b9"]
    assert box.dropped == 7 + 9


def test_a_burst_is_bounded_even_when_not_congested() -> None:
    box = Outbox(Clock())
    box.configure("/a", 0, 0)
    for i in range(BURST_LIMIT + 5):
        box.publish("/a", b"%d" % i, congested=False)
    out, _ = box.take()
    assert len(out) == BURST_LIMIT and out[-1][0] == b"%d" % (BURST_LIMIT + 4)


def test_throttle_sends_one_frame_per_interval() -> None:
    clock = Clock()
    box = Outbox(clock)
    box.configure("/a", 100, 2, fragment_size=50)
    box.publish("/a", b"0", congested=False)
    out, wake = box.take()
    assert out == [(b"0", 50)] and wake is None
    for i in range(1, 5):
        box.publish("/a", b"%d" % i, congested=False)
    out, wake = box.take()
    assert out == [] and wake == 100.1
    clock.t = 100.1
    out, wake = box.take()
    assert frames(out) == [b"3"] and wake is not None and abs(wake - 100.2) < 1e-9
    clock.t = 100.25
    out, wake = box.take()
    assert frames(out) == [b"4"] and wake is None


def test_reconfigure_and_remove() -> None:
    box = Outbox(Clock())
    box.configure("/a", 0, 0)
    box.publish("/a", b"x", congested=False)
    box.configure("/a", 0, 5)
    assert frames(box.take()[0]) == [b"x"]
    box.remove("/a")
    assert not box.publish("/a", b"y", congested=False)
