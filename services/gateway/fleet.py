"""`Fleet`: the robots one gateway serves: each built on a `RobotView` of its namespace,
configured at start or found in the graph later, and their API (`FleetApi`)."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from zenros.errors import ConfigError, NodeClosedError
from zenros.node import Node

from .http.fleet import ROBOTS, FleetApi
from .ports.topic_hub import TopicError, TopicHub
from .robot import Robot, RobotOptions, RobotView, robot_name

__all__ = ["LOOK_PERIOD", "Fleet"]

LOOK_PERIOD = 2.0
"""Seconds between two looks at the graph for robots not served yet, besides the look each
graph change asks for: a robot whose change was missed, or that could not be built, is
served at the next look (a ten-robot fleet on a loaded box once left one robot unserved)."""


class Fleet:
    """The robots of a fleet gateway (``node``, in the root namespace) and their API.

    Args:
        node: the gateway; each robot's `RobotView` is its own (closed with it).
        options: what the robots share.
        data_home: where each robot's settings go (``<data_home>/<robot>/``).
        names: the robots to serve from the start (validated: one chunk each).
        default: the robot of the single-robot paths (default: the first of ``names``).
        discover: also serve every robot that shows up in the graph (`start`).

    Raises:
        ConfigError: a bad name, or nothing to name the default robot by.
    """

    def __init__(self, node: Node, options: RobotOptions, data_home: Path,
                 names: Sequence[object], default: str, discover: bool) -> None:
        self.node = node
        self.options = options
        self.data_home = data_home
        chosen = [robot_name(n) for n in names]
        default = robot_name(default) if default else (chosen[0] if chosen else "")
        if not default:
            raise ConfigError("discover_robots without default_robot (or robots): name the "
                              "robot the single-robot paths serve, e.g. default_robot: robot1")
        self.robots: dict[str, Robot] = {}
        self.api = FleetApi(options.tokens, default, self.discover if discover else None)
        self.discovers = discover
        self._pending = threading.Event()  # a look at the graph is on its way
        self._loop: asyncio.AbstractEventLoop | None = None
        self._failed: dict[str, str] = {}  # robot -> why it could not be built (logged once)
        for name in dict.fromkeys([*chosen, default]):
            self.add(name)

    @property
    def default(self) -> Robot:
        return self.robots[self.api.default]

    def add(self, name: str) -> Robot:
        """Serve robot ``name``: its ports on a `RobotView` (``/<name>/gateway``)."""
        view = self.node.own(RobotView(f"/{name}", self.node.context, self.data_home / name,
                                       self.options))
        robot = self.robots[name] = view.robot
        self.api.add(name, robot.api)
        return robot

    def set_port(self, port: int) -> None:
        """The REST port bound: every robot's identity (and those to come) says it."""
        self.options = replace(self.options, rest_port=port)
        for robot in self.robots.values():
            robot.core.identity = replace(robot.core.identity, port=port)

    def start(self, loop: asyncio.AbstractEventLoop) -> None:
        """With ``discover``: look at the graph on ``loop`` now and after each change."""
        if not self.discovers:
            return
        self._loop = loop
        graph = self.node.context.graph
        self.node.on_close(graph.add_listener(lambda ev, tok: self._discover_soon()))
        self._discover_soon()  # the robots already there
        loop.call_soon_threadsafe(self._look_again)

    def _look_again(self) -> None:  # on the loop, every LOOK_PERIOD until the node closes
        if self.node.closed or self._loop is None:
            return
        self.discover()
        self._loop.call_later(LOOK_PERIOD, self._look_again)

    def _discover_soon(self) -> None:  # on Zenoh's thread: the work goes to the loop
        if self._loop is None or self.node.closed or self._pending.is_set():
            return  # a look at the graph is already on its way: it sees this change too
        self._pending.set()
        self._loop.call_soon_threadsafe(self.discover)

    def discover(self) -> None:
        """Serve every robot the graph shows (a namespace of one chunk with a ``chassis``
        node) that is not served yet. On the gateway's loop."""
        self._pending.clear()
        if not self.discovers or self.node.closed:
            return
        for ns in sorted({n.name.rsplit("/", 1)[0] for n in self.node.graph.nodes()
                          if n.name.endswith("/chassis")}):
            name = ns.strip("/")
            if not name or "/" in name or name in self.robots:
                continue  # a robot's name is one chunk: /robots/<name>/... in the URL
            try:
                self.add(name)
            except NodeClosedError:
                return
            except Exception as exc:  # one robot that cannot be built never stops the others
                why = f"{type(exc).__name__}: {exc}"
                if self._failed.get(name) != why:  # tried again at each look: logged once
                    self._failed[name] = why
                    self.node.logger.exception("cannot serve robot %s (tried again every "
                                               "%g s)", name, LOOK_PERIOD)
                continue
            self._failed.pop(name, None)
            self.node.logger.info("serving robot %s (found in the graph)", name)

    def names(self) -> list[str]:
        """The robots served now, after a look at the graph."""
        self.discover()
        return list(self.robots)

    def hub_of(self, path: str) -> tuple[TopicHub, str]:
        """The topic WebSocket's hub and topic for a URL path: ``robots/<name>/<topic>`` is
        robot ``name``'s, any other path the default robot's.

        Raises:
            TopicError: no robot ``name`` on this gateway.
        """
        rest = path.strip("/")
        if rest.startswith("robots/"):
            name, _, topic = rest[len("robots/"):].partition("/")
            robot = self.robots.get(name)
            if robot is None:
                raise TopicError(f"no robot {name!r} on this gateway "
                                 f"(GET {ROBOTS} lists its robots)")
            return robot.hub, topic
        return self.default.hub, rest
