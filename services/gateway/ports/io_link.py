"""`IoLink`: the chassis's IO ports: the levels from its latched ``chassis/io``
(zenros_msgs/IoState), a set through its ``chassis/set_io`` service."""

from __future__ import annotations

from zenros.msgs.zenros_msgs.chassis import IoState, SetIo, SetIoRequest, SetIoResponse
from zenros.node import Node
from zenros.qos import QOS_LATCHED

from ..errors import Conflict, Refused, Unavailable
from .calls import call_port

__all__ = ["IoLink"]


class IoLink:
    """The chassis's IO state (latched) and its set service, for the doors."""

    def __init__(self, node: Node, timeout: float = 5.0) -> None:
        self.timeout = timeout
        self.state: IoState | None = None
        self.client = node.create_client(SetIo, "chassis/set_io")
        node.create_subscription(IoState, "chassis/io", self._on_state, QOS_LATCHED)

    def _on_state(self, msg: IoState) -> None:
        self.state = msg

    def ext_bits(self) -> tuple[list[int], list[int]]:
        """The extension board's (inputs, outputs), empty before the chassis reports."""
        st = self.state
        return ([], []) if st is None else (list(st.ext_inputs), list(st.ext_outputs))

    def current(self) -> IoState:
        if self.state is None:
            raise Unavailable("no IO state: the chassis is not running (nothing on "
                              "chassis/io)")
        return self.state

    async def set(self, board: str, port: int, level: int) -> IoState:
        res: SetIoResponse = await call_port(
            self.client, SetIoRequest(board=board, port=port, level=level), self.timeout,
            lambda: Unavailable("the chassis is not running (no chassis/set_io)"))
        if not res.success:
            raise (Conflict if "no extension" in res.message else Refused)(res.message)
        self.state = res.state
        return res.state
