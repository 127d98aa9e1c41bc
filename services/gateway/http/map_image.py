"""`grid_png` / `grid_pgm`: an OccupancyGrid rendered as the map_server image (white free, black occupied,
grey unknown; the image's top row is the map's far edge in y)."""

from __future__ import annotations

import io

import numpy as np
from PIL import Image
from zenros.msgs.nav_msgs import OccupancyGrid

__all__ = ["grid_pgm", "grid_png"]


def _pixels(grid: OccupancyGrid) -> np.ndarray:
    w, h = grid.info.width, grid.info.height
    cells = np.asarray(grid.data, dtype=np.int16).reshape(h, w)
    img = np.where(cells < 0, 205, 254 - (np.clip(cells, 0, 100) * 254) // 100).astype(np.uint8)
    return np.ascontiguousarray(img[::-1])


def grid_png(grid: OccupancyGrid) -> bytes:
    out = io.BytesIO()
    Image.fromarray(_pixels(grid)).save(out, format="PNG")
    return out.getvalue()


def grid_pgm(grid: OccupancyGrid) -> bytes:
    """The same image as a binary PGM (P5), as map_server saves it."""
    px = _pixels(grid)
    return f"P5\n{px.shape[1]} {px.shape[0]}\n255\n".encode() + px.tobytes()
