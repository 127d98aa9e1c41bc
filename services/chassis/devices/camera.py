"""The front and back cameras: ``sensor_msgs/Image`` (rgb8), ``CompressedImage`` (JPEG) and
``CameraInfo``, rendered from the simulated world (`zenros.services.chassis.camera`).

Topics (relative, so in the robot's namespace), as the robot API names them: the front
camera on ``camera_node/...`` and ``multi/front/...``, the back one on ``multi/back/...``;
each has ``image_raw``, ``image_raw/compressed`` (image_transport's name) and
``camera_info``. Frames: ``camera_front_link`` / ``camera_back_link`` on the base (x ahead)
and their ``..._optical_frame`` (z ahead, x right, y down), which the images are stamped in.

A frame is rendered only when someone subscribes to one of its camera's topics, and not
again while the robot and the world stand still. Rendering runs on a thread of its own, off
the physics step: when it falls behind, a camera skips frames rather than slowing the robot.
"""

from __future__ import annotations

import io
import math
import threading
from dataclasses import dataclass
from typing import Annotated

import msgspec
import numpy as np
from msgspec import Meta
from PIL import Image as PilImage
from zenros.clock import Time
from zenros.images import numpy_to_image
from zenros.message import Float64Array, UInt8Array, to_array
from zenros.msgs.geometry_msgs import Quaternion, Transform, TransformStamped, Vector3
from zenros.msgs.sensor_msgs import CameraInfo, CompressedImage, Image
from zenros.msgs.std_msgs import Header
from zenros.pubsub import Publisher
from zenros.qos import QOS_SENSOR
from zenros.se2 import Pose2

from .. import messages
from ..camera import DOCK_ID, Camera, CameraConfig
from ..device import Chassis, Device, Endpoints
from ..laser import Laser, LaserConfig
from ..obstacles import Obstacle
from ..param_types import NonNegative
from .dock import DockDevice

__all__ = ["CameraDevice", "CameraParameters", "camera_info", "dock_block"]

OPTICAL = Quaternion(x=-0.5, y=0.5, z=-0.5, w=0.5)  # x ahead, z up -> z ahead, y down (REP 103)
DOCK_DEPTH, DOCK_WIDTH, DOCK_AHEAD = 0.12, 0.5, 0.35  # the charger, ahead of the docked pose


class CameraParameters(msgspec.Struct, kw_only=True, frozen=True):
    camera_rate: Annotated[NonNegative, Meta(
        description="frames per sim second of each camera (0: no cameras)")] = 10.0
    camera_width: Annotated[int, Meta(ge=8, le=4096)] = 640
    camera_height: Annotated[int, Meta(ge=8, le=4096)] = 480
    camera_hfov: Annotated[float, Meta(description="horizontal field of view (rad)")] = 1.2
    camera_z: Annotated[float, Meta(description="lens height above the floor (m)")] = 0.5
    camera_front_x: float = 0.2
    camera_back_x: float = -0.2
    camera_jpeg_quality: Annotated[int, Meta(ge=1, le=95)] = 80
    camera_error_yaw: Annotated[float, Meta(
        ge=-0.3, le=0.3, description="how far the front camera is really turned from straight "
                                     "ahead (rad)")] = 0.0
    camera_error_f: Annotated[float, Meta(
        ge=-0.2, le=0.2, description="the front lens's focal length off its nominal one "
                                     "(relative)")] = 0.0

    def __post_init__(self) -> None:
        self.config()
        self.front_lens()

    def config(self) -> CameraConfig:
        """The renderer's configuration (raises ValueError for a bad combination)."""
        return CameraConfig(width=self.camera_width, height=self.camera_height,
                            hfov=self.camera_hfov, z=self.camera_z)

    def front_lens(self) -> CameraConfig:
        """The front camera's lens as it really is: the nominal one with ``camera_error_f``
        (what a camera calibration measures)."""
        c = self.config()
        f = c.f * (1.0 + self.camera_error_f)
        return CameraConfig(width=c.width, height=c.height, z=c.z,
                            hfov=2 * math.atan(c.width / 2 / f))


@dataclass
class _View:
    """One camera: where it sits on the base and the topics it publishes on."""

    name: str  # front, back
    mount: Pose2  # where it really is on the base (it renders from there)
    camera: Camera
    images: list[Publisher[Image]]
    compressed: list[Publisher[CompressedImage]]
    infos: list[Publisher[CameraInfo]]
    k: list[float]  # the intrinsics CameraInfo publishes (a calibration may correct them)
    published: Pose2  # the mount /tf_static publishes (likewise)
    jpeg: tuple[object, UInt8Array] | None = None  # (the frame it is of, its JPEG)

    @property
    def optical_frame(self) -> str:
        return f"camera_{self.name}_optical_frame"

    def listened(self) -> bool:
        return (any(p.subscription_count for p in self.images)
                or any(p.subscription_count for p in self.compressed)
                or any(p.subscription_count for p in self.infos))


class CameraDevice(Device[CameraParameters]):
    """Two `Camera` views of the chassis's world (one map caster between them)."""

    Parameters = CameraParameters
    _node: Endpoints

    def __init__(self, params: CameraParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.rate = params.camera_rate
        self.config = params.config()
        self.caster: Laser | None = None
        if self.rate > 0:
            self.caster = Laser(chassis.sim.world,
                                LaserConfig(beams=1, range_max=self.config.range_max))
        self.views: list[_View] = []
        self._jobs: dict[str, tuple[Time, Pose2, tuple[Obstacle, ...]]] = {}
        self._wake = threading.Condition()
        self._worker: threading.Thread | None = None
        self.frames = 0  # rendered and published, for tests and the bench

    def open(self, node: Endpoints) -> None:
        if self.caster is None:
            return
        p = self.params
        self._node = node
        for name, mount, lens, error, bases in (
                ("front", Pose2(p.camera_front_x, 0.0, 0.0), p.front_lens(),
                 p.camera_error_yaw, ["camera_node", "multi/front"]),
                ("back", Pose2(p.camera_back_x, 0.0, math.pi), self.config, 0.0,
                 ["multi/back"])):
            view = _View(
                name, Pose2(mount.x, mount.y, mount.theta + error),
                Camera(self.chassis.sim.world, lens, self.caster),
                [node.create_publisher(Image, f"{b}/image_raw", QOS_SENSOR) for b in bases],
                [node.create_publisher(CompressedImage, f"{b}/image_raw/compressed", QOS_SENSOR)
                 for b in bases],
                [node.create_publisher(CameraInfo, f"{b}/camera_info", QOS_SENSOR)
                 for b in bases], self.config.k, mount)
            self.views.append(view)
            link = f"camera_{name}_link"
            self._send_mount(view)
            node.static_transform(TransformStamped(
                header=Header(stamp=node.stamp(), frame_id=link),
                child_frame_id=view.optical_frame,
                transform=Transform(translation=Vector3(), rotation=OPTICAL)))
        self._worker = threading.Thread(target=self._run, name="cameras", daemon=True)
        self._worker.start()

    def _send_mount(self, view: _View) -> None:
        self._node.static_transform(messages.transform(
            self._node.stamp(), self.chassis.frames.base, f"camera_{view.name}_link",
            view.published, self.params.camera_z))

    def view(self, name: str) -> _View | None:
        """The camera ``name`` (front, back), or None without cameras."""
        return next((v for v in self.views if v.name == name), None)

    def frame_now(self, name: str) -> np.ndarray:
        """What camera ``name`` sees now (rendered at once, on the caller's thread; a copy)."""
        view = self.view(name)
        if view is None:
            raise LookupError(f"no {name} camera")
        pose = self.chassis.sim.truth * view.mount
        things = (*self.chassis.sim.world.obstacles.values(), *dock_block(self.chassis))
        return view.camera.render(pose.x, pose.y, pose.theta, things).copy()

    def set_calibration(self, name: str, f: float, cx: float, yaw: float) -> None:
        """Publish a calibration's result for camera ``name``: focal length ``f`` and
        principal point column ``cx`` (pixels) in its CameraInfo, its yaw on the base on
        ``/tf_static`` (the lens and the camera stay as they are)."""
        view = self.view(name)
        if view is None:
            raise LookupError(f"no {name} camera")
        k = list(view.k)
        k[0], k[2], k[4] = f, cx, f
        view.k = k
        view.published = Pose2(view.published.x, view.published.y, yaw)
        self._send_mount(view)

    def publish(self, stamp: Time) -> None:
        if self.caster is None:
            return
        truth = self.chassis.sim.truth
        things: tuple[Obstacle, ...] | None = None
        for view in self.views:
            if not view.listened():
                continue
            if things is None:
                things = (*self.chassis.sim.world.obstacles.values(),
                          *dock_block(self.chassis))
            with self._wake:
                self._jobs[view.name] = (stamp, truth * view.mount, things)
                self._wake.notify()

    def _run(self) -> None:
        while True:
            with self._wake:
                self._wake.wait_for(lambda: bool(self._jobs))
                jobs, self._jobs = self._jobs, {}
            for view in self.views:
                job = jobs.get(view.name)
                if job is None:
                    continue
                try:
                    self._send(view, *job)
                except Exception:  # a bad frame must not end the cameras
                    self.chassis.logger.exception("camera %s: frame failed", view.name)

    def _send(self, view: _View, stamp: Time, pose: Pose2,
              things: tuple[Obstacle, ...]) -> None:
        pixels = view.camera.render(pose.x, pose.y, pose.theta, things)
        header = Header(stamp=stamp, frame_id=view.optical_frame)
        if any(p.subscription_count for p in view.images):
            image = numpy_to_image(pixels, "rgb8", header)
            for pub in view.images:
                pub.publish(image)
        if any(p.subscription_count for p in view.compressed):
            if view.jpeg is None or view.jpeg[0] is not pixels:  # a still view: encoded once
                jpeg = io.BytesIO()
                PilImage.fromarray(pixels).save(jpeg, "JPEG",
                                                quality=self.params.camera_jpeg_quality)
                view.jpeg = (pixels, to_array(UInt8Array, jpeg.getvalue()))
            data = view.jpeg[1]
            compressed = CompressedImage(header=header, format="rgb8; jpeg compressed rgb8",
                                         data=data)
            for cpub in view.compressed:
                cpub.publish(compressed)
        info = camera_info(self.config, header, view.k)
        for ipub in view.infos:
            ipub.publish(info)
        self.frames += 1


def dock_block(chassis: Chassis) -> list[Obstacle]:
    """The charger as the cameras see it: a block ahead of the docked pose (none without a
    dock)."""
    fitted = chassis.device(DockDevice)
    if fitted is None or fitted.dock is None:
        return []
    d = fitted.dock.pose
    x = d.x + DOCK_AHEAD * math.cos(d.theta)
    y = d.y + DOCK_AHEAD * math.sin(d.theta)
    return [Obstacle(DOCK_ID, "box", x, y, d.theta, size_x=DOCK_DEPTH, size_y=DOCK_WIDTH)]


def camera_info(config: CameraConfig, header: Header, k: list[float] | None = None
                ) -> CameraInfo:
    """The pinhole's calibration: no distortion, K (default: from the field of view),
    P = [K | 0]."""
    k = config.k if k is None else k
    return CameraInfo(
        header=header, height=config.height, width=config.width, distortion_model="plumb_bob",
        d=to_array(Float64Array, [0.0] * 5), k=to_array(Float64Array, k),
        r=to_array(Float64Array, [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]),
        p=to_array(Float64Array, [k[0], 0.0, k[2], 0.0, 0.0, k[4], k[5], 0.0, 0.0, 0.0, 1.0,
                                  0.0]))
