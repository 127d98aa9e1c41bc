"""TF buffer benchmark: zenros.tf.Buffer against pytransform3d on the same 10-link chain.

Prints one JSON line. Chain root → f1 → … → f10 with random rigid links. pytransform3d's
``TransformManager(check=False)`` (its fast mode; the default ``check=True`` is also
timed) holds one matrix per link; its ``TemporalTransformManager`` and our Buffer hold a
time series per link (samples 10 ms apart over 1 s). Our lookups ask for a different
interpolated time on every call (times between samples, never repeated back to back),
so nothing is answered from a cache of earlier results.

Ratios are ours ÷ theirs for times (lower is better) and ours ÷ theirs for insert rates
(higher is better). Each figure is the minimum over repeats after a warm-up. Inserts go
into a 0.5 s window (each prunes a sample); ``insert_us_zenros_10s_window`` is the same
with tf2's default 10 s window full (1001 samples per link).

Ours is the buffer as installed: with the compiled hot paths (``zenros.tf._speedups``,
built by ``pip install`` where a C compiler is) if they are there. The same lookup and
insert in pure Python (``ZENROS_TF_PURE=1``) are timed too and reported as ``*_pure``.

Run: ``python bench/tf.py`` (needs the ``bench`` extra: ``pip install pytransform3d``).
"""

from __future__ import annotations

import json
import os
import platform
import sys
import time
from collections.abc import Callable

import numpy as np
from _harness import missing_extra

try:
    import pytransform3d
    from pytransform3d import transformations as pt
    from pytransform3d.transform_manager import (
        NumpyTimeseriesTransform,
        TemporalTransformManager,
        TransformManager,
    )
except ModuleNotFoundError as err:
    raise SystemExit(missing_extra(err, "bench")) from None
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.tf import Buffer, chain, quaternion_normalize, store, transform_stamped
from zenros.tf.accel import speedups

LINKS = 10
SAMPLES = 101  # per link, 10 ms apart: t = 1.00 … 2.00 s
QUERIES = 997  # distinct query times, cycled
FRAMES = ["root"] + [f"f{i}" for i in range(1, LINKS + 1)]
NS = 1_000_000_000


def best(
    *fns: Callable[[], object], number: int, repeat: int = 7, warmup: int = 0
) -> list[float]:
    """Seconds per call of each function: the minimum over ``repeat`` runs of ``number``
    calls, after a warm-up. Runs of the functions alternate, so that load changes on a
    shared machine hit all of them alike."""
    for fn in fns:
        for _ in range(warmup or max(number // 10, 1)):
            fn()
    out = [float("inf")] * len(fns)
    for _ in range(repeat):
        for j, fn in enumerate(fns):
            t0 = time.perf_counter()
            for _ in range(number):
                fn()
            out[j] = min(out[j], (time.perf_counter() - t0) / number)
    return out


def cycler(fn: Callable[[int], object], n: int) -> Callable[[], object]:
    """A no-argument call that passes 0, 1, … n-1, 0, … to ``fn``."""
    state = [0]

    def call() -> object:
        i = state[0]
        state[0] = i + 1 if i + 1 < n else 0
        return fn(i)

    return call


def chain_data(rng: np.random.Generator) -> np.ndarray:
    """Random links: shape (LINKS, SAMPLES, 7) as x y z qw qx qy qz (pytransform3d order)."""
    pqs = np.empty((LINKS, SAMPLES, 7))
    for i in range(LINKS):
        for k in range(SAMPLES):
            pqs[i, k, :3] = rng.uniform(-1.0, 1.0, 3)
            q = quaternion_normalize(tuple(rng.normal(size=4).tolist()))
            pqs[i, k, 3:] = (q[3], q[0], q[1], q[2])
    return pqs


def fill(buf: Buffer, pqs: np.ndarray, stamps: list[int], static: set[int]) -> None:
    """Links root → f1 → … → f10 (those in ``static`` as static links)."""
    for i in range(LINKS):
        for k in range(1 if i in static else SAMPLES):
            x, y, z, qw, qx, qy, qz = pqs[i, k].tolist()
            msg = transform_stamped(FRAMES[i], FRAMES[i + 1], (x, y, z, qx, qy, qz, qw),
                                    Time.from_nanoseconds(stamps[k]))  # fmt: skip
            if i in static:
                buf.set_transform_static(msg, "bench")
            else:
                buf.set_transform(msg, "bench")


class Pure:
    """Within the block, new buffers and every chain evaluation use pure Python."""

    def __enter__(self) -> None:
        self.saved = store.speedups, chain._c_evaluate, chain._c_latest
        store.speedups, chain._c_evaluate, chain._c_latest = None, None, None

    def __exit__(self, *exc: object) -> None:
        store.speedups, chain._c_evaluate, chain._c_latest = self.saved


def insert_messages(stamps: list[int]) -> list[TransformStamped]:
    """60 000 links cycling over the chain, stamps only growing, 10 ms apart per link."""
    msgs = []
    for k in range(60_000):
        i = k % LINKS
        msgs.append(transform_stamped(
            FRAMES[i], FRAMES[i + 1], (0.1, 0.2, 0.3, 0.0, 0.0, 0.6, 0.8),
            Time.from_nanoseconds(stamps[-1] + 10_000_000 * (k // LINKS + 1)),
        ))  # fmt: skip
    return msgs


def inserter(
    msgs: list[TransformStamped], cache_time: float = 0.5, prefill: int = 2 * LINKS
) -> Callable[[], object]:
    """Inserts the next message into a fresh buffer; ``prefill`` messages go in before
    timing (by default the links exist; with a full window each insert prunes one sample).
    Callers keep prefill + warm-up + timed calls within the 60 000 messages."""
    fresh = Buffer(cache_time=cache_time)
    for m in msgs[:prefill]:
        fresh.set_transform(m, "bench")
    seq = iter(msgs[prefill:])
    return lambda: fresh.set_transform(next(seq), "bench")


def pure_figures(
    pqs: np.ndarray, stamps: list[int], times: list[Time], msgs: list[TransformStamped]
) -> tuple[float, float]:
    """(interpolated lookup, insert) seconds with the compiled paths switched off."""
    with Pure():
        buf = Buffer()
        fill(buf, pqs, stamps, static=set())
        insert = inserter(msgs)
        lookup, ins = best(
            cycler(lambda i: buf.lookup_transform("root", "f10", times[i]), QUERIES),
            insert, number=500, repeat=30, warmup=QUERIES,
        )  # fmt: skip
    return lookup, ins


def main() -> None:
    pqs = chain_data(np.random.default_rng(42))
    stamps = [NS + k * 10_000_000 for k in range(SAMPLES)]
    ours = Buffer()
    fill(ours, pqs, stamps, static=set())
    mixed = Buffer()  # a robot-like chain: map→odom→base dynamic, 8 static links below
    fill(mixed, pqs, stamps, static=set(range(2, LINKS)))
    # query times strictly between samples, spread over the whole second
    times = [Time.from_nanoseconds(NS + 1 + (q * 1_000_003_001) % (NS - 2)) for q in range(QUERIES)]

    plain = TransformManager(check=False)
    checked = TransformManager()
    temporal = TemporalTransformManager(check=False)
    for i in range(LINKS):
        a2b = pt.transform_from_pq(pqs[i, 0])
        plain.add_transform(FRAMES[i + 1], FRAMES[i], a2b)
        checked.add_transform(FRAMES[i + 1], FRAMES[i], a2b)
        temporal.add_transform(
            FRAMES[i + 1], FRAMES[i], NumpyTimeseriesTransform(np.array(stamps) / NS, pqs[i])
        )
    fsec = [t.to_sec() for t in times]

    # sanity check before timing: both agree at a sample time (between samples they
    # differ on purpose: tf2 interpolates linearly + slerp, pytransform3d by ScLERP)
    at = Time.from_nanoseconds(stamps[37])
    tr = ours.lookup_transform("root", "f10", at).transform.translation
    theirs = temporal.get_transform_at_time("f10", "root", at.to_sec())
    assert np.allclose(theirs[:3, 3], [tr.x, tr.y, tr.z], atol=1e-6), "libraries disagree"

    # every call goes through the same cycler, theirs included, so harness costs match
    lookup_z, lookup_p, can_z, latest_z, mixed_z = best(
        cycler(lambda i: ours.lookup_transform("root", "f10", times[i]), QUERIES),
        cycler(lambda i: plain.get_transform("f10", "root"), QUERIES),
        cycler(lambda i: ours.can_transform("root", "f10", times[i]), QUERIES),
        cycler(lambda i: ours.lookup_transform("root", "f10", 0), QUERIES),
        cycler(lambda i: mixed.lookup_transform("root", "f10", times[i]), QUERIES),
        number=500, repeat=100, warmup=QUERIES,  # warm: every query time seen once
        # many short runs: on a shared machine, some run undisturbed
    )
    (lookup_checked,) = best(
        cycler(lambda i: checked.get_transform("f10", "root"), QUERIES), number=30, repeat=3
    )
    (temporal_p,) = best(
        cycler(lambda i: temporal.get_transform_at_time("f10", "root", fsec[i]), QUERIES),
        number=30, repeat=3,
    )

    # inserts: ours appends a new stamp from a TransformStamped (validated; the 0.5 s
    # window prunes one sample per insert); theirs overwrites the link's ready 4x4 matrix
    # (no history, no checks), or first builds it from the same message (from_msg)
    msgs = insert_messages(stamps)
    a2b = pt.transform_from_pq(pqs[0, 0])

    def from_msg(i: int) -> object:
        m = msgs[i]
        v, q = m.transform.translation, m.transform.rotation
        a2b = pt.transform_from_pq(np.array([v.x, v.y, v.z, q.w, q.x, q.y, q.z]))
        return plain.add_transform(m.child_frame_id, m.header.frame_id, a2b)

    insert_z, insert_p = best(
        inserter(msgs),
        cycler(lambda i: plain.add_transform(FRAMES[i + 1], FRAMES[i], a2b), LINKS),
        number=500, repeat=100, warmup=1_000,
    )
    (insert_msg_p,) = best(cycler(from_msg, LINKS), number=500, repeat=5)
    # tf2's default 10 s window, full (1001 samples per link at 100 Hz): 10 010 + 1 000
    # warm-up + 500 x 40 calls
    (insert_10s,) = best(inserter(msgs, 10.0, 10_010), number=500, repeat=40, warmup=1_000)
    lookup_pure, insert_pure = pure_figures(pqs, stamps, times, msgs)

    us = 1e6
    print(json.dumps({
        "bench": "tf",
        "lookup_ratio": round(lookup_z / lookup_p, 3),
        "can_transform_ratio": round(can_z / lookup_p, 3),
        "temporal_lookup_ratio": round(lookup_z / temporal_p, 5),
        "insert_ratio": round(insert_p / insert_z, 3),
        "insert_from_msg_ratio": round(insert_msg_p / insert_z, 3),
        "lookup_mixed_ratio": round(mixed_z / lookup_p, 3),
        "lookup_us_zenros": round(lookup_z * us, 2),
        "lookup_us_pytransform3d": round(lookup_p * us, 2),
        "lookup_checked_us_pytransform3d": round(lookup_checked * us, 1),
        "lookup_latest_us_zenros": round(latest_z * us, 2),
        "lookup_mixed_us_zenros": round(mixed_z * us, 2),
        "can_transform_us_zenros": round(can_z * us, 2),
        "temporal_lookup_us_pytransform3d": round(temporal_p * us, 1),
        "insert_us_zenros": round(insert_z * us, 3),
        "insert_us_pytransform3d": round(insert_p * us, 3),
        "insert_us_zenros_10s_window": round(insert_10s * us, 3),
        "insert_from_msg_us_pytransform3d": round(insert_msg_p * us, 2),
        "speedups": speedups is not None,
        "lookup_ratio_pure": round(lookup_pure / lookup_p, 3),
        "insert_ratio_pure": round(insert_p / insert_pure, 3),
        "lookup_us_zenros_pure": round(lookup_pure * us, 2),
        "insert_us_zenros_pure": round(insert_pure * us, 3),
        "links": LINKS,
        "samples_per_link": SAMPLES,
        "pytransform3d": pytransform3d.__version__,
        "python": sys.version.split()[0],
        "numpy": np.__version__,
        "machine": platform.machine(),
        "cpus": os.cpu_count(),
    }))


if __name__ == "__main__":
    main()
