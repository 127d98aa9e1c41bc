"""`MediaLink`: snapshots and recordings for the tasks service (``image_action``,
``video_record_action``, ``audio_record_action``, ``onvif_camera_snapshot_action``), made by
the gateway, which keeps the robot's Pictures, Videos and Audios, over its ``media/save``
(zenros_msgs/SaveMedia).

The call is made at once and answered once the file is saved (a video: after its duration);
cancelling returns at once and leaves a recording to end by itself (the file keeps what was
recorded)."""

from __future__ import annotations

import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Final, Literal

from zenros.errors import ZenrosError
from zenros.msgs.zenros_msgs import SaveMedia, SaveMediaRequest, SaveMediaResponse
from zenros.node import Node

from .robot import Outcome

__all__ = ["MediaLink"]

POLL: Final = 0.05
GRACE: Final = 40.0  # s past a video's duration the answer may take (the gateway's 30 s + call)


class MediaLink:
    """One save per call; made at the first (most tasks never save a picture)."""

    def __init__(self, node: Node, server_wait: float = 5.0) -> None:
        self.node = node
        self.server_wait = server_wait
        self._client: Any = None
        self._calls = ThreadPoolExecutor(2, thread_name_prefix="media")  # a call blocks
        node.on_close(lambda: self._calls.shutdown(wait=False, cancel_futures=True))

    def save(self, kind: Literal["image", "video", "audio"], topic: str, duration: float,
             filename: str, progress: Callable[[float], None],
             cancelled: Callable[[], bool]) -> Outcome:
        """`Robot.save_media`."""
        what = {"image": "snapshot", "video": "video", "audio": "recording"}[kind] \
            + f" of {topic}"
        if self._client is None:
            self._client = self.node.create_client(SaveMedia, "media/save")
        if not self._client.wait_for_service(self.server_wait):
            return Outcome("error", f"{what}: no gateway serves media/save (it keeps the "
                                    "robot's pictures, videos and audio recordings)")
        timeout = (duration if kind != "image" else 0.0) + GRACE
        future = self._calls.submit(self._client.call, SaveMediaRequest(
            kind=kind, topic=topic, duration=float(duration), filename=filename), timeout)
        start = time.monotonic()
        while not future.done():
            if cancelled():  # the call ends by itself, its answer unread
                return Outcome("preempted")
            if kind != "image":
                progress(min(0.99, (time.monotonic() - start) / duration))
            time.sleep(POLL)
        try:
            res: SaveMediaResponse = future.result()
        except ZenrosError as exc:
            return Outcome("error", f"{what}: {exc}")
        if not res.success:
            return Outcome("error", f"{what}: {res.message}")
        progress(1.0)
        return Outcome("complete", res.message)
