"""docs/robot-api.md §3.9 snapshots through a real server and a real simulated camera: a
picture taken from the front and the back camera is a PNG an outside decoder opens, listed,
downloaded and deleted; an unknown topic, a bad file name and an unknown picture are refused."""

from __future__ import annotations

import io
from collections.abc import Iterator
from pathlib import Path

import httpx
import numpy as np
import pytest
from PIL import Image
from zenros.context import Context
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.node import GatewayNode


@pytest.fixture
def chassis(ctx_pair: list[Context]) -> Iterator[ChassisNode]:
    node = ChassisNode(context=ctx_pair[1], parameter_overrides={
        "camera_width": 160, "camera_height": 120, "seed": 1})
    yield node
    node.close()


def _refused(r: httpx.Response, status: int, words: str) -> None:
    assert r.status_code == status, r.text
    assert r.json()["status"] == "error" and words in r.json()["description"], r.text


def test_no_camera_is_a_503_at_once(gw: GatewayNode, http: httpx.Client) -> None:
    r = http.post("/system/saved_images", json={})
    assert r.status_code == 503 and "no camera publishes on /camera_node/image_raw" in \
        r.json()["description"], r.text
    assert r.elapsed.total_seconds() < 2.0


def test_snapshots_round_trip(chassis: ChassisNode, gw: GatewayNode, http: httpx.Client,
                              tmp_path: Path) -> None:
    front = http.post("/system/saved_images", json={}, timeout=30)
    assert front.status_code == 200, front.text
    name = front.json()["image"]
    assert name.endswith(".png") and front.json()["file_timestamp"] == name[:-4]
    back = http.post("/system/saved_images",
                     json={"topic": "/multi/back/image_raw", "filename": "behind"}, timeout=30)
    assert back.json()["image"] == "behind.png", back.text
    pictures = tmp_path / "data" / "Pictures"
    assert sorted(p.name for p in pictures.iterdir()) == sorted([name, "behind.png"])
    listed = http.get("/system/saved_images/").json()
    assert {e["filename"] for e in listed} == {name, "behind.png"}
    got = http.get(f"/system/saved_images/{name[:-4]}")
    assert got.status_code == 200 and got.headers["content-type"] == "image/png"
    image = Image.open(io.BytesIO(got.content))  # an outside decoder reads it
    assert image.format == "PNG" and image.size == (160, 120) and image.mode == "RGB"
    pixels = np.asarray(image)
    assert pixels.std() > 5  # a rendered view, not a blank frame
    assert not np.array_equal(pixels, np.asarray(Image.open(pictures / "behind.png")))
    assert http.delete("/system/saved_images/behind").json() == {"status": "ok"}
    assert [e["filename"] for e in http.get("/system/saved_images/").json()] == [name]
    _refused(http.get("/system/saved_images/behind"), 404, "no saved image 'behind'")
    _refused(http.delete("/system/saved_images/..%2Fsettings"), 404, "settings")  # not routed
    _refused(http.post("/system/saved_images", json={"topic": "/scan"}), 404,
             "/multi/front/image_raw")
    _refused(http.post("/system/saved_images", json={"filename": "../escape"}), 400,
             "filename")
    _refused(http.post("/system/saved_images", json={"topic": 5}), 400, "topic")
