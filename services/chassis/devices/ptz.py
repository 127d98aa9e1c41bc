"""The pan-tilt-zoom (ONVIF) camera fixed in the world, watching the robot (docs/chassis.md,
PTZ camera): its video and camera_info on ``ptz_camera/...`` while someone listens, its state
(``ptz_camera/state``, zenros_msgs/PtzState), its moves (``ptz_camera/move``, ``move_speed``,
``goto_preset``) and its thermal reading (``ptz_camera/temperature``); on ``/tf`` its frames
``ptz_camera_base`` (the mount, on ``map``), ``ptz_camera_link`` (panned and tilted) and
``ptz_camera_optical_frame``.

It sees the walls, the obstacles, the other robots, the dock and this robot's own body. Its
frames are rendered on a thread of its own, off the physics step (a slow frame is skipped,
never waited for); the thermal reading is computed in the call, on a smaller image.
"""

from __future__ import annotations

import io
import math
import threading
from typing import Annotated

import msgspec
from msgspec import Meta
from PIL import Image as PilImage
from zenros.clock import Time
from zenros.images import numpy_to_image
from zenros.message import UInt8Array, to_array
from zenros.msgs.geometry_msgs import Quaternion, Transform, TransformStamped, Vector3
from zenros.msgs.sensor_msgs import CameraInfo, CompressedImage, Image
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs import (
    GetPtzTemperature,
    GetPtzTemperatureRequest,
    GetPtzTemperatureResponse,
    GotoPtzPreset,
    GotoPtzPresetRequest,
    MovePtz,
    MovePtzRequest,
    MovePtzSpeed,
    MovePtzSpeedRequest,
    PtzMoveResponse,
    PtzState,
    ThermalRule,
)
from zenros.pubsub import Publisher
from zenros.qos import QOS_SENSOR
from zenros.se2 import Pose2
from zenros.tf.quaternion import quaternion_from_euler

from .. import messages
from ..camera import ROBOT_PREFIX
from ..device import Chassis, Device, Endpoints
from ..obstacles import Obstacle
from ..param_types import Positive
from ..ptz import PanTiltZoom, PtzError, PtzLimits, UnknownPreset, parse_presets
from ..ptz_view import Mount, PtzView
from ..thermal import ThermalModel, read_rule
from .battery import BatteryDevice
from .camera import OPTICAL, camera_info, dock_block

__all__ = ["PtzDevice", "PtzParameters"]

SELF_ID = ROBOT_PREFIX + "self"  # this robot's body, as the PTZ camera sees it
DEG = math.pi / 180


class PtzParameters(msgspec.Struct, kw_only=True, frozen=True):
    ptz_camera: Annotated[bool, Meta(
        description="a PTZ camera fixed in the world watches the robot (docs/chassis.md)")] = True
    ptz_x: Annotated[float, Meta(description="its mount in map (m; on the demo office's "
                                             "corridor wall, over the east room)")] = 24.0
    ptz_y: float = 1.05
    ptz_z: Annotated[float, Meta(description="its lens height (m), below the walls' 2.5")] = 2.4
    ptz_yaw: Annotated[float, Meta(description="where it faces at pan 0 (rad in map)")] = -2.618
    ptz_pan_limit: Annotated[float, Meta(
        gt=0, le=math.pi, description="pan range ±this (rad; 2.967 = 170 deg)")] = 2.967
    ptz_tilt_min: Annotated[float, Meta(description="lowest tilt (rad; -30 deg)")] = -0.5236
    ptz_tilt_max: Annotated[float, Meta(description="highest tilt (rad; +30 deg)")] = 0.5236
    ptz_zoom_max: Annotated[float, Meta(gt=1, le=100)] = 10.0
    ptz_hfov: Annotated[float, Meta(description="field of view at zoom 1 (rad)")] = 1.2
    ptz_pan_speed: Annotated[Positive, Meta(description="top pan speed (rad/s)")] = 1.5708
    ptz_tilt_speed: Annotated[Positive, Meta(description="top tilt speed (rad/s)")] = 0.7854
    ptz_zoom_speed: Annotated[Positive, Meta(description="top zoom speed (x per s)")] = 4.0
    ptz_width: Annotated[int, Meta(ge=32, le=1920)] = 640
    ptz_height: Annotated[int, Meta(ge=32, le=1080)] = 480
    ptz_rate: Annotated[Positive, Meta(
        description="frames (and states) per sim second, while listened to")] = 5.0
    ptz_jpeg_quality: Annotated[int, Meta(ge=1, le=95)] = 80
    ptz_presets: Annotated[list[str], Meta(
        description="name=pan,tilt,zoom (rad, rad, x); tokens are 1, 2, ... in order")] = (
        msgspec.field(default_factory=lambda: [
            "home=0,-0.17,1", "corridor=0.48,-0.089,4", "dock=-0.846,-0.216,3",
            "room=-0.463,-0.32,1.5"]))

    def __post_init__(self) -> None:
        self.presets()
        self.mount()

    def limits(self) -> PtzLimits:
        return PtzLimits(-self.ptz_pan_limit, self.ptz_pan_limit, self.ptz_tilt_min,
                         self.ptz_tilt_max, self.ptz_zoom_max, self.ptz_pan_speed,
                         self.ptz_tilt_speed, self.ptz_zoom_speed)

    def presets(self) -> PanTiltZoom:
        """The head at pan 0, level, zoom 1 with its presets (raises ValueError)."""
        limits = self.limits()
        return PanTiltZoom(limits, parse_presets(self.ptz_presets, limits))

    def mount(self) -> Mount:
        if not all(math.isfinite(v) for v in (self.ptz_x, self.ptz_y, self.ptz_z, self.ptz_yaw)):
            raise ValueError("ptz_x, ptz_y, ptz_z and ptz_yaw must be finite")
        if not 0.05 <= self.ptz_hfov <= 3.0 or self.ptz_hfov / self.ptz_zoom_max < 0.05:
            raise ValueError(f"ptz_hfov must be 0.05..3 rad and ptz_hfov / ptz_zoom_max at "
                             f"least 0.05, got {self.ptz_hfov:g} and {self.ptz_zoom_max:g}")
        if not 0 < self.ptz_z < 2.5:
            raise ValueError(f"ptz_z must be above the floor and below the walls (2.5 m), "
                             f"got {self.ptz_z:g}")
        return Mount(self.ptz_x, self.ptz_y, self.ptz_z, self.ptz_yaw, self.ptz_hfov,
                     self.ptz_width, self.ptz_height)


def _quaternion(roll: float, pitch: float, yaw: float) -> Quaternion:
    qx, qy, qz, qw = quaternion_from_euler(roll, pitch, yaw)
    return Quaternion(x=qx, y=qy, z=qz, w=qw)


class PtzDevice(Device[PtzParameters]):
    """The head (`PanTiltZoom`) stepped with the body and its view (`PtzView`); nothing when
    ``ptz_camera`` is false or its mount is not in a free place of the map (logged)."""

    Parameters = PtzParameters
    _node: Endpoints
    _state: Publisher[PtzState]
    _image: Publisher[Image]
    _compressed: Publisher[CompressedImage]
    _info: Publisher[CameraInfo]

    def __init__(self, params: PtzParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.head = params.presets()
        self.view: PtzView | None = None
        mount = params.mount()
        world = chassis.sim.world
        if params.ptz_camera:
            if world.inside(mount.x, mount.y) and world.map_clearance(mount.x, mount.y,
                                                                     0.1) > 0.0:
                self.view = PtzView(world, mount)
            else:
                chassis.logger.warning("no PTZ camera: its mount (%g, %g) is outside the map "
                                       "or in a wall (parameters ptz_x, ptz_y)", mount.x,
                                       mount.y)
        self.rate = params.ptz_rate if self.view is not None else 0.0
        self.inert = self.view is None
        self._battery = chassis.device(BatteryDevice)
        self._changed = False
        self._job: tuple[Time, float, float, float, tuple[Obstacle, ...]] | None = None
        self._wake = threading.Condition()
        self._worker: threading.Thread | None = None  # started at the first frame asked
        self._jpeg: tuple[object, UInt8Array] | None = None
        self.frames = 0  # rendered and published, for tests and the bench

    @property
    def on(self) -> bool:
        return self.view is not None

    def open(self, node: Endpoints) -> None:
        if self.view is None:
            return
        self._node = node
        self._state = node.create_publisher(PtzState, "ptz_camera/state", 10)
        self._image = node.create_publisher(Image, "ptz_camera/image_raw", QOS_SENSOR)
        self._compressed = node.create_publisher(CompressedImage,
                                                 "ptz_camera/image_raw/compressed", QOS_SENSOR)
        self._info = node.create_publisher(CameraInfo, "ptz_camera/camera_info", QOS_SENSOR)
        node.serve(MovePtz, "ptz_camera/move", self.handle_move)
        node.serve(MovePtzSpeed, "ptz_camera/move_speed", self.handle_move_speed)
        node.serve(GotoPtzPreset, "ptz_camera/goto_preset", self.handle_goto_preset)
        node.serve(GetPtzTemperature, "ptz_camera/temperature", self.handle_temperature)
        m = self.view.mount
        stamp = node.stamp()
        node.static_transform(messages.transform(stamp, self.chassis.frames.map,
                                                 "ptz_camera_base", Pose2(m.x, m.y, m.yaw), m.z))
        node.static_transform(TransformStamped(
            header=Header(stamp=stamp, frame_id="ptz_camera_link"),
            child_frame_id="ptz_camera_optical_frame",
            transform=Transform(translation=Vector3(), rotation=OPTICAL)))

    # ------------------------------------------------------------------ stepping

    def step(self, dt: float) -> None:
        if self.view is not None:
            self._changed |= self.head.step(dt)

    def changed(self) -> bool:
        changed, self._changed = self._changed, False
        return changed

    def state(self) -> PtzState:
        h, lim = self.head, self.head.limits
        x, y, z = h.normalised()
        hfov = self.view.mount.hfov / h.zoom if self.view is not None else 0.0
        return PtzState(
            header=Header(stamp=self._node.stamp(), frame_id="ptz_camera_link"), x=x, y=y,
            zoom_ratio=z, pan=h.pan, tilt=h.tilt, zoom=h.zoom, hfov=hfov,
            pan_min=lim.pan_min, pan_max=lim.pan_max, tilt_min=lim.tilt_min,
            tilt_max=lim.tilt_max, zoom_max=lim.zoom_max, moving=h.moving,
            presets=[p.name for p in h.presets], width=self.params.ptz_width,
            height=self.params.ptz_height, frame_rate=self.params.ptz_rate,
            jpeg_quality=self.params.ptz_jpeg_quality)

    def things(self) -> tuple[Obstacle, ...]:
        """What the camera may see besides the walls: the world's obstacles and other
        robots, the dock, this robot's body."""
        sim = self.chassis.sim
        body = Obstacle(SELF_ID, "circle", sim.truth.x, sim.truth.y, radius=sim.radius)
        return (*sim.world.obstacles.values(), *dock_block(self.chassis), body)

    def publish(self, stamp: Time) -> None:
        if self.view is None:
            return
        if self._state.subscription_count:
            self._state.publish(self.state())
        h = self.head
        self._node.transforms().send_transform(TransformStamped(
            header=Header(stamp=stamp, frame_id="ptz_camera_base"),
            child_frame_id="ptz_camera_link",
            transform=Transform(translation=Vector3(),
                                rotation=_quaternion(0.0, -h.tilt, -h.pan))))
        if (self._image.subscription_count or self._compressed.subscription_count
                or self._info.subscription_count):
            if self._worker is None:
                self._worker = threading.Thread(target=self._run, name="ptz-camera",
                                                daemon=True)
                self._worker.start()
            with self._wake:
                self._job = (stamp, h.pan, h.tilt, h.zoom, self.things())
                self._wake.notify()

    # ------------------------------------------------------------------ the frames

    def _run(self) -> None:
        while True:
            with self._wake:
                self._wake.wait_for(lambda: self._job is not None)
                job, self._job = self._job, None
            assert job is not None
            try:
                self._send(*job)
            except Exception:  # a bad frame must not end the camera
                self.chassis.logger.exception("PTZ camera: frame failed")

    def _send(self, stamp: Time, pan: float, tilt: float, zoom: float,
              things: tuple[Obstacle, ...]) -> None:
        assert self.view is not None
        pixels = self.view.frame(pan, tilt, zoom, things)
        header = Header(stamp=stamp, frame_id="ptz_camera_optical_frame")
        if self._image.subscription_count:
            self._image.publish(numpy_to_image(pixels, "rgb8", header))
        if self._compressed.subscription_count:
            if self._jpeg is None or self._jpeg[0] is not pixels:  # a still view: once
                jpeg = io.BytesIO()
                PilImage.fromarray(pixels).save(jpeg, "JPEG",
                                                quality=self.params.ptz_jpeg_quality)
                self._jpeg = (pixels, to_array(UInt8Array, jpeg.getvalue()))
            self._compressed.publish(CompressedImage(
                header=header, format="rgb8; jpeg compressed rgb8", data=self._jpeg[1]))
        if self._info.subscription_count:
            self._info.publish(camera_info(self.view.config(zoom, tilt), header))
        self.frames += 1

    # ------------------------------------------------------------------ services

    def _answer(self, what: str, error: PtzError | None = None) -> PtzMoveResponse:
        if error is not None:
            return PtzMoveResponse(success=False, message=str(error),
                                   not_found=isinstance(error, UnknownPreset),
                                   state=self.state())
        self._changed = True
        self._node.logger.info("PTZ camera: %s", what)
        return PtzMoveResponse(success=True, message=what, state=self.state())

    def handle_move(self, req: MovePtzRequest) -> PtzMoveResponse:
        try:
            self.head.move(req.x, req.y, req.zoom)
        except PtzError as exc:
            return self._answer("", exc)
        return self._answer(f"moving to x={req.x:g}, y={req.y:g}, zoom={req.zoom:g}")

    def handle_move_speed(self, req: MovePtzSpeedRequest) -> PtzMoveResponse:
        try:
            self.head.move_speed(req.speed_x, req.speed_y, req.speed_zoom)
        except PtzError as exc:
            return self._answer("", exc)
        if not self.head.moving:
            return self._answer("stopped")
        return self._answer(f"moving at speed_x={req.speed_x:g}, speed_y={req.speed_y:g}, "
                            f"speed_zoom={req.speed_zoom:g}")

    def handle_goto_preset(self, req: GotoPtzPresetRequest) -> PtzMoveResponse:
        try:
            p = self.head.goto_preset(req.preset)
        except PtzError as exc:
            return self._answer("", exc)
        return self._answer(f"going to preset {p.name!r}")

    def handle_temperature(self, req: GetPtzTemperatureRequest) -> GetPtzTemperatureResponse:
        assert self.view is not None
        h = self.head
        charging = self._battery is not None and self._battery.battery.charging
        temps = self.view.thermal(h.pan, h.tilt, h.zoom, self.things(),
                                  ThermalModel(charging=charging))
        r = read_rule(temps)
        rule = ThermalRule(id=1, max_temperature=round(r.max, 2),
                           min_temperature=round(r.min, 2),
                           average_temperature=round(r.average, 2), max_x=r.max_at[0],
                           max_y=r.max_at[1], min_x=r.min_at[0], min_y=r.min_at[1])
        return GetPtzTemperatureResponse(success=True, message="", rules=[rule],
                                         width=temps.shape[1], height=temps.shape[0],
                                         state=self.state())
