"""The REST inputs' checked field types: map and path names, coordinates and angles (a value
out of bounds is a 400 naming the field)."""

from __future__ import annotations

from typing import Annotated

import msgspec

__all__ = ["Angle", "Coord", "Name", "OptName"]

Name = Annotated[str, msgspec.Meta(pattern=r"^[A-Za-z0-9_][A-Za-z0-9_.\-]{0,63}$")]
"""A map or path name: no path separators, no leading dot (path traversal is a 400)."""
OptName = Annotated[str, msgspec.Meta(pattern=r"^([A-Za-z0-9_][A-Za-z0-9_.\-]{0,63})?$")]
Coord = Annotated[float, msgspec.Meta(ge=-1e5, le=1e5)]
Angle = Annotated[float, msgspec.Meta(ge=-100.0, le=100.0)]
