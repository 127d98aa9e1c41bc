"""``python -m zenros.services.rmw_zenoh``: run the rmw_zenoh bridge."""

from zenros import run

from .bridge import RmwZenohBridge

run(RmwZenohBridge)
