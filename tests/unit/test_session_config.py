"""session: the zenoh.Config built from flags, environment and files (no session is opened)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import pytest
import zenoh
from zenros.errors import StartupError
from zenros.session import (
    DEFAULT_ROUTER,
    SessionOptions,
    add_session_arguments,
    build_config,
    options_from_args,
)


@pytest.fixture(autouse=True)
def _clean_env(monkeypatch: pytest.MonkeyPatch) -> None:
    for var in ("ZENROS_CONNECT", "ZENROS_MODE", "ZENROS_CONFIG"):
        monkeypatch.delenv(var, raising=False)


def get(conf: zenoh.Config, key: str) -> object:
    return json.loads(conf.get_json(key))


def parse(*argv: str) -> SessionOptions:
    parser = argparse.ArgumentParser()
    add_session_arguments(parser)
    return options_from_args(parser.parse_args(list(argv)))


def write(tmp_path: Path, text: str) -> str:
    path = tmp_path / "zenoh.json5"
    path.write_text(text)
    return str(path)


# ------------------------------------------------------------------ defaults


def test_defaults() -> None:
    conf = build_config(parse())
    assert get(conf, "mode") == "peer"
    assert get(conf, "connect/endpoints") == [DEFAULT_ROUTER] == ["tcp/127.0.0.1:7447"]
    assert get(conf, "listen/endpoints") == ["tcp/127.0.0.1:0"]
    assert get(conf, "scouting/multicast/enabled") is False
    assert get(conf, "transport/link/tx/lease") == 2500
    assert get(conf, "transport/link/tx/keep_alive") == 2
    assert get(conf, "transport/shared_memory/enabled") is False
    assert get(conf, "timestamping/enabled") is True
    assert get(conf, "connect/exit_on_failure") in (None, False)


def test_default_options() -> None:
    opts = parse()
    assert opts == SessionOptions()
    assert opts.connect is None and not opts.strict_connect and not opts.multicast_scouting


def test_client_mode_has_no_listen_endpoint() -> None:
    conf = build_config(parse("-m", "client"))
    assert get(conf, "mode") == "client"
    assert get(conf, "listen/endpoints") == []
    assert get(conf, "connect/endpoints") == [DEFAULT_ROUTER]


def test_empty_connect_means_none() -> None:
    conf = build_config(SessionOptions(connect=[]))
    assert get(conf, "connect/endpoints") == []
    assert get(conf, "listen/endpoints") == ["tcp/127.0.0.1:0"]


def test_explicit_endpoints_and_strict_connect() -> None:
    opts = parse("-e", "tcp/127.0.0.1:7500", "--connect", "tcp/127.0.0.1:7501",
                 "-l", "tcp/127.0.0.1:7600")
    assert opts.strict_connect
    conf = build_config(opts)
    assert get(conf, "connect/endpoints") == ["tcp/127.0.0.1:7500", "tcp/127.0.0.1:7501"]
    assert get(conf, "listen/endpoints") == ["tcp/127.0.0.1:7600"]
    assert get(conf, "connect/exit_on_failure") is True
    assert get(conf, "connect/timeout_ms") == 3000


def test_environment_fallbacks_are_not_strict(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ZENROS_CONNECT", "tcp/127.0.0.1:7701,,tcp/127.0.0.1:7702")
    monkeypatch.setenv("ZENROS_MODE", "client")
    opts = parse()
    assert opts.connect == ["tcp/127.0.0.1:7701", "tcp/127.0.0.1:7702"]
    assert opts.mode == "client"
    assert not opts.strict_connect
    conf = build_config(opts)
    assert get(conf, "connect/endpoints") == ["tcp/127.0.0.1:7701", "tcp/127.0.0.1:7702"]
    assert get(conf, "connect/exit_on_failure") in (None, False)


def test_flags_win_over_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ZENROS_CONNECT", "tcp/127.0.0.1:7701")
    monkeypatch.setenv("ZENROS_MODE", "client")
    opts = parse("-m", "peer", "-e", "tcp/127.0.0.1:7800")
    assert (opts.mode, opts.connect) == ("peer", ["tcp/127.0.0.1:7800"])


def test_multicast_scouting_flag() -> None:
    key = "scouting/multicast/enabled"
    assert get(build_config(parse("--multicast-scouting")), key) is True
    assert get(build_config(parse("--no-multicast-scouting")), key) is False


def test_shared_memory_is_opt_in(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Off by default (its transport wakes every idle link); ``--shm`` or ``$ZENROS_SHM`` turn
    it on with zenros's pool, and over a config file too."""
    key, pool = "transport/shared_memory/enabled", \
        "transport/shared_memory/transport_optimization/pool_size"
    monkeypatch.delenv("ZENROS_SHM", raising=False)
    assert get(build_config(parse()), key) is False
    on = build_config(parse("--shm"))
    assert get(on, key) is True and get(on, pool) == 20 << 20
    monkeypatch.setenv("ZENROS_SHM", "1")
    assert parse().shm and get(build_config(parse()), key) is True
    monkeypatch.setenv("ZENROS_SHM", "0")
    assert not parse().shm
    path = tmp_path / "off.json5"
    path.write_text('{transport: {shared_memory: {enabled: false}}}')
    assert get(build_config(parse("-c", str(path))), key) is False  # the file as written
    assert get(build_config(parse("-c", str(path), "--shm")), key) is True


def test_bad_mode_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        parse("-m", "router")
    assert exc.value.code == 2
    assert "invalid choice" in capsys.readouterr().err


# ------------------------------------------------------------------ --cfg


def test_cfg_overrides_come_last() -> None:
    conf = build_config(parse("--cfg", "transport/link/tx/lease:4500",
                              "--cfg", 'listen/endpoints:["tcp/127.0.0.1:7900"]'))
    assert get(conf, "transport/link/tx/lease") == 4500
    assert get(conf, "listen/endpoints") == ["tcp/127.0.0.1:7900"]


def test_cfg_value_may_contain_colons() -> None:
    opts = parse("--cfg", 'connect/endpoints:["tcp/127.0.0.1:7447"]')
    assert opts.cfg == [("connect/endpoints", '["tcp/127.0.0.1:7447"]')]


@pytest.mark.parametrize("item", ["no_colon", ":5"])
def test_malformed_cfg_raises_startup_error(item: str) -> None:
    with pytest.raises(StartupError, match="expected KEY:VALUE"):
        parse("--cfg", item)


@pytest.mark.parametrize("item", ["mode:not json{", "no/such/key:1"])
def test_bad_cfg_raises_startup_error(item: str) -> None:
    with pytest.raises(StartupError, match="invalid --cfg"):
        build_config(parse("--cfg", item))


# ------------------------------------------------------------------ config files


def test_config_file_is_respected_and_multicast_stays_off(tmp_path: Path) -> None:
    path = write(tmp_path, """{
      mode: "client",
      connect: { endpoints: ["tcp/127.0.0.1:7999"] },
      transport: { link: { tx: { lease: 4000 } } },
    }""")
    conf = build_config(parse("-c", path))
    assert get(conf, "mode") == "client"
    assert get(conf, "connect/endpoints") == ["tcp/127.0.0.1:7999"]
    assert get(conf, "transport/link/tx/lease") == 4000
    assert get(conf, "scouting/multicast/enabled") is False
    assert get(conf, "timestamping/enabled") is True


def test_config_file_may_enable_multicast(tmp_path: Path) -> None:
    path = write(tmp_path, "{ scouting: { multicast: { enabled: true } } }")
    assert get(build_config(parse("-c", path)), "scouting/multicast/enabled") is True


def test_config_file_from_environment(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = write(tmp_path, '{ mode: "client" }')
    monkeypatch.setenv("ZENROS_CONFIG", path)
    opts = parse()
    assert opts.config_file == path
    assert get(build_config(opts), "mode") == "client"


def test_flags_win_over_the_config_file(tmp_path: Path) -> None:
    path = write(tmp_path, """{
      mode: "client",
      connect: { endpoints: ["tcp/127.0.0.1:7999"] },
      listen: { endpoints: ["tcp/127.0.0.1:7998"] },
    }""")
    conf = build_config(parse("-c", path, "-m", "peer", "-e", "tcp/127.0.0.1:7001",
                              "-l", "tcp/127.0.0.1:7002", "--cfg", "transport/link/tx/lease:3000"))
    assert get(conf, "mode") == "peer"
    assert get(conf, "connect/endpoints") == ["tcp/127.0.0.1:7001"]
    assert get(conf, "listen/endpoints") == ["tcp/127.0.0.1:7002"]
    assert get(conf, "transport/link/tx/lease") == 3000
    assert get(conf, "connect/exit_on_failure") is True


def test_config_file_endpoints_are_kept_without_flags(tmp_path: Path) -> None:
    path = write(tmp_path, """{
      connect: { endpoints: ["tcp/127.0.0.1:7999"] },
      listen: { endpoints: ["tcp/127.0.0.1:7998"] },
    }""")
    conf = build_config(parse("-c", path))
    assert get(conf, "connect/endpoints") == ["tcp/127.0.0.1:7999"]
    assert get(conf, "listen/endpoints") == ["tcp/127.0.0.1:7998"]


def test_missing_config_file_raises_startup_error(tmp_path: Path) -> None:
    with pytest.raises(StartupError, match=r"cannot read Zenoh config .*nope\.json5"):
        build_config(SessionOptions(config_file=str(tmp_path / "nope.json5")))


def test_malformed_config_file_raises_startup_error(tmp_path: Path) -> None:
    path = write(tmp_path, "{ mode: ")
    with pytest.raises(StartupError, match="cannot read Zenoh config"):
        build_config(SessionOptions(config_file=path))
