"""`Core`: the gateway's shared state that every protocol front end reads and commands."""

from __future__ import annotations

import hashlib
import socket
import threading
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

from zenros.msgs.galileo_msgs import GalileoStatus

from .config import GatewayConfig
from .deadman import DeadMan
from .presence import Presence
from .settings import Settings
from .status import RobotState, compose_status
from .tokens import TokenStore

__all__ = ["Core", "Identity", "NativeSink", "NavPort", "NavUnavailable", "make_identity"]


@dataclass(frozen=True)
class Identity:
    """Who this robot is on the network (docs/robot-api.md §1.3, §3.1 ``info``)."""

    id: str
    mac: str
    version: str
    code_name: str
    port: int


def make_identity(namespace: str, version: str, port: int) -> Identity:
    """A stable id per host and robot namespace, and the host's MAC address."""
    node = uuid.getnode()
    mac = ":".join(f"{(node >> s) & 0xFF:02x}" for s in range(40, -8, -8))
    digest = hashlib.sha256(f"{socket.gethostname()}|{mac}|{namespace}".encode()).hexdigest()
    return Identity(id=digest[:40].upper(), mac=mac, version=version, code_name="zenros",
                    port=port)


class NativeSink(Protocol):
    def __call__(self, data: bytes) -> None: ...


class NavUnavailable(Exception):
    """The navigation service the command needs is not running (yet)."""


class NavPort(Protocol):
    """What the front ends ask of navigation: coroutines that start work at a distance.

    Each raises `NavUnavailable` when nav is not there, ValueError for a bad argument.
    """

    def open(self) -> None: ...
    async def stop(self) -> None: ...
    async def goto_pose(self, x: float, y: float, theta: float) -> None: ...
    async def goto_index(self, index: int) -> None: ...
    async def cancel(self) -> None: ...
    async def pause(self) -> None: ...
    async def resume(self) -> None: ...
    async def go_charge(self) -> None: ...
    async def stop_charge(self) -> None: ...


class Core:
    """Robot state, the latest GalileoStatus, the dead-man speed command, tokens, settings.

    The zenros side (`robot_topics.RobotTopics`) feeds `state` and calls `refresh()` at 30 Hz; REST,
    WebSocket, Modbus and serial read `status` and command through `deadman` and `native`.
    """

    def __init__(self, config: GatewayConfig, settings: Settings, identity: Identity,
                 deadman_timeout: float = 0.5, startup_grace: float = 30.0,
                 tokens: TokenStore | None = None) -> None:
        self.config = config
        self.settings = settings
        self.identity = identity
        self.tokens = tokens or TokenStore(config)  # a fleet gateway's robots share one
        self.state = RobotState()
        self.deadman = DeadMan(deadman_timeout)
        self._seq = 0
        self.status: GalileoStatus = compose_status(self.state, 0, time.time_ns())
        self.status_listeners: list[Callable[[GalileoStatus], None]] = []
        self.native: NativeSink | None = None   # where native command bytes go (§12)
        # optional backends: "maps" -> async () -> (map names, current map)
        self.services: dict[str, Any] = {}
        self.nav: NavPort | None = None
        self.presence = Presence(startup_grace)  # which backends are starting, up, gone
        self._lock = threading.Lock()

    def refresh(self, stamp_ns: int | None = None) -> GalileoStatus:
        """Compose a new GalileoStatus, keep it as `status` and tell the listeners."""
        with self._lock:
            self._seq += 1
            st = compose_status(self.state, self._seq,
                                time.time_ns() if stamp_ns is None else stamp_ns)
            self.status = st
        for fn in list(self.status_listeners):
            fn(st)
        return st

    def navigation(self) -> NavPort:
        """The navigation port, or `NavUnavailable`."""
        if self.nav is None:
            raise NavUnavailable("navigation is not available: the nav service is not running")
        return self.nav

    def send_native(self, data: bytes) -> None:
        """Hand a §12.3 native command to the robot (``galileo/cmds``)."""
        if self.native is None:
            raise RuntimeError("native commands are not wired")
        self.native(data)
