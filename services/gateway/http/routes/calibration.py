"""REST calibrations (docs/robot-api.md §3.3): ``GET /system/calibrate_imu`` (measures the
gyro's bias while the robot stands still, applied at once),
``GET /system/calibrate_laser/{start,status,complete,cancel}`` (the robot turns and drives
to measure the laser's mount; ``complete`` applies it) and
``GET /system/calibrate_camera/{start,status,complete,cancel}`` (the robot faces a board and
turns a little to measure the front camera's focal length and yaw), over the chassis's
``calibration/command`` (`ports.calibration_link.CalibrationLink`)."""

from __future__ import annotations

from typing import Annotated, Any

import msgspec
from zenros.msgs.zenros_msgs import CalibrationState

from ...ports.calibration_link import CalibrationLink
from ..api import Answer, Api, ApiError, Call

__all__ = ["add_calibration_routes"]


def _link(call: Call[Any, Any]) -> CalibrationLink:
    if call.ctx.calibration is None:
        raise ApiError(501, "this gateway has no robot whose calibrations it could reach")
    return call.ctx.calibration


def _state(s: CalibrationState) -> dict[str, Any]:
    """A calibration's state in the spec's words: ``status`` CALIBRATING, CALIBRATED or FREE
    (a failed one is FREE with ``failed`` true and the reason in ``message``)."""
    out: dict[str, Any] = {
        "status": "FREE" if s.state == "FAILED" else s.state, "failed": s.state == "FAILED",
        "progress": s.progress, "accuracy": s.accuracy, "message": s.message}
    if s.values:
        out["result"] = dict(zip(s.names, s.values, strict=True))
    out["applied"] = dict(zip(s.names, s.applied, strict=False))
    return out


async def calibrate_imu(call: Call[None, None]) -> Answer:
    """Measure the gyro's bias (the robot must stand still): ``result`` true once measured
    and applied, false with ``description`` when the robot moved or could not start."""
    state = await _link(call).calibrate_imu()
    ok = state.state == "CALIBRATED"
    body: dict[str, Any] = {"result": ok, "description": state.message}
    if ok:
        body["gyro_bias"] = state.values[0]
    return body


async def laser_start(call: Call[None, None]) -> Answer:
    """Start the laser's calibration: the robot turns once in place, then drives a little
    ahead and back (1 m must be free both ways)."""
    return _state(await _link(call).command("laser", "start"))


async def laser_status(call: Call[None, None]) -> Answer:
    return _state(await _link(call).command("laser", "status"))


async def laser_complete(call: Call[None, None]) -> Answer:
    """Apply a CALIBRATED result: the laser's mount on ``/tf_static`` (409 in another state)."""
    return _state(await _link(call).command("laser", "complete"))


async def laser_cancel(call: Call[None, None]) -> Answer:
    """Stop the calibration (the robot stops) or drop a result not completed."""
    return _state(await _link(call).command("laser", "cancel"))


class CameraQuery(msgspec.Struct, forbid_unknown_fields=True):
    camera_id: Annotated[int, msgspec.Meta(ge=0, le=15)] = 0


async def camera_start(call: Call[None, CameraQuery]) -> Answer:
    """Start the camera's calibration (``camera_id`` 0, the front one, is the one that
    calibrates): the robot must face a board; it turns a little either way to see it across
    the image."""
    if call.query.camera_id != 0:
        raise ApiError(404, f"camera {call.query.camera_id} does not calibrate: camera 0 (the "
                            "front one) does")
    state = await _link(call).command("camera", "start")
    return {"result": state.state, **_state(state)}


async def camera_status(call: Call[None, None]) -> Answer:
    return _state(await _link(call).command("camera", "status"))


async def camera_complete(call: Call[None, None]) -> Answer:
    """Apply a CALIBRATED result: the focal length in the camera's CameraInfo, its yaw on
    ``/tf_static`` (409 in another state)."""
    return _state(await _link(call).command("camera", "complete"))


async def camera_cancel(call: Call[None, None]) -> Answer:
    state = await _link(call).command("camera", "cancel")
    return {"result": state.message, **_state(state)}


def add_calibration_routes(api: Api) -> None:
    """Route the §3.3 calibrations of the IMU, the laser and the camera."""
    api.add("GET", "/system/calibrate_imu", calibrate_imu)
    api.add("GET", "/system/calibrate_laser/start", laser_start)
    api.add("GET", "/system/calibrate_laser/status", laser_status)
    api.add("GET", "/system/calibrate_laser/complete", laser_complete)
    api.add("GET", "/system/calibrate_laser/cancel", laser_cancel)
    api.add("GET", "/system/calibrate_camera/start", camera_start)
    api.add("GET", "/system/calibrate_camera/status", camera_status)
    api.add("GET", "/system/calibrate_camera/complete", camera_complete)
    api.add("GET", "/system/calibrate_camera/cancel", camera_cancel)
