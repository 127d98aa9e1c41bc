"""``python -m zenros.services.gateway.rosbridge``: the rosbridge server on its own."""

from zenros import run

from .node import RosbridgeNode

run(RosbridgeNode)
