"""docs/robot-api.md §3.9 videos through a real server and a real simulated camera: a recording
started over REST runs in the background and lands as a Matroska file that an outside decoder
(PyAV's FFmpeg) opens, its frames counted and sized; listed, downloaded, deleted; refusals
with the reason; without PyAV a 503 naming the extra."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
from zenros.context import Context
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.node import GatewayNode
from zenros.testing import wait_for

av = pytest.importorskip("av", reason="video recordings need PyAV: pip install 'zenros[video]'")


@pytest.fixture
def chassis(ctx_pair: list[Context]) -> Iterator[ChassisNode]:
    node = ChassisNode(context=ctx_pair[1], parameter_overrides={
        "camera_width": 160, "camera_height": 120, "camera_rate": 10.0, "seed": 1})
    yield node
    node.close()


def _refused(r: httpx.Response, status: int, words: str) -> None:
    assert r.status_code == status, r.text
    assert r.json()["status"] == "error" and words in r.json()["description"], r.text


def test_a_recording_lands_as_a_video_a_player_opens(chassis: ChassisNode, gw: GatewayNode,
                                                      http: httpx.Client,
                                                      tmp_path: Path) -> None:
    assert wait_for(lambda: chassis.context.graph.publishers("/multi/back/image_raw") != [], 20)
    r = http.post("/system/saved_videos", json={"topic": "/multi/back/image_raw",
                                                "duration": 2, "filename": "clip"})
    assert r.status_code == 200, r.text
    assert r.json() == {"video": "clip.mkv", "file_timestamp": "clip", "duration": 2,
                        "status": "recording"}
    _refused(http.post("/system/saved_videos", json={"filename": "clip", "duration": 1}),
             409, "exists already")
    assert wait_for(lambda: any(v["filename"] == "clip.mkv"
                                for v in http.get("/system/saved_videos/").json()), 30)
    r = http.get("/system/saved_videos/clip")
    assert r.status_code == 200 and r.headers["content-type"] == "video/x-matroska"
    (tmp_path / "clip.mkv").write_bytes(r.content)
    with av.open(str(tmp_path / "clip.mkv")) as container:
        [stream] = container.streams.video
        assert stream.codec_context.name == "h264"
        frames = list(container.decode(stream))
    assert (frames[0].width, frames[0].height) == (160, 120)
    # 2 s of a 10 Hz camera (sim time at speed 1; a loaded box renders fewer)
    assert 3 <= len(frames) <= 25, len(frames)
    times = [f.time for f in frames]
    assert times == sorted(times) and times[-1] - times[0] <= 2.5, times
    assert http.delete("/system/saved_videos/clip").json() == {"status": "ok"}
    _refused(http.get("/system/saved_videos/clip"), 404, "no saved video 'clip'")


def test_refusals(chassis: ChassisNode, gw: GatewayNode, http: httpx.Client,
                  monkeypatch: pytest.MonkeyPatch) -> None:
    _refused(http.post("/system/saved_videos", json={"topic": "/scan"}), 404,
             "no camera topic '/scan'")
    _refused(http.post("/system/saved_videos", json={"duration": 0}), 400, "duration")
    _refused(http.post("/system/saved_videos", json={"duration": "ten"}), 400, "duration")
    _refused(http.post("/system/saved_videos", json={"filename": "../x"}), 400, "filename")
    assert http.get("/system/saved_videos/..%2Fsecret").status_code == 404
    assert http.get("/system/saved_videos/").json() == []
    monkeypatch.setitem(sys.modules, "av", None)  # as a plain install has it
    _refused(http.post("/system/saved_videos", json={}), 503, "pip install 'zenros[video]'")


def test_no_camera_is_a_503(gw: GatewayNode, http: httpx.Client) -> None:
    _refused(http.post("/system/saved_videos", json={}), 503,
             "no camera publishes on /camera_node/image_raw")
