"""The compiled hot paths (`zenros.tf._speedups`) against their Python reference.

(tests/unit/tf runs every buffer test with and without them; this file checks the
compiled code's own contract: agreement, fallbacks, arguments, GC state, reference counts.)
"""

from __future__ import annotations

import asyncio
import gc
import math
import os
import random
import shutil
import sys
import threading
from collections.abc import Callable
from typing import Any

import pytest
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import Quaternion, Transform, TransformStamped, Vector3
from zenros.msgs.std_msgs import Header
from zenros.tf import Buffer, quaternion_normalize, store, transform_stamped
from zenros.tf.accel import speedups
from zenros.tf.cache import TimeCache
from zenros.tf.chain import Chain

NS = 1_000_000_000


@pytest.fixture
def c_only() -> Any:
    """The compiled module."""
    if speedups is None:
        pytest.skip("zenros.tf._speedups is not built here (or ZENROS_TF_PURE is set)")
    return speedups


def pure_buffer(monkeypatch: pytest.MonkeyPatch, **kw: Any) -> Buffer:
    with monkeypatch.context() as m:
        m.setattr(store, "speedups", None)
        return Buffer(**kw)


def link(parent: str, child: str, xyz: tuple[Any, ...], q: tuple[Any, ...], t: int) -> TransformStamped:
    return TransformStamped(
        header=Header(stamp=Time(sec=t // NS, nanosec=t % NS), frame_id=parent),
        child_frame_id=child,
        transform=Transform(
            translation=Vector3(x=xyz[0], y=xyz[1], z=xyz[2]),
            rotation=Quaternion(x=q[0], y=q[1], z=q[2], w=q[3]),
        ),
    )


def state(buf: Buffer) -> dict[str, object]:
    out: dict[str, object] = {"authority": dict(buf._authority), "frames": list(buf._frames)}
    for child, c in buf._caches.items():
        if isinstance(c, TimeCache):
            out[child] = (list(c.stamps), list(c.parents), list(c.vals), c.parent, c.lo)
        else:
            out[child] = ("static", c.parent, c.value)
    return out


def test_built_wherever_a_compiler_is() -> None:
    if os.environ.get("ZENROS_TF_PURE", "") not in ("", "0"):
        pytest.skip("ZENROS_TF_PURE is set")
    if not (shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")):
        pytest.skip("no C compiler here: the build leaves the module out")
    assert speedups is not None, "pip install should have built zenros.tf._speedups"


def test_inserts_agree_with_python(c_only: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    rng = random.Random(7)
    fast = Buffer(cache_time=0.5)
    ref = pure_buffer(monkeypatch, cache_time=0.5)
    assert "set_transform" in fast.__dict__ and "set_transform" not in ref.__dict__
    frames = ["map", "odom", "base", "arm", "hand"]
    t = NS
    for k in range(3000):
        t += rng.randrange(1, NS // 20)
        child = rng.choice(frames[1:])
        parent = frames[frames.index(child) - 1]
        if rng.random() < 0.03:  # re-parent for a while
            parent = rng.choice(frames[: frames.index(child)])
        q: tuple[Any, ...] = quaternion_normalize(tuple(rng.gauss(0, 1) for _ in range(4)))
        xyz: tuple[Any, ...] = (rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1))
        stamp = t
        odd = rng.random()
        if odd < 0.02:
            q = (q[0] * 1.004, q[1] * 1.004, q[2] * 1.004, q[3] * 1.004)  # normalised on insert
        elif odd < 0.03:
            xyz = (math.nan, 0.0, 0.0)
        elif odd < 0.04:
            q = (0.0, 0.0, 0.0, 2.0)  # refused
        elif odd < 0.05:
            xyz = (1, 2, 3)  # ints: the Python path takes them
        elif odd < 0.06:
            parent = "/" + parent
        elif odd < 0.08:
            stamp = t - rng.randrange(0, NS)  # out of order, maybe too old
        elif odd < 0.09:
            stamp = t - rng.randrange(0, NS) // 1000 * 1000
        msg = link(parent, child, xyz, q, stamp)
        auth = f"node{k % 3}"
        assert fast.set_transform(msg, auth) == ref.set_transform(msg, auth), k
        if k % 50 == 0:
            assert state(fast) == state(ref), k
        if rng.random() < 0.005:
            fast.clear()
            ref.clear()
    assert state(fast) == state(ref)


def test_chain_evaluation_agrees_with_python(c_only: Any) -> None:
    rng = random.Random(3)
    buf = Buffer(cache_time=5.0)
    frames = [f"f{i}" for i in range(8)]
    for i in range(1, 8):
        parent = frames[rng.randrange(0, i)]
        static = rng.random() < 0.3
        stamp = NS + i
        for _ in range(1 if static else 40):
            q = quaternion_normalize(tuple(rng.gauss(0, 1) for _ in range(4)))
            xyz = (rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1))
            msg = transform_stamped(parent, frames[i], (*xyz, *q), Time.from_nanoseconds(stamp))
            # steady, jittered, or bursts and gaps (the C lookup guesses from even spacing)
            stamp += rng.choice([100_000_000, rng.randrange(1, 200_000_000), 1, 900_000_000])
            if static:
                buf.set_transform_static(msg, "t")
            else:
                buf.set_transform(msg, "t")
    checked = 0
    for a in frames:
        for b in frames:
            buf.can_transform(a, b, 0)  # builds the pair's chain
            ch = buf._chains.get((a, b))
            if not isinstance(ch, Chain):
                continue
            times = [0, NS, NS + 7, 2 * NS + 123_456_789, 9 * NS, 40 * NS]
            for t in times + [rng.randrange(NS, 30 * NS) for _ in range(40)]:
                want, got = ch.evaluate_py(t), ch.evaluate(t)
                assert (want is None) == (got is None), (a, b, t)
                if want is not None and got is not None:
                    assert got == pytest.approx(want, abs=1e-12), (a, b, t)
                    checked += 1
    assert checked > 300


def spy() -> tuple[list[tuple[Any, ...]], Callable[..., bool]]:
    calls: list[tuple[Any, ...]] = []

    def fallback(*args: Any, **kw: Any) -> bool:
        calls.append((*args, kw))
        return False

    return calls, fallback


def primed(c_only: Any) -> tuple[Any, dict[str, Any], dict[str, str], threading.Lock, list[Any]]:
    """An Inserter over one link odom → base with a sample at 1 s, and its fallback's calls."""
    cache = TimeCache(10 * NS)
    cache.insert(NS, "odom", (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0))
    caches: dict[str, Any] = {"base": cache}
    authority: dict[str, str] = {}
    lock = threading.Lock()
    calls, fallback = spy()
    return c_only.Inserter(caches, authority, lock, 10 * NS, fallback), caches, authority, lock, calls


def sample(t: int = 2 * NS, parent: str = "odom", child: str = "base", **kw: Any) -> TransformStamped:
    xyz = kw.get("xyz", (1.0, 2.0, 3.0))
    q = kw.get("q", (0.0, 0.0, 0.0, 1.0))
    return link(parent, child, xyz, q, t)


def test_inserter_stores_the_hot_case_itself(c_only: Any) -> None:
    ins, caches, authority, _, calls = primed(c_only)
    assert ins(sample(), "me") is True
    assert ins(sample(3 * NS), authority="you", strict=True) is True
    assert calls == []
    assert caches["base"].stamps == [NS, 2 * NS, 3 * NS]
    assert caches["base"].vals[-1] == (1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 1.0)
    assert authority == {"base": "you"}
    assert ins(sample(4 * NS)) is True and authority["base"] == "default_authority"
    # ints are numbers too (as in the Python path, the objects themselves are kept)
    assert ins(sample(5 * NS, xyz=(1, 2, 3), q=(0, 0, 0, 1))) is True
    assert caches["base"].vals[-1] == (1, 2, 3, 0, 0, 0, 1)
    assert ins(sample(6 * NS, q=(0, 0, 0, 1.004))) is True  # normalised
    assert caches["base"].vals[-1] == (1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 1.0)
    assert calls == []


@pytest.mark.parametrize(
    "msg",
    [
        sample(parent="/odom"),
        sample(child="/base"),
        sample(parent="map"),  # another parent: re-parenting
        sample(child="new"),  # a new link
        sample(t=NS),  # not newer
        sample(t=NS // 2),  # older
        sample(xyz=(1 << 2000, 2, 3)),  # an int no float can hold
        sample(xyz=("1", 2.0, 3.0)),
        sample(xyz=(math.inf, 0.0, 0.0)),
        sample(q=(0.0, 0.0, 0.0, 1.5)),
        sample(q=(math.nan, 0.0, 0.0, 1.0)),
        sample(parent=""),
        sample(parent="base"),  # self link
    ],
)
def test_inserter_hands_everything_else_to_python(c_only: Any, msg: TransformStamped) -> None:
    ins, caches, _, _, calls = primed(c_only)
    before = list(caches["base"].stamps)
    assert ins(msg, "me", strict=True) is False
    assert calls == [(msg, "me", {"strict": True})]
    assert caches["base"].stamps == before


def test_inserter_defers_to_python_while_the_lock_is_held_or_someone_waits(c_only: Any) -> None:
    ins, caches, _, lock, calls = primed(c_only)
    with lock:
        assert ins(sample()) is False
    ins.watchers = 1
    assert ins(sample()) is False
    assert len(calls) == 2 and caches["base"].stamps == [NS]
    ins.watchers = 0
    assert ins(sample()) is True


def test_inserter_arguments(c_only: Any) -> None:
    ins, _, _, _, calls = primed(c_only)
    with pytest.raises(TypeError, match="set_transform"):
        ins()
    with pytest.raises(TypeError, match="set_transform"):
        ins(sample(), "a", "b")
    with pytest.raises(TypeError, match="set_transform"):
        ins(sample(), colour="red")
    assert ins("not a message") is False  # Python decides what to say
    assert calls[-1][0] == "not a message"


async def test_buffer_falls_back_for_waiters_and_wakes_them(c_only: Any) -> None:
    buf = Buffer()
    buf.set_transform(transform_stamped("odom", "base", (0, 0, 0, 0, 0, 0, 1), Time(sec=1)))
    fut = buf.wait_for_transform_async("odom", "base", Time(sec=2))
    assert not fut.done() and buf._inserter.watchers == 1
    buf.set_transform(transform_stamped("odom", "base", (1, 0, 0, 0, 0, 0, 1), Time(sec=2)))
    assert await asyncio.wait_for(fut, 10) is True
    assert buf._inserter.watchers == 0


@pytest.mark.parametrize("enabled", [True, False])
def test_gc_state_is_restored(c_only: Any, enabled: bool) -> None:
    ins = primed(c_only)[0]
    was = gc.isenabled()
    try:
        gc.enable() if enabled else gc.disable()
        assert ins(sample()) is True
        assert gc.isenabled() is enabled
    finally:
        gc.enable() if was else gc.disable()


def test_no_reference_leaks(c_only: Any) -> None:
    ins, caches, _, _, _ = primed(c_only)
    x = float("1.2345")  # a fresh object, shared by every message below
    base = sys.getrefcount(x)
    msgs = [sample(t=2 * NS + k * NS // 100, xyz=(x, 0.0, 0.0)) for k in range(5000)]
    held = sys.getrefcount(x) - base
    for m in msgs:
        assert ins(m) is True
    kept = len(caches["base"].vals)  # 10 s window at 100 Hz: older samples were pruned
    assert 0 < kept < 5000
    assert sys.getrefcount(x) - base == held + kept
    del msgs, m
    caches["base"].clear()
    assert sys.getrefcount(x) == base


def test_evaluate_refuses_malformed_chains(c_only: Any) -> None:
    ok = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)
    with pytest.raises(TypeError):
        c_only.evaluate(None, "steps", None, [], 5)
    with pytest.raises(TypeError):
        c_only.evaluate(None, [("a", "b")], None, [], 5)
    with pytest.raises(TypeError):
        c_only.evaluate((1.0, 2.0), [], None, [], 5)
    cache = TimeCache(10 * NS)
    with pytest.raises(TypeError):
        c_only.evaluate(None, [([1, 3], [("short",)], cache, None)], None, [], 2)
    with pytest.raises(AttributeError):
        c_only.evaluate(None, [([1, 3], [None, None], "no cache", None)], None, [], 2)
    cache.lo = 5
    with pytest.raises(ValueError):
        c_only.evaluate(None, [([1, 3], [None, None], cache, None)], None, [], 2)
    cache.lo = 0
    with pytest.raises(TypeError):
        c_only.evaluate(ok, [], None, [], "t")
    assert c_only.evaluate(ok, [], None, [], 5) == ok
    assert c_only.evaluate(None, [], None, [], 5) == ok
    assert c_only.evaluate(None, [([1, 3], [None, None], cache, None)], None, [], 9) is None


def test_latest_common_stamp(c_only: Any) -> None:
    assert c_only.latest([]) == 0
    assert c_only.latest([[1, 5], [2, 3], [9]]) == 3
    with pytest.raises(ValueError):
        c_only.latest([[1], []])
    with pytest.raises(TypeError):
        c_only.latest(([1],))
    with pytest.raises(TypeError):
        c_only.latest([[1, "x"]])


def test_a_subclass_override_of_set_transform_runs(c_only: Any) -> None:
    seen: list[str] = []

    class Logged(Buffer):  # type: ignore[misc]
        def set_transform(self, transform: TransformStamped, authority: str = "x",
                          *, strict: bool = False) -> bool:
            seen.append(transform.child_frame_id)
            return bool(super().set_transform(transform, authority, strict=strict))

    buf = Logged()
    assert "set_transform" not in buf.__dict__
    for k in range(3):
        assert buf.set_transform(sample(t=(k + 1) * NS))
    assert seen == ["base"] * 3
    assert buf.can_transform("odom", "base", Time(sec=2))
