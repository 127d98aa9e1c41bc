"""zenros_msgs for the gateway's media folders (docs/robot-api.md §3.9): the tasks service's
``image_action``, ``video_record_action``, ``audio_record_action`` and
``onvif_camera_snapshot_action`` ask the gateway, which keeps the robot's ``Pictures``,
``Videos`` and ``Audios``, through ``media/save``.
"""

from __future__ import annotations

from typing import Literal

from ...message import Message, define_service

__all__ = ["SaveMedia", "SaveMediaRequest", "SaveMediaResponse"]


class SaveMediaRequest(Message):
    """``kind`` ``image``: the next frame of camera ``topic`` as a PNG in Pictures; ``video``:
    ``duration`` seconds of it as an MKV in Videos (answered once recorded); ``audio``:
    ``duration`` seconds of the microphone (``audio/audio``; ``topic`` not used) as a WAV in
    Audios. ``filename``: the file's name (default ``<ms timestamp>.png|.mkv|.wav``)."""

    __msgtype__ = "zenros_msgs/SaveMediaRequest"
    kind: Literal["image", "video", "audio"] = "image"
    topic: str = "/camera_node/image_raw"
    duration: float = 10.0
    filename: str = ""


class SaveMediaResponse(Message):
    """``success`` false with the reason in ``message``; ``file``: the file's name in its
    folder; ``frames``: a video's frames."""

    __msgtype__ = "zenros_msgs/SaveMediaResponse"
    success: bool = False
    message: str = ""
    file: str = ""
    frames: int = 0


SaveMedia = define_service("zenros_msgs/SaveMedia", SaveMediaRequest, SaveMediaResponse)
