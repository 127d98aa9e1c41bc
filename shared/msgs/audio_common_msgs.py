"""audio_common_msgs: a microphone's sound as ROS's audio_common carries it: ``audio``
(AudioData: chunks of raw samples) and ``audio_info`` (AudioInfo: their format). The simulated
robot's microphone (docs/chassis.md, "Microphone") publishes them; the gateway records them
as WAV (``audio_record_action``)."""

from __future__ import annotations

import msgspec

from .. import primitives
from ..message import Message, UInt8Array, array_field
from .std_msgs import Header

__all__ = ["AudioData", "AudioDataStamped", "AudioInfo"]


class AudioData(Message):
    """One chunk of audio: the bytes as ``audio_info`` describes them (``S16LE`` samples
    for ``wave`` coding)."""

    __msgtype__ = "audio_common_msgs/AudioData"
    __bulk__ = True
    data: UInt8Array = array_field(UInt8Array)


class AudioDataStamped(Message):
    """A chunk with the time its first sample was taken."""

    __msgtype__ = "audio_common_msgs/AudioDataStamped"
    __bulk__ = True
    header: Header = msgspec.field(default_factory=Header)
    audio: AudioData = msgspec.field(default_factory=AudioData)


class AudioInfo(Message):
    """The format of the ``audio`` chunks: ``channels``, ``sample_rate`` (Hz),
    ``sample_format`` (``S16LE``), ``bitrate`` (0 for raw samples), ``coding_format``
    (``wave``: raw PCM; ``mp3``)."""

    __msgtype__ = "audio_common_msgs/AudioInfo"
    channels: primitives.UInt8 = 1
    sample_rate: primitives.UInt32 = 16000
    sample_format: str = "S16LE"
    bitrate: primitives.UInt32 = 0
    coding_format: str = "wave"
