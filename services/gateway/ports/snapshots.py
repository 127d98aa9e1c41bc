"""`Snapshots`: camera pictures saved as PNG files in the robot's ``Pictures`` folder
(docs/robot-api.md §3.9): one frame of a camera topic, taken when asked."""

from __future__ import annotations

import asyncio
import re
import threading
import time
from pathlib import Path
from typing import Any

from PIL import Image as PilImage
from zenros.images import image_to_numpy
from zenros.msgs.sensor_msgs import Image
from zenros.node import Node
from zenros.qos import QOS_SENSOR

__all__ = ["CAMERA_TOPICS", "SnapshotError", "Snapshots"]

CAMERA_TOPICS = ("/camera_node/image_raw", "/multi/front/image_raw", "/multi/back/image_raw")
FRAME_TIMEOUT = 5.0  # s to wait for a frame of the camera
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,99}$")


class SnapshotError(Exception):
    """A picture that cannot be taken or found: ``status`` is the HTTP status to answer."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status


class Snapshots:
    """Takes pictures from the robot's cameras (topics relative to ``node``'s namespace, so
    a fleet's robot gets its own) into ``folder``."""

    def __init__(self, node: Node, folder: Path) -> None:
        self.node = node
        self.folder = folder
        self._lock = threading.Lock()

    async def take(self, topic: str, filename: str = "") -> Path:
        """Save the next frame of ``topic`` as ``<ms timestamp>.png`` (or ``filename``)."""
        if topic not in CAMERA_TOPICS:
            raise SnapshotError(404, f"no camera topic {topic!r}: the cameras publish on "
                                     f"{', '.join(CAMERA_TOPICS)}")
        name = self._file_name(filename)
        msg = await asyncio.to_thread(self._one_frame, topic.lstrip("/"))
        path = self.folder / name
        await asyncio.to_thread(self._save, msg, path)
        return path

    def _file_name(self, filename: str) -> str:
        if not filename:
            return f"{int(time.time() * 1000)}.png"
        stem = filename.removesuffix(".png")
        if not _NAME.match(stem):
            raise SnapshotError(400, f"filename {filename!r}: letters, digits, '_', '-' and "
                                     "'.' only, at most 100, not starting with a dot")
        return f"{stem}.png"

    def _one_frame(self, topic: str) -> Image:
        name = self.node.resolve_name(topic)
        if not self.node.context.graph.publishers(name):
            raise SnapshotError(503, f"no camera publishes on {name}: is the chassis (its "
                                     "cameras: parameter camera_rate) running?")
        got: list[Image] = []
        done = threading.Event()

        def on_frame(msg: Image) -> None:
            if not got:
                got.append(msg)
                done.set()

        sub = self.node.create_subscription(Image, topic, on_frame, QOS_SENSOR)
        try:
            if not done.wait(FRAME_TIMEOUT):
                raise SnapshotError(503, f"no frame on {name} within {FRAME_TIMEOUT:g} s")
        finally:
            self.node.destroy(sub)
        return got[0]

    def _save(self, msg: Image, path: Path) -> None:
        try:
            pixels = image_to_numpy(msg)
        except Exception as exc:
            raise SnapshotError(502, f"the camera sent a frame that cannot be read: {exc}") \
                from exc
        mode = {"rgb8": "RGB", "rgba8": "RGBA", "mono8": "L"}.get(msg.encoding)
        if mode is None:
            if msg.encoding == "bgr8":
                pixels, mode = pixels[:, :, ::-1], "RGB"
            else:
                raise SnapshotError(502, f"frames in {msg.encoding} are not saved as pictures")
        with self._lock:
            self.folder.mkdir(parents=True, exist_ok=True)
            tmp = path.with_suffix(".png.part")
            PilImage.fromarray(pixels, mode).save(tmp, "PNG")
            tmp.replace(path)

    def listing(self) -> list[dict[str, Any]]:
        """The saved pictures, newest first: name, size in bytes, time (ms)."""
        if not self.folder.is_dir():
            return []
        out = []
        for p in self.folder.glob("*.png"):
            st = p.stat()
            out.append({"file_timestamp": p.stem, "filename": p.name, "size": st.st_size,
                        "time": int(st.st_mtime * 1000)})
        return sorted(out, key=lambda e: e["time"], reverse=True)

    def find(self, file_timestamp: str) -> Path:
        """The picture saved as ``file_timestamp`` (with or without ``.png``)."""
        stem = file_timestamp.removesuffix(".png")
        path = self.folder / f"{stem}.png"
        if not _NAME.match(stem) or not path.is_file():
            raise SnapshotError(404, f"no saved image {file_timestamp!r} "
                                     "(GET /system/saved_images/ lists them)")
        return path
