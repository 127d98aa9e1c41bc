"""`TfNode`: wires the buffer server, the frame monitor and static transforms to Zenoh."""

from __future__ import annotations

from typing import Annotated, Any

import msgspec
from msgspec import Meta
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.msgs.tf_srvs import CanTransform, Frames, LookupTransform
from zenros.node import Node
from zenros.params import Parameter, SetParametersResult
from zenros.tf import Buffer, StaticTransformBroadcaster

from .monitor import FrameMonitor
from .server import TfServer
from .static import parse_static_transforms
from .tap import TfTap

__all__ = ["TfNode", "TfParameters"]


class TfParameters(msgspec.Struct, kw_only=True):
    """The tf node's parameters; ``static_transforms`` may change at run time."""

    static_transforms: Annotated[list[Any], Meta(
        description="links to publish, each 'x y z yaw pitch roll parent child', 'x y z qx qy "
                    "qz qw parent child' or a mapping; setting it adds or replaces links")] = (
        msgspec.field(default_factory=list))
    cache_time: Annotated[float, Meta(ge=0, description="seconds of history kept per "
                                                        "dynamic link")] = 10.0
    stats_window: Annotated[float, Meta(gt=0, description="seconds of arrivals the rate and "
                                                          "delay figures cover")] = 10.0


class TfNode(Node):
    """The TF buffer server.

    Listens to ``/tf`` and ``/tf_static``; answers ``~/lookup_transform``
    (tf2_msgs/LookupTransform), ``~/can_transform`` (zenros_tf/CanTransform) and
    ``~/frames`` (zenros_tf/Frames); publishes the static transforms it is given on
    ``/tf_static``.

    Parameters: `TfParameters` (static links in the forms `parse_static_transforms` reads).
    """

    node_name = "tf"

    def setup(self) -> None:
        p = self.declare_parameters(TfParameters)
        statics = parse_static_transforms(p.static_transforms, self.now())
        self.buffer = Buffer(p.cache_time)
        self.server = TfServer(self.buffer, FrameMonitor(p.stats_window), self.get_clock(),
                               self.logger)
        self.create_service(LookupTransform, "~/lookup_transform", self.server.lookup_transform)
        self.create_service(CanTransform, "~/can_transform", self.server.can_transform)
        self.create_service(Frames, "~/frames", self.server.frames)
        self.tap = self.own(TfTap(self, self.server.on_message))
        self.server.resolve = self.tap.resolve
        self.statics = StaticTransformBroadcaster(self)
        self._publish_statics(statics)
        self.add_on_set_parameters_callback(self._check_statics)
        self.on_parameter_change(lambda p: self._publish_statics(
            parse_static_transforms(p.value, self.now())), "static_transforms")

    def _publish_statics(self, links: list[TransformStamped]) -> None:
        if not links:
            return
        self.statics.send_transform(links)
        for t in links:
            v, q = t.transform.translation, t.transform.rotation
            self.logger.info("static transform %s -> %s: xyz (%g, %g, %g) q (%g, %g, %g, %g)",
                             t.header.frame_id, t.child_frame_id, v.x, v.y, v.z,
                             q.x, q.y, q.z, q.w)

    def _check_statics(self, params: list[Parameter]) -> SetParametersResult:
        for p in params:
            if p.name == "static_transforms":
                try:
                    parse_static_transforms(p.value)
                except ValueError as exc:
                    return SetParametersResult(False, str(exc))
        return SetParametersResult(True)
