"""Tasks benchmark: create + start + complete of one-sleep tasks per second, every state
stored in SQLite before it is told, and the state change -> ``tasks/status`` latency.

The tasks service runs as its own process (``python -m zenros.services.tasks``, as a user
launches it); this process calls it over Zenoh as the gateway does: ``tasks/create``, then
``tasks/start``, then waits for the task's COMPLETE on ``tasks/status``. Beside it, in the same
run, raw zenoh-python: a get/queryable round trip and a put -> subscriber one-way latency,
so the figures read as multiples of the transport underneath. Prints one JSON line.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import threading
import time

import zenoh
from _harness import emit, free_port, percentile, raw_config, unique_prefix
from zenros.context import Context
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.tasks import (
    CreateTask,
    TaskCommand,
    TaskCommandRequest,
    TaskStatus,
    task_request,
)
from zenros.node import Node
from zenros.testing import loopback_options

EXTRA = os.environ.get("BENCH_TASKS_ARGS", "").split()
TASK = task_request("create", body={"name": "b", "sub_tasks": [{"type": "sleep_action",
                                                                "wait_time": 0}]})


def bench_tasks(n: int) -> tuple[float, list[float]]:
    port, prefix = free_port(), unique_prefix()
    home = tempfile.mkdtemp(prefix="zenros-bench-tasks-")
    proc = subprocess.Popen(
        [sys.executable, "-m", "zenros.services.tasks", "-l", f"tcp/127.0.0.1:{port}",
         "--prefix", prefix, "--no-multicast-scouting", *EXTRA],
        env={**os.environ, "ZENROS_HOME": home}, stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL)
    ctx = Context(loopback_options(connect=[port]), prefix=prefix)
    node = Node("bench", context=ctx)
    done: dict[str, threading.Event] = {}
    lat: list[float] = []

    def on_status(msg: TaskStatus) -> None:
        lat.append(time.time() - msg.stamp.to_sec())
        if msg.state == "COMPLETE" and msg.id in done:
            done[msg.id].set()

    try:
        node.create_subscription(TaskStatus, "/tasks/status", on_status, 10_000)
        create = node.create_client(CreateTask, "/tasks/create")
        start = node.create_client(TaskCommand, "/tasks/start")
        for c in (create, start):
            assert c.wait_for_service(30), "tasks service did not start"
        for _ in range(20):  # warm up
            one(create, start, done)
        lat.clear()
        t0 = time.perf_counter()
        for _ in range(n):
            one(create, start, done)
        rate = n / (time.perf_counter() - t0)
        return rate, list(lat)
    finally:
        node.close()
        ctx.close()
        proc.terminate()
        proc.wait(10)


def one(create: object, start: object, done: dict[str, threading.Event]) -> None:
    reply = create.call(TASK, timeout=10)  # type: ignore[attr-defined]
    assert reply.code == ResultCode.OK, reply.message
    task_id = reply.task.id
    ev = done[task_id] = threading.Event()
    reply = start.call(TaskCommandRequest(id=task_id), timeout=10)  # type: ignore[attr-defined]
    assert reply.code == ResultCode.OK, reply.message
    assert ev.wait(10), f"task {task_id} did not complete"
    del done[task_id]


def bench_raw(n: int) -> tuple[float, float]:
    """Raw get/queryable round trip and put -> subscriber latency (s, medians)."""
    port, key = free_port(), unique_prefix()
    a = zenoh.open(raw_config(listen=port))
    b = zenoh.open(raw_config(connect=port))
    try:
        q = a.declare_queryable(f"{key}/q", lambda query: query.reply(query.key_expr, b"{}"))
        got = threading.Event()
        one_way: list[float] = []

        def on_sample(s: zenoh.Sample) -> None:
            one_way.append(time.time() - float(s.payload.to_string()))
            got.set()

        sub = a.declare_subscriber(f"{key}/t", on_sample)
        pub = b.declare_publisher(f"{key}/t")
        time.sleep(0.5)  # let the two sessions match (raw zenoh has no graph to wait on)
        rtts = []
        for _ in range(n):
            t0 = time.perf_counter()
            for _r in b.get(f"{key}/q"):
                pass
            rtts.append(time.perf_counter() - t0)
            got.clear()
            pub.put(repr(time.time()))
            got.wait(1)
        q.undeclare()
        sub.undeclare()
        pub.undeclare()
        return percentile(rtts, 50), percentile(one_way, 50)
    finally:
        b.close()
        a.close()


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 1000
    raw_rtt, raw_one_way = bench_raw(500)
    rate, lat = bench_tasks(n)
    emit("tasks", {
        "tasks_per_s": round(rate, 1),
        "status_latency_p50_ms": round(percentile(lat, 50) * 1e3, 3),
        "status_latency_p99_ms": round(percentile(lat, 99) * 1e3, 3),
        "raw_get_rtt_ms": round(raw_rtt * 1e3, 3),
        "raw_put_latency_p50_ms": round(raw_one_way * 1e3, 3),
        "task_in_raw_rtts": round((1 / rate) / raw_rtt, 2),
        "status_latency_ratio": round(percentile(lat, 50) / raw_one_way, 2),
    }, tasks=n, targets={"tasks_per_s": ">= 200", "status_latency_p50_ms": "<= 2"})


if __name__ == "__main__":
    main()
