"""``python -m zenros.services.nav``: run the navigation service."""

from zenros import run

from .node import NavNode

run(NavNode)
