"""`AudioRecordings`: the robot's microphone (``audio/audio`` and ``audio/audio_info``,
audio_common_msgs, as the chassis's microphone or ROS's audio_capture publish them) recorded
as WAV files in the robot's ``Audios`` folder, for the tasks service's ``audio_record_action``
(over ``media/save``).

A recording takes ``duration`` seconds of sound, counted in samples (so on a simulated robot
they are sim seconds), from the chunks that arrive after it starts; it is written to
``<name>.wav.part`` and renamed once whole, so a listed recording is always complete.
"""

from __future__ import annotations

import asyncio
import threading
import time
import wave
from pathlib import Path
from typing import Final

import numpy as np
from zenros.msgs.audio_common_msgs import AudioData, AudioInfo
from zenros.node import Node
from zenros.qos import QOS_LATCHED, QoSProfile

from .media_folder import MediaError, MediaFolder

__all__ = ["MAX_DURATION", "AudioRecordings"]

MAX_DURATION: Final = 600  # s
SILENCE: Final = 5.0  # wall s without a chunk (or the format) before a recording fails
POLL: Final = 0.02
SAMPLE_BYTES: Final = {"S16LE": 2}  # the sample formats a WAV is written from


class _Take:
    """One recording's chunks, as they arrive."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.info: AudioInfo | None = None
        self.chunks: list[bytes] = []
        self.size = 0
        self.heard = time.monotonic()

    def on_info(self, msg: AudioInfo) -> None:
        with self.lock:
            self.info = msg

    def on_audio(self, msg: AudioData) -> None:
        data = np.asarray(msg.data, dtype=np.uint8).tobytes()
        with self.lock:
            self.chunks.append(data)
            self.size += len(data)
            self.heard = time.monotonic()


class AudioRecordings:
    """Records ``node``'s ``audio/audio`` into ``folder``."""

    def __init__(self, node: Node, folder: Path) -> None:
        self.node = node
        self.folder = folder
        self.files = MediaFolder(folder, ".wav", "saved audio", "the Audios folder")

    async def record(self, duration: float, filename: str = "") -> tuple[Path, float]:
        """``duration`` s of the microphone as ``<ms timestamp>.wav`` (or ``filename``): the
        file and the seconds it holds, once saved.

        Raises:
            MediaError: 400 a bad name or duration, 409 the name is taken, 503 no
                microphone (nothing on ``audio/audio_info`` or ``audio/audio``), or it fell
                silent, or a format a WAV cannot hold.
        """
        if not 0 < duration <= MAX_DURATION:
            raise MediaError(400, f"duration must be in (0, {MAX_DURATION}] s, got {duration}")
        path = self.folder / self.files.file_name(filename)
        if path.exists():
            raise MediaError(409, f"a saved audio named {path.name} exists already")
        take = _Take()
        subs = [self.node.create_subscription(AudioInfo, "audio/audio_info", take.on_info,
                                              QOS_LATCHED),
                self.node.create_subscription(AudioData, "audio/audio", take.on_audio,
                                              QoSProfile(depth=100))]
        try:
            info, data = await asyncio.to_thread(self._collect, take, duration)
        finally:
            for sub in subs:
                self.node.destroy(sub)
        self.folder.mkdir(parents=True, exist_ok=True)
        part = path.with_name(path.name + ".part")
        with wave.open(str(part), "wb") as out:
            out.setnchannels(info.channels)
            out.setsampwidth(SAMPLE_BYTES[info.sample_format])
            out.setframerate(info.sample_rate)
            out.writeframes(data)
        part.replace(path)
        frame = info.channels * SAMPLE_BYTES[info.sample_format]
        return path, len(data) / frame / info.sample_rate

    def _collect(self, take: _Take, duration: float) -> tuple[AudioInfo, bytes]:
        """Wait for ``duration`` s of chunks: the format and the bytes, cut at the end."""
        started = time.monotonic()
        while True:
            with take.lock:
                info, size, heard = take.info, take.size, take.heard
            now = time.monotonic()
            if info is None and now - started > SILENCE:
                raise MediaError(503, "no microphone: nothing on audio/audio_info within "
                                      f"{SILENCE:g} s (the chassis's microphone_rate is 0, or "
                                      "no chassis runs)")
            if info is not None:
                if info.coding_format != "wave" or info.sample_format not in SAMPLE_BYTES \
                        or not info.channels or not info.sample_rate:
                    raise MediaError(503, f"the microphone sends {info.coding_format} "
                                          f"{info.sample_format} x{info.channels} at "
                                          f"{info.sample_rate} Hz; a WAV is written from "
                                          "wave S16LE only")
                need = round(duration * info.sample_rate) * info.channels \
                    * SAMPLE_BYTES[info.sample_format]
                if size >= need:
                    with take.lock:
                        return info, b"".join(take.chunks)[:need]
                if now - heard > SILENCE and now - started > SILENCE:
                    raise MediaError(503, f"the microphone fell silent: nothing on "
                                          f"audio/audio for {SILENCE:g} s")
            time.sleep(POLL)
