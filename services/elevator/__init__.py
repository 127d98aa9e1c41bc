"""The elevator controller (docs/building.md, "The elevator controller"): one node simulating
every car of a building, shared by every robot in it (docs/robot-api.md §6.11)."""
