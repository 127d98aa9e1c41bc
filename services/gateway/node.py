"""`GatewayNode`: wires the robot API's front ends (REST, WebSocket, Modbus, serial, UDP) to zenros."""

from __future__ import annotations

import asyncio
import os
from collections.abc import Callable, Coroutine
from dataclasses import replace
from pathlib import Path
from typing import Any

from starlette.types import ASGIApp
from zenros.errors import ConfigError
from zenros.home import data_dir
from zenros.memory import keep_freed_buffers
from zenros.node import Node

from .fleet import Fleet
from .http.app import HttpApp
from .http.dashboard import dashboard_app
from .http.ws import ws_app
from .http.ws_protocol import SlicedWebSocketProtocol
from .modbus.front import ModbusFront
from .params import GatewayParameters
from .ports.fs_sandbox import FileRoot
from .ports.native import NativeCommands
from .robot import Robot, RobotOptions
from .rosbridge import DEFAULT_PORT as DEFAULT_ROSBRIDGE_PORT
from .rosbridge import RosbridgeServer
from .runner import AsyncRunner, bind_tcp, start_uvicorn
from .serial.bridge import SerialBridge
from .state.config import default_config_path, load_config
from .state.tokens import TokenStore
from .udp.discovery import Discovery

__all__ = ["GatewayNode"]


class GatewayNode(Node):
    """The protocol gateway of one robot (its namespace), or of a fleet (``robots``,
    ``discover_robots``): docs/robot-api.md over the network.

    Parameters: `GatewayParameters` (zenros.services.gateway.params), read once at start.
    """

    node_name = "gateway"

    def setup(self) -> None:
        keep_freed_buffers()  # large frames reuse mapped memory (zenros.memory)
        p = self.params = self.declare_parameters(GatewayParameters)
        host = self.host = p.host
        self.data_dir = Path(p.data_dir or self._default_dir())
        config_path = Path(p.config_file) if p.config_file else default_config_path()
        config = load_config(config_path,
                             {"no_token_check": True} if p.no_token_check else None)
        files = FileRoot(data_dir(p.fs_root), [config_path], p.fs_max_upload)
        self.options = RobotOptions(config, TokenStore(config), files, p.api_version,
                                    p.rest_port, p.status_rate, p.deadman_timeout,
                                    p.startup_grace, p.max_body)
        self.fleet = self._fleet()
        robot = self.fleet.default if self.fleet else Robot(self, self.data_dir, self.options)
        self.robots = self.fleet.robots if self.fleet else {robot.name: robot}
        self.robot = robot
        self.core, self.topics, self.tasks, self.hub = (robot.core, robot.topics, robot.tasks,
                                                        robot.hub)
        self.nav_actions, self.nav_services, self.io = (robot.nav_actions, robot.nav_services,
                                                        robot.io)
        self.files, self.speech, self.audio, self.api = files, robot.speech, robot.audio, robot.api
        self.runner = AsyncRunner()
        self.on_close(self.runner.stop)  # after every server on it has stopped
        self.rosbridge: RosbridgeServer | None = None
        if p.rosbridge_port >= 0:
            self.rosbridge = RosbridgeServer(self, host, p.rosbridge_port)
            self._close_on_loop(self.rosbridge.stop)
            self.runner.call(self.rosbridge.start())
        self.foxglove = self._start_foxglove(host, p.foxglove_port)
        self.http = HttpApp(self.fleet.api if self.fleet else self.api, dashboard_app(
            self.rosbridge.port if self.rosbridge else DEFAULT_ROSBRIDGE_PORT,
            robot.namespace, robots=self.fleet.names if self.fleet else None))
        self.rest_port = self.serve_asgi(self.http, host, p.rest_port)
        if self.fleet is not None:
            self.fleet.set_port(self.rest_port)
        else:
            self.core.identity = replace(self.core.identity, port=self.rest_port)
        self.logger.info("REST API on http://%s:%d/api/v1 (token check %s)", host,
                         self.rest_port, "on" if self.core.tokens.checking else "off")
        if self.fleet is not None:
            self.logger.info("fleet gateway: %s; the single-robot paths serve %s",
                             ", ".join(self.robots), robot.name)
        self.ws_port = self.serve_asgi(
            ws_app(self.hub, self.core.tokens, self.fleet.hub_of if self.fleet else None),
            host, p.ws_port, ws_ping_interval=p.ws_ping_interval,
            ws_ping_timeout=p.ws_ping_timeout, ws_max_size=p.ws_max_frame,
            ws=SlicedWebSocketProtocol)
        self.logger.info("topic WebSocket on ws://%s:%d/<topic>", host, self.ws_port)
        self.modbus = ModbusFront(self.core, self.logger, self.io.ext_bits)
        self._close_on_loop(self.modbus.stop)
        self.modbus_port = self.runner.call(self.modbus.start(host, p.modbus_port))
        self.logger.info("Modbus TCP on %s:%d", host, self.modbus_port)
        self.native = NativeCommands(self.core, self.logger, self.runner.loop)
        self.topics.on_native = self.native
        self.serial: SerialBridge | None = None
        if p.serial_port:
            self.serial = self.own(SerialBridge(self.core, p.serial_port, self.logger,
                                                baud=p.serial_baud))
        else:
            self.logger.info("serial bridge off (parameter serial_port is empty)")
        if p.discovery_port >= 0:
            address = p.discovery_address or (
                "127.0.0.1" if host.startswith("127.") else "255.255.255.255")
            port = p.discovery_port or 22002
            self.discovery: Discovery | None = Discovery(
                self.core, address, port, self.logger, p.discovery_period)
            self._close_on_loop(self.discovery.stop)
            self.runner.call(self.discovery.start())
            self.logger.info("discovery broadcast to %s:%d every %g s", address, port,
                             p.discovery_period)
        else:
            self.discovery = None
        if self.fleet is not None:
            self.fleet.start(self.runner.loop)

    def _fleet(self) -> Fleet | None:
        """The fleet when ``robots`` or ``discover_robots`` is set, else None (this node's
        namespace is the one robot)."""
        p = self.params
        names, discover, default = p.robots, p.discover_robots, p.default_robot
        if names or discover:
            home = Path(p.data_dir) if p.data_dir else self._default_dir().parent
            return Fleet(self, self.options, home, names, default, discover)
        if default:
            raise ConfigError("default_robot is set, but neither robots nor discover_robots: "
                              "a single-robot gateway serves its own namespace")
        return None

    def _start_foxglove(self, host: str, port: int) -> Any:
        if port < 0:
            return None
        try:
            from .foxglove.bridge import FoxgloveBridge
        except ImportError as exc:
            self.logger.error("Foxglove off: foxglove-sdk is not installed (pip install "
                              "'zenros[foxglove]'): %s", exc)
            return None
        bridge = FoxgloveBridge(self, host, port)
        self.on_close(bridge.stop)
        bridge.start()
        return bridge

    def _default_dir(self) -> Path:
        home = Path(os.environ.get("ZENROS_HOME") or Path.home() / ".zenros")
        robot = self.namespace.strip("/").replace("/", "_") or "robot"
        return home / "galileo_api" / robot

    def serve_asgi(self, app: ASGIApp, host: str, port: int, **kw: Any) -> int:
        """Serve an ASGI app with uvicorn on the gateway's loop; returns the bound port."""
        sock = self.own(bind_tcp(host, port))
        server, task = self.runner.call(start_uvicorn(app, sock, **kw))

        async def stop() -> None:
            server.should_exit = True
            await asyncio.gather(task, return_exceptions=True)

        self._close_on_loop(stop)
        bound: int = sock.getsockname()[1]
        return bound

    def _close_on_loop(self, stop: Callable[[], Coroutine[Any, Any, object]]) -> None:
        """Run ``stop()`` on the gateway's loop when the node closes (`Node.on_close`)."""
        self.on_close(lambda: self.runner.call(stop(), 8.0))
