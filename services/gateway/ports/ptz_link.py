"""`PtzLink`: the chassis's simulated PTZ (ONVIF) camera for the doors: its state from
``ptz_camera/state`` (zenros_msgs/PtzState), its moves and thermal reading through the
``ptz_camera/...`` services, its JPEG frames from ``ptz_camera/image_raw/compressed``, and its
simulated network address and credentials (`OnvifAddress`).

The camera is reached over Zenoh; its address is what the ONVIF operations take and list: by
default the gateway's own (``127.0.0.1`` and the REST port, where its MJPEG stream is served).
"""

from __future__ import annotations

import asyncio
import hmac
import threading
from collections.abc import AsyncIterator, Callable
from dataclasses import dataclass, replace

from zenros.msgs.sensor_msgs import CompressedImage
from zenros.msgs.zenros_msgs import (
    GetPtzTemperature,
    GetPtzTemperatureRequest,
    GetPtzTemperatureResponse,
    GotoPtzPreset,
    GotoPtzPresetRequest,
    MovePtz,
    MovePtzRequest,
    MovePtzSpeed,
    MovePtzSpeedRequest,
    PtzMoveResponse,
    PtzState,
)
from zenros.node import Node
from zenros.qos import QOS_SENSOR

from ..errors import NotFound, PortError, Refused, Unavailable
from .calls import Lazy, call_port

__all__ = ["FRAME_TIMEOUT", "NO_CAMERA", "BadCredentials", "OnvifAddress", "PtzLink"]

NO_CAMERA = ("no PTZ camera: nothing publishes ptz_camera/state (the chassis is not running, "
             "or its ptz_camera parameter is false or its mount is not in the map)")
FRAME_TIMEOUT = 5.0  # s without a frame before a stream ends


class BadCredentials(Exception):
    """The camera's username or password is wrong (HTTP 401)."""


@dataclass(frozen=True)
class OnvifAddress:
    """The simulated camera's address and credentials (empty username: none asked)."""

    ip: str
    port: int
    username: str = ""
    password: str = ""

    def check(self, ip: str | None, port: int | None, username: str | None,
              password: str | None) -> None:
        """Refuse a request for another camera (`NotFound`) or with the wrong credentials
        (`BadCredentials`); ``None`` for what the request left out."""
        if (ip is not None and ip != self.ip) or (port is not None and port != self.port):
            raise NotFound(f"no ONVIF camera at {ip or self.ip}:{port or self.port}; the "
                           f"camera is at {self.ip}:{self.port}")
        if self.username and not (
                hmac.compare_digest((username or "").encode(), self.username.encode())
                and hmac.compare_digest((password or "").encode(), self.password.encode())):
            raise BadCredentials("the ONVIF camera refused the username or password")


class PtzLink:
    """The camera's latest state, its services and its frames; ``address`` is where it is
    said to be (port 0: ``rest_port()``, the gateway's REST port once it listens)."""

    def __init__(self, node: Node, address: OnvifAddress, rest_port: Callable[[], int],
                 timeout: float = 5.0, first_state: float = 3.0) -> None:
        self.node = node
        self._address = address
        self._rest_port = rest_port
        self.timeout = timeout
        self.first_state = first_state
        self.state: PtzState | None = None
        self._heard = threading.Event()
        self._sub = Lazy(lambda: node.create_subscription(PtzState, "ptz_camera/state",
                                                          self._on_state))
        self._move = Lazy(lambda: node.create_client(MovePtz, "ptz_camera/move"))
        self._speed = Lazy(lambda: node.create_client(MovePtzSpeed, "ptz_camera/move_speed"))
        self._preset = Lazy(lambda: node.create_client(GotoPtzPreset, "ptz_camera/goto_preset"))
        self._thermal = Lazy(lambda: node.create_client(GetPtzTemperature,
                                                        "ptz_camera/temperature"))

    @property
    def address(self) -> OnvifAddress:
        a = self._address
        return a if a.port else replace(a, port=self._rest_port())

    def _on_state(self, msg: PtzState) -> None:
        self.state = msg
        self._heard.set()

    def present(self) -> bool:
        """Whether a PTZ camera is in the graph now (its state publisher)."""
        return bool(self.node.context.graph.publishers(self.node.resolve_name("ptz_camera/state")))

    async def current(self) -> PtzState:
        """The camera's state: subscribed at the first ask (which waits ``first_state`` s for
        it), then the latest one heard."""
        if not self.present():
            raise Unavailable(NO_CAMERA)
        if not self._sub.made or self.state is None:
            self._sub.get()
            await asyncio.to_thread(self._heard.wait, self.first_state)
        if self.state is None:
            raise Unavailable(NO_CAMERA)
        return self.state

    async def _moved(self, res: PtzMoveResponse) -> PtzMoveResponse:
        if not res.success:
            raise (NotFound if res.not_found else Refused)(res.message)
        self.state = res.state
        return res

    async def move(self, req: MovePtzRequest) -> PtzMoveResponse:
        """An absolute move (normalised units); `Refused` out of range."""
        res: PtzMoveResponse = await call_port(self._move.get(), req, self.timeout, _absent)
        return await self._moved(res)

    async def move_speed(self, req: MovePtzSpeedRequest) -> PtzMoveResponse:
        """A continuous move (all zeros: stop); `Refused` out of range."""
        res: PtzMoveResponse = await call_port(self._speed.get(), req, self.timeout, _absent)
        return await self._moved(res)

    async def goto_preset(self, preset: str) -> PtzMoveResponse:
        """To a preset by name or token; `NotFound` for an unknown one."""
        res: PtzMoveResponse = await call_port(self._preset.get(), GotoPtzPresetRequest(preset=preset),
                              self.timeout, _absent)
        return await self._moved(res)

    async def temperature(self) -> GetPtzTemperatureResponse:
        """The thermal reading of the view now."""
        res: GetPtzTemperatureResponse = await call_port(
            self._thermal.get(), GetPtzTemperatureRequest(), self.timeout, _absent)
        if not res.success:
            raise Refused(res.message)
        return res

    async def frames(self) -> AsyncIterator[bytes]:
        """The camera's JPEG frames as they come (the newest when the reader lags); ends
        after `FRAME_TIMEOUT` s without one. Its subscription lives as long as the loop."""
        loop = asyncio.get_running_loop()
        queue: asyncio.Queue[bytes] = asyncio.Queue(maxsize=2)

        def put(data: bytes) -> None:  # on the loop
            if queue.full():
                queue.get_nowait()
            queue.put_nowait(data)

        def on_frame(msg: CompressedImage) -> None:  # on Zenoh's thread
            loop.call_soon_threadsafe(put, bytes(msg.data))

        sub = self.node.create_subscription(CompressedImage, "ptz_camera/image_raw/compressed",
                                            on_frame, QOS_SENSOR)
        try:
            while True:
                try:
                    yield await asyncio.wait_for(queue.get(), FRAME_TIMEOUT)
                except TimeoutError:
                    return
        finally:
            self.node.destroy(sub)


def _absent() -> PortError:
    return Unavailable(NO_CAMERA)
