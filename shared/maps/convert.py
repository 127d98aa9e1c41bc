"""Pixels <-> occupancy values, with map_server semantics (specs/tf-nav.md, Part D1).

Choices where the ROS versions differ: trinary and scale compare strictly (ROS 1 and
Nav2 up to Jazzy), scale maps in-between values to ``round(100 r)`` (Nav2), and any pixel
with alpha < 255 is unknown (Nav2 2025+), in every mode. Grids are int8 (rows, cols) with
row 0 at the bottom (OccupancyGrid order); images are top row first.
"""

from __future__ import annotations

import numpy as np

from .meta import Mode

__all__ = ["FREE", "OCCUPIED", "UNKNOWN", "grid_to_pixels", "pixels_to_grid"]

FREE = 0
OCCUPIED = 100
UNKNOWN = -1


def pixels_to_grid(pixels: np.ndarray, *, mode: Mode = "trinary", negate: bool = False,
                   occupied_thresh: float = 0.65, free_thresh: float = 0.196) -> np.ndarray:
    """Occupancy values (int8, row 0 = bottom) of an image (grey, grey+alpha, RGB or RGBA)."""
    px = np.asarray(pixels)
    alpha = None
    if px.ndim == 3:
        channels = px.shape[2]
        if channels in (2, 4):
            alpha = px[..., -1]
            px = px[..., :-1]
        grey = px.astype(np.float64).mean(axis=2)
    else:
        grey = px.astype(np.float64)
    if mode == "raw":
        value = 255.0 - grey if negate else grey
        out = np.where(value <= 100, value, UNKNOWN).astype(np.int8)
    else:
        shade = grey / 255.0
        p = shade if negate else 1.0 - shade
        out = np.full(p.shape, UNKNOWN, dtype=np.int8)
        if mode == "scale":
            mid = (p >= free_thresh) & (p <= occupied_thresh)
            r = (p[mid] - free_thresh) / (occupied_thresh - free_thresh)
            out[mid] = np.round(100.0 * r).astype(np.int8)
        out[p > occupied_thresh] = OCCUPIED
        out[p < free_thresh] = FREE
    if alpha is not None:
        out[alpha < 255] = UNKNOWN
    return np.ascontiguousarray(out[::-1])


def grid_to_pixels(grid: np.ndarray, *, mode: Mode = "trinary",
                   occupied_thresh: float = 0.65, free_thresh: float = 0.196) -> np.ndarray:
    """Image pixels (top row first) for occupancy values, as map_saver writes them.

    Trinary gives grey (rows, cols): 254 free (v <= free_thresh*100), 0 occupied
    (v >= occupied_thresh*100), 205 otherwise. Scale gives grey+alpha (rows, cols, 2):
    grey (100 - v) / 100 * 255, unknown transparent (so it needs PNG). Raw gives grey v,
    unknown 255.
    """
    g = np.asarray(grid)[::-1].astype(np.int16)
    if mode == "trinary":
        px = np.full(g.shape, 205, dtype=np.uint8)
        px[(g >= 0) & (g <= free_thresh * 100)] = 254
        px[g >= occupied_thresh * 100] = 0
        return px
    if mode == "scale":
        grey = np.round((100 - np.clip(g, 0, 100)) * 2.55).astype(np.uint8)
        a = np.where(g < 0, 0, 255).astype(np.uint8)
        return np.stack([grey, a], axis=-1)
    return np.where((g >= 0) & (g <= 100), g, 255).astype(np.uint8)
