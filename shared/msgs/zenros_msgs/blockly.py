"""zenros_msgs for Blockly programs (docs/robot-api.md §10), kept and run by the tasks service.

=====================  ==============  ==============================================
service                type            answers
=====================  ==============  ==============================================
tasks/blockly/save     SaveBlockly     the program (a new one when ``id`` is empty)
tasks/blockly/get      GetBlockly      ``programs``: the one with ``id``, or all
tasks/blockly/delete   DeleteBlockly   nothing
=====================  ==============  ==============================================

A program is run by a task's ``blockly_action`` (``api_key``: the program's id), which
interprets its block XML (``blocklyxml``); its ``py`` text is kept for the editor and never
run.
"""

from __future__ import annotations

import msgspec

from ...message import Message, define_service
from .result import ResultCode

__all__ = [
    "BlocklyProgram", "DeleteBlockly", "DeleteBlocklyRequest", "DeleteBlocklyResponse",
    "GetBlockly", "GetBlocklyRequest", "GetBlocklyResponse", "SaveBlockly",
    "SaveBlocklyRequest", "SaveBlocklyResponse",
]


class BlocklyProgram(msgspec.Struct, kw_only=True):
    """One program, as ``/blockly_task`` shows it; times in ms."""

    id: str = ""
    title: str = ""
    description: str = ""
    blocklyxml: str = ""
    py: str = ""
    is_enabled: bool = True
    create_time: int = 0
    update_time: int = 0


class SaveBlocklyRequest(Message):
    """Create ``program`` (empty ``id``) or replace the fields ``fields`` names of the stored
    one (every field when ``fields`` is empty)."""

    __msgtype__ = "zenros_msgs/SaveBlocklyRequest"
    program: BlocklyProgram = msgspec.field(default_factory=BlocklyProgram)
    fields: list[str] = msgspec.field(default_factory=list)


class SaveBlocklyResponse(Message):
    __msgtype__ = "zenros_msgs/SaveBlocklyResponse"
    code: ResultCode = ResultCode.OK
    message: str = ""
    program: BlocklyProgram | None = None


class GetBlocklyRequest(Message):
    __msgtype__ = "zenros_msgs/GetBlocklyRequest"
    id: str = ""  # "": every program


class GetBlocklyResponse(Message):
    __msgtype__ = "zenros_msgs/GetBlocklyResponse"
    code: ResultCode = ResultCode.OK
    message: str = ""
    programs: list[BlocklyProgram] = msgspec.field(default_factory=list)


class DeleteBlocklyRequest(Message):
    __msgtype__ = "zenros_msgs/DeleteBlocklyRequest"
    id: str = ""


class DeleteBlocklyResponse(Message):
    __msgtype__ = "zenros_msgs/DeleteBlocklyResponse"
    code: ResultCode = ResultCode.OK
    message: str = ""


SaveBlockly = define_service("zenros_msgs/SaveBlockly", SaveBlocklyRequest, SaveBlocklyResponse)
GetBlockly = define_service("zenros_msgs/GetBlockly", GetBlocklyRequest, GetBlocklyResponse)
DeleteBlockly = define_service("zenros_msgs/DeleteBlockly", DeleteBlocklyRequest,
                               DeleteBlocklyResponse)
