"""``python -m zenros.services.gateway.foxglove``: the Foxglove server on its own."""

from zenros import run

from .node import FoxgloveNode

run(FoxgloveNode)
