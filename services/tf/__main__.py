"""``python -m zenros.services.tf``: run the TF buffer server."""

from zenros import run

from .node import TfNode

run(TfNode)
