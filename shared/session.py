"""Zenoh session configuration from flags, environment or file; the shared session flags."""

from __future__ import annotations

import argparse
import json
import os
from dataclasses import dataclass, field

import zenoh

from .errors import StartupError

__all__ = [
    "DEFAULT_ROUTER",
    "SessionOptions",
    "add_session_arguments",
    "build_config",
    "open_session",
    "options_from_args",
]

DEFAULT_ROUTER = "tcp/127.0.0.1:7447"
# A frozen process or a cut link leaves the graph within the lease, 1.25-2.5 s (a killed one
# at once: the kernel closes its TCP links). An idle link carries a keep-alive every 1.25 s: each
# costs the processes on both ends their wake-ups, most of an idle process's CPU. And the lease
# bounds how long a receiving process may take over a batch before Zenoh runs the link out
# (lease - keep-alive period: 1.25 s; with 1500 it was 0.75 s, which a starved router
# exceeded, docs/zenoh-config.md, "lease: 2500, keep_alive: 2").
DEFAULT_LEASE_MS = 2500
DEFAULT_KEEP_ALIVE = 2
SHM_POOL_BYTES = 20 << 20
SHM_ENV = "ZENROS_SHM"


def shm_from_env() -> bool:
    """Whether ``$ZENROS_SHM`` turns shared memory on (1, true, yes, on)."""
    return os.environ.get(SHM_ENV, "").strip().lower() in ("1", "true", "yes", "on")


@dataclass
class SessionOptions:
    """What a process needs to open its Zenoh session.

    The default is a peer that connects to the local router and listens on a loopback port of
    its own, so peers mesh directly (a peer without a listen endpoint gets nothing through a
    router) and survive the router's death; multicast scouting is off. ``shm``: large payloads
    to processes of this host that turn it on too go through shared memory (off unless
    ``$ZENROS_SHM`` says on: at rest, Zenoh's shared-memory transport wakes every link ten
    times a second).
    """

    mode: str | None = None  # None: peer, unless a config file says otherwise
    connect: list[str] | None = None  # None: the local router; []: connect to nothing
    listen: list[str] = field(default_factory=list)
    config_file: str | None = None
    cfg: list[tuple[str, str]] = field(default_factory=list)
    multicast_scouting: bool = False
    lease_ms: int = DEFAULT_LEASE_MS
    shm: bool = field(default_factory=shm_from_env)
    strict_connect: bool = False  # explicit endpoints: fail at startup if none answers


def add_session_arguments(parser: argparse.ArgumentParser) -> None:
    """The session flags shared by every service and CLI (as Zenoh's own z_* tools)."""
    g = parser.add_argument_group("zenoh session")
    g.add_argument("-m", "--mode", choices=["peer", "client"], help="session mode (default peer)")
    g.add_argument("-e", "--connect", action="append", default=[], metavar="ENDPOINT",
                   help=f"endpoint to connect to (repeatable; default {DEFAULT_ROUTER})")
    g.add_argument("-l", "--listen", action="append", default=[], metavar="ENDPOINT",
                   help="endpoint to listen on (repeatable; default tcp/127.0.0.1:0)")
    g.add_argument("-c", "--config", metavar="FILE", help="a Zenoh JSON5 config file")
    g.add_argument("--cfg", action="append", default=[], metavar="KEY:VALUE",
                   help="set a config key to a JSON5 value, e.g. --cfg 'transport/link/tx/lease:2000'")
    g.add_argument("--multicast-scouting", action="store_true",
                   help="enable multicast scouting (off by default)")
    g.add_argument("--no-multicast-scouting", dest="multicast_scouting", action="store_false",
                   help=argparse.SUPPRESS)
    g.add_argument("--shm", action="store_true", default=None,
                   help="send payloads of 3 KiB or more to processes of this host that turn it "
                        f"on too through shared memory (off by default; or ${SHM_ENV}=1)")
    g.add_argument("--prefix", help="key-expression prefix (default $ZENROS_PREFIX or 'zenros')")


def _parse_cfg(items: list[str]) -> list[tuple[str, str]]:
    out = []
    for item in items:
        key, sep, value = item.partition(":")
        if not sep or not key:
            raise StartupError(f"invalid --cfg {item!r}: expected KEY:VALUE")
        out.append((key, value))
    return out


def options_from_args(ns: argparse.Namespace) -> SessionOptions:
    """Session options from parsed flags, with ZENROS_CONNECT / ZENROS_LISTEN / ZENROS_MODE
    (comma-separated endpoints) as fallbacks."""
    env_connect = [e for e in os.environ.get("ZENROS_CONNECT", "").split(",") if e]
    env_listen = [e for e in os.environ.get("ZENROS_LISTEN", "").split(",") if e]
    connect = list(ns.connect) or env_connect
    return SessionOptions(
        mode=ns.mode or os.environ.get("ZENROS_MODE") or None,
        connect=connect or None,
        listen=list(ns.listen) or env_listen,
        config_file=ns.config or os.environ.get("ZENROS_CONFIG") or None,
        cfg=_parse_cfg(ns.cfg),
        multicast_scouting=bool(ns.multicast_scouting),
        shm=bool(ns.shm) or shm_from_env(),
        strict_connect=bool(ns.connect),
    )



def build_config(opts: SessionOptions) -> zenoh.Config:
    """A `zenoh.Config` from options.

    Without a file, zenros's defaults apply (peer, local router, own loopback listen
    endpoint, 2.5 s lease with a keep-alive every 1.25 s, shared memory off unless
    ``opts.shm``, then with a 20 MiB pool). A file is taken as written, except that timestamping is always on,
    multicast scouting stays off unless the file sets it, and ``opts.shm`` turns shared memory on.
    Explicit flags then override, and ``--cfg`` last of all.
    """
    try:
        conf = zenoh.Config.from_file(opts.config_file) if opts.config_file else zenoh.Config()
    except Exception as exc:  # zenoh raises its own ZError for bad files
        raise StartupError(f"cannot read Zenoh config {opts.config_file}: {exc}") from exc
    from_file = opts.config_file is not None

    def put(key: str, value: object) -> None:
        conf.insert_json5(key, json.dumps(value))

    if opts.mode or not from_file:
        put("mode", opts.mode or "peer")
    mode = json.loads(conf.get_json("mode") or "\"peer\"")
    if opts.connect is not None or not from_file:
        put("connect/endpoints", [DEFAULT_ROUTER] if opts.connect is None else opts.connect)
    if opts.listen or not from_file:
        put("listen/endpoints", opts.listen or (["tcp/127.0.0.1:0"] if mode == "peer" else []))
    if opts.multicast_scouting or not from_file or conf.get_json("scouting/multicast/enabled") == "null":
        put("scouting/multicast/enabled", opts.multicast_scouting)
    put("timestamping/enabled", True)  # latched topics (advanced pub/sub) and sender ids need it
    if not from_file:
        put("transport/link/tx/lease", opts.lease_ms)
        put("transport/link/tx/keep_alive", DEFAULT_KEEP_ALIVE)
        # Zenoh's shared-memory transport keeps a task per priority on every link that polls
        # ten times a second, in both processes: 0.001 core per link at rest (measured with
        # a bare zenoh session pair, lease 10 s: 0.0011 cores on, 0.0001 off), which a robot's
        # process pays for each of its links. Payloads then go over loopback TCP: 1 MiB in
        # 4.7 ms instead of 0.8 ms, 8 MB in 64 ms instead of 3.8 ms (docs/zenoh-config.md).
        put("transport/shared_memory/enabled", opts.shm)
        # A dropped link to a configured endpoint is made again within 0.5-2 s, not after
        # Zenoh's 1-4 s backoff: an action client waits 3 s for a server that went away.
        put("connect/retry", {"period_init_ms": 500, "period_max_ms": 2000,
                              "period_increase_factor": 2})
        # Zenoh's 16 MiB default fits only one 8 MiB sample (plus its header) at a time and
        # sends the rest over TCP (specs/zenoh-ops.md, section 4). 20 MiB fits two; larger
        # pools were slower for 1 MiB samples here (64 MiB: 0.65-0.74x raw; 20 MiB: 1.0x).
        # Lazily allocated: only processes that put large samples pay for it.
        if opts.shm:
            put("transport/shared_memory/transport_optimization/pool_size", SHM_POOL_BYTES)
    elif opts.shm:
        put("transport/shared_memory/enabled", True)
    if opts.strict_connect:
        put("connect/exit_on_failure", True)
        put("connect/timeout_ms", 3000)
    for key, value in opts.cfg:
        try:
            conf.insert_json5(key, value)
        except Exception as exc:
            raise StartupError(f"invalid --cfg {key}:{value}: {exc}") from exc
    return conf


RX_RUNTIME = "(rx: (worker_threads: 32))"


def apply_runtime_defaults() -> None:
    """Zenoh runtime settings, read once when the first session of the process opens.

    Zenoh closes a link whose lease expired on one of its "rx" threads, and that close can
    block for the 10 s SO_LINGER while the peer is unreachable; with the default 2 rx threads,
    a process with several links to a lost host stops receiving from everyone (measured in
    the multi-host demo, docs/demo.md). A robot runs 8 to 13 processes (its services, its
    launch, the examples), and a process on another host holds a link to each: 8 rx threads
    all blocked (robot2 stalled 4.2 s during robot1's 5 s outage), and 16 did again once the
    demo's robot ran 12 processes (4.1 s); 32 keep the other links flowing (0.22 s). An
    explicit ``$ZENOH_RUNTIME`` wins.
    """
    os.environ.setdefault("ZENOH_RUNTIME", RX_RUNTIME)


def open_session(opts: SessionOptions | zenoh.Config) -> zenoh.Session:
    """Open a session; raises `StartupError` with one clear line when it cannot."""
    apply_runtime_defaults()
    conf = opts if isinstance(opts, zenoh.Config) else build_config(opts)
    try:
        return zenoh.open(conf)
    except Exception as exc:
        raise StartupError(f"cannot open Zenoh session: {exc}") from exc
