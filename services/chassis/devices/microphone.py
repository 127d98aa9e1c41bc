"""The microphone: ``audio/audio`` (audio_common_msgs/AudioData, 16-bit little-endian mono
chunks of ``microphone_chunk`` sim seconds) and ``audio/audio_info`` (AudioInfo, latched), as
ROS's audio_capture publishes them.

The sound is rendered from the world: a noise floor (``microphone_noise``) and the drive's
hum, its loudness growing with the wheels' speed (``microphone_motor_gain`` of full scale per
m/s, capped at half) and its pitch too (80 Hz, plus 300 Hz per m/s), with its second
harmonic. A still robot hears only the floor. Chunks are rendered only while someone listens.
"""

from __future__ import annotations

import math
from typing import Annotated

import msgspec
import numpy as np
from msgspec import Meta
from zenros.clock import Time
from zenros.message import UInt8Array, to_array
from zenros.msgs.audio_common_msgs import AudioData, AudioInfo
from zenros.pubsub import Publisher
from zenros.qos import QOS_LATCHED, QoSProfile
from zenros.se2 import wrap_angle

from ..device import Chassis, Device, Endpoints

__all__ = ["MicrophoneDevice", "MicrophoneParameters", "render"]

FULL_SCALE = 32767
HUM_HZ = 80.0      # the drive's pitch standing still
HUM_HZ_PER_MS = 300.0  # and its rise per m/s
QOS_AUDIO = QoSProfile(depth=20)  # reliable: a recording needs every chunk


class MicrophoneParameters(msgspec.Struct, kw_only=True, frozen=True):
    microphone_rate: Annotated[int, Meta(
        ge=0, le=48000, description="samples per sim second (0: no microphone)")] = 16000
    microphone_chunk: Annotated[float, Meta(
        ge=0.01, le=1.0, description="sim seconds of sound in one audio message")] = 0.1
    microphone_noise: Annotated[float, Meta(
        ge=0.0, le=1.0, description="std dev of the noise floor, of full scale")] = 0.003
    microphone_motor_gain: Annotated[float, Meta(
        ge=0.0, le=10.0, description="the drive's hum amplitude per m/s of wheel speed, "
                                     "of full scale")] = 0.3


def render(samples: int, speed: float, phase: float, params: MicrophoneParameters,
           rng: np.random.Generator) -> tuple[bytes, float]:
    """``samples`` of sound for a robot driving at ``speed`` (m/s, the wheels' mean), the
    hum starting at ``phase`` (rad): the S16LE bytes and the hum's phase after them."""
    rate = params.microphone_rate
    freq = HUM_HZ + HUM_HZ_PER_MS * speed
    amp = min(0.5, params.microphone_motor_gain * speed)
    t = np.arange(samples, dtype=np.float64)
    angle = phase + 2.0 * math.pi * freq * t / rate
    wave = amp * (0.8 * np.sin(angle) + 0.2 * np.sin(2.0 * angle))
    if params.microphone_noise > 0:
        wave = wave + rng.normal(0.0, params.microphone_noise, samples)
    pcm = np.clip(np.round(wave * FULL_SCALE), -FULL_SCALE, FULL_SCALE).astype("<i2")
    return pcm.tobytes(), wrap_angle(phase + 2.0 * math.pi * freq * samples / rate)


class MicrophoneDevice(Device[MicrophoneParameters]):
    """Hears the drive each physics step; publishes a chunk every ``microphone_chunk``."""

    Parameters = MicrophoneParameters
    _pub: Publisher[AudioData]

    def __init__(self, params: MicrophoneParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.rate = 1.0 / params.microphone_chunk if params.microphone_rate > 0 else 0.0
        self.inert = self.rate <= 0
        self._heard = 0.0   # sim seconds since the last chunk
        self._motion = 0.0  # their integral of the wheels' mean speed (m)
        self._owed = 0.0    # samples' fractions carried to the next chunk
        self._phase = 0.0
        self._rng = np.random.default_rng(16000)  # its own: the other devices' noise stays

    def open(self, node: Endpoints) -> None:
        if self.rate <= 0:
            return
        self._pub = node.create_publisher(AudioData, "audio/audio", QOS_AUDIO)
        info = node.create_publisher(AudioInfo, "audio/audio_info", QOS_LATCHED)
        info.publish(AudioInfo(channels=1, sample_rate=self.params.microphone_rate,
                               sample_format="S16LE", bitrate=0, coding_format="wave"))

    def step(self, dt: float) -> None:
        if self.rate <= 0:
            return
        sim = self.chassis.sim
        self._heard += dt
        self._motion += (abs(sim.linear) + 0.15 * abs(sim.angular)) * dt

    def publish(self, stamp: Time) -> None:
        if self.rate <= 0:
            return
        heard, motion = self._heard, self._motion
        self._heard = self._motion = 0.0
        if not self._pub.subscription_count:
            self._owed = 0.0
            return
        exact = heard * self.params.microphone_rate + self._owed
        samples = int(exact)
        self._owed = exact - samples
        if samples <= 0:
            return
        speed = motion / heard if heard > 0 else 0.0
        data, self._phase = render(samples, speed, self._phase, self.params, self._rng)
        self._pub.publish(AudioData(data=to_array(UInt8Array, data)))
