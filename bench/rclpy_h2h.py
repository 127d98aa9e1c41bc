"""Head-to-head against rclpy: the same small programs written with zenros and with rclpy.

Each figure runs each side in its own processes (publisher and subscriber apart, as a robot
runs them), one side after the other in each repeat, and ``<figure>_ratio`` is the median of
the per-repeat ratios zenros / rclpy (load on a shared box hits both sides of a repeat):

- ``timer_pub_cpu`` / ``timer_sub_cpu``: a 100 Hz timer publishing a Twist, and its
  subscriber: cores each process uses over ``--window`` seconds (every thread, /proc schedstat);
- ``rtt_p50_us`` / ``rtt_p99_us``: Twist ping-pong between two processes, ``--pings`` round trips
  2 ms apart;
- ``burst_rate``: a reliable (keep-last 10) publisher sends Twists as fast as it can for 2 s;
  messages per second reaching the subscriber; ``burst_loss`` the share of those sent that
  never arrived (no ratio: it is 0 for zenros);
- ``cloud_latency_p50_us`` / ``cloud_sub_cpu``: a 1 MB PointCloud2 at 10 Hz, one-way latency
  (send time in the header, CLOCK_MONOTONIC) and the subscriber's cores (its own
  ``time.process_time`` over the stream);
- ``trigger_rtt_p50_us``: std_srvs/Trigger calls one after another, client and server apart;
- ``idle_cpu`` / ``idle_rss_mb``: a process with one subscription and no traffic, both sides'
  at the same time, cores over ``--idle-window`` seconds and resident memory.

rclpy runs on the RMW its wheels give (Fast DDS); zenros on its defaults, its processes peers of
a zenros router. DDS discovery is multicast, so the bench re-runs itself in a network namespace
it creates (``unshare -n``, loopback with multicast, as bench/ros2.py; needs root and the
``ros2`` extra): no packet of either side leaves loopback. Prints one JSON line.

Run: ``python bench/rclpy_h2h.py [--repeats 3] [--window 5] [--idle-window 20] [--only idle ...]``.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from _harness import cpu_seconds, emit, free_port, missing_extra, percentile, unique_prefix

HERE = Path(__file__).resolve()
NETNS = ("ip link set lo up && ip link set lo multicast on && "
         "ip route add 224.0.0.0/4 dev lo && exec \"$@\"")
IMPLS = ("rclpy", "zenros")
GROUPS = ("timer", "pingpong", "burst", "cloud", "trigger", "idle")
CLOUD_BYTES = 1 << 20
CLOUD_N, CLOUD_HZ = 40, 10.0
BURST_S = 2.0
WARM, MEASURE, END = 0.0, 1.0, 2.0  # phases a Twist's linear.y carries


# ------------------------------------------------------------------ the two APIs, side by side

class Side:
    """What a child program needs of its middleware: publishers, subscriptions, a timer, a
    service and its client, and a way to wait while callbacks run."""

    def __init__(self, impl: str, name: str, endpoint: str, prefix: str) -> None:
        self.impl = impl
        if impl == "rclpy":
            import rclpy
            from rclpy.node import Node

            rclpy.init()
            self._rclpy = rclpy
            self.node: Any = Node(name)
        else:
            from zenros.context import Context
            from zenros.node import Node as ZNode
            from zenros.session import SessionOptions

            self.ctx = Context(SessionOptions(connect=[endpoint]), prefix=prefix)
            self.node = ZNode(name, context=self.ctx)

    def types(self) -> Any:
        """The message module namespace of this side: Twist, PointCloud2, String, Trigger."""
        if self.impl == "rclpy":
            from geometry_msgs.msg import Twist
            from sensor_msgs.msg import PointCloud2
            from std_msgs.msg import String
            from std_srvs.srv import Trigger
        else:
            from zenros.msgs.geometry_msgs import Twist
            from zenros.msgs.sensor_msgs import PointCloud2
            from zenros.msgs.std_msgs import String
            from zenros.msgs.std_srvs import Trigger
        return argparse.Namespace(Twist=Twist, PointCloud2=PointCloud2, String=String,
                                  Trigger=Trigger)

    def wait_matched(self, pub: Any, timeout: float = 30.0) -> None:
        if self.impl == "zenros":
            if not pub.wait_for_subscribers(1, timeout):
                raise RuntimeError("no subscriber matched")
            return
        deadline = time.monotonic() + timeout
        while pub.get_subscription_count() < 1:
            if time.monotonic() > deadline:
                raise RuntimeError("no subscriber matched")
            time.sleep(0.02)

    def spin_until(self, done: Callable[[], bool] | threading.Event, timeout: float) -> None:
        """Run callbacks until ``done`` (rclpy spins here; zenros's run on Zenoh's threads)."""
        deadline = time.monotonic() + timeout
        if isinstance(done, threading.Event):
            if self.impl == "zenros":
                done.wait(timeout)
                return
            event = done
            done = event.is_set
        while not done() and time.monotonic() < deadline:
            if self.impl == "rclpy":
                self._rclpy.spin_once(self.node, timeout_sec=0.1)
            else:
                time.sleep(0.01)

    def serve(self) -> None:
        """Run callbacks until the parent ends the process (SIGTERM)."""
        signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
        if self.impl == "rclpy":
            from rclpy.executors import ExternalShutdownException

            try:
                self._rclpy.spin(self.node)
            except (KeyboardInterrupt, ExternalShutdownException):
                pass
        else:
            threading.Event().wait()


def stamp_now(msg: Any) -> None:
    ns = time.monotonic_ns()
    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(ns, 1_000_000_000)


def zstamp_now(msg: Any) -> Any:
    """zenros's Time is immutable: a new one."""
    from zenros.msgs.builtin_interfaces import Time

    sec, nsec = divmod(time.monotonic_ns(), 1_000_000_000)
    msg.header.stamp = Time(sec=sec, nanosec=nsec)
    return msg


def ready(extra: str = "") -> None:
    print(f"ready {extra}".strip(), flush=True)


def report(obj: dict[str, Any]) -> None:
    print(json.dumps(obj), flush=True)


# ------------------------------------------------------------------ child programs

def role_timer_pub(s: Side) -> None:
    t = s.types()
    pub = s.node.create_publisher(t.Twist, "/h2h_timer", 10)
    n = [0]

    def tick() -> None:
        n[0] += 1
        m = t.Twist()
        m.linear.x = float(n[0])
        pub.publish(m)

    s.node.create_timer(0.01, tick)
    ready()
    s.serve()


def role_timer_sub(s: Side) -> None:
    t = s.types()
    first = threading.Event()

    def on(_m: Any) -> None:
        if not first.is_set():
            first.set()
            print("got", flush=True)

    s.node.create_subscription(t.Twist, "/h2h_timer", on, 10)
    ready()
    s.serve()


def role_pong(s: Side) -> None:
    t = s.types()
    pub = s.node.create_publisher(t.Twist, "/h2h_pong", 10)
    s.node.create_subscription(t.Twist, "/h2h_ping", pub.publish, 10)
    ready()
    s.serve()


def role_ping(s: Side, pings: int) -> None:
    t = s.types()
    pub = s.node.create_publisher(t.Twist, "/h2h_ping", 10)
    got = threading.Event()
    want = [-1.0]

    def on(m: Any) -> None:
        if m.linear.x == want[0]:
            got.set()

    s.node.create_subscription(t.Twist, "/h2h_pong", on, 10)
    ready()

    def one(seq: int, timeout: float) -> float | None:
        got.clear()
        want[0] = float(seq)
        m = t.Twist()
        m.linear.x = float(seq)
        t0 = time.perf_counter()
        pub.publish(m)
        s.spin_until(got, timeout)
        return time.perf_counter() - t0 if got.is_set() else None

    deadline = time.monotonic() + 60
    seq = 0
    while one(seq, 0.2) is None:  # until the path works end to end
        seq += 1
        if time.monotonic() > deadline:
            raise RuntimeError("no pong")
    rtts = []
    for i in range(100 + pings):
        seq += 1
        rtt = one(seq, 5.0)
        if rtt is None:
            raise RuntimeError(f"ping {seq} lost")
        if i >= 100:
            rtts.append(rtt)
        time.sleep(0.002)
    report({"p50_us": percentile(rtts, 50) * 1e6, "p99_us": percentile(rtts, 99) * 1e6})


def role_burst_pub(s: Side) -> None:
    t = s.types()
    pub = s.node.create_publisher(t.Twist, "/h2h_burst", 10)  # reliable, keep-last 10
    ready()
    s.wait_matched(pub)

    def send(phase: float) -> None:
        m = t.Twist()
        m.linear.y = phase
        pub.publish(m)

    for _ in range(20):  # 1 s: the path settles (discovery, routes)
        send(WARM)
        time.sleep(0.05)
    sent = 0
    t_end = time.monotonic() + BURST_S
    while time.monotonic() < t_end:
        send(MEASURE)
        sent += 1
    time.sleep(1.0)
    for _ in range(20):
        send(END)
        time.sleep(0.05)
    report({"sent": sent})


def role_burst_sub(s: Side) -> None:
    t = s.types()
    arrivals: list[float] = []
    done = threading.Event()

    def on(m: Any) -> None:
        if m.linear.y == MEASURE:
            arrivals.append(time.monotonic())
        elif m.linear.y == END:
            done.set()

    s.node.create_subscription(t.Twist, "/h2h_burst", on, 10)
    ready()
    s.spin_until(done, 120)
    rate = (len(arrivals) - 1) / (arrivals[-1] - arrivals[0]) if len(arrivals) > 1 else 0.0
    report({"received": len(arrivals), "rate": rate})


def role_cloud_pub(s: Side) -> None:
    t = s.types()
    pub = s.node.create_publisher(t.PointCloud2, "/h2h_cloud", 10)
    points = CLOUD_BYTES // 16
    if s.impl == "rclpy":
        import array

        from sensor_msgs.msg import PointField

        fields = [PointField(name=n, offset=4 * i, datatype=PointField.FLOAT32, count=1)
                  for i, n in enumerate("xyz")]
        data: Any = array.array("B", bytes(CLOUD_BYTES))
    else:
        from zenros.msgs.sensor_msgs import PointField as ZPointField

        fields = [ZPointField(name=n, offset=4 * i, datatype=ZPointField.FLOAT32, count=1)
                  for i, n in enumerate("xyz")]
        data = bytes(CLOUD_BYTES)

    def make(phase: str) -> Any:
        m = t.PointCloud2(height=1, width=points, fields=fields, point_step=16,
                          row_step=CLOUD_BYTES, data=data, is_dense=True)
        m.header.frame_id = phase
        if s.impl == "rclpy":
            stamp_now(m)
        else:
            zstamp_now(m)
        return m

    ready()
    s.wait_matched(pub)
    period = 1.0 / CLOUD_HZ
    for _ in range(10):
        pub.publish(make("warm"))
        time.sleep(period)
    t_next = time.monotonic()
    for _ in range(CLOUD_N):
        pub.publish(make("m"))
        t_next += period
        time.sleep(max(0.0, t_next - time.monotonic()))
    for _ in range(10):
        pub.publish(make("end"))
        time.sleep(period)
    report({"sent": CLOUD_N})


def role_cloud_sub(s: Side) -> None:
    t = s.types()
    lat: list[float] = []
    cpu: list[tuple[float, float]] = []  # (wall, process CPU) at the first and last sample
    done = threading.Event()

    def on(m: Any) -> None:
        now = time.monotonic_ns()
        if m.header.frame_id == "m":
            st = m.header.stamp
            lat.append((now - (st.sec * 1_000_000_000 + st.nanosec)) / 1e9)
            mark = (time.monotonic(), time.process_time())
            cpu[1:] = [mark] if cpu else []
            if not cpu:
                cpu.append(mark)
        elif m.header.frame_id == "end":
            done.set()

    s.node.create_subscription(t.PointCloud2, "/h2h_cloud", on, 10)
    ready()
    s.spin_until(done, 120)
    cores = (cpu[-1][1] - cpu[0][1]) / (cpu[-1][0] - cpu[0][0]) if len(cpu) == 2 else 0.0
    report({"received": len(lat), "p50_us": percentile(lat, 50) * 1e6 if lat else 0.0,
            "cores": cores})


def role_trigger_srv(s: Side) -> None:
    t = s.types()

    def handle(_req: Any, res: Any) -> Any:
        res.success, res.message = True, "ok"
        return res

    s.node.create_service(t.Trigger, "/h2h_trigger", handle)
    ready()
    s.serve()


def role_trigger_cli(s: Side, calls: int) -> None:
    t = s.types()
    cli = s.node.create_client(t.Trigger, "/h2h_trigger")
    ready()
    if s.impl == "rclpy":
        req = t.Trigger.Request()
        if not cli.wait_for_service(timeout_sec=60):
            raise RuntimeError("no Trigger server")

        def call() -> bool:
            fut = cli.call_async(req)
            s._rclpy.spin_until_future_complete(s.node, fut, timeout_sec=5)
            return bool(fut.done() and fut.result().success)
    else:
        zreq = t.Trigger.Request()
        if not cli.wait_for_service(60):
            raise RuntimeError("no Trigger server")

        def call() -> bool:
            return bool(cli.call(zreq).success)

    rtts = []
    for i in range(50 + calls):
        t0 = time.perf_counter()
        if not call():
            raise RuntimeError("a Trigger call failed")
        if i >= 50:
            rtts.append(time.perf_counter() - t0)
    report({"p50_us": percentile(rtts, 50) * 1e6, "p99_us": percentile(rtts, 99) * 1e6})


def role_idle(s: Side) -> None:
    t = s.types()
    s.node.create_subscription(t.String, "/h2h_idle", lambda _m: None, 10)
    ready()
    s.serve()


def child(role: str, impl: str, endpoint: str, prefix: str, a: argparse.Namespace) -> None:
    s = Side(impl, f"h2h_{role}", endpoint, prefix)
    roles: dict[str, Callable[[], None]] = {
        "timer_pub": lambda: role_timer_pub(s), "timer_sub": lambda: role_timer_sub(s),
        "pong": lambda: role_pong(s), "ping": lambda: role_ping(s, a.pings),
        "burst_pub": lambda: role_burst_pub(s), "burst_sub": lambda: role_burst_sub(s),
        "cloud_pub": lambda: role_cloud_pub(s), "cloud_sub": lambda: role_cloud_sub(s),
        "trigger_srv": lambda: role_trigger_srv(s),
        "trigger_cli": lambda: role_trigger_cli(s, a.calls),
        "idle": lambda: role_idle(s),
    }
    roles[role]()
    sys.stdout.flush()
    os._exit(0)  # a result is out: no teardown of either middleware to wait for


# ------------------------------------------------------------------ the parent, in the namespace

class Kid:
    """A child process of one role and side, in its own process group."""

    def __init__(self, role: str, impl: str, endpoint: str, prefix: str, a: argparse.Namespace,
                 logdir: str) -> None:
        env = {**os.environ, "AMENT_PREFIX_PATH": sys.prefix, "ROS_DOMAIN_ID": "0",
               "PYTHONUNBUFFERED": "1"}
        self.name = f"{impl}:{role}"
        self.err = open(os.path.join(logdir, f"{impl}_{role}.err"), "w")  # noqa: SIM115
        self.p = subprocess.Popen(
            [sys.executable, str(HERE), "--role", role, "--impl", impl, "--endpoint", endpoint,
             "--prefix", prefix, "--pings", str(a.pings), "--calls", str(a.calls)],
            stdout=subprocess.PIPE, stderr=self.err, text=True, env=env,
            start_new_session=True)
        self.expect("ready", 60)

    def expect(self, word: str, timeout: float) -> str:
        """The next stdout line, which must start with ``word``."""
        assert self.p.stdout is not None
        out: list[str] = []
        reader = threading.Thread(target=lambda: out.append(self.p.stdout.readline()),  # type: ignore[union-attr]
                                  daemon=True)
        reader.start()
        reader.join(timeout)
        line = out[0] if out else ""
        if not line.startswith(word):
            self.stop()
            raise RuntimeError(f"{self.name}: expected {word!r}, got {line!r}; stderr in "
                               f"{self.err.name}")
        return line

    def result(self, timeout: float = 120) -> dict[str, Any]:
        r: dict[str, Any] = json.loads(self.expect("{", timeout))
        return r

    def stop(self) -> None:
        if self.p.poll() is None:
            os.killpg(self.p.pid, signal.SIGTERM)
            try:
                self.p.wait(10)
            except subprocess.TimeoutExpired:
                os.killpg(self.p.pid, signal.SIGKILL)
                self.p.wait(5)
        self.err.close()


def cores(pids: list[int], window: float) -> list[float]:
    before = [cpu_seconds(p) for p in pids]
    t0 = time.monotonic()
    time.sleep(window)
    dt = time.monotonic() - t0
    return [(cpu_seconds(p) - b) / dt for p, b in zip(pids, before, strict=True)]


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


class Run:
    """One side's figures of one repeat."""

    def __init__(self, impl: str, endpoint: str, a: argparse.Namespace, logdir: str) -> None:
        self.impl, self.endpoint, self.a, self.logdir = impl, endpoint, a, logdir

    def kids(self, *roles: str) -> list[Kid]:
        prefix = unique_prefix()
        made: list[Kid] = []
        try:
            for role in roles:
                made.append(Kid(role, self.impl, self.endpoint, prefix, self.a, self.logdir))
        except BaseException:
            for k in made:
                k.stop()
            raise
        return made

    def timer(self) -> dict[str, float]:
        sub, pub = self.kids("timer_sub", "timer_pub")
        try:
            sub.expect("got", 60)
            time.sleep(1.0)
            c_pub, c_sub = cores([pub.p.pid, sub.p.pid], self.a.window)
        finally:
            pub.stop()
            sub.stop()
        return {"timer_pub_cpu": c_pub, "timer_sub_cpu": c_sub}

    def pingpong(self) -> dict[str, float]:
        pong, ping = self.kids("pong", "ping")
        try:
            r = ping.result()
        finally:
            ping.stop()
            pong.stop()
        return {"rtt_p50_us": r["p50_us"], "rtt_p99_us": r["p99_us"]}

    def burst(self) -> dict[str, float]:
        sub, pub = self.kids("burst_sub", "burst_pub")
        try:
            sent = pub.result()["sent"]
            r = sub.result()
        finally:
            pub.stop()
            sub.stop()
        return {"burst_rate": r["rate"], "burst_loss": 1.0 - r["received"] / sent if sent else 1.0}

    def cloud(self) -> dict[str, float]:
        sub, pub = self.kids("cloud_sub", "cloud_pub")
        try:
            r = sub.result()
            pub.result()  # its last "end" is out: stopping it now interrupts nothing
        finally:
            pub.stop()
            sub.stop()
        if r["received"] < CLOUD_N // 2:
            raise RuntimeError(f"{self.impl}: {r['received']} of {CLOUD_N} clouds arrived")
        return {"cloud_latency_p50_us": r["p50_us"], "cloud_sub_cpu": r["cores"],
                "cloud_received": r["received"]}

    def trigger(self) -> dict[str, float]:
        srv, cli = self.kids("trigger_srv", "trigger_cli")
        try:
            r = cli.result()
        finally:
            cli.stop()
            srv.stop()
        return {"trigger_rtt_p50_us": r["p50_us"], "trigger_rtt_p99_us": r["p99_us"]}

    def all(self, only: list[str]) -> dict[str, float]:
        out: dict[str, float] = {}
        for group in GROUPS[:-1]:  # idle: both sides at once (`idle`)
            if group in only:
                out.update(getattr(self, group)())
        return out


def idle(endpoint: str, a: argparse.Namespace, logdir: str) -> dict[str, dict[str, float]]:
    """Both sides' processes at rest, measured over the same window."""
    kids = [Kid("idle", impl, endpoint, unique_prefix(), a, logdir) for impl in IMPLS]
    try:
        time.sleep(5.0)  # discovery, parameter lookups: what a fresh process does once
        c = cores([k.p.pid for k in kids], a.idle_window)
        return {impl: {"idle_cpu": c[i], "idle_rss_mb": rss_mb(kids[i].p.pid)}
                for i, impl in enumerate(IMPLS)}
    finally:
        for k in kids:
            k.stop()


RATIOS = ("timer_pub_cpu", "timer_sub_cpu", "rtt_p50_us", "rtt_p99_us", "burst_rate",
          "cloud_latency_p50_us", "cloud_sub_cpu", "trigger_rtt_p50_us", "trigger_rtt_p99_us",
          "idle_cpu", "idle_rss_mb")
ROUND = {"cpu": 5, "us": 1, "rate": 1, "loss": 4, "mb": 1, "received": 0}


def rounded(key: str, v: float) -> float:
    return round(v, next((n for k, n in ROUND.items() if key.endswith(k)), 3))


def in_namespace(a: argparse.Namespace) -> None:
    port = free_port()
    endpoint = f"tcp/127.0.0.1:{port}"
    logdir = tempfile.mkdtemp(prefix="zenros-h2h-")
    router = subprocess.Popen([sys.executable, "-m", "zenros.router", "-l", endpoint],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                              start_new_session=True)
    from zenros.router import router_reachable

    per: dict[str, dict[str, list[float]]] = {impl: {} for impl in IMPLS}
    load = [os.getloadavg()[0]]
    try:
        deadline = time.monotonic() + 30
        while not router_reachable(endpoint, 1.0):
            if time.monotonic() > deadline:
                raise RuntimeError("the zenros router did not start")
            time.sleep(0.1)
        for rep in range(a.repeats):
            order = IMPLS if rep % 2 == 0 else IMPLS[::-1]
            figures = {impl: Run(impl, endpoint, a, logdir).all(a.only) for impl in order}
            figures_idle = idle(endpoint, a, logdir) if "idle" in a.only else {i: {} for i in IMPLS}
            for impl in IMPLS:
                for k, v in {**figures[impl], **figures_idle[impl]}.items():
                    per[impl].setdefault(k, []).append(v)
            load.append(os.getloadavg()[0])
    finally:
        if router.poll() is None:
            os.killpg(router.pid, signal.SIGINT)
            try:
                router.wait(10)
            except subprocess.TimeoutExpired:
                os.killpg(router.pid, signal.SIGKILL)
    metrics: dict[str, float] = {}
    for key in per["zenros"]:
        for impl in IMPLS:
            metrics[f"{key}_{impl}"] = rounded(key, statistics.median(per[impl][key]))
        if key in RATIOS:
            ratios = [z / r for z, r in zip(per["zenros"][key], per["rclpy"][key], strict=True)
                      if r]
            metrics[f"{key}_ratio"] = round(statistics.median(ratios), 3) if ratios else 0.0
    import rclpy

    emit("rclpy_h2h", metrics, repeats=a.repeats, window_s=a.window, idle_window_s=a.idle_window,
         per_repeat={k: [round(z / r, 3) if r else 0.0 for z, r in
                         zip(per["zenros"][k], per["rclpy"][k], strict=True)]
                     for k in RATIOS if k in per["zenros"]},
         load_average=[round(x, 2) for x in load],
         rmw=os.environ.get("RMW_IMPLEMENTATION", "rmw_fastrtps_cpp (the wheels' default)"),
         rclpy=getattr(rclpy, "__version__", None) or _rclpy_version(),
         stat="medians over repeats; ratios zenros / rclpy, medians of per-repeat ratios")


def _rclpy_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("rclpy")
    except PackageNotFoundError:
        return "unknown"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--role", default="parent")
    ap.add_argument("--impl", choices=IMPLS, default="zenros")
    ap.add_argument("--endpoint", default="")
    ap.add_argument("--prefix", default="h2h")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--window", type=float, default=5.0, help="timer CPU window (s)")
    ap.add_argument("--idle-window", type=float, default=20.0, help="idle CPU window (s)")
    ap.add_argument("--pings", type=int, default=500)
    ap.add_argument("--calls", type=int, default=500)
    ap.add_argument("--only", nargs="+", choices=GROUPS, default=list(GROUPS),
                    help="measure only these figures")
    a = ap.parse_args()
    if a.role != "parent":
        child(a.role, a.impl, a.endpoint, a.prefix, a)
        return
    try:
        import rclpy  # noqa: F401
    except ModuleNotFoundError as err:
        sys.exit(missing_extra(err, "ros2"))
    if a.repeats < 1:
        ap.error("--repeats must be at least 1")
    if os.environ.get("ZENROS_BENCH_NETNS") != "1":
        if os.geteuid() != 0:
            emit("rclpy_h2h", {}, error="needs root for a network namespace (unshare -n)")
            return
        env = {**os.environ, "ZENROS_BENCH_NETNS": "1"}
        p = subprocess.run(["unshare", "-n", "sh", "-c", NETNS, "sh", sys.executable,
                            str(HERE), *sys.argv[1:]], env=env, check=False)
        sys.exit(p.returncode)
    in_namespace(a)


if __name__ == "__main__":
    main()
