"""What a node owns (`Node.own`, `Node.on_close`, its endpoints) is closed with it, in reverse
order, also when ``setup()`` raised half-way: no service needs a guarded ``close()``."""

from __future__ import annotations

import socket
import threading
from typing import Any, ClassVar

import pytest
from zenros import Node
from zenros.context import Context
from zenros.errors import NodeClosedError
from zenros.msgs.std_msgs import String


class Recorder:
    """A resource that notes when it is closed, and whether a publisher was open then."""

    def __init__(self, name: str, log: list[str]) -> None:
        self.name, self.log = name, log
        self.closes = 0

    def close(self) -> None:
        self.closes += 1
        self.log.append(self.name)


class HalfBuilt(Node):
    """Opens a socket, a thread and endpoints, then fails in the middle of ``setup()``."""

    opened: ClassVar[dict[str, Any]] = {}

    def setup(self) -> None:
        opened = HalfBuilt.opened
        sock = opened["socket"] = self.own(socket.socket())
        sock.bind(("127.0.0.1", 0))
        sock.listen(1)
        stop = threading.Event()
        worker = opened["thread"] = threading.Thread(target=stop.wait, name="half-built")
        worker.start()
        self.on_close(lambda: (stop.set(), worker.join(5)))
        opened["pub"] = self.create_publisher(String, "half")
        opened["sub"] = self.create_subscription(String, "half", lambda m: None)
        raise RuntimeError("setup failed half-way")


def test_a_setup_that_raises_half_way_closes_what_it_opened(ctx_pair: list[Context]) -> None:
    HalfBuilt.opened = {}
    with pytest.raises(RuntimeError, match="half-way"):
        HalfBuilt(context=ctx_pair[0])
    opened = HalfBuilt.opened
    assert opened["socket"].fileno() == -1          # closed
    assert not opened["thread"].is_alive()          # stopped and joined
    assert opened["pub"].closed and opened["sub"].closed
    assert not [t for t in threading.enumerate() if t.name == "half-built"]
    assert "/half_built" not in ctx_pair[0].graph.node_names()


def test_close_goes_in_reverse_order_of_opening(ctx_pair: list[Context]) -> None:
    log: list[str] = []
    seen: dict[str, bool] = {}

    class Ordered(Node):
        def setup(self) -> None:
            self.first = self.own(Recorder("first", log))
            self.pub = self.create_publisher(String, "ordered")
            self.on_close(lambda: (log.append("callback"),
                                   seen.__setitem__("pub_open", not self.pub.closed)))
            self.last = self.own(Recorder("last", log))

    node = Ordered(context=ctx_pair[0])
    assert log == []
    node.close()
    assert log == ["last", "callback", "first"]
    assert seen == {"pub_open": True}  # the publisher, opened before, was still open
    assert node.pub.closed
    node.close()  # idempotent: nothing closes twice
    assert log == ["last", "callback", "first"] and node.first.closes == 1


def test_one_failing_close_does_not_stop_the_others(ctx_pair: list[Context]) -> None:
    log: list[str] = []

    def boom() -> None:
        raise OSError("cannot close")

    node = Node("failing_close", context=ctx_pair[0])
    node.own(Recorder("a", log))
    node.on_close(boom)
    node.own(Recorder("b", log))
    node.close()
    assert log == ["b", "a"]


def test_owning_after_close_closes_at_once(ctx_pair: list[Context]) -> None:
    log: list[str] = []
    node = Node("closed_owner", context=ctx_pair[0])
    node.close()
    with pytest.raises(NodeClosedError):
        node.own(Recorder("late", log))
    with pytest.raises(NodeClosedError):
        node.on_close(lambda: log.append("late callback"))
    assert log == ["late", "late callback"]
