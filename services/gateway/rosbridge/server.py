"""`RosbridgeServer`: the rosbridge v2 WebSocket endpoint (``websockets``), one
`ClientProtocol` and one writer task per connection, on one asyncio loop."""

from __future__ import annotations

import asyncio
import itertools
import threading
from collections.abc import Sequence
from typing import Any

from websockets.asyncio.server import Server, ServerConnection, broadcast, serve
from websockets.exceptions import ConnectionClosed
from zenros.errors import ConfigError
from zenros.node import Node

from ..ws_slices import SLICE, SLICE_PAUSE, paced_slices
from .bridge import Bridge
from .cbor import is_binary
from .client import ClientProtocol
from .fragments import fragment
from .outbox import Turnstile

__all__ = ["CONGESTED_BYTES", "DEFAULT_PORT", "RosbridgeServer"]

DEFAULT_PORT = 9090
CONGESTED_BYTES = 256 * 1024
"""Bytes waiting in a client's socket buffer past which its topics keep only the newest."""
MAX_FRAME = 64 * 1024 * 1024


class RosbridgeServer:
    """Serves rosbridge v2 on ``ws://host:port/`` for the zenros graph of ``node``.

    Run it on an existing loop (``await start()`` / ``await stop()``), or on a thread of its
    own (``start_in_thread()`` / ``stop_in_thread()``).

    Args:
        node: the node whose session, graph and parameters the bridge uses.
        host: the address to bind (127.0.0.1 unless configured).
        port: the TCP port (0 picks a free one; see ``port`` after start).
    """

    name = "rosbridge"  # as a front end of the gateway (front_ends.FrontEnd)

    def __init__(self, node: Node, host: str = "127.0.0.1", port: int = DEFAULT_PORT) -> None:
        self.node = node
        self.host = host
        self.port = port
        self.logger = node.logger.getChild("rosbridge")
        self.clients: set[ClientProtocol] = set()
        self._ids = itertools.count(1)
        self._turnstile = Turnstile()  # whole large frames start one client at a time
        self._server: Server | None = None
        self._bridge: Bridge | None = None
        self._thread: threading.Thread | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._stop: asyncio.Event | None = None

    @property
    def bridge(self) -> Bridge:
        assert self._bridge is not None, "the server is not started"
        return self._bridge

    # ------------------------------------------------------------------ on a loop

    async def start(self) -> None:
        """Bind and start accepting connections on the running loop.

        Raises:
            ConfigError: the port cannot be bound.
        """
        self._loop = asyncio.get_running_loop()
        self._bridge = Bridge(self.node, self._loop)
        try:
            self._server = await serve(
                self._connection, self.host, self.port, compression=None, max_size=MAX_FRAME,
                max_queue=64, write_limit=CONGESTED_BYTES, ping_interval=20, ping_timeout=20,
                close_timeout=2,
                logger=self.logger.getChild("ws"),
            )
        except OSError as exc:
            raise ConfigError(f"cannot listen on {self.host}:{self.port}: "
                              f"{exc.strerror or exc}") from exc
        sock = next(iter(self._server.sockets))
        self.port = int(sock.getsockname()[1])
        self.logger.info("rosbridge v2 listening on ws://%s:%d/", self.host, self.port)

    async def stop(self) -> None:
        """Stop accepting, close every connection, release the bridge's endpoints."""
        if self._server is not None:
            self._server.close()
            await self._server.wait_closed()
            self._server = None
        for client in list(self.clients):
            client.close()
        self.clients.clear()
        if self._bridge is not None:
            self._bridge.close()

    async def _connection(self, ws: ServerConnection) -> None:
        wake = asyncio.Event()
        lane = _Lane(ws)
        client = ClientProtocol(self.bridge, next(self._ids), wake.set, lane.congested,
                                self.logger, self._turnstile)
        self.clients.add(client)
        self.logger.info("client %d connected from %s", client.client_id, ws.remote_address)
        writer = asyncio.create_task(self._write(ws, client, wake, lane))
        try:
            async for message in ws:
                client.incoming(message)
        except ConnectionClosed:
            pass
        finally:
            writer.cancel()
            client.close()
            self.clients.discard(client)
            self.logger.info("client %d disconnected", client.client_id)

    async def _write(self, ws: ServerConnection, client: ClientProtocol,
                     wake: asyncio.Event, lane: _Lane) -> None:
        """Sends what the client's `Outbox` gives: every small frame that waits, then one
        piece of a large frame (then waits for the socket to drain), and again."""
        loop = asyncio.get_running_loop()
        next_piece = 0.0  # large pieces go SLICE_PAUSE apart; small frames go between them
        try:
            while True:
                wake.clear()
                frames, due = client.outbox.take()
                for frame, size in frames:
                    text = not is_binary(frame)  # CBOR goes binary, whole
                    for part in fragment(frame, size) if size and text else (frame,):
                        if _congested(ws):  # ws.send waits until the socket drains
                            await ws.send(part, text=text)
                        else:  # written at once, no task switch per frame
                            broadcast((ws,), part, text=text)
                if loop.time() < next_piece:
                    due = next_piece if due is None else min(due, next_piece)
                else:
                    piece = client.outbox.take_bulk(_split)
                    held = client.outbox.bulk_wake
                    if held is not None:  # a whole large frame waits for a gap
                        due = held if due is None else min(due, held)
                    if piece is not None:
                        lane.in_flight = len(piece)  # not congestion: the frame just written
                        text = not is_binary(piece)
                        try:  # a large piece as a fragmented message: the loop is free between
                            await ws.send(paced_slices(piece) if len(piece) > SLICE else piece,
                                          text=text)
                        finally:
                            lane.in_flight = 0
                        next_piece = loop.time() + SLICE_PAUSE
                        continue
                if frames:
                    continue
                if due is None:
                    await wake.wait()
                else:
                    try:
                        await asyncio.wait_for(wake.wait(), max(0.0, due - loop.time()))
                    except TimeoutError:
                        pass
        except ConnectionClosed:
            return

    # ------------------------------------------------------------------ on a thread

    def start_in_thread(self, timeout: float = 10.0) -> None:
        """Run the server on a loop in a daemon thread; returns once it listens.

        Raises:
            ConfigError: the port cannot be bound (raised here, in the caller's thread).
        """
        started = threading.Event()
        failure: list[BaseException] = []

        def main() -> None:
            loop = asyncio.new_event_loop()
            asyncio.set_event_loop(loop)

            async def run() -> None:
                self._stop = asyncio.Event()
                try:
                    await self.start()
                except BaseException as exc:  # noqa: BLE001 handed to the starting thread
                    failure.append(exc)
                    started.set()
                    return
                started.set()
                await self._stop.wait()
                await self.stop()

            try:
                loop.run_until_complete(run())
            finally:
                loop.run_until_complete(loop.shutdown_default_executor())
                loop.close()

        self._thread = threading.Thread(target=main, name="rosbridge", daemon=True)
        self._thread.start()
        if not started.wait(timeout):
            raise TimeoutError(f"rosbridge did not start within {timeout:g} s")
        if failure:
            self._thread.join(timeout)
            raise failure[0]

    def stop_in_thread(self, timeout: float = 10.0) -> None:
        """Stop a server started with `start_in_thread` and join its thread."""
        thread, loop, stop = self._thread, self._loop, self._stop
        if thread is None or loop is None or stop is None:
            return
        if thread.is_alive():
            try:
                loop.call_soon_threadsafe(stop.set)
            except RuntimeError:  # the loop already closed
                pass
            thread.join(timeout)
        self._thread = None



class _Lane:
    """A client's socket, and the large frame being written to it (not congestion)."""

    def __init__(self, ws: ServerConnection) -> None:
        self.ws = ws
        self.in_flight = 0

    def congested(self) -> bool:
        transport: Any = self.ws.transport
        return bool(transport.get_write_buffer_size() > CONGESTED_BYTES + self.in_flight)


def _split(frame: bytes, size: int) -> Sequence[bytes]:
    """A large frame as the pieces it is sent in: ``fragment`` frames of ``size`` characters
    for a client that asked for them (text only: CBOR goes whole), else the frame."""
    if size and not is_binary(frame):
        return fragment(frame, size)
    return [frame]


def _congested(ws: ServerConnection) -> bool:
    """True while the client's socket buffer holds more than `CONGESTED_BYTES`."""
    transport: Any = ws.transport
    return bool(transport.get_write_buffer_size() > CONGESTED_BYTES)
