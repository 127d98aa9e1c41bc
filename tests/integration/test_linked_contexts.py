"""`linked_contexts`: a port taken between its pick and the listener's bind is replaced."""

from __future__ import annotations

import socket

import pytest
from zenros import testing
from zenros.msgs.std_msgs import String
from zenros.node import Node
from zenros.testing import Collector, linked_contexts, wait_for


def test_a_port_taken_before_the_bind_is_replaced(monkeypatch: pytest.MonkeyPatch) -> None:
    with socket.socket() as thief:
        thief.bind(("127.0.0.1", testing.free_port()))
        thief.listen()
        picks = iter([thief.getsockname()[1], testing.free_port(), testing.free_port()])
        monkeypatch.setattr(testing, "free_port", lambda: next(picks))
        with linked_contexts(2) as (a, b):
            assert next(picks, None) is None  # the stolen port, then one for each context
            talker, listener = Node("talker", context=a), Node("listener", context=b)
            try:
                got: Collector[String] = Collector()
                listener.create_subscription(String, "chatter", got)
                pub = talker.create_publisher(String, "chatter")
                assert wait_for(lambda: pub.publish(String(data="hi")) or got.items, 10)
            finally:
                talker.close()
                listener.close()
