"""The spec's media task actions (docs/robot-api.md §9.2, docs/tasks.md) through the real
tasks service, gateway and simulated cameras: ``image_action`` and
``onvif_camera_snapshot_action`` land as PNGs in the robot's Pictures and
``video_record_action`` as a Matroska file in its Videos (made by the gateway, over
``media/save``), each listed over REST; bad parameters are refused with the reason."""

from __future__ import annotations

import io
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from PIL import Image as PilImage
from task_runs import run_task
from zenros.context import Context
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.node import GatewayNode
from zenros.services.tasks.node import TasksNode
from zenros.testing import wait_for


@pytest.fixture
def chassis(ctx_pair: list[Context]) -> Iterator[ChassisNode]:
    node = ChassisNode(context=ctx_pair[1], parameter_overrides={
        "camera_width": 160, "camera_height": 120, "camera_rate": 10.0, "seed": 1,
        "actuators": False, "ptz_width": 160, "ptz_height": 120})
    yield node
    node.close()


def run(http: httpx.Client, *actions: dict[str, Any], timeout: float = 60) -> dict[str, Any]:
    return run_task(http, *actions, name="media", timeout=timeout)


def test_snapshots_as_task_actions(chassis: ChassisNode, tasks: TasksNode, gw: GatewayNode,
                                   http: httpx.Client) -> None:
    assert wait_for(lambda: chassis.context.graph.publishers("/multi/back/image_raw") != [], 20)
    done = run(http, {"type": "image_action", "topic": "/multi/back/image_raw",
                      "timestamp": 1700000000123},
               {"type": "onvif_camera_snapshot_action", "ip": "127.0.0.1", "channel": 1})
    assert done["state"] == "COMPLETE", done
    names = {f["filename"] for f in http.get("/system/saved_images/").json()}
    assert "1700000000123.png" in names and len(names) == 2, names
    r = http.get("/system/saved_images/1700000000123")
    assert PilImage.open(io.BytesIO(r.content)).size == (160, 120)
    r = http.post("/task", json={"name": "bad", "sub_tasks": [
        {"type": "image_action", "topic": "/no/camera"}]})
    assert r.status_code == 400 and "topic" in r.json()["description"], r.text
    r = http.post("/task", json={"name": "bad", "sub_tasks": [
        {"type": "video_record_action", "video_url": "rtsp://10.0.0.9/live"}]})
    assert r.status_code == 400 and "video_url" in r.json()["description"], r.text


def test_a_recording_as_a_task_action(chassis: ChassisNode, tasks: TasksNode, gw: GatewayNode,
                                      http: httpx.Client, tmp_path: Path) -> None:
    av = pytest.importorskip("av", reason="video recordings need PyAV: pip install "
                                          "'zenros[video]'")
    assert wait_for(lambda: chassis.context.graph.publishers("/multi/front/image_raw") != [], 20)
    done = run(http, {"type": "video_record_action", "topic": "/multi/front/image_raw",
                      "duration": 2, "filename": "patrol"})
    assert done["state"] == "COMPLETE", done
    assert "frames" in done["sub_tasks"][0]["result"] and done["sub_tasks"][0]["progress"] == 1
    r = http.get("/system/saved_videos/patrol")
    assert r.status_code == 200, r.text
    (tmp_path / "patrol.mkv").write_bytes(r.content)
    with av.open(str(tmp_path / "patrol.mkv")) as container:
        frames = list(container.decode(container.streams.video[0]))
    assert frames and (frames[0].width, frames[0].height) == (160, 120)
