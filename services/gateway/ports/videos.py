"""`Videos`: camera recordings saved as Matroska (``.mkv``, H.264) files in the robot's
``Videos`` folder (docs/robot-api.md §3.9), recorded in the background.

A recording subscribes to a camera topic and encodes each frame as it arrives, its time in
the file taken from the frame's stamp, for ``duration`` seconds of wall time; it is written to
``<name>.mkv.part`` and renamed when complete, so a listed video is always whole. Encoding
uses PyAV (FFmpeg), the ``video`` extra: without it, a start is a 503 naming the extra.
"""

from __future__ import annotations

import importlib
import queue
import threading
import time
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any, Final

import numpy as np
from zenros.msgs.sensor_msgs import Image
from zenros.node import Node
from zenros.qos import QOS_SENSOR

from .media_folder import MediaError, MediaFolder
from .snapshots import camera_publishes, check_camera_topic, frame_pixels

__all__ = ["MAX_DURATION", "Videos"]

MAX_DURATION: Final = 3600  # s
FIRST_FRAME: Final = 5.0  # s a recording waits for its first frame
CODEC: Final = "libx264"
TIME_BASE: Final = 1000  # the file's ticks per second (ms)


def _av() -> Any:
    try:
        return importlib.import_module("av")
    except ImportError:
        raise MediaError(503, "recording videos needs PyAV, the video extra: "
                              "pip install 'zenros[video]'") from None


@dataclass
class Recording:
    """One recording under way."""

    topic: str
    path: Path
    duration: float
    frames: int = 0
    error: str = ""
    started: float = field(default_factory=time.monotonic)
    done: threading.Event = field(default_factory=threading.Event)


class Videos:
    """Records the robot's cameras (topics relative to ``node``'s namespace) into ``folder``;
    at most ``max_active`` recordings at once."""

    def __init__(self, node: Node, folder: Path, max_active: int = 2) -> None:
        self.node = node
        self.folder = folder
        self.files = MediaFolder(folder, ".mkv", "saved video", "/system/saved_videos/")
        self.max_active = max_active
        self._lock = threading.Lock()
        self._active: dict[str, Recording] = {}

    def start(self, topic: str, duration: float, filename: str = "") -> Recording:
        """Start recording ``topic`` for ``duration`` s into ``<ms timestamp>.mkv`` (or
        ``filename``); returns at once.

        Raises:
            MediaError: 404 not a camera topic, 400 a bad name or duration, 409 the name is
                taken or too many recordings run, 503 no camera publishes or no PyAV.
        """
        av = _av()
        check_camera_topic(topic)
        if not 0 < duration <= MAX_DURATION:
            raise MediaError(400, f"duration must be 1-{MAX_DURATION} s, got {duration:g}")
        name = self.files.file_name(filename)
        resolved = camera_publishes(self.node, topic)
        path = self.folder / name
        with self._lock:
            if path.exists() or name in self._active:
                raise MediaError(409, f"a video {name} exists already")
            if len(self._active) >= self.max_active:
                raise MediaError(409, f"{len(self._active)} recordings are under way (at "
                                      f"most {self.max_active}); wait for one to end")
            rec = self._active[name] = Recording(resolved, path, duration)
        threading.Thread(target=self._record, args=(av, rec, topic.lstrip("/")),
                         name=f"video:{name}", daemon=True).start()
        return rec

    def recording(self) -> list[dict[str, Any]]:
        """The recordings under way: name, topic, seconds recorded, frames."""
        with self._lock:
            return [{"filename": r.path.name, "topic": r.topic, "frames": r.frames,
                     "elapsed": round(time.monotonic() - r.started, 1),
                     "duration": r.duration} for r in self._active.values()]

    def close(self) -> None:
        """End the recordings under way (each keeps what it has recorded)."""
        with self._lock:
            recs = list(self._active.values())
        for rec in recs:
            rec.duration = 0.0
        for rec in recs:
            rec.done.wait(10)

    def _record(self, av: Any, rec: Recording, topic: str) -> None:
        frames: queue.Queue[Image] = queue.Queue(maxsize=64)

        def on_frame(msg: Image) -> None:
            try:
                frames.put_nowait(msg)
            except queue.Full:  # the encoder is behind: this frame is dropped
                pass

        sub = self.node.create_subscription(Image, topic, on_frame, QOS_SENSOR)
        tmp = rec.path.with_suffix(".mkv.part")
        try:
            self._encode(av, rec, frames, tmp)
            if rec.frames:
                tmp.replace(rec.path)
                self.node.logger.info("video %s: %d frames from %s", rec.path.name,
                                      rec.frames, rec.topic)
        except MediaError as exc:
            rec.error = str(exc)
        except Exception as exc:  # noqa: BLE001 -- the encoder's failure ends this recording only
            rec.error = f"the encoder failed: {exc}"
        finally:
            self.node.destroy(sub)
            tmp.unlink(missing_ok=True)
            with self._lock:
                self._active.pop(rec.path.name, None)
            if rec.error:
                self.node.logger.error("video %s: %s", rec.path.name, rec.error)
            rec.done.set()

    def _encode(self, av: Any, rec: Recording, frames: queue.Queue[Image], tmp: Path) -> None:
        try:
            first = frames.get(timeout=FIRST_FRAME)
        except queue.Empty:
            raise MediaError(503, f"no frame on {rec.topic} within {FIRST_FRAME:g} s") from None
        pixels, mode = frame_pixels(first)
        height, width = pixels.shape[:2]
        self.folder.mkdir(parents=True, exist_ok=True)
        t0 = first.header.stamp.nanoseconds
        last_pts = -1
        with av.open(str(tmp), "w", format="matroska") as container:
            stream = container.add_stream(CODEC, rate=30)
            stream.width, stream.height = width - width % 2, height - height % 2
            stream.pix_fmt = "yuv420p"
            stream.codec_context.time_base = Fraction(1, TIME_BASE)
            msg: Image | None = first
            while True:
                if msg is not None:
                    pixels, mode = frame_pixels(msg)
                    pts = max(last_pts + 1, (msg.header.stamp.nanoseconds - t0) // 1_000_000)
                    frame = av.VideoFrame.from_ndarray(
                        _rgb(pixels, mode)[:stream.height, :stream.width], format="rgb24")
                    frame.pts, frame.time_base = pts, stream.codec_context.time_base
                    for packet in stream.encode(frame):
                        container.mux(packet)
                    last_pts = pts
                    rec.frames += 1
                left = rec.duration - (time.monotonic() - rec.started)
                if left <= 0:
                    break
                try:
                    msg = frames.get(timeout=min(left, 0.5))
                except queue.Empty:
                    msg = None
            for packet in stream.encode():
                container.mux(packet)


def _rgb(pixels: Any, mode: str) -> Any:
    """Pixels as HxWx3 RGB (a mono frame repeated, an alpha channel dropped)."""
    if mode == "L":
        return np.repeat(pixels[:, :, None], 3, axis=2)
    if mode == "RGBA":
        return np.ascontiguousarray(pixels[:, :, :3])
    return np.ascontiguousarray(pixels)
