"""`BlocklyLink`: the tasks service's Blockly programs (``tasks/blockly/*``, zenros_msgs.blockly):
saved, listed, deleted; refusals as port errors."""

from __future__ import annotations

from typing import Any

from zenros.msgs.zenros_msgs import blockly as bm
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.node import Node

from ..errors import port_error
from ..state.presence import Presence
from .calls import Lazy, call_port

__all__ = ["BlocklyLink"]


class BlocklyLink:
    def __init__(self, node: Node, presence: Presence, timeout: float = 10.0) -> None:
        self.presence = presence
        self.timeout = timeout
        self._save = Lazy(lambda: node.create_client(bm.SaveBlockly, "tasks/blockly/save"))
        self._get = Lazy(lambda: node.create_client(bm.GetBlockly, "tasks/blockly/get"))
        self._delete = Lazy(lambda: node.create_client(bm.DeleteBlockly,
                                                       "tasks/blockly/delete"))

    async def _call(self, client: Any, request: Any) -> Any:
        res = await call_port(client, request, self.timeout,
                              lambda: self.presence.error("tasks", f"no server for "
                                                                   f"{client.name}"),
                              "the tasks service")
        if res.code != ResultCode.OK:
            raise port_error(res.code, res.message or f"{client.name} failed ({res.code})")
        return res

    async def programs(self, ident: str = "") -> list[bm.BlocklyProgram]:
        res = await self._call(self._get.get(), bm.GetBlocklyRequest(id=ident))
        return list(res.programs)

    async def save(self, program: bm.BlocklyProgram, fields: list[str]) -> bm.BlocklyProgram:
        res = await self._call(self._save.get(), bm.SaveBlocklyRequest(program=program,
                                                                       fields=fields))
        saved: bm.BlocklyProgram = res.program
        return saved

    async def delete(self, ident: str) -> None:
        await self._call(self._delete.get(), bm.DeleteBlocklyRequest(id=ident))
