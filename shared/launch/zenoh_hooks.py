"""The Zenoh side of `zenros launch`: a local router when none answers, node readiness from
liveliness, and the launch's restart and shutdown services (`LaunchControl`)."""

from __future__ import annotations

import asyncio
import contextlib
import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import AsyncIterator
from dataclasses import replace

from ..context import Context
from ..errors import StartupError
from ..param_backend import MASTER_IN_LAUNCH
from ..param_client import ParameterClient
from ..router import router_reachable
from ..session import DEFAULT_ROUTER, SessionOptions
from .cli import LaunchHooks, LaunchOptions
from .control import LaunchControl, run_shutdown_command
from .model import ProcessSpec
from .supervisor import Supervisor

__all__ = ["ZenohLaunch", "is_master", "router_endpoint"]

READY_TIMEOUT = 60.0  # a node is ready once set up: nav loading its map on a busy host takes a while
READY_SLICE = 0.25
MASTER_WAIT = 5.0
MASTER_MODULE = "zenros.services.master"


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


def is_master(spec: ProcessSpec) -> bool:
    """Whether a process of the launch is the master (``module: zenros.services.master``)."""
    return MASTER_MODULE in spec.cmd


def router_endpoint() -> str:
    """The router a launch uses: the first of ``$ZENROS_CONNECT``, else tcp/127.0.0.1:7447."""
    first = os.environ.get("ZENROS_CONNECT", "").split(",")[0].strip()
    return first or DEFAULT_ROUTER


class ZenohLaunch:
    """Builds the `LaunchHooks`: router, endpoint injection and liveliness readiness."""

    def __init__(self, endpoint: str | None = None) -> None:
        self.endpoint = endpoint or router_endpoint()
        self.ctx: Context | None = None
        self._master_in_launch = False
        self._master_waited = False
        self._mesh: dict[tuple[str, str, str], str] = {}  # each peer's listen endpoint

    def hooks(self) -> LaunchHooks:
        return LaunchHooks(startup=self.startup, before_start=self.before_start,
                           wait_ready=self.wait_ready, stop_last=is_master,
                           control=self.control)

    @contextlib.asynccontextmanager
    async def control(self, supervisor: Supervisor,
                      options: LaunchOptions) -> AsyncIterator[None]:
        """The launch's restart and shutdown services (`LaunchControl`) while it runs; the
        ``--on-shutdown`` command after a shutdown they were asked for."""
        if self.ctx is None:
            yield
            return
        loop = asyncio.get_running_loop()
        node = await asyncio.to_thread(LaunchControl, self.ctx, options.control, supervisor,
                                       loop)
        try:
            yield
        finally:
            await asyncio.to_thread(node.close)
            if node.shutdown_requested and options.on_shutdown:
                await asyncio.to_thread(run_shutdown_command, options.on_shutdown)

    @contextlib.asynccontextmanager
    async def startup(self, options: LaunchOptions) -> AsyncIterator[None]:
        router: subprocess.Popen[bytes] | None = None
        if not options.no_router and not router_reachable(self.endpoint):
            router = await asyncio.to_thread(self._start_router, options)
        elif not options.no_router:
            print(f"[launch] using the router at {self.endpoint}", flush=True)
        try:
            self.ctx = await asyncio.to_thread(
                Context, SessionOptions(connect=[self.endpoint]))
            yield
        finally:
            if self.ctx is not None:
                await asyncio.to_thread(self.ctx.close)
            if router is not None:
                await asyncio.to_thread(_stop, router)

    def _start_router(self, options: LaunchOptions) -> subprocess.Popen[bytes]:
        options.run_dir.mkdir(parents=True, exist_ok=True)
        log = open(options.run_dir / "router.log", "ab")  # noqa: SIM115 (lives with the router)
        proc = subprocess.Popen(
            [sys.executable, "-m", "zenros.router", "-l", self.endpoint],
            stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
        )
        log.close()
        deadline = time.monotonic() + 15
        while not router_reachable(self.endpoint, 0.2):
            if proc.poll() is not None or time.monotonic() > deadline:
                _stop(proc)
                raise StartupError(f"could not start a Zenoh router on {self.endpoint}; "
                                   f"see {options.run_dir / 'router.log'}")
            time.sleep(0.05)
        print(f"[launch] started a Zenoh router on {self.endpoint} (pid {proc.pid})", flush=True)
        return proc

    async def before_start(self, spec: ProcessSpec) -> ProcessSpec:
        if is_master(spec):
            self._master_in_launch = True
        elif spec.ros_args and self._master_in_launch and not self._master_waited:
            self._master_waited = True  # once: a node started later or respawned just joins
            await self._wait_for_master()
        env = dict(spec.env)
        if spec.ros_args and self._master_in_launch and not is_master(spec):
            env[MASTER_IN_LAUNCH] = "1"  # the node waits briefly for master's services
        if self._meshed(spec):
            env.update(self._mesh_env(spec))
        elif "ZENROS_CONNECT" not in spec.env and "ZENROS_CONNECT" not in os.environ:
            env["ZENROS_CONNECT"] = self.endpoint
        return spec if env == spec.env else replace(spec, env=env)

    @staticmethod
    def _meshed(spec: ProcessSpec) -> bool:
        """A zenros process in peer mode on the default config (no Zenoh config file: one
        listens where its file says, for other hosts) whose endpoints the launch may choose."""
        mode = spec.env.get("ZENROS_MODE") or os.environ.get("ZENROS_MODE") or "peer"
        own = ("ZENROS_CONNECT", "ZENROS_LISTEN", "ZENROS_CONFIG")
        return ((spec.ros_args or bool(spec.components)) and mode == "peer"
                and not any(k in spec.env for k in own)
                and not any(k in os.environ for k in own[1:]))

    def _mesh_env(self, spec: ProcessSpec) -> dict[str, str]:
        """The launch's peers link by configured endpoints, not only by gossip: each listens
        on a loopback port of its own, kept across respawns, and connects to the router and
        to every peer started before it. Zenoh makes a lost link to a configured endpoint
        again, never one found by gossip (docs/zenoh-config.md, 'Known limit')."""
        key = (spec.namespace, spec.name, spec.origin)
        own = self._mesh.get(key) or f"tcp/127.0.0.1:{_free_port()}"
        earlier = [ep for k, ep in self._mesh.items() if k != key]
        self._mesh.setdefault(key, own)
        routers = [e for e in os.environ.get("ZENROS_CONNECT", "").split(",") if e.strip()]
        return {"ZENROS_LISTEN": own,
                "ZENROS_CONNECT": ",".join([*(routers or [self.endpoint]), *earlier])}

    async def _wait_for_master(self) -> None:
        """Hold the nodes after master until its parameter services are up (MASTER_WAIT s at
        most), so they read their stored parameters instead of each warning it is down."""
        if self.ctx is None:
            return
        client = ParameterClient(self.ctx)
        if client.wait_for_master(0):
            return
        print(f"[launch] waiting for master's parameter services before starting the other "
              f"nodes (at most {MASTER_WAIT:g} s)", flush=True)
        deadline = time.monotonic() + MASTER_WAIT
        while time.monotonic() < deadline:
            if await asyncio.to_thread(client.wait_for_master, READY_SLICE):
                return
        print(f"[launch] master is not up after {MASTER_WAIT:g} s; starting the other nodes "
              "anyway", flush=True)

    async def wait_ready(self, spec: ProcessSpec) -> bool:
        """A zenros node is up when its liveliness token is seen (a container when each of
        its components' is); other programs at once."""
        if not spec.ros_args or self.ctx is None:
            return True
        graph = self.ctx.graph
        deadline = time.monotonic() + READY_TIMEOUT
        waiting = [spec.fqn, *(c.fqn for c in spec.components)]
        # Short waits in a worker thread, so that cancelling this (the process ended, the
        # launch stops) ends the wait within one slice instead of holding the exit 20 s.
        while waiting:
            left = deadline - time.monotonic()
            if left <= 0:
                return False
            if await asyncio.to_thread(graph.wait_for_node, waiting[0], min(left, READY_SLICE)):
                waiting.pop(0)
        return True


def _stop(proc: subprocess.Popen[bytes]) -> None:
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
