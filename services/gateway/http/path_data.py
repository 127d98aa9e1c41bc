"""The docs/robot-api.md §6.6 and §6.8 text formats: ``path_data`` (points, nav points),
``virtual_wall`` (polylines), ``skip_area`` (rectangles), parsed strictly and printed back."""

from __future__ import annotations

import math

from zenros.msgs.geometry_msgs import Point
from zenros.msgs.zenros_msgs import ForbiddenArea, NavPoint, VirtualWall

__all__ = ["format_areas", "format_nav_points", "format_points", "format_walls", "parse_areas",
           "parse_nav_points", "parse_points", "parse_walls"]

MAX_LINES = 10000


def _floats(line: str, n: int, where: str) -> list[float]:
    parts = line.split()
    if len(parts) < n:
        raise ValueError(f"{where}: expected {n} numbers, got {len(parts)}: {line!r}")
    try:
        values = [float(p) for p in parts[:n]]
    except ValueError:
        raise ValueError(f"{where}: not a number in {line!r}") from None
    if not all(math.isfinite(v) and abs(v) < 1e6 for v in values):
        raise ValueError(f"{where}: numbers must be finite, got {line!r}")
    return values


def _lines(text: str, what: str) -> list[tuple[int, str]]:
    lines = [(i + 1, ln.strip()) for i, ln in enumerate(text.splitlines())]
    if len(lines) > MAX_LINES:
        raise ValueError(f"{what}: more than {MAX_LINES} lines")
    return lines


def parse_points(text: str) -> list[Point]:
    """Lines ``x y z``."""
    out = []
    for n, ln in _lines(text, "path_data"):
        if ln:
            if len(ln.split()) != 3:
                raise ValueError(f"path_data line {n}: expected 'x y z', got {ln!r}")
            x, y, z = _floats(ln, 3, f"path_data line {n}")
            out.append(Point(x=x, y=y, z=z))
    return out


def format_points(points: list[Point]) -> str:
    return "".join(f"{p.x:g} {p.y:g} {p.z:g}\n" for p in points)


def parse_nav_points(text: str) -> list[NavPoint]:
    """Lines ``x y z theta errorX errorY direction [name]``."""
    out = []
    for n, ln in _lines(text, "path_data"):
        if not ln:
            continue
        parts = ln.split()
        if len(parts) not in (7, 8):
            raise ValueError(f"path_data line {n}: expected 'x y z theta errorX errorY "
                             f"direction [name]', got {ln!r}")
        x, y, z, th, ex, ey = _floats(ln, 6, f"path_data line {n}")
        try:
            direction = int(parts[6])
        except ValueError:
            raise ValueError(f"path_data line {n}: direction must be an integer") from None
        out.append(NavPoint(x=x, y=y, z=z, theta=th, error_x=ex, error_y=ey,
                            direction=direction, name=parts[7] if len(parts) == 8 else ""))
    return out


def format_nav_points(points: list[NavPoint]) -> str:
    return "".join(
        f"{p.x:g} {p.y:g} {p.z:g} {p.theta:g} {p.error_x:g} {p.error_y:g} {p.direction}"
        + (f" {p.name}" if p.name else "") + "\n" for p in points)


def parse_walls(text: str) -> list[VirtualWall]:
    """Lines ``x y``, one polyline; an empty line starts the next wall."""
    walls: list[VirtualWall] = []
    current: list[Point] = []
    for n, ln in _lines(text, "virtual_wall"):
        if not ln:
            if current:
                walls.append(VirtualWall(points=current))
                current = []
            continue
        x, y = _floats(ln, 2, f"virtual_wall line {n}")
        current.append(Point(x=x, y=y))
    if current:
        walls.append(VirtualWall(points=current))
    for i, w in enumerate(walls):
        if len(w.points) < 2:
            raise ValueError(f"virtual_wall {i + 1}: a wall needs at least 2 points")
    return walls


def format_walls(walls: list[VirtualWall]) -> str:
    return "\n".join("".join(f"{p.x:g} {p.y:g}\n" for p in w.points) for w in walls)


def parse_areas(text: str) -> list[ForbiddenArea]:
    """Lines ``x1 y1 x2 y2``: rectangles by two opposite corners."""
    out = []
    for n, ln in _lines(text, "skip_area"):
        if ln:
            x1, y1, x2, y2 = _floats(ln, 4, f"skip_area line {n}")
            if x1 == x2 or y1 == y2:
                raise ValueError(f"skip_area line {n}: the rectangle has no area")
            out.append(ForbiddenArea(points=[Point(x=x1, y=y1), Point(x=x2, y=y1),
                                             Point(x=x2, y=y2), Point(x=x1, y=y2)]))
    return out


def format_areas(areas: list[ForbiddenArea]) -> str:
    lines = []
    for a in areas:
        xs, ys = [p.x for p in a.points], [p.y for p in a.points]
        if xs:
            lines.append(f"{min(xs):g} {min(ys):g} {max(xs):g} {max(ys):g}\n")
    return "".join(lines)
