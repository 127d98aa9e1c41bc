"""``python -m zenros.services.slam``: run the mapping service."""

from zenros import run

from .node import SlamNode

run(SlamNode)
