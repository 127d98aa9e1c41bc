"""The cached-chain fast path agrees with the tf2 walk port on random trees, times and edits.

`WalkOnly` never builds a chain, so every query goes through ``walk``/``latest_common_time``
(a step-for-step port of tf2's ``walkToTopParent``/``getLatestCommonTime``). Both buffers
get the same inserts; every lookup must give the same transform, or the same exception
type and message, and ``can_transform`` must say True exactly when the lookup succeeds.
"""

from __future__ import annotations

import random
from typing import cast

import pytest
from zenros.errors import TransformException
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.tf import Buffer, quaternion_normalize, transform_stamped
from zenros.tf.chain import WALK, Chain, NoChain

NS = 1_000_000_000


class WalkOnly(Buffer):  # type: ignore[misc]
    def _chain(self, target: str, source: str) -> Chain | NoChain:
        self._chains[(target, source)] = WALK
        return WALK


def random_link(rng: random.Random, parent: str, child: str, t: int) -> TransformStamped:
    q = quaternion_normalize(tuple(rng.gauss(0, 1) for _ in range(4)))
    xyz = (rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2))
    return transform_stamped(parent, child, (*xyz, *q), Time.from_nanoseconds(t))


def outcome(buf: Buffer, target: str, source: str, t: int) -> tuple[str, object]:
    try:
        m = buf.lookup_transform(target, source, t)
    except TransformException as e:
        return type(e).__name__, str(e)
    v, q = m.transform.translation, m.transform.rotation
    sign = -1.0 if q.w < 0 else 1.0
    return "ok", (m.header.stamp, (v.x, v.y, v.z, sign * q.x, sign * q.y, sign * q.z, sign * q.w))


def same(a: tuple[str, object], b: tuple[str, object]) -> bool:
    if a[0] != b[0]:
        return False
    if a[0] != "ok":
        return a == b
    sa, va = cast(tuple[Time, tuple[float, ...]], a[1])
    sb, vb = cast(tuple[Time, tuple[float, ...]], b[1])
    return bool(sa == sb and va == pytest.approx(vb, abs=1e-9))


@pytest.mark.parametrize("seed", range(12))
def test_fast_path_matches_tf2_walk(seed: int) -> None:
    rng = random.Random(seed)
    fast, ref = Buffer(cache_time=3.0), WalkOnly(cache_time=3.0)
    frames = [f"f{i}" for i in range(9)]
    parent = {f: (rng.choice(frames[:i]) if i else None) for i, f in enumerate(frames)}
    static = {f: rng.random() < 0.3 for f in frames}
    roots_extra = ["island", "islet"]

    def insert(msg: TransformStamped, is_static: bool) -> None:
        if is_static:
            assert fast.set_transform_static(msg, "t") == ref.set_transform_static(msg, "t")
        else:
            assert fast.set_transform(msg, "t") == ref.set_transform(msg, "t")

    now = NS
    for step in range(60):
        now += rng.randrange(NS // 20, NS // 3)
        for f in frames[1:]:
            if rng.random() < 0.6:
                p = parent[f]
                assert p is not None
                stamp = now - rng.randrange(0, NS // 2)  # some out of order
                insert(random_link(rng, p, f, stamp), static[f])
        insert(random_link(rng, "island", "islet", now), False)
        if rng.random() < 0.08:  # re-parent a frame under an earlier one
            f = rng.choice(frames[2:])
            parent[f] = rng.choice(frames[: frames.index(f)])
        if rng.random() < 0.04:
            fast.clear()
            ref.clear()
        if rng.random() < 0.05:  # a static becomes dynamic or back (cache replaced)
            f = rng.choice(frames[1:])
            static[f] = not static[f]
        for _ in range(15):
            a, b = rng.choice(frames + roots_extra), rng.choice(frames + roots_extra)
            t = rng.choice([0, now, now - rng.randrange(0, 4 * NS), now + NS])
            got, want = outcome(fast, a, b, t), outcome(ref, a, b, t)
            assert same(got, want), (step, a, b, t, got, want)
            assert fast.can_transform(a, b, t) == (want[0] == "ok")
            assert ref.can_transform(a, b, t) == (want[0] == "ok")
