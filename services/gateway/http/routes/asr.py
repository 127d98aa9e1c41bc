"""REST ``/system/asr/*`` (docs/robot-api.md §3.8): the ASR (voice) board's IO, PWM and servos.

The state comes from the chassis's latched ``asr/state``; a set goes to its ``asr/set``
service and the answer waits for it (`ports.asr_link.AsrLink`). IO ports 0-3 are outputs and
4-7 inputs (our reading of the spec's examples); PWM channels and servos are 0-3.
"""

from __future__ import annotations

from typing import Annotated, Any

import msgspec
from zenros.msgs.zenros_msgs import SetAsrBoardRequest

from ...ports.asr_link import AsrLink
from ..api import Answer, Api, ApiError, Call

__all__ = ["add_asr_routes"]

PortName = Annotated[str, msgspec.Meta(pattern=r"^[0-9]{1,2}$")]
IoTable = Annotated[dict[PortName, bool], msgspec.Meta(min_length=1, max_length=8)]
Channel = Annotated[int, msgspec.Meta(ge=0, le=3)]


class PwmQuery(msgspec.Struct, forbid_unknown_fields=True):
    port: Channel
    freq: Annotated[int, msgspec.Meta(ge=0, le=100_000)]
    percent: Annotated[int, msgspec.Meta(ge=0, le=100)]


class ServoQuery(msgspec.Struct, forbid_unknown_fields=True):
    port: Channel
    angle: Annotated[int, msgspec.Meta(ge=0, le=180)]


def _asr(call: Call[Any, Any]) -> AsrLink:
    if call.ctx.asr is None:
        raise ApiError(501, "this gateway has no robot whose ASR board it could reach")
    return call.ctx.asr


async def get_asr_io(call: Call[None, None]) -> Answer:
    """The board's IO ports ``{"0": false, ..., "7": false}`` (0-3 outputs, 4-7 inputs)."""
    state = await _asr(call).current()
    return {str(i): bool(v) for i, v in enumerate(state.io)}


async def put_asr_io(call: Call[IoTable, None]) -> Answer:
    """Set outputs: ``{"0": true, "3": false}``, all or none (an input port is a 400)."""
    ports = sorted(call.body)
    req = SetAsrBoardRequest(kind="io", ports=[int(p) for p in ports],
                             levels=[call.body[p] for p in ports])
    await _asr(call).set(req)
    return {"status": "ok"}


async def asr_pwm(call: Call[None, PwmQuery]) -> Answer:
    """PWM on channel ``port``: ``freq`` Hz (0: off), ``percent`` duty cycle."""
    q = call.query
    await _asr(call).set(SetAsrBoardRequest(kind="pwm", port=q.port, freq=q.freq,
                                              percent=q.percent))
    return {"status": "ok"}


async def asr_servo(call: Call[None, ServoQuery]) -> Answer:
    """Turn servo ``port`` to ``angle`` degrees (0-180); it turns at the servo's speed."""
    q = call.query
    await _asr(call).set(SetAsrBoardRequest(kind="servo", port=q.port, angle=float(q.angle)))
    return {"status": "ok"}


def add_asr_routes(api: Api) -> None:
    """Route the ASR board's operations."""
    api.add("GET", "/system/asr/io", get_asr_io)
    api.add("PUT", "/system/asr/io", put_asr_io)
    api.add("GET", "/system/asr/pwm", asr_pwm)
    api.add("GET", "/system/asr/servo", asr_servo)


