"""A CLI verb's session is a client of its endpoint unless told otherwise (docs/cli.md); a
waiting verb with nothing to connect to falls back to a peer, which keeps trying."""

from __future__ import annotations

import argparse
from typing import Any

import pytest
from zenros.cli import common
from zenros.errors import StartupError


class Opened:
    """Stands in for `Context`: records the options of each open; a client finds nobody when
    ``nobody`` is set (as Zenoh's open fails at once in client mode)."""

    def __init__(self, nobody: bool = False) -> None:
        self.modes: list[str | None] = []
        self.nobody = nobody

    def __call__(self, opts: Any, prefix: str | None = None) -> Any:
        self.modes.append(opts.mode)
        if self.nobody and opts.mode == "client":
            raise StartupError("cannot open Zenoh session: Unable to connect to any of [...]")
        return object()


def args(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    common.add_common(parser)
    return parser.parse_args(list(argv))


@pytest.fixture(autouse=True)
def clean_env(monkeypatch: pytest.MonkeyPatch) -> None:
    for var in ("ZENROS_MODE", "ZENROS_CONFIG", "ZENROS_LISTEN", "ZENROS_CONNECT"):
        monkeypatch.delenv(var, raising=False)


@pytest.mark.parametrize("argv", [(), ("-e", "tcp/127.0.0.1:7447")])
def test_a_verb_is_a_client_by_default(monkeypatch: pytest.MonkeyPatch, argv: tuple[str, ...]
                                       ) -> None:
    opened = Opened()
    monkeypatch.setattr(common, "Context", opened)
    common._open(common.options_from_args(args(*argv)), None, waits=False)
    assert opened.modes == ["client"]


@pytest.mark.parametrize(("argv", "env"), [
    (("-m", "peer"), {}), ((), {"ZENROS_MODE": "peer"}), (("-l", "tcp/127.0.0.1:0"), {}),
    (("--multicast-scouting",), {}), (("-c", "peer.json5"), {}),
    ((), {"ZENROS_LISTEN": "tcp/127.0.0.1:0"}),  # a process a launch started
])
def test_what_the_user_says_is_kept(monkeypatch: pytest.MonkeyPatch, argv: tuple[str, ...],
                                    env: dict[str, str]) -> None:
    for k, v in env.items():
        monkeypatch.setenv(k, v)
    opened = Opened()
    monkeypatch.setattr(common, "Context", opened)
    opts = common.options_from_args(args(*argv))
    common._open(opts, None, waits=False)
    assert opened.modes == [opts.mode] and opened.modes != ["client"]


def test_a_waiting_verb_with_nobody_there_waits_as_a_peer(monkeypatch: pytest.MonkeyPatch
                                                          ) -> None:
    opened = Opened(nobody=True)
    monkeypatch.setattr(common, "Context", opened)
    common._open(common.options_from_args(args()), None, waits=True)
    assert opened.modes == ["client", None]  # None: the default, a peer


def test_a_snapshot_verb_with_nobody_there_says_so(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(common, "Context", Opened(nobody=True))
    with pytest.raises(StartupError, match="nothing answered at tcp/127.0.0.1:7447"):
        common.open_context(args(), settle=True)


def test_a_verb_announces_a_longer_lease_unless_told(monkeypatch: pytest.MonkeyPatch) -> None:
    leases: list[int] = []
    monkeypatch.setattr(common, "Context", lambda opts, prefix=None: leases.append(opts.lease_ms))
    common._open(common.options_from_args(args()), None, waits=False)
    common._open(common.options_from_args(args("-m", "peer")), None, waits=False)
    assert leases == [common.VERB_LEASE_MS, common.DEFAULT_LEASE_MS]
