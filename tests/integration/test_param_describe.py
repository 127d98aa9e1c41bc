"""Each node answers its parameter declarations (type, description, read-only) over Zenoh."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from zenros.context import Context
from zenros.param_describe import fetch_descriptions


def test_a_node_describes_what_it_declared(
    make_node: Callable[..., Any], ctx_pair: list[Context]
) -> None:
    node = make_node("talker", side=0)
    node.declare_parameter("rate", 2.0, description="publish rate in Hz")
    node.declare_parameter("frame", "map", read_only=True)
    found = fetch_descriptions(ctx_pair[1], "/talker")
    assert found is not None
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
    assert fetch_descriptions(ctx_pair[1], "/gone") is not None
    node.close()
    assert fetch_descriptions(ctx_pair[1], "/gone", timeout=0.5) is None
