"""``audio_record_action`` (docs/tasks.md) through the real tasks service, gateway and the
simulated microphone: the robot's sound lands as a WAV in the gateway's Audios (over
``media/save``), as long as asked, and louder while the robot drives than while it stands;
without a microphone the action ends in ERROR saying so."""

from __future__ import annotations

import threading
import wave
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest
from task_runs import run_task
from zenros.context import Context
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.node import Node
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.node import GatewayNode
from zenros.services.tasks.node import TasksNode
from zenros.testing import wait_for

QUIET = {"camera_rate": 0.0, "actuators": False, "ptz_camera": False, "imu_rate": 0.0,
         "seed": 1}


@pytest.fixture
def chassis(ctx_pair: list[Context]) -> Iterator[ChassisNode]:
    node = ChassisNode(context=ctx_pair[1], parameter_overrides=QUIET)
    yield node
    node.close()


def run(http: httpx.Client, *actions: dict[str, Any], timeout: float = 60) -> dict[str, Any]:
    return run_task(http, *actions, name="audio", timeout=timeout)


def loudness(path: Path) -> tuple[int, int, float]:
    """(frame rate, frames, RMS) of a WAV file."""
    with wave.open(str(path)) as w:
        pcm = np.frombuffer(w.readframes(w.getnframes()), "<i2").astype(np.float64)
        return w.getframerate(), w.getnframes(), float(np.sqrt(np.mean(pcm ** 2)))


def test_the_microphone_is_recorded_as_a_task_action(
        chassis: ChassisNode, tasks: TasksNode, gw: GatewayNode, http: httpx.Client,
        ctx_pair: list[Context]) -> None:
    assert wait_for(lambda: gw.graph.publishers("/audio/audio") != [], 20)
    done = run(http, {"type": "audio_record_action", "duration": 2, "filename": "still"},
               {"type": "audio_record_action", "duration": 1, "timestamp": 1700000000123})
    assert done["state"] == "COMPLETE", done
    assert "recorded still.wav (2 s)" in done["sub_tasks"][0]["result"], done
    folder = gw.robot.audios.folder
    rate, frames, still = loudness(folder / "still.wav")
    assert (rate, frames) == (16000, 32000)
    assert loudness(folder / "1700000000123.wav")[1] == 16000
    # the same while the robot drives (cmd_vel at 10 Hz, as a joystick): the drive hums
    driver = Node("driver", context=ctx_pair[0])
    pub = driver.create_publisher(Twist, "cmd_vel")
    stop = threading.Event()

    def drive() -> None:
        while not stop.wait(0.1):
            pub.publish(Twist(linear=Vector3(x=0.3), angular=Vector3(z=0.5)))
    thread = threading.Thread(target=drive, daemon=True)
    thread.start()
    try:
        done = run(http, {"type": "audio_record_action", "duration": 2, "filename": "moving"})
    finally:
        stop.set()
        thread.join(5)
        driver.close()
    assert done["state"] == "COMPLETE", done
    assert loudness(folder / "moving.wav")[2] > 5 * still
    done = run(http, {"type": "audio_record_action", "duration": 1, "filename": "still"})
    assert done["state"] == "ERROR" and "exists already" in done["sub_tasks"][0]["result"]


def test_no_microphone_is_an_error_saying_so(ctx_pair: list[Context], tasks: TasksNode,
                                             gw: GatewayNode, http: httpx.Client) -> None:
    node = ChassisNode(context=ctx_pair[1], parameter_overrides={**QUIET,
                                                                 "microphone_rate": 0})
    try:
        done = run(http, {"type": "audio_record_action", "duration": 1})
    finally:
        node.close()
    assert done["state"] == "ERROR"
    assert "no microphone" in done["sub_tasks"][0]["result"], done
