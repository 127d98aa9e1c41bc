"""shape_msgs: made by `zenros interface generate` from its .msg files."""

from __future__ import annotations

from typing import ClassVar

import msgspec

from ..message import Float64Array, Message, array_field
from ..primitives import UInt8, UInt32
from .geometry_msgs import Point, Polygon

__all__ = ["Mesh", "MeshTriangle", "Plane", "SolidPrimitive"]


class MeshTriangle(Message):
    """Definition of a triangle's vertices."""

    __msgtype__ = "shape_msgs/MeshTriangle"
    vertex_indices: list[UInt32] = msgspec.field(default_factory=lambda: [0, 0, 0])


class Mesh(Message):
    """Definition of a mesh."""

    __msgtype__ = "shape_msgs/Mesh"
    triangles: list[MeshTriangle] = msgspec.field(default_factory=list)
    vertices: list[Point] = msgspec.field(default_factory=list)


class Plane(Message):
    """Representation of a plane, using the plane equation ax + by + cz + d = 0.

    a := coef[0]
    b := coef[1]
    c := coef[2]
    d := coef[3]
    """

    __msgtype__ = "shape_msgs/Plane"
    coef: Float64Array = array_field(Float64Array, [0.0, 0.0, 0.0, 0.0])


class SolidPrimitive(Message):
    """Defines box, sphere, cylinder, cone and prism.
    All shapes are defined to have their bounding boxes centered around 0,0,0.
    """

    __msgtype__ = "shape_msgs/SolidPrimitive"
    BOX: ClassVar[int] = 1
    SPHERE: ClassVar[int] = 2
    CYLINDER: ClassVar[int] = 3
    CONE: ClassVar[int] = 4
    PRISM: ClassVar[int] = 5
    BOX_X: ClassVar[int] = 0
    BOX_Y: ClassVar[int] = 1
    BOX_Z: ClassVar[int] = 2
    SPHERE_RADIUS: ClassVar[int] = 0
    CYLINDER_HEIGHT: ClassVar[int] = 0
    CYLINDER_RADIUS: ClassVar[int] = 1
    CONE_HEIGHT: ClassVar[int] = 0
    CONE_RADIUS: ClassVar[int] = 1
    PRISM_HEIGHT: ClassVar[int] = 0
    type: UInt8 = 0
    dimensions: Float64Array = array_field(Float64Array)
    polygon: Polygon = msgspec.field(default_factory=Polygon)
