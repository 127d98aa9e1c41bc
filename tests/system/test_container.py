"""`zenros.container` under `zenros launch`: nodes as components of one process, handing
messages over in-process; readiness of every component; a bad component stops it (exit 3)."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from typing import Any

import pytest
from zenros.context import Context
from zenros.testing import Proc

pytestmark = pytest.mark.system

LAUNCH = """
nodes:
  - container: pair
    namespace: demo
    components:
      - {plugin: "zenros.examples.talker:Talker", name: chatty, params: {rate: 20.0}}
      - plugin: "zenros.examples.listener:Listener"
        name: ear
        remap: {chatter: /demo/chatter}
"""


@pytest.fixture
def launched(launch_text: Any) -> Iterator[tuple[Proc, Context]]:
    with launch_text(LAUNCH, "-v") as rig:
        yield rig


def test_components_share_one_process_and_talk_in_process(
        launched: tuple[Proc, Context]) -> None:
    proc, ctx = launched
    assert proc.wait_line("demo/pair is ready", 90), proc.output
    g = ctx.graph
    names = {"/demo/pair", "/demo/chatty", "/demo/ear"}
    assert g.wait_for(lambda: names <= set(g.node_names()), 10), g.node_names()
    pids = {n.pid for n in g.nodes() if n.name in names}
    assert len(pids) == 1, pids  # one process for the three nodes
    assert proc.wait_line("[demo/ear]: I heard: hello world", 20), proc.output
    sessions = {n.zid for n in g.nodes() if n.name in names}
    assert len(sessions) == 1  # and one Zenoh session


def test_a_component_that_cannot_load_stops_the_container_with_exit_3(router: str,
                                                                     prefix: str) -> None:
    proc = Proc([sys.executable, "-m", "zenros.container", "--name", "c", "-e", router,
                 "--component", '{"plugin": "zenros.examples.talker:Talker", "name": "ok"}',
                 "--component", '{"plugin": "zenros.examples.talker:NoSuchNode", "name": "x"}'],
                env={"ZENROS_PREFIX": prefix})
    try:
        assert proc.wait(60) == 3, proc.output
        assert "startup failed: plugin 'zenros.examples.talker:NoSuchNode': " \
               "zenros.examples.talker has no Node class NoSuchNode" in proc.output
    finally:
        proc.stop()
