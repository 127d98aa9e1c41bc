"""The demo's sequence counter: losses, late (recovered) samples, duplicates, gaps, restarts."""

from __future__ import annotations

from zenros.examples.heartbeat import SeqTracker


class FakeTime:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_in_order_stream_has_no_loss() -> None:
    t = SeqTracker(FakeTime())
    for i in range(1, 101):
        t.add(i)
    assert (t.received, t.lost, t.late, t.duplicates) == (100, 0, 0, 0)


def test_holes_count_as_lost_until_filled_then_late() -> None:
    t = SeqTracker(FakeTime())
    for i in (1, 2, 6, 7):
        t.add(i)
    assert t.lost == 3
    t.add(4)
    assert (t.lost, t.late) == (2, 1)
    t.add(4)
    assert t.duplicates == 1


def test_longest_arrival_gap() -> None:
    clock = FakeTime()
    t = SeqTracker(clock)
    for i, at in ((1, 0.0), (2, 0.02), (3, 5.2), (4, 5.22)):
        clock.now = at
        t.add(i)
    assert abs(t.max_gap - 5.18) < 1e-9 and t.max_gap_end == 5.2


def test_restarted_publisher_keeps_old_holes_as_lost() -> None:
    t = SeqTracker(FakeTime())
    for i in (1, 2, 5):
        t.add(i)
    t.add(1)  # the publisher restarted
    t.add(2)
    assert t.restarts == 1 and t.lost == 2
