"""`GatewayParameters`: the gateway node's parameters, their only defaults and their limits.

`GatewayNode` declares them with ``declare_parameters(GatewayParameters)``, so
``zenros param describe /gateway`` shows each one's range and meaning. The servers read them
once, at start: a change made later is stored and takes effect at the next start.
"""

from __future__ import annotations

from typing import Annotated, Any

import msgspec
from msgspec import Meta

__all__ = ["GatewayParameters"]

Port = Annotated[int, Meta(ge=0, le=65535)]
OptionalPort = Annotated[int, Meta(ge=-1, le=65535)]


class GatewayParameters(msgspec.Struct, kw_only=True):
    """The gateway's parameters (docs/gateway.md, "Ports and parameters")."""

    host: Annotated[str, Meta(
        description="address every server binds (0.0.0.0: every interface)")] = "127.0.0.1"
    rest_port: Annotated[Port, Meta(
        description="REST API /api/v1 and the dashboard (0 picks a free port)")] = 3546
    ws_port: Annotated[Port, Meta(
        description="topic WebSocket (0 picks a free port)")] = 3547
    modbus_port: Annotated[Port, Meta(
        description="Modbus TCP (0 picks a free port)")] = 3551
    serial_port: Annotated[str, Meta(
        description="serial bridge device path or pyserial URL (empty: no bridge)")] = ""
    serial_baud: Annotated[int, Meta(gt=0, description="serial baud rate (8N1)")] = 115200
    discovery_port: Annotated[OptionalPort, Meta(
        description="UDP port of the discovery broadcast (-1: off; 0: 22002)")] = 22002
    discovery_address: Annotated[str, Meta(
        description="where the broadcast goes (empty: 127.0.0.1 when host is loopback, else "
                    "255.255.255.255)")] = ""
    discovery_period: Annotated[float, Meta(
        gt=0, description="seconds between discovery broadcasts")] = 1.0
    config_file: Annotated[str, Meta(
        description="the server configuration file (empty: "
                    "$ZENROS_HOME/galileo_api/config.json)")] = ""
    no_token_check: Annotated[bool, Meta(
        description="accept requests without a token (false: tokens required unless the "
                    "configuration file says otherwise)")] = False
    max_body: Annotated[int, Meta(gt=0, description="largest request body, bytes")] = 65536
    api_version: Annotated[str, Meta(
        description="API version reported in /system/info and discovery")] = "6.6.8"
    status_rate: Annotated[float, Meta(
        gt=0, description="GalileoStatus rate, Hz of wall time")] = 30.0
    deadman_timeout: Annotated[float, Meta(
        gt=0, description="seconds a speed command holds")] = 0.5
    data_dir: Annotated[str, Meta(
        description="where settings live (empty: $ZENROS_HOME/galileo_api/<robot>)")] = ""
    startup_grace: Annotated[float, Meta(
        ge=0, description="seconds after start during which a backend not seen yet counts "
                          "as starting (503 with Retry-After)")] = 30.0
    tls_cert: Annotated[str, Meta(
        description="a PEM certificate: the REST API is served over HTTPS with it and "
                    "tls_key (empty: plain HTTP); /system/check_cert reads it")] = ""
    tls_key: Annotated[str, Meta(description="the certificate's PEM private key")] = ""
    launch_control: Annotated[str, Meta(
        description="the launch supervising the robot, whose NAME/restart and NAME/shutdown "
                    "/system/restart_robot and /system/shutdown call (zenros launch "
                    "--control)")] = "/launch"
    fs_root: Annotated[str, Meta(
        description="the folder the /fs API works in (empty: $ZENROS_HOME)")] = ""
    fs_max_upload: Annotated[int, Meta(
        gt=0, description="largest /fs upload, bytes")] = 32 * 1024 * 1024
    rosbridge_port: Annotated[OptionalPort, Meta(
        description="rosbridge v2 for roslibpy/roslibjs and the dashboard (-1: off; 0 picks "
                    "a free port)")] = 9090  # zenros.services.gateway.rosbridge.DEFAULT_PORT
    foxglove_port: Annotated[OptionalPort, Meta(
        description="the Foxglove server, needs zenros[foxglove] (-1: off; 0 picks a free "
                    "port)")] = -1
    ws_ping_interval: Annotated[float, Meta(
        gt=0, description="seconds between the topic WebSocket's pings")] = 5.0
    ws_ping_timeout: Annotated[float, Meta(
        gt=0, description="seconds a pong may be late before the connection is closed")] = 10.0
    ws_max_frame: Annotated[int, Meta(
        gt=0, description="largest WebSocket frame a client may send, bytes (larger: close "
                          "1009)")] = 1 << 20
    # names are checked by the fleet (one chunk each), which names the bad one
    robots: Annotated[list[Any], Meta(
        description="a fleet gateway's robots (namespaces): the robot API of each under "
                    "/api/v1/robots/<name>/ (docs/fleet.md); empty: one robot, this node's "
                    "namespace")] = msgspec.field(default_factory=list)
    discover_robots: Annotated[bool, Meta(
        description="also serve every robot that shows up in the graph (a namespace with a "
                    "chassis node)")] = False
    schedule_server: Annotated[str, Meta(
        pattern=r"^[A-Za-z0-9_]{0,64}$",
        description="a fleet's schedule server whose traffic reservations the dashboard's "
                    "fleet view draws (docs/fleet.md, 'Traffic schedule'; empty: none)")] = "local"
    default_robot: Annotated[str, Meta(
        description="the robot the single-robot paths (/api/v1/..., the topic WebSocket, "
                    "Modbus, serial, discovery) serve in a fleet (empty: the first of "
                    "robots)")] = ""
