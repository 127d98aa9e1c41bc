"""Small worlds for the chassis unit tests."""

from __future__ import annotations

import numpy as np
import pytest
from zenros.maps import GridMap
from zenros.services.chassis.world import World


def box_world(width: int = 100, height: int = 60, res: float = 0.05) -> World:
    """A free room with one-cell walls all round; origin at the lower-left corner (0, 0)."""
    grid = np.zeros((height, width), np.int8)
    grid[0, :] = grid[-1, :] = grid[:, 0] = grid[:, -1] = 100
    return World(GridMap(grid, res, (0.0, 0.0, 0.0)))


@pytest.fixture
def room() -> World:
    """5 m x 3 m inside walls: free space from x = 0.05 to 4.95 and y = 0.05 to 2.95."""
    return box_world()


@pytest.fixture
def hall() -> World:
    """20 m x 10 m inside walls: free space from x = 0.05 to 19.95 and y = 0.05 to 9.95."""
    return box_world(width=400, height=200)
