"""The rmw_zenoh bridge tests' rig: a zenros node and the bridge, each in its own session on
the test router, and an rmw_zenoh peer (`rmw_peer.RmwPeer`), on a ROS domain of the test's own
(rmw_zenoh keys have no zenros prefix to keep tests apart)."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from zenros.context import Context
from zenros.node import Node
from zenros.session import SessionOptions

_domains = itertools.count(60)

Rig = tuple[Node, Any, Any, Context]


@pytest.fixture
def make_rmw_rig(router: str, prefix: str) -> Iterator[Callable[..., Rig]]:
    """``make_rmw_rig(node, namespace="/", peer_node="rmw_peer")``: (zenros node, bridge,
    rmw_zenoh peer, the node's context), all closed at teardown."""
    from rmw_peer import RmwPeer
    from zenros.services.rmw_zenoh.bridge import RmwZenohBridge

    made: list[tuple[Any, ...]] = []

    def factory(node: str, namespace: str = "/", peer_node: str = "rmw_peer") -> Rig:
        domain = next(_domains)
        ctx_b = Context(SessionOptions(connect=[router]), prefix=prefix)
        ctx_n = Context(SessionOptions(connect=[router]), prefix=prefix)
        bridge = RmwZenohBridge(context=ctx_b, parameter_overrides={"domain_id": domain})
        n = Node(node, namespace=namespace, context=ctx_n)
        peer = RmwPeer(router, domain, node=peer_node)
        made.append((peer, n, bridge, ctx_n, ctx_b))
        return n, bridge, peer, ctx_n

    try:
        yield factory
    finally:
        for peer, n, bridge, ctx_n, ctx_b in made:
            peer.close()
            n.close()
            bridge.close()
            ctx_n.close()
            ctx_b.close()
        try:
            import zenoh_ros2_sdk as sdk
        except ImportError:
            return
        if sdk.ZenohSession._instance is not None:  # the SDK keeps one session per process
            sdk.ZenohSession._instance.close()
            sdk.ZenohSession._instance = None
