"""A link's time window against a plain model of tf2's rules, through lazy pruning.

Pruned samples stay in a cache's lists (before ``lo``) until the dead prefix is as long as
the live part; nothing may see them meanwhile.
"""

from __future__ import annotations

import random
from itertools import pairwise

import pytest
from zenros.errors import BackwardExtrapolationException
from zenros.msgs.builtin_interfaces import Time
from zenros.tf import Buffer, transform_stamped
from zenros.tf.cache import COMPACT_AT, REJECTED, TimeCache

MS = 1_000_000


@pytest.mark.parametrize("seed", range(4))
def test_window_matches_a_model_of_tf2(seed: int) -> None:
    rng = random.Random(seed)
    window = 200 * MS
    cache = TimeCache(window)
    model: dict[int, str] = {}
    newest = 0
    for k in range(4000):
        stamp = newest + rng.choice([MS, 3 * MS, 10 * MS]) if rng.random() < 0.8 else (
            newest - rng.randrange(0, 300 * MS)
        )  # fmt: skip
        stamp = max(stamp, 1)
        parent = "a" if rng.random() < 0.9 else rng.choice(["b", "c"])
        code = cache.insert(stamp, parent, (float(k), 0.0, 0.0, 0.0, 0.0, 0.0, 1.0))
        if newest and stamp < newest - window:
            assert code == REJECTED
        else:
            assert code != REJECTED
            model[stamp] = parent
            newest = max(newest, stamp)
            model = {s: p for s, p in model.items() if s >= newest - window}
        live = sorted(model)
        lo = cache.lo
        assert cache.stamps[lo:] == live
        assert cache.parents[lo:] == [model[s] for s in live]
        assert len(cache) == len(live) and cache.oldest() == live[0]
        assert len(cache.stamps) <= max(2 * len(live), COMPACT_AT + len(live))
        breaks = sum(model[a] != model[b] for a, b in pairwise(live))
        assert cache._breaks == breaks
        assert cache.parent == (model[live[0]] if breaks == 0 else None)


def test_lookups_never_see_pruned_samples(tf_impl: str) -> None:
    buf = Buffer(cache_time=1.0)
    t0 = 1_000_000_000
    for k in range(1, 2001):  # 20 s at 100 Hz through a 1 s window: compacts many times
        t = t0 + k * 10 * MS
        buf.set_transform(transform_stamped("odom", "base", (k * 1.0, 0, 0, 0, 0, 0, 1),
                                            Time.from_nanoseconds(t)), "x")  # fmt: skip
        if k >= 100 and (k % 37 == 0 or k == 2000):  # once the window is full
            edge = t - 1_000_000_000
            assert buf.lookup_transform("odom", "base", Time.from_nanoseconds(edge)) is not None
            assert buf.can_transform("odom", "base", Time.from_nanoseconds(edge))
            assert not buf.can_transform("odom", "base", Time.from_nanoseconds(edge - 1))
            with pytest.raises(BackwardExtrapolationException, match="earliest data is at time"):
                buf.lookup_transform("odom", "base", Time.from_nanoseconds(edge - 1))
            got = buf.lookup_transform("odom", "base", Time.from_nanoseconds(edge + 5 * MS))
            assert got.transform.translation.x == pytest.approx(k - 100 + 0.5)
    report = buf.all_frames_as_yaml()
    assert "rate: 101.000" in report and "buffer_length: 1.000" in report
