"""`free_port`: ports outside the kernel's ephemeral range, never one in use."""

from __future__ import annotations

import os
import socket

import pytest
from zenros import testing


def test_free_ports_lie_below_the_ephemeral_range_and_differ() -> None:
    floor = testing._ephemeral_floor()
    ports = [testing.free_port() for _ in range(50)]
    assert len(set(ports)) == 50
    assert all(testing._LOWEST_PORT <= p < floor for p in ports), (floor, ports)


def test_a_port_something_listens_on_is_skipped(monkeypatch: pytest.MonkeyPatch) -> None:
    with socket.socket() as held:
        held.bind(("127.0.0.1", testing.free_port()))
        held.listen()
        taken = held.getsockname()[1]
        monkeypatch.setattr(testing, "_next_port", (os.getpid(), taken))
        port = testing.free_port()
    assert port == taken + 1
    with socket.socket() as s:
        s.bind(("127.0.0.1", port))


def test_a_forked_process_starts_its_own_walk(monkeypatch: pytest.MonkeyPatch) -> None:
    """A cursor left by another pid (the parent of a fork) is not continued: two processes
    walking the same ports would hand out the same ones."""
    monkeypatch.setattr(testing, "_next_port", (os.getpid() + 1, testing._LOWEST_PORT))
    span = testing._ephemeral_floor() - testing._LOWEST_PORT
    start = testing._LOWEST_PORT + (os.getpid() * 7919) % span
    port = testing.free_port()
    assert (port - start) % span < 100, (start, port)
    after = testing._LOWEST_PORT + (port + 1 - testing._LOWEST_PORT) % span
    assert testing._next_port == (os.getpid(), after)
