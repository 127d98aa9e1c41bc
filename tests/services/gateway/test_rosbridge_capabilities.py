"""rosbridge ops as capabilities (as rosbridge_suite's ``capability.py``): each capability of
a client's session names the op codes it answers and keeps its own state; the session
registers them once and hands each frame to its op's handler."""

from __future__ import annotations

import json
import logging
from types import SimpleNamespace
from typing import Any, cast

import pytest
from zenros.services.gateway.rosbridge import client as client_mod
from zenros.services.gateway.rosbridge.capability import Capability, Session
from zenros.services.gateway.rosbridge.client import ClientProtocol
from zenros.services.gateway.rosbridge.frames import Frame, Publish
from zenros.services.gateway.rosbridge.opaque import OpaqueTopics

REFERENCE_OPS = {  # rosbridge v2's ops (ROS 2 actions included) and the session's own
    "advertise", "unadvertise", "publish", "subscribe", "unsubscribe", "call_service",
    "service_response", "advertise_service", "unadvertise_service", "send_action_goal",
    "cancel_action_goal", "advertise_action", "unadvertise_action", "action_feedback",
    "action_result", "set_level", "fragment", "auth"}


def _session() -> ClientProtocol:
    bridge = SimpleNamespace(opaque=OpaqueTopics(), loop=None)  # what closing reads of it
    return ClientProtocol(cast(Any, bridge), 1, lambda: None, lambda: False,
                          logging.getLogger("test.rosbridge"))


def test_each_op_is_answered_by_one_capability() -> None:
    session = _session()
    assert set(session._ops) == REFERENCE_OPS
    owners = {op: type(c).__name__ for c in session.capabilities for op in c.handlers()}
    assert owners["subscribe"] == "TopicOps" and owners["call_service"] == "ServiceOps"
    assert owners["send_action_goal"] == "ActionOps"


class EchoFrame(Frame, tag="echo"):
    """A new op's frame: its fields, typed; ``op`` is its tag."""

    text: str = ""


class Echo(Capability):
    """A capability as a new one is written: its ops, its state, its close."""

    ops = {EchoFrame: "op_echo"}

    def __init__(self, session: Session) -> None:
        super().__init__(session)
        self.seen: list[Any] = []
        self.closed = False

    def op_echo(self, frame: EchoFrame) -> None:
        self.seen.append(frame.text)
        self.send({"op": "echo", "text": frame.text})

    def close(self) -> None:
        self.closed = True


def test_a_new_capability_is_one_class_and_one_entry(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(client_mod, "CAPABILITIES", (*client_mod.CAPABILITIES, Echo))
    session = _session()
    echo = next(c for c in session.capabilities if isinstance(c, Echo))
    session.incoming(json.dumps({"op": "echo", "text": "hi"}))
    assert echo.seen == ["hi"]
    frames, _ = session.outbox.take()
    assert json.loads(frames[0][0]) == {"op": "echo", "text": "hi"}
    session.close()
    assert echo.closed


def test_an_op_registered_twice_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    class Again(Echo):
        ops = {Publish: "op_echo"}

    monkeypatch.setattr(client_mod, "CAPABILITIES", (*client_mod.CAPABILITIES, Again))
    with pytest.raises(ValueError, match="'publish' is registered twice"):
        _session()


def test_a_frame_decodes_into_its_ops_type_in_one_step() -> None:
    """A frame is its op's Struct at once (fields typed, unknown ones ignored); one that does
    not fit is reported with its id, as the reference does, and the session stays."""
    session = _session()
    echo = Echo(session)
    session.register_operation(EchoFrame, echo.op_echo)
    session._decoder = client_mod.frame_decoder(tuple(session._frames))
    session.incoming('{"op": "echo", "text": "x", "extra": [1, 2]}')
    session.incoming('{"op": "echo", "text": NaN}')  # not JSON to msgspec: read leniently
    session.incoming('{"op": "echo", "id": "e1", "text": 3}')
    session.incoming('{"op": "bogus", "id": "b1"}')
    session.incoming('{"id": "n1"}')
    session.incoming('{"op": "set_level", "level": "error"}')
    session.incoming('{"op": "echo", "id": "e2", "text": 4}')
    assert echo.seen == ["x"]
    frames, _ = session.outbox.take()
    status = [json.loads(f) for f, _ in frames if b'"status"' in f]
    assert status and status[-1]["id"] == "e2" and "Expected `str`" in status[-1]["msg"]
