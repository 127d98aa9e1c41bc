"""``python -m zenros.container``: several nodes in one process, as a ROS 2 component container.

The container is a node of its own (``--name``, default ``container``) and builds each
``--component`` on its Zenoh session, in order: a message between two of its nodes is handed
over in-process (no serialization, no Zenoh), and the process keeps one session, one link to
the router and one set of Zenoh threads for all of them. A launch file declares it with
``container:`` and ``components:`` (docs/launch.md); each component is JSON::

    {"plugin": "zenros.services.chassis.node:ChassisNode", "name": "chassis",
     "namespace": "/robot1", "remaps": [["/tf", "tf"]],
     "params": [{"map": "office.yaml"}, "/path/to/params.yaml"]}

``params`` apply in order, later winning, as a launch file's ``params`` do. A component that
cannot be built (a bad plugin, its own startup failure) stops the container with exit code 3,
the nodes built before it closed in reverse order.
"""

from __future__ import annotations

import argparse
import importlib
from collections.abc import Sequence
from typing import Any

import msgspec

from .context import Context
from .errors import ConfigError
from .names import Remapper, join
from .node import Node
from .params import flatten, load_params_file
from .runtime import add_node_arguments, node_kwargs, serve

__all__ = ["Component", "ComponentError", "load_plugin", "main"]


class ComponentError(ConfigError):
    """A component that cannot be built: malformed JSON, an unknown plugin, a bad name (a
    configuration error: exit code 3)."""


class Component(msgspec.Struct, forbid_unknown_fields=True):
    """One node the container builds (the JSON of a ``--component`` argument)."""

    plugin: str
    name: str
    namespace: str = "/"
    remaps: list[tuple[str, str]] = msgspec.field(default_factory=list)
    params: list[dict[str, Any] | str] = msgspec.field(default_factory=list)

    @classmethod
    def parse(cls, text: str) -> Component:
        try:
            return msgspec.json.decode(text, type=cls)
        except msgspec.DecodeError as exc:
            raise ComponentError(f"bad --component {text[:80]!r}: {exc}") from None

    def overrides(self) -> dict[str, Any]:
        """The parameters ``params`` give this node, in order (later items win)."""
        fqn = join(self.namespace, self.name)
        out: dict[str, Any] = {}
        for item in self.params:
            out.update(load_params_file(item, fqn) if isinstance(item, str) else flatten(item))
        return out


class ComponentContainer(Node):
    """The container's own node: it owns the process; its components are nodes beside it."""

    node_name = "container"


def load_plugin(plugin: str) -> type[Node]:
    """The node class ``package.module:Class`` names.

    Raises:
        ComponentError: the module does not import, has no such class, or it is no Node.
    """
    module_name, _, cls_name = plugin.partition(":")
    if not module_name or not cls_name:
        raise ComponentError(f"plugin {plugin!r}: expected package.module:Class")
    try:
        module = importlib.import_module(module_name)
    except ImportError as exc:
        raise ComponentError(f"plugin {plugin!r}: cannot import {module_name}: {exc}") from exc
    cls = getattr(module, cls_name, None)
    if not (isinstance(cls, type) and issubclass(cls, Node)):
        raise ComponentError(f"plugin {plugin!r}: {module_name} has no Node class {cls_name}")
    return cls


def build(ctx: Context, args: argparse.Namespace) -> list[Node]:
    """The container node, then each component in order (see `zenros.runtime.Build`)."""
    components = [Component.parse(text) for text in args.component]
    classes = [load_plugin(c.plugin) for c in components]  # all found before any is built
    nodes: list[Node] = [ComponentContainer(context=ctx, **node_kwargs(args))]
    try:
        for c, cls in zip(components, classes, strict=True):
            nodes.append(cls(c.name, namespace=c.namespace, context=ctx,
                             remappings=Remapper.parse([f"{a}:={b}" for a, b in c.remaps]),
                             parameter_overrides=c.overrides()))
            nodes[0].logger.info("loaded %s as %s", c.plugin, nodes[-1].fqn)
    except BaseException:
        for made in reversed(nodes):
            made.close()
        raise
    return nodes


def main(argv: Sequence[str] | None = None) -> int:
    """Run the container until SIGINT/SIGTERM; the exit codes of `zenros.runtime.main`."""
    parser = argparse.ArgumentParser(prog="zenros.container", description=__doc__.split("\n")[0])
    add_node_arguments(parser)
    parser.add_argument("--component", action="append", default=[], metavar="JSON",
                        help="a node to build in this process (repeatable; see the module doc)")
    return serve(parser, build, argv)


if __name__ == "__main__":
    raise SystemExit(main())
