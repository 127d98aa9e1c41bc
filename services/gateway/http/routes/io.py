"""REST ``/system/io`` and ``/system/bw_io`` (docs/robot-api.md §3.8): the chassis's IO ports.

The levels come from the chassis's latched ``chassis/io`` (zenros_msgs/IoState); a set goes
to its ``chassis/set_io`` service, and the answer waits for it (`ports.io_link.IoLink`).
"""

from __future__ import annotations

from typing import Annotated, Literal

import msgspec

from ..api import Answer, Api, ApiError, Call

__all__ = ["add_io_routes"]


class IoBody(msgspec.Struct, forbid_unknown_fields=True):
    """``level`` "0"/"1" and ``port`` "1".."3" (the spec's strings; numbers are accepted)."""

    level: Literal["0", "1", 0, 1]
    port: Literal["1", "2", "3", 1, 2, 3]


class BwIoBody(msgspec.Struct, forbid_unknown_fields=True):
    level: Literal[0, 1]
    port: Annotated[int, msgspec.Meta(ge=0, le=7)]


async def get_io(call: Call[None, None]) -> Answer:
    """Main-board outputs: ``out1``..``out3`` as "0" (low) or "1" (high)."""
    io = call.ctx.io
    outs = io.current().outputs
    return {"status": "ok", **{f"out{i + 1}": str(v) for i, v in enumerate(outs)}}


async def post_io(call: Call[IoBody, None]) -> Answer:
    """Set main-board output ``port`` ("1".."3") to ``level`` ("0"/"1")."""
    io = call.ctx.io
    b = call.body
    await io.set("main", int(b.port), int(b.level))
    return {"status": "ok"}


async def get_bw_io(call: Call[None, None]) -> Answer:
    """The extension IO board: ``in`` (16 inputs) and ``out`` (8 outputs), port -> 0/1."""
    io = call.ctx.io
    state = io.current()
    if not state.ext_outputs:
        raise ApiError(404, "this robot has no extension IO board")
    return {"in": {str(i): v for i, v in enumerate(state.ext_inputs)},
            "out": {str(i): v for i, v in enumerate(state.ext_outputs)}}


async def put_bw_io(call: Call[BwIoBody, None]) -> Answer:
    """Set extension-board output ``port`` (0..7) to ``level`` (0/1)."""
    io = call.ctx.io
    b = call.body
    await io.set("ext", b.port, b.level)
    return {"status": "ok"}


def add_io_routes(api: Api) -> None:
    """Route §3.8's main-board and extension-board IO."""
    api.add("GET", "/system/io", get_io)
    api.add("POST", "/system/io", post_io)
    api.add("GET", "/system/bw_io", get_bw_io)
    api.add("PUT", "/system/bw_io", put_bw_io)
