"""REST ``/blockly_task`` (docs/robot-api.md §10): Blockly programs, kept by the tasks service
(`ports.blockly_link.BlocklyLink`) and run by a task's ``blockly_action`` (``api_key``: the
program's ``id``), which interprets the blocks; the ``py`` text is kept for the editor only."""

from __future__ import annotations

from typing import Annotated, Any

import msgspec
from msgspec import UNSET, UnsetType
from zenros.msgs.zenros_msgs.blockly import BlocklyProgram

from ...ports.blockly_link import BlocklyLink
from ..api import Answer, Api, ApiError, Call

__all__ = ["add_blockly_routes"]

Title = Annotated[str, msgspec.Meta(max_length=200)]
Text = Annotated[str, msgspec.Meta(max_length=4000)]
Xml = Annotated[str, msgspec.Meta(max_length=256 * 1024)]
Ident = Annotated[str, msgspec.Meta(min_length=1, max_length=64)]


class NewProgram(msgspec.Struct, forbid_unknown_fields=True):
    blocklyxml: Xml
    title: Title = ""
    description: Text = ""
    py: Xml = ""
    is_enabled: bool = True


class ProgramChange(msgspec.Struct, forbid_unknown_fields=True):
    id: Ident
    blocklyxml: Xml | UnsetType = UNSET
    title: Title | UnsetType = UNSET
    description: Text | UnsetType = UNSET
    py: Xml | UnsetType = UNSET
    is_enabled: bool | UnsetType = UNSET


class IdQuery(msgspec.Struct, forbid_unknown_fields=True):
    id: Ident | None = None


def _link(call: Call[Any, Any]) -> BlocklyLink:
    if call.ctx.blockly is None:
        raise ApiError(501, "this gateway keeps no Blockly programs (no robot node)")
    return call.ctx.blockly


async def list_programs(call: Call[None, IdQuery]) -> Answer:
    """Every program, or (``id``) the one with that id (404 if none)."""
    return await _link(call).programs(call.query.id or "")


async def create_program(call: Call[NewProgram, None]) -> Answer:
    """A new program; its blocks are checked first (a block this robot does not run is a
    400 naming it)."""
    b = call.body
    return await _link(call).save(BlocklyProgram(**msgspec.structs.asdict(b)), [])


async def update_program(call: Call[ProgramChange, None]) -> Answer:
    """Change the given fields of program ``id``; the others stay."""
    b = call.body
    given = {k: v for k, v in msgspec.structs.asdict(b).items() if v is not UNSET}
    fields = sorted(set(given) - {"id"})
    if not fields:
        raise ApiError(400, "give at least one field to change: blocklyxml, title, "
                            "description, py, is_enabled")
    return await _link(call).save(BlocklyProgram(**given), fields)


async def delete_program(call: Call[None, IdQuery]) -> Answer:
    """Delete program ``id``."""
    if not call.query.id:
        raise ApiError(400, "missing field 'id'")
    await _link(call).delete(call.query.id)
    return {"status": "ok"}


def add_blockly_routes(api: Api) -> None:
    """Route §10's program operations."""
    api.add("GET", "/blockly_task", list_programs)
    api.add("POST", "/blockly_task", create_program)
    api.add("PUT", "/blockly_task", update_program)
    api.add("DELETE", "/blockly_task", delete_program)
