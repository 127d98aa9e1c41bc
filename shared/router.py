"""The Zenoh router runner: a zenoh session in router mode, served until SIGINT/SIGTERM.

zenoh-python ships no ``zenohd``; a session opened with ``mode: "router"`` *is* a router.
``zenros router`` and ``python -m zenros.router`` both run `main`.
"""

from __future__ import annotations

import argparse
import json
import logging
import re
import socket
import sys
import threading
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager
from types import FrameType

import zenoh

from .errors import StartupError
from .exits import EXIT_STARTUP
from .session import apply_runtime_defaults
from .signals import handling_signals

__all__ = [
    "DEFAULT_KEEP_ALIVE",
    "DEFAULT_LEASE_MS",
    "DEFAULT_LISTEN",
    "build_router_config",
    "listen_endpoints",
    "main",
    "parse_cfg_entry",
    "router_reachable",
    "serve_router",
]

DEFAULT_LISTEN = "tcp/127.0.0.1:7447"
DEFAULT_LEASE_MS = 2500  # a frozen or cut-off router is noticed in 1.25-2.5 s (zenoh: 10000)
DEFAULT_KEEP_ALIVE = 2  # keep-alives per lease: one every 1.25 s on an idle link

_TCP_BASED = ("tcp", "tls", "ws")
_RUST_LOCATION = re.compile(r" at /\S+?\.rs:\d+\.?")

log = logging.getLogger("zenros.router")


def parse_cfg_entry(text: str) -> tuple[str, str]:
    """Split a ``--cfg KEY:VALUE`` argument at its first colon.

    Args:
        text: for example ``transport/link/tx/lease:2000`` or ``mode:"router"``.

    Returns:
        ``(key, value)``; the value is JSON5 text, inserted as is.

    Raises:
        ValueError: there is no colon, or the key or the value is empty.
    """
    key, sep, value = text.partition(":")
    if not sep or not key.strip() or not value.strip():
        raise ValueError(
            f"invalid --cfg {text!r}: expected KEY:VALUE with a JSON5 value, "
            "e.g. transport/link/tx/lease:2000"
        )
    return key.strip(), value


def _clean(exc: BaseException) -> str:
    """A zenoh error as one line, without the Rust source locations it carries."""
    return " ".join(_RUST_LOCATION.sub("", str(exc)).split())


def _get(conf: zenoh.Config, key: str) -> object:
    return json.loads(conf.get_json(key))


def _put(conf: zenoh.Config, key: str, value: object) -> None:
    conf.insert_json5(key, json.dumps(value))


def build_router_config(
    listen: Sequence[str] = (),
    config_file: str | None = None,
    cfg: Sequence[tuple[str, str]] = (),
    multicast: bool = False,
) -> zenoh.Config:
    """The config of a zenros router.

    Precedence, lowest first: zenoh's defaults; the config file; zenros's defaults for what the
    file leaves unset; ``listen``; ``multicast``; the ``cfg`` entries. zenros's defaults are:
    listen on `DEFAULT_LISTEN`, multicast scouting off, shared memory off (as in zenros's
    sessions: at rest its transport wakes every link ten times a second), and
    ``transport/link/tx`` lease `DEFAULT_LEASE_MS` with keep_alive `DEFAULT_KEEP_ALIVE`. A value
    still at zenoh's own default (lease 10000, shared memory on) counts as unset; force it with
    ``cfg``, e.g. ``[("transport/link/tx/lease", "10000")]``.

    Args:
        listen: endpoints to listen on; replaces the file's and the default.
        config_file: a zenoh JSON5 config file; its ``mode`` must be unset or ``"router"``.
        cfg: ``(key, json5_value)`` pairs inserted last, as ``--cfg`` does.
        multicast: enable multicast scouting (off unless the file enables it).

    Returns:
        A `zenoh.Config` in router mode.

    Raises:
        StartupError: the file cannot be read, sets another mode, or a value is invalid.
    """
    stock = zenoh.Config()
    try:
        conf = zenoh.Config.from_file(config_file) if config_file else zenoh.Config()
    except zenoh.ZError as exc:
        raise StartupError(f"cannot read Zenoh config {config_file}: {_clean(exc)}") from exc
    mode = _get(conf, "mode")
    if mode not in (None, "router"):
        raise StartupError(
            f"{config_file} sets mode {mode!r}; a router config needs mode \"router\" or no mode"
        )
    _put(conf, "mode", "router")
    if _get(conf, "listen/endpoints") == _get(stock, "listen/endpoints"):
        _put(conf, "listen/endpoints", [DEFAULT_LISTEN])
    if _get(conf, "scouting/multicast/enabled") is None:
        _put(conf, "scouting/multicast/enabled", False)
    for key, ours in (("lease", DEFAULT_LEASE_MS), ("keep_alive", DEFAULT_KEEP_ALIVE)):
        if _get(conf, f"transport/link/tx/{key}") == _get(stock, f"transport/link/tx/{key}"):
            _put(conf, f"transport/link/tx/{key}", ours)
    shm = "transport/shared_memory/enabled"
    if _get(conf, shm) == _get(stock, shm):
        _put(conf, shm, False)
    if listen:
        _put(conf, "listen/endpoints", list(listen))
    if multicast:
        _put(conf, "scouting/multicast/enabled", True)
    for key, value in cfg:
        try:
            conf.insert_json5(key, value)
        except zenoh.ZError as exc:
            raise StartupError(f"invalid --cfg {key}:{value}: {_clean(exc)}") from exc
    if _get(conf, "mode") != "router":
        raise StartupError(f"--cfg sets mode {_get(conf, 'mode')!r}; a router needs \"router\"")
    return conf


def listen_endpoints(config: zenoh.Config) -> list[str]:
    """The endpoints a router config listens on (the router entry of a per-mode default)."""
    value = _get(config, "listen/endpoints")
    if isinstance(value, dict):
        value = value.get("router", [])
    return [str(e) for e in value] if isinstance(value, list) else []


def _stop_on_signals(stop: threading.Event) -> AbstractContextManager[None]:
    """Set ``stop`` on SIGINT/SIGTERM (a second signal forces); restore the old handlers.

    ``stop`` is set from a thread of its own: the main thread, waiting on it, may hold its
    lock when the handler runs (`zenros.runtime.capture_signals`)."""

    def handle(signum: int, frame: FrameType | None) -> None:
        if stop.is_set():
            raise KeyboardInterrupt
        threading.Thread(target=stop.set, name="zenros-signal", daemon=True).start()

    return handling_signals(handle)


def serve_router(
    config: zenoh.Config,
    ready: Callable[[zenoh.Session], None] | None = None,
    *,
    stop: threading.Event | None = None,
) -> int:
    """Run a router until SIGINT/SIGTERM (or ``stop``), then close it.

    Args:
        config: a router config, usually from `build_router_config`.
        ready: called with the open session once the router listens.
        stop: an event that ends the router when set. Signal handlers are installed only on
            the main thread; from another thread, pass ``stop`` to end the router.

    Returns:
        0 after a normal stop; `EXIT_STARTUP` (3), after one line on stderr, when the
        router cannot open (port in use, missing certificate, bad dictionary file...).
    """
    stop = stop if stop is not None else threading.Event()
    endpoints = ", ".join(listen_endpoints(config)) or "(no endpoint)"
    with _stop_on_signals(stop):
        try:
            apply_runtime_defaults()
            session = zenoh.open(config)
        except zenoh.ZError as exc:
            print(f"zenros router: cannot listen on {endpoints}: {_clean(exc)}", file=sys.stderr)
            return EXIT_STARTUP
        try:
            log.info("router listening on %s (zid %s)", endpoints, session.zid())
            if ready is not None:
                ready(session)
            while not stop.wait(0.5):
                pass
            log.info("router stopping")
        finally:
            session.close()  # type: ignore[no-untyped-call]
    return 0


def _split_endpoint(endpoint: str) -> tuple[str, str, int]:
    """``tcp/host:port`` (or ``tcp/[v6]:port``, with ``?metadata``/``#config``) as parts."""
    proto, sep, rest = endpoint.partition("/")
    address = re.split(r"[?#]", rest, maxsplit=1)[0]
    host, colon, port = address.rpartition(":")
    if not sep or not colon or not host or not port.isdigit():
        raise StartupError(f"invalid endpoint {endpoint!r}: expected PROTO/HOST:PORT")
    return proto, host.strip("[]"), int(port)


def router_reachable(endpoint: str = DEFAULT_LISTEN, timeout: float = 0.5) -> bool:
    """Whether something accepts TCP connections at a ``tcp/``, ``tls/`` or ``ws/`` endpoint.

    A plain TCP connect, cheap and without a Zenoh handshake: it says a port is open, not that
    a zenoh router (or one that would accept our credentials) is behind it.

    Raises:
        StartupError: the endpoint is malformed or its protocol is not TCP-based.
    """
    proto, host, port = _split_endpoint(endpoint)
    if proto not in _TCP_BASED:
        raise StartupError(
            f"cannot probe {endpoint!r}: only {', '.join(p + '/' for p in _TCP_BASED)} "
            "endpoints can be checked with a TCP connect"
        )
    try:
        with socket.create_connection((host, port), timeout=timeout):
            return True
    except OSError:
        return False


def _cfg_argument(text: str) -> tuple[str, str]:
    try:
        return parse_cfg_entry(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from exc


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="zenros router",
        description="Run a Zenoh router (a zenoh session in router mode) until Ctrl-C.",
    )
    parser.add_argument("-l", "--listen", action="append", default=[], metavar="ENDPOINT",
                        help=f"endpoint to listen on (repeatable; default {DEFAULT_LISTEN})")
    parser.add_argument("-c", "--config", metavar="FILE", help="a Zenoh JSON5 config file")
    parser.add_argument("--cfg", action="append", default=[], type=_cfg_argument,
                        metavar="KEY:VALUE",
                        help="set a config key to a JSON5 value (repeatable), "
                             "e.g. --cfg transport/link/tx/lease:2000")
    parser.add_argument("--multicast-scouting", action="store_true",
                        help="enable multicast scouting (off by default)")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """``zenros router``: parse flags, build the config and serve; returns the exit code."""
    args = _parser().parse_args(argv)
    if not logging.getLogger().handlers:
        logging.basicConfig(level=logging.INFO, format="%(name)s: %(message)s")
    zenoh.try_init_log_from_env()  # type: ignore[no-untyped-call]  # RUST_LOG=debug: zenoh logs
    try:
        config = build_router_config(args.listen, args.config, args.cfg, args.multicast_scouting)
    except StartupError as exc:
        print(f"zenros router: {exc}", file=sys.stderr)
        return EXIT_STARTUP
    return serve_router(config)


if __name__ == "__main__":
    raise SystemExit(main())
