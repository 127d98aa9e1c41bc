"""Master replicas: writes on either are seen by both, a starting replica syncs, and after a
partition heals the later write wins.

The partition is real: the two replicas' sessions meet only through a TCP proxy on loopback
(gossip off, so they cannot find a direct path). Cutting the proxy closes the link and
refuses reconnections while both masters keep serving their own side; healing lets Zenoh's
connect retry restore the link.
"""

from __future__ import annotations

import socket
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from zenros.context import Context
from zenros.errors import ParameterNotFoundError
from zenros.param_client import ParameterClient
from zenros.services.master.node import MasterNode
from zenros.session import SessionOptions
from zenros.testing import free_port, wait_for

RETRY = "{period_init_ms: 100, period_max_ms: 200, period_increase_factor: 1}"


class Proxy:
    """Forwards TCP connections to a port; `cut()` drops them and refuses new ones."""

    def __init__(self, target: int) -> None:
        self.target = target
        self.port = free_port()
        self._server = socket.create_server(("127.0.0.1", self.port))
        self._lock = threading.Lock()
        self._conns: list[socket.socket] = []
        self.open = True
        threading.Thread(target=self._accept, daemon=True).start()

    def _accept(self) -> None:
        while True:
            try:
                client, _ = self._server.accept()
            except OSError:
                return
            if not self.open:
                client.close()
                continue
            try:
                upstream = socket.create_connection(("127.0.0.1", self.target))
            except OSError:  # the target is gone (teardown)
                client.close()
                continue
            with self._lock:
                self._conns += [client, upstream]
            for a, b in ((client, upstream), (upstream, client)):
                threading.Thread(target=self._pump, args=(a, b), daemon=True).start()

    @staticmethod
    def _pump(src: socket.socket, dst: socket.socket) -> None:
        try:
            while data := src.recv(65536):
                dst.sendall(data)
        except OSError:
            pass
        for s in (src, dst):
            try:
                s.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass

    def cut(self) -> None:
        self.open = False
        with self._lock:
            conns, self._conns = self._conns, []
        for s in conns:
            try:
                s.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass
            s.close()

    def heal(self) -> None:
        self.open = True

    def close(self) -> None:
        self.cut()
        self._server.close()


def _options(listen: int, connect: list[int]) -> SessionOptions:
    return SessionOptions(
        mode="peer", listen=[f"tcp/127.0.0.1:{listen}"],
        connect=[f"tcp/127.0.0.1:{p}" for p in connect],
        cfg=[("scouting/gossip/enabled", "false"), ("connect/retry", RETRY)],
    )


def start(ctx: Context, data: Path, name: str) -> MasterNode:
    return MasterNode(name, context=ctx, parameter_overrides={"data_dir": str(data)})


def values(m: MasterNode) -> Any:
    return m.store.get("/")


def test_a_write_to_either_replica_is_seen_by_both(ctx_pair: list[Context],
                                                   tmp_path: Path) -> None:
    a = start(ctx_pair[0], tmp_path / "a", "master")
    b = start(ctx_pair[1], tmp_path / "b", "master_b")
    try:
        ca, cb = ParameterClient(ctx_pair[0]), ParameterClient(ctx_pair[1])
        assert ca.wait_for_master(5) and cb.wait_for_master(5)
        ca.set("/nav/max_speed", 0.5)
        cb.set("/nav/name", "robot")
        expected = {"nav": {"max_speed": 0.5, "name": "robot"}}
        assert wait_for(lambda: values(a) == expected and values(b) == expected, 10)
        cb.delete("/nav/max_speed")
        assert wait_for(lambda: not a.store.has("/nav/max_speed"), 10)
        assert ca.get("/nav") == cb.get("/nav") == {"name": "robot"}
        # Rows cross in both directions (pushes, and pulls started by graph events), so the
        # replicas agree eventually, not at the instant the delete lands on `a`.
        assert wait_for(lambda: a.store.digest() == b.store.digest(), 10), (
            a.store.entries(), b.store.entries())
    finally:
        b.close()
        a.close()


def test_a_starting_replica_syncs_before_serving(ctx_pair: list[Context], tmp_path: Path) -> None:
    a = start(ctx_pair[0], tmp_path / "a", "master")
    try:
        ParameterClient(ctx_pair[0]).set("/cfg", {"x": 1, "y": [b"raw"]})
        assert ctx_pair[1].graph.wait_for_service("/master/sync", 5)
        b = start(ctx_pair[1], tmp_path / "b", "master_b")
        try:
            assert values(b) == {"cfg": {"x": 1, "y": [b"raw"]}}  # before it serves anything
        finally:
            b.close()
    finally:
        a.close()


@pytest.fixture
def partitioned(prefix: str, tmp_path: Path) -> Iterator[tuple[Proxy, MasterNode, MasterNode]]:
    port_a = free_port()
    proxy = Proxy(port_a)
    ctx_a = Context(_options(port_a, []), prefix=prefix)
    ctx_b = Context(_options(free_port(), [proxy.port]), prefix=prefix)
    a = start(ctx_a, tmp_path / "a", "master")
    b = start(ctx_b, tmp_path / "b", "master_b")
    try:
        yield proxy, a, b
    finally:
        b.close()
        a.close()
        ctx_b.close()
        ctx_a.close()
        proxy.close()


def test_after_a_partition_heals_the_later_write_wins(
    partitioned: tuple[Proxy, MasterNode, MasterNode]
) -> None:
    proxy, a, b = partitioned
    ga, gb = a.context.graph, b.context.graph
    ca, cb = ParameterClient(a.context), ParameterClient(b.context)
    assert ga.wait_for_node("/master_b", 10) and gb.wait_for_node("/master", 10)
    ca.set("/shared", "before")
    assert wait_for(lambda: b.store.has("/shared"), 10)

    proxy.cut()
    assert ga.wait_for(lambda: "/master_b" not in ga.node_names(), 10)
    assert gb.wait_for(lambda: "/master" not in gb.node_names(), 10)
    ca.set("/k1", "a-early")
    cb.set("/k1", "b-late")  # later: wins
    cb.set("/k2", "b-early")
    ca.set("/k2", "a-late")  # later: wins
    ca.set("/only_a", 1)
    cb.delete("/shared")
    assert ca.get("/shared") == "before"  # each side serves on its own
    with pytest.raises(ParameterNotFoundError):
        cb.get("/shared")

    proxy.heal()
    expected = {"k1": "b-late", "k2": "a-late", "only_a": 1}
    assert wait_for(lambda: values(a) == expected and values(b) == expected, 15), (
        values(a), values(b))
    assert a.store.digest() == b.store.digest()
    assert ca.get("/k1") == cb.get("/k1") == "b-late"
