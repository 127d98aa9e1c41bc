"""`Snapshots`: camera pictures saved as PNG files in the robot's ``Pictures`` folder
(docs/robot-api.md §3.9): one frame of a camera topic, taken when asked."""

from __future__ import annotations

import asyncio
import threading
from pathlib import Path
from typing import Any

from PIL import Image as PilImage
from zenros.images import image_to_numpy
from zenros.msgs.sensor_msgs import Image
from zenros.node import Node
from zenros.qos import QOS_SENSOR

from .media_folder import MediaError, MediaFolder

__all__ = ["CAMERA_TOPICS", "PTZ_TOPIC", "Snapshots", "camera_publishes", "check_camera_topic",
           "frame_pixels"]

PTZ_TOPIC = "/ptz_camera/image_raw"  # the PTZ (ONVIF) camera's, fixed in the world
CAMERA_TOPICS = ("/camera_node/image_raw", "/multi/front/image_raw", "/multi/back/image_raw",
                 PTZ_TOPIC)
FRAME_TIMEOUT = 5.0  # s to wait for a frame of the camera


def check_camera_topic(topic: str) -> None:
    """404 (a `MediaError`) for a topic that is not one of the cameras'."""
    if topic not in CAMERA_TOPICS:
        raise MediaError(404, f"no camera topic {topic!r}: the cameras publish on "
                              f"{', '.join(CAMERA_TOPICS)}")


def camera_publishes(node: Node, topic: str) -> str:
    """The resolved camera topic; 503 (a `MediaError`) when nothing publishes on it."""
    name = node.resolve_name(topic.lstrip("/"))
    if not node.context.graph.publishers(name):
        which = "ptz_camera" if "ptz_camera" in name else "camera_rate"
        raise MediaError(503, f"no camera publishes on {name}: is the chassis (its "
                              f"cameras: parameter {which}) running?")
    return name


def frame_pixels(msg: Image) -> tuple[Any, str]:
    """A camera frame's pixels and their PIL mode (``RGB``, ``RGBA``, ``L``); 502 (a
    `MediaError`) for a frame that cannot be read or an encoding that is not kept."""
    try:
        pixels = image_to_numpy(msg)
    except Exception as exc:
        raise MediaError(502, f"the camera sent a frame that cannot be read: {exc}") from exc
    mode = {"rgb8": "RGB", "rgba8": "RGBA", "mono8": "L"}.get(msg.encoding)
    if mode is None:
        if msg.encoding != "bgr8":
            raise MediaError(502, f"frames in {msg.encoding} are not kept")
        pixels, mode = pixels[:, :, ::-1], "RGB"
    return pixels, mode


class Snapshots:
    """Takes pictures from the robot's cameras (topics relative to ``node``'s namespace, so
    a fleet's robot gets its own) into ``folder``."""

    def __init__(self, node: Node, folder: Path) -> None:
        self.node = node
        self.files = MediaFolder(folder, ".png", "saved image", "/system/saved_images/")
        self.folder = folder
        self._lock = threading.Lock()

    async def take(self, topic: str, filename: str = "") -> Path:
        """Save the next frame of ``topic`` as ``<ms timestamp>.png`` (or ``filename``)."""
        check_camera_topic(topic)
        name = self.files.file_name(filename)
        msg = await asyncio.to_thread(self._one_frame, topic.lstrip("/"))
        path = self.folder / name
        await asyncio.to_thread(self._save, msg, path)
        return path

    def _one_frame(self, topic: str) -> Image:
        name = camera_publishes(self.node, topic)
        got: list[Image] = []
        done = threading.Event()

        def on_frame(msg: Image) -> None:
            if not got:
                got.append(msg)
                done.set()

        sub = self.node.create_subscription(Image, topic, on_frame, QOS_SENSOR)
        try:
            if not done.wait(FRAME_TIMEOUT):
                raise MediaError(503, f"no frame on {name} within {FRAME_TIMEOUT:g} s")
        finally:
            self.node.destroy(sub)
        return got[0]

    def _save(self, msg: Image, path: Path) -> None:
        pixels, mode = frame_pixels(msg)
        with self._lock:
            self.folder.mkdir(parents=True, exist_ok=True)
            tmp = path.with_suffix(".png.part")
            PilImage.fromarray(pixels, mode).save(tmp, "PNG")
            tmp.replace(path)
