"""Each node answers its parameter declarations (type, description, read-only) over Zenoh."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from zenros.context import Context
from zenros.param_describe import fetch_descriptions
from zenros.testing import wait_for


def served(ctx: Context, node_fqn: str) -> dict[str, Any]:
    """The descriptions once the other session has learned the node's queryable (a node just
    made on one session is not yet routed to from the other; a get then finds no server)."""
    found: list[dict[str, Any]] = []

    def answered() -> bool:
        got = fetch_descriptions(ctx, node_fqn, timeout=0.5)
        if got is not None:
            found.append(got)
        return bool(found)

    assert wait_for(answered, timeout=10.0), f"{node_fqn} never answered its descriptions"
    return found[0]


def test_a_node_describes_what_it_declared(
    make_node: Callable[..., Any], ctx_pair: list[Context]
) -> None:
    node = make_node("talker", side=0)
    node.declare_parameter("rate", 2.0, description="publish rate in Hz")
    node.declare_parameter("frame", "map", read_only=True)
    found = served(ctx_pair[1], "/talker")
    assert found["rate"] == {"type": "float", "description": "publish rate in Hz",
                             "read_only": False}
    assert found["frame"]["type"] == "str" and found["frame"]["read_only"] is True
    assert found["use_sim_time"]["type"] == "bool"


def test_an_absent_node_gives_none(ctx_pair: list[Context]) -> None:
    assert fetch_descriptions(ctx_pair[1], "/nobody", timeout=0.5) is None


def test_a_closed_node_stops_answering(
    make_node: Callable[..., Any], ctx_pair: list[Context]
) -> None:
    node = make_node("gone", side=0)
    served(ctx_pair[1], "/gone")
    node.close()
    assert fetch_descriptions(ctx_pair[1], "/gone", timeout=0.5) is None
