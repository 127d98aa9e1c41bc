"""The ``tasks/blockly/*`` service calls (zenros_msgs.blockly): a `ProgramStore`'s save, get and
delete, every refusal a response with its `ResultCode` (INVALID: a program that does not
parse or an unknown field; NOT_FOUND: an unknown id)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

from zenros.message import Message, ServiceType
from zenros.msgs.zenros_msgs import blockly as bm
from zenros.msgs.zenros_msgs.result import ResultCode

from .blockly import ProgramError
from .programs import ProgramStore, UnknownProgramError

__all__ = ["PROGRAM_CALLS", "program_call"]


def _save(store: ProgramStore, req: bm.SaveBlocklyRequest) -> Message:
    return bm.SaveBlocklyResponse(program=store.save(req.program, req.fields))


def _get(store: ProgramStore, req: bm.GetBlocklyRequest) -> Message:
    return bm.GetBlocklyResponse(programs=[store.get(req.id)] if req.id else store.list())


def _delete(store: ProgramStore, req: bm.DeleteBlocklyRequest) -> Message:
    store.delete(req.id)
    return bm.DeleteBlocklyResponse()


PROGRAM_CALLS: Final[dict[str, tuple[ServiceType, Callable[[ProgramStore, Any], Message]]]] = {
    "save": (bm.SaveBlockly, _save),
    "get": (bm.GetBlockly, _get),
    "delete": (bm.DeleteBlockly, _delete),
}


def program_call(store: ProgramStore, name: str, req: Message) -> Message:
    """Run call ``name``; a refusal becomes a response with its code and reason."""
    srv, run = PROGRAM_CALLS[name]
    try:
        return run(store, req)
    except ProgramError as exc:
        refusal: Message = srv.Response(code=ResultCode.INVALID, message=str(exc))
    except UnknownProgramError as exc:
        refusal = srv.Response(code=ResultCode.NOT_FOUND, message=str(exc))
    return refusal
