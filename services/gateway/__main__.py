"""``python -m zenros.services.gateway``: run the protocol gateway."""

from zenros import run

from .node import GatewayNode

run(GatewayNode)
