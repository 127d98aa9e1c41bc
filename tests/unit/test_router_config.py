"""build_router_config and the router's flag parsing: defaults, --cfg, config-file merge."""

from __future__ import annotations

import json
import socket
from pathlib import Path

import pytest
import zenoh
from zenros.errors import StartupError
from zenros.router import (
    DEFAULT_LISTEN,
    build_router_config,
    listen_endpoints,
    main,
    parse_cfg_entry,
    router_reachable,
)

DEPLOY = Path(__file__).resolve().parents[2] / "deploy" / "zenoh"


def get(conf: zenoh.Config, key: str) -> object:
    return json.loads(conf.get_json(key))


def write(tmp_path: Path, text: str) -> str:
    path = tmp_path / "conf.json5"
    path.write_text(text)
    return str(path)


# ------------------------------------------------------------------ defaults


def test_defaults() -> None:
    conf = build_router_config()
    assert get(conf, "mode") == "router"
    assert get(conf, "listen/endpoints") == [DEFAULT_LISTEN] == ["tcp/127.0.0.1:7447"]
    assert get(conf, "scouting/multicast/enabled") is False
    assert get(conf, "transport/link/tx/lease") == 2500
    assert get(conf, "transport/link/tx/keep_alive") == 2
    assert get(conf, "transport/shared_memory/enabled") is False


def test_listen_replaces_the_default() -> None:
    conf = build_router_config(["tcp/127.0.0.1:7500", "tls/127.0.0.1:7501"])
    assert get(conf, "listen/endpoints") == ["tcp/127.0.0.1:7500", "tls/127.0.0.1:7501"]
    assert listen_endpoints(conf) == ["tcp/127.0.0.1:7500", "tls/127.0.0.1:7501"]


def test_multicast_flag() -> None:
    assert get(build_router_config(multicast=True), "scouting/multicast/enabled") is True


# ------------------------------------------------------------------ --cfg


def test_cfg_is_applied_last() -> None:
    conf = build_router_config(
        ["tcp/127.0.0.1:7500"], None,
        [("transport/link/tx/lease", "2000"), ("listen/endpoints", '["tcp/127.0.0.1:7600"]')],
    )
    assert get(conf, "transport/link/tx/lease") == 2000
    assert get(conf, "listen/endpoints") == ["tcp/127.0.0.1:7600"]


@pytest.mark.parametrize(("key", "value"), [
    ("transport/link/tx/lease", "abc"),
    ("no/such/key", "1"),
])
def test_invalid_cfg_is_a_startup_error(key: str, value: str) -> None:
    with pytest.raises(StartupError, match=f"invalid --cfg {key}:{value}"):
        build_router_config(cfg=[(key, value)])


def test_cfg_cannot_change_the_mode() -> None:
    with pytest.raises(StartupError, match="a router needs"):
        build_router_config(cfg=[("mode", '"peer"')])


@pytest.mark.parametrize(("text", "expected"), [
    ("transport/link/tx/lease:2000", ("transport/link/tx/lease", "2000")),
    ('connect/endpoints:["tcp/10.0.0.1:7447"]', ("connect/endpoints", '["tcp/10.0.0.1:7447"]')),
])
def test_parse_cfg_entry(text: str, expected: tuple[str, str]) -> None:
    assert parse_cfg_entry(text) == expected


@pytest.mark.parametrize("text", ["lease", ":1", "a/b:", ""])
def test_parse_cfg_entry_rejects(text: str) -> None:
    with pytest.raises(ValueError, match="expected KEY:VALUE"):
        parse_cfg_entry(text)


# ------------------------------------------------------------------ config file merge


def test_file_values_win_over_zenros_defaults(tmp_path: Path) -> None:
    path = write(tmp_path, """{
      // a comment: this is JSON5
      listen: { endpoints: ["tcp/127.0.0.1:7700"] },
      scouting: { multicast: { enabled: true } },
      transport: { link: { tx: { lease: 5000 } },
                   auth: { usrpwd: { dictionary_file: "users.txt" } } },
    }""")
    conf = build_router_config(config_file=path)
    assert get(conf, "mode") == "router"
    assert get(conf, "listen/endpoints") == ["tcp/127.0.0.1:7700"]
    assert get(conf, "scouting/multicast/enabled") is True
    assert get(conf, "transport/link/tx/lease") == 5000
    assert get(conf, "transport/link/tx/keep_alive") == 2  # unset in the file: ours
    assert get(conf, "transport/auth/usrpwd/dictionary_file") == "users.txt"


def test_zenros_defaults_fill_what_the_file_leaves_unset(tmp_path: Path) -> None:
    conf = build_router_config(config_file=write(tmp_path, '{mode: "router"}'))
    assert get(conf, "listen/endpoints") == [DEFAULT_LISTEN]
    assert get(conf, "scouting/multicast/enabled") is False
    assert get(conf, "transport/link/tx/lease") == 2500


def test_flags_and_cfg_win_over_the_file(tmp_path: Path) -> None:
    path = write(tmp_path, '{listen: {endpoints: ["tcp/127.0.0.1:7700"]},'
                           ' transport: {link: {tx: {lease: 5000}}}}')
    conf = build_router_config(["tcp/127.0.0.1:7800"], path, [("transport/link/tx/lease", "3000")])
    assert get(conf, "listen/endpoints") == ["tcp/127.0.0.1:7800"]
    assert get(conf, "transport/link/tx/lease") == 3000


def test_a_lease_equal_to_zenohs_default_counts_as_unset(tmp_path: Path) -> None:
    path = write(tmp_path, "{transport: {link: {tx: {lease: 10000}}}}")
    assert get(build_router_config(config_file=path), "transport/link/tx/lease") == 2500
    forced = build_router_config(config_file=path, cfg=[("transport/link/tx/lease", "10000")])
    assert get(forced, "transport/link/tx/lease") == 10000


def test_file_with_another_mode_is_refused(tmp_path: Path) -> None:
    with pytest.raises(StartupError, match="sets mode 'client'"):
        build_router_config(config_file=write(tmp_path, '{mode: "client"}'))


def test_unreadable_files_are_startup_errors(tmp_path: Path) -> None:
    missing = str(tmp_path / "missing.json5")
    with pytest.raises(StartupError, match="cannot read Zenoh config .*missing.json5"):
        build_router_config(config_file=missing)
    with pytest.raises(StartupError, match="cannot read Zenoh config"):
        build_router_config(config_file=write(tmp_path, "{mode: "))


# ------------------------------------------------------------------ shipped configs


ROUTERS = sorted(p.name for p in DEPLOY.glob("*router*.json5"))
OTHERS = sorted(p.name for p in DEPLOY.glob("*.json5") if "router" not in p.name)


def test_deploy_ships_the_expected_configs() -> None:
    assert ROUTERS == ["router-acl.json5", "router-mtls.json5", "router-tls.json5",
                       "router-usrpwd.json5", "router.json5", "station-router.json5"]
    assert OTHERS == ["client-mtls.json5", "client-tls.json5", "client-usrpwd.json5",
                      "client.json5", "peer.json5", "robot-peer.json5"]


@pytest.mark.parametrize("name", ROUTERS)
def test_shipped_router_configs_build(name: str) -> None:
    conf = build_router_config(config_file=str(DEPLOY / name))
    assert get(conf, "scouting/multicast/enabled") is False
    assert get(conf, "transport/link/tx/lease") == 2500
    assert listen_endpoints(conf)


@pytest.mark.parametrize("name", OTHERS)
def test_shipped_session_configs_parse(name: str) -> None:
    conf = zenoh.Config.from_file(str(DEPLOY / name))
    assert get(conf, "mode") in ("peer", "client")
    assert get(conf, "scouting/multicast/enabled") is False
    assert get(conf, "transport/link/tx/lease") == 2500
    assert get(conf, "connect/endpoints")
    if get(conf, "mode") == "peer":  # a peer without a listen endpoint gets nothing via a router
        assert get(conf, "listen/endpoints")


# ------------------------------------------------------------------ reachability, main()


def test_router_reachable() -> None:
    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        server.listen()
        port = server.getsockname()[1]
        assert router_reachable(f"tcp/127.0.0.1:{port}", 1.0)
        assert router_reachable(f"tls/127.0.0.1:{port}?meta=1", 1.0)
    assert not router_reachable(f"tcp/127.0.0.1:{port}", 1.0)


@pytest.mark.parametrize("endpoint", ["udp/127.0.0.1:7447", "tcp/127.0.0.1", "7447"])
def test_router_reachable_rejects(endpoint: str) -> None:
    with pytest.raises(StartupError, match="endpoint"):
        router_reachable(endpoint)


def test_main_config_error_exits_3(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["-c", str(tmp_path / "missing.json5")]) == 3
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("zenros router: cannot read Zenoh config")


def test_main_bad_cfg_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["--cfg", "lease"])
    assert exc.value.code == 2
    assert "expected KEY:VALUE" in capsys.readouterr().err
