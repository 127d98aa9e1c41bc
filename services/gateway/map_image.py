"""`grid_png`: an OccupancyGrid rendered as the map_server PNG (white free, black occupied,
grey unknown; the image's top row is the map's far edge in y)."""

from __future__ import annotations

import io

import numpy as np
from PIL import Image
from zenros.msgs.nav_msgs import OccupancyGrid

__all__ = ["grid_png"]


def grid_png(grid: OccupancyGrid) -> bytes:
    w, h = grid.info.width, grid.info.height
    cells = np.asarray(grid.data, dtype=np.int16).reshape(h, w)
    img = np.where(cells < 0, 205, 254 - (np.clip(cells, 0, 100) * 254) // 100).astype(np.uint8)
    out = io.BytesIO()
    Image.fromarray(img[::-1]).save(out, format="PNG")
    return out.getvalue()
