"""The simulated microphone (services/chassis/devices/microphone.py): its chunks are as long
as the sim time they cover, silent but for the noise floor when the robot stands, and louder
and higher the faster the wheels turn; nothing is rendered while nobody listens."""

from __future__ import annotations

import logging
from typing import Any

import numpy as np
from zenros.clock import Time
from zenros.msgs.audio_common_msgs import AudioData, AudioInfo
from zenros.params import Parameters
from zenros.services.chassis.config import declare_chassis
from zenros.services.chassis.device import Chassis, Schedule
from zenros.services.chassis.devices import MicrophoneDevice
from zenros.services.chassis.devices.microphone import MicrophoneParameters, render

STAMP = Time(sec=1, nanosec=0)


class Pub:
    def __init__(self) -> None:
        self.sent: list[Any] = []
        self.subscription_count = 1

    def publish(self, msg: Any) -> None:
        self.sent.append(msg)


class Node:
    """Only the publishers the microphone makes."""

    namespace = "/"
    logger = logging.getLogger("test")

    def __init__(self) -> None:
        self.publishers: dict[str, Pub] = {}

    def create_publisher(self, msg_type: type[Any], topic: str, qos: Any = 10) -> Pub:
        self.publishers[topic] = Pub()
        return self.publishers[topic]


def microphone(values: dict[str, object] | None = None) -> tuple[Chassis, MicrophoneDevice,
                                                                  Node]:
    chassis = declare_chassis(Parameters("/chassis", values or {})).build(
        logging.getLogger("test"))
    mic = chassis.device(MicrophoneDevice)
    assert mic is not None
    node = Node()
    mic.open(node)  # type: ignore[arg-type]
    return chassis, mic, node


def listen(chassis: Chassis, mic: MicrophoneDevice, seconds: float, speed: float) -> bytes:
    """``seconds`` of sound at 50 steps a second with the base at ``speed`` m/s."""
    schedule = Schedule([mic], 50.0)
    out = b""
    pub = chassis_node_pub(mic)
    start = len(pub.sent)
    for step in range(1, round(seconds * 50) + 1):
        chassis.sim.linear = speed
        mic.step(0.02)
        schedule.publish(step, STAMP)
    for msg in pub.sent[start:]:
        out += np.asarray(msg.data, dtype=np.uint8).tobytes()
    return out


def chassis_node_pub(mic: MicrophoneDevice) -> Pub:
    return mic._pub  # type: ignore[return-value]


def rms(pcm: bytes) -> float:
    return float(np.sqrt(np.mean(np.frombuffer(pcm, "<i2").astype(np.float64) ** 2)))


def test_the_format_is_announced_and_chunks_cover_their_sim_time() -> None:
    chassis, mic, node = microphone()
    (info,) = node.publishers["audio/audio_info"].sent
    assert isinstance(info, AudioInfo)
    assert (info.channels, info.sample_rate, info.sample_format, info.coding_format) == (
        1, 16000, "S16LE", "wave")
    pcm = listen(chassis, mic, 2.0, 0.0)
    chunks = node.publishers["audio/audio"].sent
    assert all(isinstance(c, AudioData) for c in chunks) and len(chunks) == 20
    assert len(pcm) == 2 * 16000 * 2  # two sim seconds of 16-bit samples


def test_a_driving_robot_hums_louder_than_a_still_one() -> None:
    chassis, mic, _ = microphone()
    still = rms(listen(chassis, mic, 1.0, 0.0))
    slow = rms(listen(chassis, mic, 1.0, 0.2))
    fast = rms(listen(chassis, mic, 1.0, 0.8))
    assert 50 < still < 200  # the noise floor: 0.003 of full scale
    assert still * 10 < slow < fast


def test_the_hum_rises_with_speed() -> None:
    params = MicrophoneParameters(microphone_noise=0.0)
    rng = np.random.default_rng(0)

    def pitch(speed: float) -> float:
        pcm, _ = render(16000, speed, 0.0, params, rng)
        spectrum = np.abs(np.fft.rfft(np.frombuffer(pcm, "<i2")))
        return float(np.argmax(spectrum))  # Hz: one second of samples
    assert pitch(0.2) == 140.0 and pitch(1.0) == 380.0


def test_nothing_is_rendered_while_nobody_listens_and_no_microphone_at_rate_0() -> None:
    chassis, mic, node = microphone()
    node.publishers["audio/audio"].subscription_count = 0
    assert listen(chassis, mic, 1.0, 0.5) == b""
    _, off, node = microphone({"microphone_rate": 0})
    assert off.rate == 0 and node.publishers == {}
