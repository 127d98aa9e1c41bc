"""REST ``/system/io`` and ``/system/bw_io`` (§3.8): the chassis's IO ports.

The levels come from the chassis's latched ``chassis/io`` (zenros_msgs/IoState); a set goes
to its ``chassis/set_io`` service, and the answer waits for it.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

import msgspec
from zenros.errors import ServiceError, ServiceUnavailableError, ZenrosTimeout
from zenros.msgs.zenros_msgs.chassis import IoState, SetIo, SetIoRequest, SetIoResponse
from zenros.node import Node
from zenros.qos import QOS_LATCHED

from .api import Api, ApiError, Call

__all__ = ["IoLink", "add_io_routes"]


class IoBody(msgspec.Struct, forbid_unknown_fields=True):
    """``level`` "0"/"1" and ``port`` "1".."3" (the spec's strings; numbers are accepted)."""

    level: Literal["0", "1", 0, 1]
    port: Literal["1", "2", "3", 1, 2, 3]


class BwIoBody(msgspec.Struct, forbid_unknown_fields=True):
    level: Literal[0, 1]
    port: Annotated[int, msgspec.Meta(ge=0, le=7)]


class IoLink:
    """The chassis's IO state (latched) and its set service, for REST handlers."""

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
            raise ApiError(503, "no IO state: the chassis is not running (nothing on "
                                "chassis/io)")
        return self.state

    async def set(self, board: str, port: int, level: int) -> IoState:
        try:
            res: SetIoResponse = await self.client.call_async(
                SetIoRequest(board=board, port=port, level=level), self.timeout)
        except ServiceUnavailableError:
            raise ApiError(503, "the chassis is not running (no chassis/set_io)") from None
        except ZenrosTimeout:
            raise ApiError(504, f"chassis/set_io did not answer within {self.timeout:g} s"
                           ) from None
        except ServiceError as exc:
            raise ApiError(502, f"chassis/set_io failed: {exc}") from exc
        if not res.success:
            raise ApiError(409 if "no extension" in res.message else 400, res.message)
        self.state = res.state
        return res.state


def add_io_routes(api: Api, io: IoLink) -> None:
    """Route §3.8's main-board and extension-board IO."""

    async def get_io(call: Call) -> Any:
        """Main-board outputs: ``out1``..``out3`` as "0" (low) or "1" (high)."""
        outs = io.current().outputs
        return {"status": "ok", **{f"out{i + 1}": str(v) for i, v in enumerate(outs)}}

    async def post_io(call: Call) -> Any:
        """Set main-board output ``port`` ("1".."3") to ``level`` ("0"/"1")."""
        b: IoBody = call.body
        await io.set("main", int(b.port), int(b.level))
        return {"status": "ok"}

    async def get_bw_io(call: Call) -> Any:
        """The extension IO board: ``in`` (16 inputs) and ``out`` (8 outputs), port -> 0/1."""
        state = io.current()
        if not state.ext_outputs:
            raise ApiError(404, "this robot has no extension IO board")
        return {"in": {str(i): v for i, v in enumerate(state.ext_inputs)},
                "out": {str(i): v for i, v in enumerate(state.ext_outputs)}}

    async def put_bw_io(call: Call) -> Any:
        """Set extension-board output ``port`` (0..7) to ``level`` (0/1)."""
        b: BwIoBody = call.body
        await io.set("ext", b.port, b.level)
        return {"status": "ok"}

    api.add("GET", "/system/io", get_io)
    api.add("POST", "/system/io", post_io, body=IoBody)
    api.add("GET", "/system/bw_io", get_bw_io)
    api.add("PUT", "/system/bw_io", put_bw_io, body=BwIoBody)
