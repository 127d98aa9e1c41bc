"""rosbridge `Outbox`: replies never drop, throttle spaces frames, congestion keeps the newest."""

from __future__ import annotations

from zenros.services.gateway.rosbridge.outbox import (
    BIG,
    BURST_LIMIT,
    GAP,
    HOLD,
    QUEUE_BYTES,
    QUIET,
    READ_RATE,
    Outbox,
    Turnstile,
)


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


def split_in(size: int):  # type: ignore[no-untyped-def]
    def split(frame: bytes, fragment_size: int) -> list[bytes]:
        n = fragment_size or len(frame)
        return [frame[i:i + n] for i in range(0, len(frame), n)]
    return split


def test_large_frames_wait_for_the_bulk_lane_and_small_ones_pass_them() -> None:
    box = Outbox(Clock())
    box.configure("/map", 0, 0)
    box.configure("/odom", 0, 0)
    big = b"m" * (BIG + 1)
    box.publish("/map", big, congested=False)
    box.publish("/odom", b"o1", congested=False)
    out, wake = box.take()
    assert frames(out) == [b"o1"] and wake is None  # the map is not among them
    assert box.take_bulk(split_in(0)) == big
    assert box.take_bulk(split_in(0)) is None


def test_fragments_of_a_large_frame_interleave_with_small_frames() -> None:
    box = Outbox(Clock())
    box.configure("/map", 0, 0, fragment_size=BIG // 2)
    box.configure("/odom", 0, 0)
    big = b"m" * (BIG * 2)
    box.publish("/map", big, congested=False)
    sent: list[bytes] = []
    split = split_in(0)
    for i in range(4):
        box.publish("/odom", b"o%d" % i, congested=False)
        out, _ = box.take()
        sent += frames(out)
        piece = box.take_bulk(split)
        assert piece is not None
        sent.append(piece)
    assert box.take_bulk(split) is None
    assert [len(p) if p.startswith(b"m") else p for p in sent] == [
        b"o0", BIG // 2, b"o1", BIG // 2, b"o2", BIG // 2, b"o3", BIG // 2]


def test_a_topic_keeps_its_order_around_a_large_frame() -> None:
    box = Outbox(Clock())
    box.configure("/map", 0, 0)
    big = b"m" * (BIG + 1)
    box.publish("/map", b"small-before", congested=False)
    box.publish("/map", big, congested=False)
    box.publish("/map", b"small-after", congested=False)
    assert frames(box.take()[0]) == [b"small-before"]
    assert box.take_bulk(split_in(0)) == big
    assert frames(box.take()[0]) == [b"small-after"]


def test_large_frames_are_bounded_in_bytes_and_keep_the_newest() -> None:
    clock = Clock()
    box = Outbox(clock)
    box.configure("/map", 0, 1)
    frames_in = [bytes([65 + i]) * (QUEUE_BYTES // 4) for i in range(8)]
    for f in frames_in:
        box.publish("/map", f, congested=False)
    assert box.dropped > 0
    got = []
    while (piece := box.take_bulk(split_in(0))) is not None:
        got.append(piece)
        clock.t += 1.0  # past the turnstile's read time for the next one
    assert got[-1] == frames_in[-1] and sum(map(len, got)) <= QUEUE_BYTES + len(frames_in[-1])


def odom_and_map(clock: Clock, turnstile: Turnstile | None = None) -> Outbox:
    box = Outbox(clock, turnstile)
    box.configure("/map", 0, 0)
    box.configure("/odom", 0, 0)
    return box


def test_a_whole_large_frame_goes_in_the_gap_after_a_small_frame() -> None:
    """A map that arrives between two odometry frames of a 50 Hz stream waits for the next
    one and goes right after it: the next odometry is then a whole period away."""
    clock = Clock()
    box = odom_and_map(clock)
    big = b"m" * (BIG + 1)
    box.publish("/odom", b"o1", congested=False)
    assert frames(box.take()[0]) == [b"o1"]
    clock.t += 0.007  # 7 ms into the 20 ms period: the map arrives
    box.publish("/map", big, congested=False)
    assert box.take() == ([], None)
    assert box.take_bulk(split_in(0)) is None
    assert box.bulk_wake == clock.t + HOLD  # the writer looks again then at the latest
    clock.t += 0.013
    box.publish("/odom", b"o2", congested=False)
    assert frames(box.take()[0]) == [b"o2"]
    clock.t += GAP / 2
    assert box.take_bulk(split_in(0)) == big


def test_a_held_large_frame_goes_after_HOLD_or_when_small_frames_stopped() -> None:
    clock = Clock()
    box = odom_and_map(clock)
    box.publish("/odom", b"o1", congested=False)
    box.take()
    clock.t += 0.005
    box.publish("/map", b"m" * (BIG + 1), congested=False)
    assert box.take_bulk(split_in(0)) is None
    clock.t += HOLD
    assert box.take_bulk(split_in(0)) is not None  # waited long enough
    clock.t += QUIET
    box.publish("/map", b"n" * (BIG + 1), congested=False)
    assert box.take_bulk(split_in(0)) is not None  # no stream to leave a gap in


def test_fragments_do_not_wait_for_a_gap() -> None:
    clock = Clock()
    box = Outbox(clock)
    box.configure("/map", 0, 0, fragment_size=BIG // 2)
    box.configure("/odom", 0, 0)
    box.publish("/odom", b"o1", congested=False)
    box.take()
    clock.t += 0.005
    box.publish("/map", b"m" * (BIG * 2), congested=False)
    assert box.take_bulk(split_in(0)) is not None


def test_whole_large_frames_start_one_client_at_a_time() -> None:
    """Clients of one server share a `Turnstile`: the second client's map waits until the
    first one's is read (at READ_RATE), then goes in that client's next gap."""
    clock = Clock()
    gate = Turnstile()
    one, two = odom_and_map(clock, gate), odom_and_map(clock, gate)
    big = b"m" * 4_000_000
    for box in (one, two):
        box.publish("/map", big, congested=False)
        box.publish("/odom", b"o1", congested=False)
        assert frames(box.take()[0]) == [b"o1"]
    assert one.take_bulk(split_in(0)) == big
    assert two.take_bulk(split_in(0)) is None  # in its gap, but the first is being read
    clock.t += len(big) / READ_RATE
    two.publish("/odom", b"o2", congested=False)
    assert frames(two.take()[0]) == [b"o2"]
    assert two.take_bulk(split_in(0)) == big
