"""``python -m zenros.services.diagnostics``: run the diagnostics aggregator."""

from zenros import run

from .node import AggregatorNode

run(AggregatorNode)
