"""The docs/robot-api.md §1.3 UDP door: the discovery broadcast."""
