"""docs/robot-api.md §3.7 speech as text through a real server: aliases applied before publishing on
``tts``, playing for len/15 s of the robot's clock and stop, the volume, persistence, bad input."""

from __future__ import annotations

from pathlib import Path

import httpx
from zenros.context import Context
from zenros.msgs.std_msgs import String
from zenros.qos import QOS_LATCHED
from zenros.services.gateway.node import GatewayNode
from zenros.services.gateway.testing import running_gateway
from zenros.testing import Collector, wait_for


def test_alias_playing_stop(gw: GatewayNode, http: httpx.Client, make_node: object) -> None:
    other = make_node("speaker", 1)  # type: ignore[operator]
    said: Collector[String] = Collector()
    other.create_subscription(String, "tts", said, QOS_LATCHED)
    assert http.get("/system/tts/alias").json() == {}
    assert http.post("/system/tts/alias", json={"hello": "hello there"}).json() == {
        "status": "ok"}
    assert http.put("/system/tts/alias", json={"bye": "goodbye"}).json() == {
        "hello": "hello there", "bye": "goodbye"}
    assert http.get("/system/tts", params={"text": "hello"}).json() == {"status": "ok"}
    assert said.wait(1, 5) and said.items[-1].data == "hello there"
    assert http.post("/system/tts/alias", json={"bye": "see you"}).status_code == 200
    assert http.get("/system/tts/alias").json() == {"bye": "see you"}   # replaced whole
    # 60 characters last 4 s: playing at once, stop ends it
    assert http.get("/system/tts", params={"text": "x" * 60}).status_code == 200
    assert http.get("/system/tts/playing").json() == {"status": True}
    assert http.get("/system/tts/stop").json() == {"status": "ok"}
    assert http.get("/system/tts/playing").json() == {"status": False}
    # a short text ends by itself (0.2 s)
    http.get("/system/tts", params={"text": "abc"})
    assert wait_for(lambda: http.get("/system/tts/playing").json() == {"status": False}, 5)
    # bad input
    assert http.get("/system/tts", params={"text": ""}).status_code == 400
    assert http.post("/system/tts/alias", json={"a": 1}).status_code == 400
    assert http.put("/system/tts/alias", json={"": "x"}).status_code == 400
    assert http.post("/system/tts/alias", content=b"[1]").status_code == 400


def test_volume(ctx_pair: list[Context], tmp_path: Path) -> None:
    with running_gateway(ctx_pair[0], tmp_path, no_token_check=True) as gw, httpx.Client(
            base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=10) as http:
        assert http.get("/system/volume").json() == {"value": 50}
        assert http.put("/system/volume", json={"value": 80}).json() == {"status": "ok"}
        assert http.get("/system/volume").json() == {"value": 80}
        for bad in (101, -1, 50.5, "80", True, None):
            r = http.put("/system/volume", json={"value": bad})
            assert r.status_code == 400 and "value" in r.json()["description"], bad
        assert http.put("/system/volume", json={}).status_code == 400
        http.put("/system/tts/alias", json={"hi": "hello"})
    # a restarted gateway keeps the volume and the aliases (data_dir/audio.json)
    with running_gateway(ctx_pair[0], tmp_path, no_token_check=True) as gw, httpx.Client(
            base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=10) as http:
        assert http.get("/system/volume").json() == {"value": 80}
        assert http.get("/system/tts/alias").json() == {"hi": "hello"}
