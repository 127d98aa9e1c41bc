"""``media/save`` (zenros_msgs/SaveMedia): the gateway's ``Pictures`` and ``Videos`` for the
robot's other services (the tasks service's ``image_action``, ``video_record_action`` and
``onvif_camera_snapshot_action``): a snapshot or a recording made as ``POST
/system/saved_images`` and ``POST /system/saved_videos`` make them, answered once saved."""

from __future__ import annotations

import asyncio

from zenros.msgs.zenros_msgs import SaveMedia, SaveMediaRequest, SaveMediaResponse
from zenros.node import Node

from .audio_recordings import AudioRecordings
from .media_folder import MediaError
from .snapshots import Snapshots
from .videos import Videos

__all__ = ["RECORD_GRACE", "MediaService"]

RECORD_GRACE = 30.0  # s past a video's duration its encoding may take before the answer fails


class MediaService:
    """Serves ``media/save`` on ``node`` with ``snapshots`` and ``videos``."""

    def __init__(self, node: Node, snapshots: Snapshots, videos: Videos,
                 audios: AudioRecordings | None = None) -> None:
        self.snapshots = snapshots
        self.videos = videos
        self.audios = audios
        node.create_service(SaveMedia, "media/save", self.save)

    async def save(self, req: SaveMediaRequest, res: SaveMediaResponse) -> SaveMediaResponse:
        try:
            if req.kind == "image":
                path = await self.snapshots.take(req.topic, req.filename)
                return SaveMediaResponse(success=True, message=f"saved {path.name}",
                                         file=path.name)
            if req.kind == "audio":
                if self.audios is None:
                    return SaveMediaResponse(message="this gateway keeps no audio recordings")
                path, seconds = await self.audios.record(req.duration, req.filename)
                return SaveMediaResponse(success=True, message=f"recorded {path.name} "
                                         f"({seconds:g} s)", file=path.name)
            rec = self.videos.start(req.topic, req.duration, req.filename)
        except MediaError as exc:
            return SaveMediaResponse(message=str(exc))
        ended = await asyncio.to_thread(rec.done.wait, req.duration + RECORD_GRACE)
        if not ended:
            return SaveMediaResponse(message=f"{rec.path.name}: still encoding "
                                             f"{RECORD_GRACE:g} s after its end", file=rec.path.name)
        if rec.error:
            return SaveMediaResponse(message=f"{rec.path.name}: {rec.error}", file=rec.path.name,
                                     frames=rec.frames)
        return SaveMediaResponse(success=True, message=f"recorded {rec.path.name} "
                                 f"({rec.frames} frames)", file=rec.path.name, frames=rec.frames)
