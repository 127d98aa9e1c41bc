"""The docs/robot-api.md §11 topic WebSocket through a real server and the `websockets` client."""

from __future__ import annotations

import asyncio
import json
import socket
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
import websockets
from websockets.asyncio.client import connect
from zenros.clock import Time
from zenros.context import Context
from zenros.msgs.geometry_msgs import Twist
from zenros.msgs.rosgraph_msgs import Clock
from zenros.msgs.std_msgs import String
from zenros.qos import QOS_LATCHED
from zenros.services.gateway.http import ws_protocol
from zenros.services.gateway.node import GatewayNode
from zenros.services.gateway.testing import running_gateway
from zenros.services.gateway.ws_slices import SLICE
from zenros.testing import Collector, RawWebSocket, wait_for


@pytest.fixture
def gw(ctx_pair: list[Context], tmp_path: Path) -> Iterator[GatewayNode]:
    with running_gateway(ctx_pair[0], tmp_path) as node:
        yield node


def token_of(gw: GatewayNode) -> str:
    r = httpx.get(f"http://127.0.0.1:{gw.rest_port}/api/v1/token",
                  params={"username": "admin", "password": "admin"})
    return str(r.json()["token"])


async def test_status_stream_and_token(gw: GatewayNode) -> None:
    base = f"ws://127.0.0.1:{gw.ws_port}"
    with pytest.raises(websockets.InvalidStatus) as info:
        async with connect(f"{base}/galileo/status"):
            pass
    assert info.value.response.status_code == 401
    assert b"missing token" in info.value.response.body
    tok = token_of(gw)
    async with connect(f"{base}/galileo/status?token={tok}") as ws:
        seqs = []
        for _ in range(5):
            st = json.loads(await asyncio.wait_for(ws.recv(), 3))
            seqs.append(st["header"]["seq"])
            assert {"navStatus", "power", "currentPosX", "busyStatus"} <= set(st)
        assert seqs == sorted(seqs) and len(set(seqs)) == 5
        pong = await ws.ping()
        await asyncio.wait_for(pong, 3)


async def test_teleop_publishes_cmd_vel_and_bad_frames_get_errors(
        gw: GatewayNode, make_node: object) -> None:
    base_node = make_node("fake_base", 1)  # type: ignore[operator]
    got: Collector[Twist] = Collector()
    base_node.create_subscription(Twist, "cmd_vel", got, 50)
    assert gw.topics.cmd_vel_pub.wait_for_subscribers(1, 5)
    url = f"ws://127.0.0.1:{gw.ws_port}/cmd_vel?token={token_of(gw)}"
    async with connect(url) as ws:
        await ws.send(json.dumps({"linear": {"x": 0.2, "y": 0, "z": 0},
                                  "angular": {"x": 0, "y": 0, "z": 0.5}}))
        assert await asyncio.to_thread(got.wait, 1, 3)
        assert got.items[0].linear.x == 0.2 and got.items[0].angular.z == 0.5
        for bad, word in [("{nope", "malformed JSON"), ("[1]", "JSON object"),
                          ('{"linear": {"x": "fast"}}', "$.linear.x"),
                          ('{"linear": {"q": 1}}', "unknown field 'q'"),
                          ('{"linear": ' + "[" * 3000 + "]" * 3000 + "}", "nested too deep")]:
            await ws.send(bad)
            while True:  # our own cmd_vel echoes may come first
                frame = json.loads(await asyncio.wait_for(ws.recv(), 3))
                if frame.get("status") == "error":
                    break
            assert word in frame["description"], (bad, frame)
        await ws.send(b"\x00binary")
        while True:
            frame = json.loads(await asyncio.wait_for(ws.recv(), 3))
            if frame.get("status") == "error":
                break
        assert "binary" in frame["description"]
        n = len(got.items)
        await ws.send(json.dumps({"linear": {"x": 0.1}}))
        assert await asyncio.to_thread(got.wait, n + 1, 3)


async def test_latched_topic_sends_last_value_first(gw: GatewayNode, make_node: object) -> None:
    pubnode = make_node("latcher", 1)  # type: ignore[operator]
    pub = pubnode.create_publisher(String, "robot_note", QOS_LATCHED)
    pub.publish(String(data="hello"))
    assert await asyncio.to_thread(
        gw.graph.wait_for, lambda: bool(gw.graph.publishers("/robot_note")), 5)
    url = f"ws://127.0.0.1:{gw.ws_port}/robot_note?token={token_of(gw)}"
    async with connect(url) as ws:
        assert json.loads(await asyncio.wait_for(ws.recv(), 5)) == {"data": "hello"}
        async with connect(url) as ws2:  # a second client of the same feed gets it too
            assert json.loads(await asyncio.wait_for(ws2.recv(), 5)) == {"data": "hello"}


async def test_unknown_topic_gets_error_frame_then_streams_once_listed(
        gw: GatewayNode, make_node: object) -> None:
    url = f"ws://127.0.0.1:{gw.ws_port}/not_yet_topic?token={token_of(gw)}"
    async with connect(url) as ws:
        frame = json.loads(await asyncio.wait_for(ws.recv(), 3))
        assert frame["status"] == "error" and "unknown topic" in frame["description"]
        # the connection stays; a publisher that appears later is streamed
        pubnode = make_node("late_talker", 1)  # type: ignore[operator]
        pub = pubnode.create_publisher(String, "not_yet_topic", 10)
        assert await asyncio.to_thread(pub.wait_for_subscribers, 1, 10)
        pub.publish(String(data="late"))
        assert json.loads(await asyncio.wait_for(ws.recv(), 5)) == {"data": "late"}


async def test_stalled_client_drops_to_latest_and_blocks_nobody(
        gw: GatewayNode, make_node: object) -> None:
    pubnode = make_node("bulk", 1)  # type: ignore[operator]
    pub = pubnode.create_publisher(String, "bulk_text", 10)
    assert await asyncio.to_thread(
        gw.graph.wait_for, lambda: bool(gw.graph.publishers("/bulk_text")), 5)
    url = f"ws://127.0.0.1:{gw.ws_port}/bulk_text?token={token_of(gw)}"
    # a client that completes the handshake and then never reads
    stalled = socket.create_connection(("127.0.0.1", gw.ws_port))
    stalled.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    stalled.sendall(f"GET /bulk_text?token={token_of(gw)} HTTP/1.1\r\nHost: x\r\n"
                    "Upgrade: websocket\r\nConnection: Upgrade\r\n"
                    "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                    "Sec-WebSocket-Version: 13\r\n\r\n".encode())
    try:
        assert stalled.recv(12) == b"HTTP/1.1 101"
        async with connect(url, max_size=None) as fast:
            assert await asyncio.to_thread(
                wait_for, lambda: len(gw.hub.slots("/bulk_text")) == 2, 5)
            assert pub.wait_for_subscribers(1, 5)
            blob = "x" * 50_000
            for i in range(300):
                pub.publish(String(data=f"{i:04d}{blob}"))
            while True:  # the fast client reaches the last message
                got = await asyncio.wait_for(fast.recv(), 5)
                if got.startswith('{"data":"0299'):
                    break
            dropped = sum(s.dropped for s in gw.hub.slots("/bulk_text"))
            assert dropped > 0
    finally:
        stalled.close()


async def test_a_large_message_goes_in_slices_and_replies_wait_for_its_end(
        gw: GatewayNode, make_node: object) -> None:
    """A message over `SLICE` bytes is one fragmented WebSocket message (a text frame, then
    continuation frames), written a slice at a time as the client reads; an error frame the
    server owes that client meanwhile comes after it, never inside it; a `websockets`
    client gets the message whole."""
    pubnode = make_node("bulk", 1)  # type: ignore[operator]
    pub = pubnode.create_publisher(String, "big_text", 10)
    assert await asyncio.to_thread(
        gw.graph.wait_for, lambda: bool(gw.graph.publishers("/big_text")), 5)
    path = f"/big_text?token={token_of(gw)}"
    text = "".join(chr(ord("a") + i % 26) for i in range(3 * SLICE + 5))
    with RawWebSocket(gw.ws_port, path) as slow:
        assert slow.status == 101
        async with connect(f"ws://127.0.0.1:{gw.ws_port}{path}", max_size=None) as fast:
            assert await asyncio.to_thread(
                wait_for, lambda: len(gw.hub.slots("/big_text")) == 2, 5)
            assert pub.wait_for_subscribers(1, 5)
            pub.publish(String(data=text))
            assert json.loads(await asyncio.wait_for(fast.recv(), 5)) == {"data": text}
            assert await asyncio.to_thread(  # both clients' senders took it
                wait_for, lambda: all(s.frame is None for s in gw.hub.slots("/big_text")), 5)
            slow.send_text("not json")  # answered with an error frame
            frames = await asyncio.to_thread(slow.read_message)
            error = await asyncio.to_thread(slow.read_message)
    assert len(frames) > 2 and frames[0][:2] == (1, False)
    assert all(op == 0 for op, _, _ in frames[1:]) and frames[-1][1]
    assert max(len(p) for _, _, p in frames) == SLICE
    assert json.loads(b"".join(p for _, _, p in frames)) == {"data": text}
    assert len(error) == 1 and json.loads(error[0][2])["status"] == "error"


async def test_a_large_messages_slices_are_paced(
        gw: GatewayNode, make_node: object, monkeypatch: pytest.MonkeyPatch) -> None:
    """Slices of one large message go out `SLICE_PAUSE` apart (a 5 MB map over 80 ms, not
    all at once to every client: on a small machine that burst delayed every other topic's
    frames); here the pause is a quarter second, so the four slices take three of them."""
    monkeypatch.setattr(ws_protocol, "SLICE_PAUSE", 0.25)
    pubnode = make_node("bulk", 1)  # type: ignore[operator]
    pub = pubnode.create_publisher(String, "paced_text", 10)
    assert await asyncio.to_thread(
        gw.graph.wait_for, lambda: bool(gw.graph.publishers("/paced_text")), 5)
    text = "p" * (3 * SLICE + 5)
    async with connect(f"ws://127.0.0.1:{gw.ws_port}/paced_text?token={token_of(gw)}",
                       max_size=None) as ws:
        assert await asyncio.to_thread(
            wait_for, lambda: len(gw.hub.slots("/paced_text")) == 1, 5)
        assert pub.wait_for_subscribers(1, 5)
        sent = time.monotonic()
        pub.publish(String(data=text))
        assert json.loads(await asyncio.wait_for(ws.recv(), 10)) == {"data": text}
        assert time.monotonic() - sent >= 3 * 0.25


def frame_opcodes(data: bytes) -> list[int]:
    """The opcodes of the (unmasked, server-sent) WebSocket frames in ``data``."""
    ops, i = [], 0
    while i + 2 <= len(data):
        op, n = data[i] & 0x0F, data[i + 1] & 0x7F
        i += 2
        if n == 126:
            n, i = int.from_bytes(data[i:i + 2], "big"), i + 2
        elif n == 127:
            n, i = int.from_bytes(data[i:i + 8], "big"), i + 8
        ops.append(op)
        i += n
    return ops


def test_silent_client_is_closed(ctx_pair: list[Context], tmp_path: Path) -> None:
    """A client that never answers the server's pings is dropped after the ping timeout."""
    with running_gateway(ctx_pair[0], tmp_path, no_token_check=True, ws_ping_interval=0.2,
                         ws_ping_timeout=0.4) as gw:
        s = socket.create_connection(("127.0.0.1", gw.ws_port))
        try:
            s.sendall(b"GET /galileo/status HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\n"
                      b"Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                      b"Sec-WebSocket-Version: 13\r\n\r\n")
            s.settimeout(10)
            got = b""
            while True:  # status frames and pings arrive; no pong goes back
                chunk = s.recv(65536)
                if not chunk:
                    break
                got += chunk
            assert got.startswith(b"HTTP/1.1 101")
            assert 9 in frame_opcodes(got.split(b"\r\n\r\n", 1)[1])  # pings were sent
        finally:
            s.close()


async def test_oversized_frame_closes_only_that_client(gw: GatewayNode) -> None:
    url = f"ws://127.0.0.1:{gw.ws_port}/cmd_vel?token={token_of(gw)}"
    async with connect(url) as big, connect(url) as other:
        await big.send("x" * (2 << 20))
        with pytest.raises(websockets.ConnectionClosed) as info:
            while True:
                await asyncio.wait_for(big.recv(), 5)
        assert info.value.rcvd is not None and info.value.rcvd.code == 1009
        await other.send(json.dumps({"linear": {"x": 0.0}}))
        pong = await other.ping()
        await asyncio.wait_for(pong, 3)


async def test_status_rate_is_wall_time_under_fast_sim_time(
        ctx_pair: list[Context], tmp_path: Path, make_node: object) -> None:
    """At use_sim_time with /clock running 10x, the status stream stays at 30 Hz of wall
    time (issue 21 item 5: it followed sim time, 299 Hz)."""
    sim = make_node("sim_clock", 1)  # type: ignore[operator]
    clock_pub = sim.create_publisher(Clock, "/clock", 10)
    stop = threading.Event()

    def run_clock() -> None:  # 10x: 10 ms of sim time per ms of wall time
        start = time.monotonic()
        while not stop.wait(0.005):
            clock_pub.publish(Clock(clock=Time.from_nanoseconds(
                int((time.monotonic() - start) * 10 * 1e9))))

    ticker = threading.Thread(target=run_clock, daemon=True)
    ticker.start()
    try:
        with running_gateway(ctx_pair[0], tmp_path, use_sim_time=True) as gw:
            assert wait_for(lambda: gw.get_clock().now().nanoseconds > 0, 5)
            async with connect(f"ws://127.0.0.1:{gw.ws_port}/galileo/status"
                               f"?token={await asyncio.to_thread(token_of, gw)}") as ws:
                await asyncio.wait_for(ws.recv(), 3)
                start, frames = time.monotonic(), 0
                while time.monotonic() - start < 1.5:
                    await asyncio.wait_for(ws.recv(), 3)
                    frames += 1
                rate = frames / (time.monotonic() - start)
            assert 10 < rate < 50, f"{rate:.0f} Hz of wall time"
    finally:
        stop.set()
        ticker.join(2)
