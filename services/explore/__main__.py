"""``python -m zenros.services.explore``: run the exploration service."""

from zenros import run

from .node import ExploreNode

run(ExploreNode)
