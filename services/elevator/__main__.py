"""``python -m zenros.services.elevator -p building:=PATH``: run the elevator controller."""

from zenros import run

from .node import ElevatorNode

run(ElevatorNode)
