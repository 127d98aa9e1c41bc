"""``python -m zenros.services.schedule``: run the schedule server."""

from zenros import run

from .node import ScheduleServerNode

run(ScheduleServerNode)
