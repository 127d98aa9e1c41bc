"""``python -m zenros.services.master``: run the parameter server and registry."""

from zenros import run

from .node import MasterNode

run(MasterNode)
