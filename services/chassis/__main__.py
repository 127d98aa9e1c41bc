"""``python -m zenros.services.chassis``: run the simulated chassis."""

from zenros import run

from .node import ChassisNode

run(ChassisNode)
