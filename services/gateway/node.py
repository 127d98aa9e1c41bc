"""`GatewayNode`: wires the robot API's front ends (REST, WebSocket, Modbus, serial, UDP) to zenros."""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path
from typing import Any

from zenros.errors import ConfigError
from zenros.home import data_dir
from zenros.memory import keep_freed_buffers
from zenros.node import Node

from .diagnostics import gateway_diagnostics
from .fleet import Fleet
from .front_ends import AsgiServer, Door, FrontEnds
from .http.app import HttpApp
from .http.dashboard import dashboard_app
from .http.routes.mapping import NativeMapping
from .http.ws import ws_app
from .http.ws_protocol import SlicedWebSocketProtocol
from .modbus.front import ModbusFront
from .params import GatewayParameters
from .ports.certificate import load_tls
from .ports.fs_sandbox import FileRoot
from .ports.native import NativeCommands
from .robot import Robot, RobotOptions
from .rosbridge import DEFAULT_PORT as DEFAULT_ROSBRIDGE_PORT
from .rosbridge import RosbridgeServer
from .runner import AsyncRunner
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
        self.host = p.host
        self.data_dir = Path(p.data_dir or self._default_dir())
        config_path = Path(p.config_file) if p.config_file else default_config_path()
        config = load_config(config_path,
                             {"no_token_check": True} if p.no_token_check else None)
        files = FileRoot(data_dir(p.fs_root), [config_path], p.fs_max_upload)
        if bool(p.tls_cert) != bool(p.tls_key):
            raise ConfigError("give both tls_cert and tls_key (HTTPS), or neither")
        if p.tls_cert:
            try:
                load_tls(p.tls_cert, p.tls_key)
            except ValueError as exc:
                raise ConfigError(str(exc)) from exc
        self.options = RobotOptions(config, TokenStore(config), files, p.api_version,
                                    p.rest_port, p.status_rate, p.deadman_timeout,
                                    p.startup_grace, p.max_body, p.launch_control, p.tls_cert)
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
        self.front_ends = FrontEnds(self.runner, self.logger)
        self.on_close(self.front_ends.stop)  # the doors, in reverse of their start
        self._start_doors(p, robot)
        if self.fleet is not None:
            self.fleet.start(self.runner.loop)
        self.diagnostics = gateway_diagnostics(self)  # front ends, clients on /diagnostics

    def _start_doors(self, p: GatewayParameters, robot: Robot) -> None:
        """Start the front ends in order: rosbridge, Foxglove, REST, the topic WebSocket,
        Modbus, serial, discovery (each off when its parameter says so)."""
        host, start = p.host, self.front_ends.start
        self.rosbridge: RosbridgeServer | None = None
        if p.rosbridge_port >= 0:
            self.rosbridge = RosbridgeServer(self, host, p.rosbridge_port)
            start(self.rosbridge)
        self.foxglove = self._foxglove(host, p.foxglove_port)
        if self.foxglove is not None:
            start(self.foxglove)
        self.http = HttpApp(self.fleet.api if self.fleet else self.api, dashboard_app(
            self.rosbridge.port if self.rosbridge else DEFAULT_ROSBRIDGE_PORT,
            robot.namespace, robots=self.fleet.names if self.fleet else None,
            schedule_server=p.schedule_server))
        rest = AsgiServer("REST", self.http, host, p.rest_port, **self._tls(p))
        self.rest_port = rest.port
        if self.fleet is not None:
            self.fleet.set_port(self.rest_port)
        else:
            self.core.identity = replace(self.core.identity, port=self.rest_port)
        start(rest)
        self.logger.info("REST API on %s://%s:%d/api/v1 (token check %s)",
                         "https" if p.tls_cert else "http", host,
                         self.rest_port, "on" if self.core.tokens.checking else "off")
        if self.fleet is not None:
            self.logger.info("fleet gateway: %s; the single-robot paths serve %s",
                             ", ".join(self.robots), robot.name)
        ws = AsgiServer(
            "topic WebSocket",
            ws_app(self.hub, self.core.tokens, self.fleet.hub_of if self.fleet else None),
            host, p.ws_port, ws_ping_interval=p.ws_ping_interval,
            ws_ping_timeout=p.ws_ping_timeout, ws_max_size=p.ws_max_frame,
            ws=SlicedWebSocketProtocol)
        self.ws_port = ws.port
        start(ws)
        self.logger.info("topic WebSocket on ws://%s:%d/<topic>", host, self.ws_port)
        self.modbus = ModbusFront(self.core, self.logger, self.io.ext_bits,
                                  self.robot.context.asr)

        async def start_modbus() -> None:
            self.modbus_port = await self.modbus.start(host, p.modbus_port)

        start(Door("Modbus", start_modbus, self.modbus.stop))
        self.logger.info("Modbus TCP on %s:%d", host, self.modbus_port)
        self.native = NativeCommands(self.core, self.logger, self.runner.loop,
                                     NativeMapping(robot.context))
        self.topics.on_native = self.native
        self.serial: SerialBridge | None = None
        if p.serial_port:
            def start_serial() -> None:
                self.serial = SerialBridge(self.core, p.serial_port, self.logger,
                                           baud=p.serial_baud)

            def stop_serial() -> None:
                if self.serial is not None:
                    self.serial.close()

            start(Door("serial", start_serial, stop_serial))
        else:
            self.logger.info("serial bridge off (parameter serial_port is empty)")
        self.discovery: Discovery | None = None
        if p.discovery_port >= 0:
            address = p.discovery_address or (
                "127.0.0.1" if host.startswith("127.") else "255.255.255.255")
            port = p.discovery_port or 22002
            self.discovery = Discovery(self.core, address, port, self.logger,
                                       p.discovery_period)
            start(Door("discovery", self.discovery.start, self.discovery.stop))
            self.logger.info("discovery broadcast to %s:%d every %g s", address, port,
                             p.discovery_period)

    @staticmethod
    def _tls(p: GatewayParameters) -> dict[str, str]:
        """uvicorn's HTTPS settings: the certificate and key, when given."""
        return {"ssl_certfile": p.tls_cert, "ssl_keyfile": p.tls_key} if p.tls_cert else {}

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

    def _foxglove(self, host: str, port: int) -> Any:
        """The Foxglove bridge (a front end), or None when off or foxglove-sdk is missing."""
        if port < 0:
            return None
        try:
            from .foxglove.bridge import FoxgloveBridge
        except ImportError as exc:
            self.logger.error("Foxglove off: foxglove-sdk is not installed (pip install "
                              "'zenros[foxglove]'): %s", exc)
            return None
        return FoxgloveBridge(self, host, port)

    def _default_dir(self) -> Path:
        home = Path(os.environ.get("ZENROS_HOME") or Path.home() / ".zenros")
        robot = self.namespace.strip("/").replace("/", "_") or "robot"
        return home / "galileo_api" / robot
