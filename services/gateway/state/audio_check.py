"""What an uploaded recording is: a WAV (RIFF/PCM, read by the standard `wave` module) or an MP3
(MPEG audio frames, walked header by header), and how long it plays. Anything else is refused
with the reason; nothing is decoded beyond the headers."""

from __future__ import annotations

import io
import wave
from typing import Final, Literal

__all__ = ["AudioError", "audio_duration"]

Kind = Literal["wav", "mp3"]

# MPEG-1 and MPEG-2/2.5 Layer III bitrates (kbit/s) by index, and sample rates by version
_BITRATES: Final = {
    3: (0, 32, 40, 48, 56, 64, 80, 96, 112, 128, 160, 192, 224, 256, 320),  # MPEG-1
    2: (0, 8, 16, 24, 32, 40, 48, 56, 64, 80, 96, 112, 128, 144, 160),      # MPEG-2
    0: (0, 8, 16, 24, 32, 40, 48, 56, 64, 80, 96, 112, 128, 144, 160),      # MPEG-2.5
}
_RATES: Final = {3: (44100, 48000, 32000), 2: (22050, 24000, 16000), 0: (11025, 12000, 8000)}


class AudioError(ValueError):
    """Not a recording we keep; the text says why."""


def audio_duration(data: bytes, filename: str) -> tuple[Kind, float]:
    """(``wav`` or ``mp3``, seconds) of a recording named ``filename``.

    Raises:
        AudioError: another suffix, or a file whose content is not what its name says.
    """
    name = filename.lower()
    if name.endswith(".wav"):
        return "wav", _wav(data)
    if name.endswith(".mp3"):
        return "mp3", _mp3(data)
    raise AudioError(f"{filename!r}: a recording is a .wav or an .mp3 file")


def _wav(data: bytes) -> float:
    try:
        with wave.open(io.BytesIO(data)) as w:
            frames, rate = w.getnframes(), w.getframerate()
    except (wave.Error, EOFError) as exc:
        raise AudioError(f"not a PCM WAV file: {exc}") from None
    if rate <= 0 or frames <= 0:
        raise AudioError("the WAV file holds no sound")
    return frames / rate


def _mp3(data: bytes) -> float:
    pos = 0
    if data[:3] == b"ID3" and len(data) >= 10:  # an ID3v2 tag first: its size is syncsafe
        size = (data[6] << 21) | (data[7] << 14) | (data[8] << 7) | data[9]
        pos = 10 + size
    seconds = 0.0
    frames = 0
    while pos + 4 <= len(data):
        b1, b2 = data[pos + 1], data[pos + 2]
        if data[pos] != 0xFF or (b1 & 0xE0) != 0xE0:
            break
        version, layer = (b1 >> 3) & 3, (b1 >> 1) & 3
        bitrate_i, rate_i, padding = b2 >> 4, (b2 >> 2) & 3, (b2 >> 1) & 1
        if version == 1 or layer != 1 or bitrate_i in (0, 15) or rate_i == 3:
            break  # reserved, not Layer III, free or bad bitrate, reserved rate
        bitrate = _BITRATES[version][bitrate_i] * 1000
        rate = _RATES[version][rate_i]
        samples = 1152 if version == 3 else 576
        length = samples // 8 * bitrate // rate + padding
        seconds += samples / rate
        frames += 1
        pos += length
    if frames < 2:
        raise AudioError("not an MP3 file (no MPEG audio Layer III frames)")
    return seconds
