"""What each action type does, given a `Robot`, as a function returning an `Outcome`.

A behaviour reads its action's parameters as the typed Struct of its type
(`zenros_msgs.task_actions`); it writes progress on the action's document (``ctx.item``).
Every behaviour polls ``cancelled`` while it waits, so a pause or stop takes effect at
once; none holds a lock while it waits.
"""

from __future__ import annotations

import json
import math
import threading
import urllib.error
import urllib.request
from collections.abc import Callable
from typing import Any, Final

from msgspec import UNSET
from zenros.msgs.zenros_msgs.task_actions import (
    AudioRecordAction,
    BlocklyAction,
    CallbackAction,
    ChargeAction,
    DownloadMapAction,
    ImageAction,
    IoAction,
    JackingAction,
    JackingRotateAction,
    LocalMoveAction,
    LocalMoveTargetAction,
    Location,
    NavAction,
    NoneStopNavAction,
    OnvifCameraMoveAction,
    OnvifCameraSnapshotAction,
    SleepAction,
    SlideAction,
    SwitchMapAction,
    TtsAction,
    UploadMapAction,
    VideoRecordAction,
    WaitReqAction,
)
from zenros.se2 import angle_diff

from .blockly import ProgramError, Runner, parse
from .context import POLL, Context
from .crossmap import navigate_across
from .elevator_calls import elevator_req, lbt_elevator_ack, lbt_elevator_req
from .host_behaviors import change_setting, roslaunch
from .robot import Feedback, Outcome

__all__ = ["BEHAVIORS", "Context"]



def _nav(ctx: Context, p: NavAction) -> Outcome:
    """Navigate on the current map, or across maps when ``map`` is another one."""
    if p.map:
        try:
            current = ctx.robot.current_map()
        except LookupError as exc:
            return Outcome("error", str(exc))
        if p.map != current:
            def note(text: str) -> None:
                ctx.item.result = text
                ctx.changed()
            return navigate_across(ctx.robot, p, current, lambda q: _nav_here(ctx, q), note,
                                   ctx.robot.elevators, ctx.cancelled)
    return _nav_here(ctx, p)


def _nav_here(ctx: Context, p: NavAction) -> Outcome:
    if isinstance(p.index, int):
        try:
            x, y, theta = ctx.robot.nav_point(p.index, p.map, p.path)
        except LookupError as exc:
            return Outcome("error", str(exc))
    elif isinstance(p.x, int | float) and isinstance(p.y, int | float):
        x, y, theta = float(p.x), float(p.y), p.theta
    else:  # check_action refuses such a document; a goal built in code might be one
        return Outcome("error", "a nav_action needs x and y, or index")
    first: list[float] = []

    def feedback(fb: Feedback) -> None:
        ctx.item.current_location = Location(x=fb.x, y=fb.y, theta=fb.theta)
        ctx.item.current_distance = fb.distance
        if not first and fb.distance > 0:
            first.append(fb.distance)
        if first:
            ctx.item.progress = round(max(0.0, min(1.0, 1 - fb.distance / first[0])), 4)
        ctx.changed()

    return ctx.robot.navigate(x, y, theta, p.timeout, feedback, ctx.cancelled)


def _none_stop_nav(ctx: Context, p: NoneStopNavAction) -> Outcome:
    """Toward (x, y), heading from where the robot is to it; complete within ``radius``
    without stopping. The task's end stops a goal still running then."""
    pose = ctx.robot.pose()
    theta = 0.0 if pose is None else math.atan2(p.y - pose[1], p.x - pose[0])
    ctx.at_end(ctx.robot.stop_passing)
    first: list[float] = []

    def feedback(fb: Feedback) -> None:
        ctx.item.current_location = Location(x=fb.x, y=fb.y, theta=fb.theta)
        ctx.item.current_distance = fb.distance
        if not first:
            first.append(max(fb.distance, p.radius + 1e-6))
        ctx.item.progress = round(max(0.0, min(1.0, (first[0] - fb.distance)
                                               / (first[0] - p.radius))), 4)
        ctx.changed()

    return ctx.robot.pass_through(p.x, p.y, theta, p.radius, p.timeout, feedback,
                                  ctx.cancelled)


def _sleep(ctx: Context, p: SleepAction) -> Outcome:
    if ctx.wait(p.wait_time):
        return Outcome("complete", "slept")
    return Outcome("preempted")


def _charge(ctx: Context, p: ChargeAction) -> Outcome:
    pose = None
    if isinstance(p.x, int | float) and isinstance(p.y, int | float):
        pose = (float(p.x), float(p.y), p.theta)
    return ctx.robot.charge(pose, p.level, p.timeout, ctx.cancelled)


def _callback(ctx: Context, p: CallbackAction) -> Outcome:
    method = p.method.upper()
    data = None if p.data is UNSET else p.data
    body = None if data is None or method in ("GET", "HEAD") else json.dumps(data).encode()
    req = urllib.request.Request(p.url, data=body, method=method,
                                 headers={"Content-Type": "application/json"} if body else {})
    box: list[Outcome] = []
    done = threading.Event()

    def call() -> None:
        try:
            with urllib.request.urlopen(req, timeout=p.timeout) as resp:
                box.append(Outcome("complete", f"HTTP {resp.status}"))
        except urllib.error.HTTPError as exc:
            box.append(Outcome("error", f"{method} {p.url}: HTTP {exc.code} {exc.reason}"))
        except (urllib.error.URLError, OSError, ValueError) as exc:
            reason = getattr(exc, "reason", exc)
            box.append(Outcome("error", f"{method} {p.url}: {reason}"))
        finally:
            done.set()

    threading.Thread(target=call, name="callback_action", daemon=True).start()
    while not done.wait(POLL):
        if ctx.cancelled():
            return Outcome("preempted")
    return box[0]


def _wait_req(ctx: Context, p: WaitReqAction) -> Outcome:
    timeout = p.timeout
    end = ctx.robot.now() + timeout if timeout > 0 else None
    while not ctx.wait_release.wait(POLL):
        if ctx.cancelled():
            return Outcome("preempted")
        if end is not None and ctx.robot.now() >= end:
            return Outcome("error", f"no update_wait_req within {timeout:g} s")
    ctx.wait_release.clear()
    return Outcome("complete", "released")


def _tts(ctx: Context, p: TtsAction) -> Outcome:
    ctx.robot.say(p.text)
    return Outcome("complete", "said")


def _switch_map(ctx: Context, p: SwitchMapAction) -> Outcome:
    return ctx.robot.switch_map(p.map, p.path, p.start_index)


def _local_move(ctx: Context, p: LocalMoveAction) -> Outcome:
    """Legs ``drive`` and ``spin`` (``method`` 0: drive first, 1: spin first); each leg is
    half the progress. A resumed move drives only what its progress says is left."""
    distance, angle = p.distance, p.angle
    legs = [(kind, amount) for kind, amount in (("drive", distance), ("spin", angle))
            if abs(amount) > 1e-6]
    if p.method == 1:
        legs.reverse()
    if not legs:
        return Outcome("complete", "nothing to do (distance and angle are 0)")
    timeout = p.timeout
    deadline = ctx.robot.now() + timeout if timeout > 0 else None
    n, before = len(legs), float(ctx.item.progress)
    for i, (kind, amount) in enumerate(legs):
        done = max(0.0, min(1.0, (before - i / n) * n))
        if done >= 0.999:
            continue
        left = amount * (1.0 - done)
        budget = 0.0
        if deadline is not None:
            budget = deadline - ctx.robot.now()
            if budget <= 0:
                return Outcome("error", f"local move not done within {timeout:g} s")

        def moved(value: float, i: int = i, done: float = done, left: float = left) -> None:
            frac = done + (1.0 - done) * min(1.0, abs(value) / abs(left))
            ctx.progress((i + frac) / n)

        if kind == "drive":
            out = ctx.robot.drive(left, p.speed, budget, moved, ctx.cancelled)
        else:
            out = ctx.robot.spin(left, budget, moved, ctx.cancelled)
        if out.name != "complete":
            return out
        ctx.progress((i + 1) / n)
    return Outcome("complete", f"moved {distance:g} m and turned {angle:g} rad")


def _local_move_target(ctx: Context, p: LocalMoveTargetAction) -> Outcome:
    return ctx.robot.local_move_target(
        p.x, p.y, p.theta, p.frame_id, p.xy_tolerance, p.yaw_tolerance, p.timeout,
        p.start_rotate_enable, p.target_rotate_enable, ctx.cancelled)


def _io(ctx: Context, p: IoAction) -> Outcome:
    return ctx.robot.set_io(int(p.port), int(p.level))


def _axis_move(ctx: Context, axis: str, mode: int, target: float, speed: float,
               duration: float) -> Outcome:
    """One actuator move. A resumed speed move runs only the time its progress leaves."""
    if mode == 1:
        duration *= 1.0 - float(ctx.item.progress)
        done = float(ctx.item.progress)
        return ctx.robot.move_axis(axis, mode, target, speed, duration,
                                   lambda v: ctx.progress(done + (1.0 - done) * v),
                                   ctx.cancelled)
    return ctx.robot.move_axis(axis, mode, target, speed, duration, ctx.progress,
                               ctx.cancelled)


def _slide(ctx: Context, p: SlideAction) -> Outcome:
    return _axis_move(ctx, "slide", p.mode, p.pose, p.speed, p.time)


def _jacking(ctx: Context, p: JackingAction) -> Outcome:
    return _axis_move(ctx, "jacking", p.mode, p.pose, p.speed, p.time)


def _jacking_rotate(ctx: Context, p: JackingRotateAction) -> Outcome:
    """An ``angle`` in ``map`` is the robot's heading away in ``base_link`` (wrapped into
    the rotation's travel), taken when the move starts."""
    angle = p.angle
    if p.mode == 3 and p.frame_id == "map":
        pose = ctx.robot.pose()
        if pose is None:
            return Outcome("error", "the robot's pose in map is unknown (is nav running?): "
                                    "cannot turn the lift to a map heading")
        angle = angle_diff(angle, pose[2])
    return _axis_move(ctx, "jacking_rotation", p.mode, angle, p.speed, p.time)


def _onvif_camera_move(ctx: Context, p: OnvifCameraMoveAction) -> Outcome:
    return ctx.robot.ptz_move(p.x, p.y, p.zoom, ctx.progress, ctx.cancelled)


def _stamped(timestamp: int | Any, suffix: str) -> str:
    """``<timestamp>.<suffix>`` for a given timestamp, or "" (the gateway's own: now)."""
    return "" if timestamp is UNSET else f"{timestamp}.{suffix}"


def _image(ctx: Context, p: ImageAction) -> Outcome:
    return ctx.robot.save_media("image", p.topic, 0.0, _stamped(p.timestamp, "png"),
                                ctx.progress, ctx.cancelled)


def _video_record(ctx: Context, p: VideoRecordAction) -> Outcome:
    return ctx.robot.save_media("video", p.topic, float(p.duration),
                                p.filename or _stamped(p.timestamp, "mkv"), ctx.progress,
                                ctx.cancelled)


def _audio_record(ctx: Context, p: AudioRecordAction) -> Outcome:
    return ctx.robot.save_media("audio", "audio/audio", float(p.duration),
                                p.filename or _stamped(p.timestamp, "wav"), ctx.progress,
                                ctx.cancelled)


def _onvif_camera_snapshot(ctx: Context, p: OnvifCameraSnapshotAction) -> Outcome:
    return ctx.robot.save_media("image", "/ptz_camera/image_raw", 0.0, "", ctx.progress,
                                ctx.cancelled)


def _blockly(ctx: Context, p: BlocklyAction) -> Outcome:
    """Run Blockly program ``api_key``: its blocks interpreted (`blockly.Runner`)."""
    try:
        program = ctx.robot.blockly_program(p.api_key)
    except LookupError as exc:
        return Outcome("error", str(exc))
    name = f"Blockly program {program.title!r} ({program.id})"
    if not program.is_enabled:
        return Outcome("error", f"{name} is disabled")
    try:
        chains = parse(program.blocklyxml)
    except ProgramError as exc:
        return Outcome("error", f"{name}: {exc}")
    return Runner(ctx.robot, ctx.cancelled).run(chains)


def _upload_map(ctx: Context, p: UploadMapAction) -> Outcome:
    return ctx.robot.upload_map(p.server_id)


def _download_map(ctx: Context, p: DownloadMapAction) -> Outcome:
    return ctx.robot.download_map(p.server_id, p.map_id)


BEHAVIORS: Final[dict[str, Callable[[Context, Any], Outcome]]] = {
    "nav_action": _nav,
    "sleep_action": _sleep,
    "charge_action": _charge,
    "callback_action": _callback,
    "wait_req_action": _wait_req,
    "tts_action": _tts,
    "switch_map_action": _switch_map,
    "local_move_action": _local_move,
    "local_move_target_action": _local_move_target,
    "io_action": _io,
    "upload_map_action": _upload_map,
    "download_map_action": _download_map,
    "slide_action": _slide,
    "jacking_action": _jacking,
    "jacking_rotate_action": _jacking_rotate,
    "blockly_action": _blockly,
    "onvif_camera_move_action": _onvif_camera_move,
    "onvif_camera_snapshot_action": _onvif_camera_snapshot,
    "image_action": _image,
    "video_record_action": _video_record,
    "audio_record_action": _audio_record,
    "none_stop_nav_action": _none_stop_nav,
    "elevator_req_action": elevator_req,
    "lbt_elevator_req_action": lbt_elevator_req,
    "lbt_elevator_ack_action": lbt_elevator_ack,
    "change_setting_action": change_setting,
    "roslaunch_action": roslaunch,
}
