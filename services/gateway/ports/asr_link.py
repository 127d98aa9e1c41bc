"""`AsrLink`: the chassis's ASR (voice) board: its state from the latched ``asr/state``
(zenros_msgs/AsrBoardState), its outputs set through ``asr/set`` (zenros_msgs/SetAsrBoard)."""

from __future__ import annotations

import asyncio
import threading

from zenros.msgs.zenros_msgs import (
    AsrBoardState,
    SetAsrBoard,
    SetAsrBoardRequest,
    SetAsrBoardResponse,
)
from zenros.node import Node
from zenros.qos import QOS_LATCHED

from ..errors import Refused, Unavailable
from .calls import Lazy, call_port

__all__ = ["AsrLink"]


class AsrLink:
    """The board's latest state and its set service, for the doors."""

    def __init__(self, node: Node, timeout: float = 5.0, first_state: float = 3.0) -> None:
        self.timeout = timeout
        self.first_state = first_state
        self.state: AsrBoardState | None = None
        self._heard = threading.Event()
        self._client = Lazy(lambda: node.create_client(SetAsrBoard, "asr/set"))
        self._sub = Lazy(lambda: node.create_subscription(AsrBoardState, "asr/state",
                                                          self._on_state, QOS_LATCHED))

    def _on_state(self, msg: AsrBoardState) -> None:
        self.state = msg
        self._heard.set()

    async def current(self) -> AsrBoardState:
        """The board's state: its latched state, subscribed at the first ask (which waits
        ``first_state`` s for it)."""
        if not self._sub.made:
            self._sub.get()
            await asyncio.to_thread(self._heard.wait, self.first_state)
        if self.state is None:
            raise Unavailable("no ASR board: nothing on asr/state (the chassis is not running, "
                              "or its asr_board parameter is false)")
        return self.state

    def io_bits(self) -> list[bool]:
        """Its IO ports 0-7 (empty before the board reports; subscribed at the first ask)."""
        self._sub.get()
        return [] if self.state is None else list(self.state.io)

    async def set(self, req: SetAsrBoardRequest) -> AsrBoardState:
        res: SetAsrBoardResponse = await call_port(self._client.get(), req, self.timeout, lambda: Unavailable(
            "no ASR board: asr/set is not in the graph (the chassis is not running, or its "
            "asr_board parameter is false)"))
        if not res.success:
            raise Refused(res.message)
        self.state = res.state
        return res.state
