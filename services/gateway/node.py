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
from zenros.node import Node

from .fleet import Fleet
from .http.app import HttpApp
from .http.dashboard import dashboard_app
from .http.ws import ws_app
from .modbus.front import ModbusFront
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

    Parameters:
        host: address every server binds (default 127.0.0.1).
        rest_port, ws_port, modbus_port: TCP ports (3546, 3547, 3551; 0 picks a free one).
        config_file: the §1.4 JSON file (default $ZENROS_HOME/galileo_api/config.json).
        no_token_check: accept requests without a token (default false: tokens required).
        max_body: largest accepted request body in bytes (default 65536).
        api_version: the API version reported in /system/info and discovery.
        status_rate: GalileoStatus rate in Hz (default 30).
        deadman_timeout: seconds a speed command holds (default 0.5).
        startup_grace: seconds after start during which a backend (nav, tasks) not seen yet
            counts as starting: its 503s carry Retry-After (default 30).
        ws_ping_interval, ws_ping_timeout: the topic WebSocket pings every interval and
            closes a connection whose pong is later than the timeout (5 s, 10 s).
        ws_max_frame: largest WebSocket frame a client may send (1 MiB; larger: close 1009).
        serial_port: the §13 serial port (device path or pyserial URL); empty: no bridge.
        serial_baud: its baud rate (default 115200, 8N1).
        discovery_port: UDP port of the §1.3 broadcast (default 22002; -1 turns it off).
        discovery_address: where it goes (default: 127.0.0.1 when host is loopback,
            else 255.255.255.255).
        discovery_period: seconds between broadcasts (default 1).
        data_dir: where settings live (default $ZENROS_HOME/galileo_api/<robot>).
        rosbridge_port: rosbridge v2 for roslibpy/roslibjs and the dashboard (default 9090;
            -1 turns it off; docs/rosbridge.md).
        foxglove_port: the Foxglove server (needs zenros[foxglove]; default -1: off;
            docs/foxglove.md).
        fs_root: the folder the /fs API works in (default $ZENROS_HOME; docs/gateway.md).
        fs_max_upload: largest /fs upload in bytes (default 32 MiB).
        robots: a fleet gateway's robots (namespaces, one chunk each): the robot API of each
            under /api/v1/robots/<name>/ (docs/fleet.md); default [] (one robot: this node's
            namespace).
        discover_robots: also serve every robot that shows up in the graph (a namespace
            with a ``chassis`` node), as it appears (default false).
        default_robot: the robot the single-robot paths (/api/v1/..., ws://host:3547/<topic>,
            Modbus, serial, discovery) serve in a fleet (default: the first of ``robots``).
    """

    node_name = "gateway"

    def setup(self) -> None:
        host = self.declare_parameter("host", "127.0.0.1")
        rest_port = self.declare_parameter("rest_port", 3546)
        ws_port = self.declare_parameter("ws_port", 3547)
        modbus_port = self.declare_parameter("modbus_port", 3551)
        serial_port = self.declare_parameter("serial_port", "")
        discovery_port = self.declare_parameter("discovery_port", 22002)
        discovery_address = self.declare_parameter("discovery_address", "")
        discovery_period = self.declare_parameter("discovery_period", 1.0)
        config_file = self.declare_parameter("config_file", "")
        no_check = self.declare_parameter("no_token_check", False)
        max_body = self.declare_parameter("max_body", 65536)
        version = self.declare_parameter("api_version", "6.6.8")
        rate = self.declare_parameter("status_rate", 30.0)
        deadman = self.declare_parameter("deadman_timeout", 0.5)
        self.data_dir = Path(self.declare_parameter("data_dir", "") or self._default_dir())
        self.host = host
        config_path = Path(config_file) if config_file else default_config_path()
        config = load_config(config_path,
                             {"no_token_check": True} if no_check else None)
        files = FileRoot(data_dir(self.declare_parameter("fs_root", "")), [config_path],
                         self.declare_parameter("fs_max_upload", 32 * 1024 * 1024))
        self.options = RobotOptions(config, TokenStore(config), files, version, rest_port,
                                    rate, deadman, self.declare_parameter("startup_grace", 30.0),
                                    max_body)
        self.fleet = self._fleet()
        robot = self.fleet.default if self.fleet else Robot(self, self.data_dir, self.options)
        self.robots = self.fleet.robots if self.fleet else {robot.name: robot}
        self.robot = robot
        self.core, self.link, self.tasks, self.hub = robot.core, robot.link, robot.tasks, robot.hub
        self.navigator, self.nav_link, self.io = robot.navigator, robot.nav_link, robot.io
        self.files, self.speech, self.audio, self.api = files, robot.speech, robot.audio, robot.api
        self.runner = AsyncRunner()
        self.on_close(self.runner.stop)  # after every server on it has stopped
        self.rosbridge: RosbridgeServer | None = None
        rosbridge_port = self.declare_parameter("rosbridge_port", DEFAULT_ROSBRIDGE_PORT)
        if rosbridge_port >= 0:
            self.rosbridge = RosbridgeServer(self, host, rosbridge_port)
            self._close_on_loop(self.rosbridge.stop)
            self.runner.call(self.rosbridge.start())
        self.foxglove = self._start_foxglove(host, self.declare_parameter("foxglove_port", -1))
        self.http = HttpApp(self.fleet.api if self.fleet else self.api, dashboard_app(
            self.rosbridge.port if self.rosbridge else DEFAULT_ROSBRIDGE_PORT,
            robot.namespace, robots=self.fleet.names if self.fleet else None))
        self.rest_port = self.serve_asgi(self.http, host, rest_port)
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
            host, ws_port,
            ws_ping_interval=self.declare_parameter("ws_ping_interval", 5.0),
            ws_ping_timeout=self.declare_parameter("ws_ping_timeout", 10.0),
            ws_max_size=self.declare_parameter("ws_max_frame", 1 << 20))
        self.logger.info("topic WebSocket on ws://%s:%d/<topic>", host, self.ws_port)
        self.modbus = ModbusFront(self.core, self.logger, self.io.ext_bits)
        self._close_on_loop(self.modbus.stop)
        self.modbus_port = self.runner.call(self.modbus.start(host, modbus_port))
        self.logger.info("Modbus TCP on %s:%d", host, self.modbus_port)
        self.native = NativeCommands(self.core, self.logger, self.runner.loop)
        self.link.on_native = self.native
        self.serial: SerialBridge | None = None
        if serial_port:
            self.serial = self.own(SerialBridge(
                self.core, serial_port, self.logger,
                baud=self.declare_parameter("serial_baud", 115200)))
        else:
            self.logger.info("serial bridge off (parameter serial_port is empty)")
        if discovery_port >= 0:
            address = discovery_address or (
                "127.0.0.1" if host.startswith("127.") else "255.255.255.255")
            self.discovery: Discovery | None = Discovery(
                self.core, address, discovery_port or 22002, self.logger, discovery_period)
            self._close_on_loop(self.discovery.stop)
            self.runner.call(self.discovery.start())
            self.logger.info("discovery broadcast to %s:%d every %g s", address,
                             discovery_port or 22002, discovery_period)
        else:
            self.discovery = None
        if self.fleet is not None:
            self.fleet.start(self.runner.loop)

    def _fleet(self) -> Fleet | None:
        """The fleet when ``robots`` or ``discover_robots`` is set, else None (this node's
        namespace is the one robot)."""
        names = self.declare_parameter("robots", [])
        discover = self.declare_parameter("discover_robots", False)
        default = self.declare_parameter("default_robot", "")
        if names or discover:
            given = self.get_parameter("data_dir")
            home = Path(given) if given else self._default_dir().parent
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
