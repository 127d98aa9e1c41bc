"""`TfNode`: wires the buffer server, the frame monitor and static transforms to Zenoh."""

from __future__ import annotations

from zenros.msgs.geometry_msgs import TransformStamped
from zenros.msgs.tf_srvs import CanTransform, Frames, LookupTransform
from zenros.node import Node
from zenros.params import Parameter, SetParametersResult
from zenros.tf import Buffer, StaticTransformBroadcaster

from .monitor import FrameMonitor
from .server import TfServer
from .static import parse_static_transforms
from .tap import TfTap

__all__ = ["TfNode"]


class TfNode(Node):
    """The TF buffer server.

    Listens to ``/tf`` and ``/tf_static``; answers ``~/lookup_transform``
    (tf2_msgs/LookupTransform), ``~/can_transform`` (zenros_tf/CanTransform) and
    ``~/frames`` (zenros_tf/Frames); publishes the static transforms it is given on
    ``/tf_static``.

    Parameters:
        static_transforms: links to publish, each ``"x y z yaw pitch roll parent child"``,
            ``"x y z qx qy qz qw parent child"`` or a mapping (see `parse_static_transforms`);
            setting it at run time adds or replaces links.
        cache_time: seconds of history kept per dynamic link (default 10).
        stats_window: seconds of arrivals the rate and delay figures cover (default 10).
    """

    node_name = "tf"

    def setup(self) -> None:
        cache_time = self.declare_parameter("cache_time", 10.0)
        window = self.declare_parameter("stats_window", 10.0)
        statics = parse_static_transforms(
            self.declare_parameter("static_transforms", []), self.now()
        )
        self.buffer = Buffer(cache_time)
        self.server = TfServer(self.buffer, FrameMonitor(window), self.get_clock(), self.logger)
        self.create_service(LookupTransform, "~/lookup_transform", self.server.lookup_transform)
        self.create_service(CanTransform, "~/can_transform", self.server.can_transform)
        self.create_service(Frames, "~/frames", self.server.frames)
        self.tap = TfTap(self, self.server.on_message)
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

    def close(self) -> None:
        tap = getattr(self, "tap", None)
        if tap is not None:
            tap.close()
        super().close()
