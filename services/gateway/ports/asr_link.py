"""`AsrLink`: the chassis's ASR (voice) board: its state from the latched ``asr/state``
(zenros_msgs/AsrBoardState), its outputs set through ``asr/set`` (zenros_msgs/SetAsrBoard)."""

from __future__ import annotations

from zenros.msgs.zenros_msgs import (
    AsrBoardState,
    SetAsrBoard,
    SetAsrBoardRequest,
    SetAsrBoardResponse,
)
from zenros.node import Node
from zenros.qos import QOS_LATCHED

from ..errors import Refused, Unavailable
from .calls import call_port

__all__ = ["AsrLink"]


class AsrLink:
    """The board's latest state and its set service, for the doors."""

    def __init__(self, node: Node, timeout: float = 5.0) -> None:
        self.timeout = timeout
        self.state: AsrBoardState | None = None
        self.client = node.create_client(SetAsrBoard, "asr/set")
        node.create_subscription(AsrBoardState, "asr/state", self._on_state, QOS_LATCHED)

    def _on_state(self, msg: AsrBoardState) -> None:
        self.state = msg

    def current(self) -> AsrBoardState:
        if self.state is None:
            raise Unavailable("no ASR board: nothing on asr/state (the chassis is not running, "
                              "or its asr_board parameter is false)")
        return self.state

    def io_bits(self) -> list[bool]:
        """Its IO ports 0-7 (empty before the board reports)."""
        return [] if self.state is None else list(self.state.io)

    async def set(self, req: SetAsrBoardRequest) -> AsrBoardState:
        res: SetAsrBoardResponse = await call_port(self.client, req, self.timeout, lambda: Unavailable(
            "no ASR board: asr/set is not in the graph (the chassis is not running, or its "
            "asr_board parameter is false)"))
        if not res.success:
            raise Refused(res.message)
        self.state = res.state
        return res.state
