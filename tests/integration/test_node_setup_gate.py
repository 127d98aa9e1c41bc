"""No callback of an endpoint created in ``setup()`` runs before ``setup()`` has returned;
what arrives meanwhile is delivered after (issue 21, item 7: a RobotLink callback met an
object whose ``seen`` was not set yet)."""

from __future__ import annotations

import threading
from typing import Any

import pytest
from zenros import Node
from zenros.context import Context
from zenros.msgs.example_interfaces import AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse
from zenros.msgs.std_msgs import String
from zenros.testing import wait_for


class SlowSetup(Node):
    """Creates its endpoints, then waits for the test before it sets what they read."""

    started: threading.Event
    proceed: threading.Event

    def setup(self) -> None:
        self.sub = self.create_subscription(String, "chatter", self.on_chatter, 10)
        self.srv = self.create_service(AddTwoInts, "add", self.on_add)
        self.timer = self.create_timer(0.01, self.on_tick)
        self.started.set()
        assert self.proceed.wait(20)
        self.heard: list[str] = []     # what the callbacks read: set last, on purpose
        self.ticks = 0
        self.setup_done = True

    def on_chatter(self, msg: String) -> None:
        self.heard.append(msg.data)

    def on_add(self, req: AddTwoIntsRequest) -> AddTwoIntsResponse:
        assert self.setup_done
        return AddTwoIntsResponse(sum=req.a + req.b)

    def on_tick(self) -> None:
        self.ticks += 1


def test_callbacks_wait_for_setup_and_nothing_is_lost(
        ctx_pair: list[Context], caplog: pytest.LogCaptureFixture) -> None:
    ctx, other = ctx_pair
    SlowSetup.started, SlowSetup.proceed = threading.Event(), threading.Event()
    built: list[Any] = []
    maker = threading.Thread(target=lambda: built.append(SlowSetup("slow", context=ctx)))
    with Node("talker", context=ctx) as local, Node("caller", context=other) as remote:
        pub = local.create_publisher(String, "chatter", 10)
        client = remote.create_client(AddTwoInts, "add")
        maker.start()
        try:
            assert SlowSetup.started.wait(10)
            for i in range(3):  # in-process: handed to the subscription right here
                pub.publish(String(data=f"m{i}"))
            assert client.wait_for_service(10)
            pending = threading.Thread(target=lambda: built.append(
                client.call(AddTwoIntsRequest(a=2, b=3), 10)))
            pending.start()
            assert not wait_for(lambda: len(built) > 0, 0.3)  # held while setup() runs
        finally:
            SlowSetup.proceed.set()
            maker.join(20)
        pending.join(20)
        node = next(b for b in built if isinstance(b, SlowSetup))
        try:
            assert wait_for(lambda: node.heard == ["m0", "m1", "m2"], 5), node.heard
            assert wait_for(lambda: node.ticks > 0, 5)
            reply = next(b for b in built if isinstance(b, AddTwoIntsResponse))
            assert reply.sum == 5
            pub.publish(String(data="after"))
            assert wait_for(lambda: node.heard[-1:] == ["after"], 5)
            assert node.sub.callback_errors == 0
            assert "raised" not in caplog.text, caplog.text
        finally:
            node.close()
