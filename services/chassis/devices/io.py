"""The IO ports: ``chassis/io`` (zenros_msgs/IoState, latched) and ``chassis/set_io``."""

from __future__ import annotations

from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs import IoState, SetIo, SetIoRequest, SetIoResponse
from zenros.pubsub import Publisher
from zenros.qos import QOS_LATCHED

from ..device import Chassis, Device, Endpoints
from ..ioports import IoError, IoPorts

__all__ = ["IoDevice", "IoParameters"]


class IoParameters(msgspec.Struct, kw_only=True, frozen=True):
    io_extension_board: Annotated[bool, Meta(
        description="the robot has the extension IO board (8 outputs, 16 inputs)")] = True


class IoDevice(Device[IoParameters]):
    """The main board's outputs and the extension board (`IoPorts`), published at start
    and on every change; nothing on a schedule."""

    Parameters = IoParameters
    _node: Endpoints
    _pub: Publisher[IoState]

    def __init__(self, params: IoParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.io = IoPorts(params.io_extension_board)

    def open(self, node: Endpoints) -> None:
        self._node = node
        self._pub = node.create_publisher(IoState, "chassis/io", QOS_LATCHED)
        node.serve(SetIo, "chassis/set_io", self.handle_set_io)
        self._pub.publish(self.state())

    def state(self) -> IoState:
        main, ext_out, ext_in = self.io.snapshot()
        return IoState(header=Header(stamp=self._node.stamp(),
                                     frame_id=self.chassis.frames.base),
                       outputs=main, ext_outputs=ext_out, ext_inputs=ext_in)

    def handle_set_io(self, req: SetIoRequest) -> SetIoResponse:
        try:
            changed = self.io.set(req.board, req.port, req.level)
        except IoError as exc:
            return SetIoResponse(success=False, message=str(exc), state=self.state())
        state = self.state()
        if changed:
            self._pub.publish(state)
            self._node.logger.info("IO %s port %d set %s", req.board, req.port,
                                   "high" if req.level else "low")
        return SetIoResponse(success=True, message="", state=state)
