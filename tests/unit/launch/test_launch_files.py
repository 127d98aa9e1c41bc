"""The launch files zenros carries: finding one by its bare name, ``zenros launch --list``, and
the demo map their ``$(dirname)`` and the services' defaults point at."""

from __future__ import annotations

from pathlib import Path

import pytest
from zenros.errors import LaunchError
from zenros.launch.cli import main
from zenros.launch.files import deploy_dir, describe, find_launch_file, launch_dir, launch_files
from zenros.launch.loader import load_launch

ROOT = Path(__file__).resolve().parents[3]


def test_in_a_checkout_the_launch_files_are_deploy_launch() -> None:
    assert deploy_dir() == ROOT / "deploy"
    assert launch_dir() == ROOT / "deploy" / "launch"
    assert [p.name for p in launch_files()] == sorted(p.name for p in
                                                      (ROOT / "deploy/launch").glob("*.yaml"))
    assert "sim.yaml" in [p.name for p in launch_files()]


def test_a_bare_name_is_found_among_the_launch_files(tmp_path: Path) -> None:
    sim = launch_dir() / "sim.yaml"
    assert find_launch_file("sim.yaml", cwd=tmp_path) == sim
    assert find_launch_file("sim", cwd=tmp_path) == sim  # .yaml may be left off


def test_a_file_here_wins_over_the_launch_files(tmp_path: Path) -> None:
    (tmp_path / "sim.yaml").write_text("nodes: []\n")
    assert find_launch_file("sim.yaml", cwd=tmp_path) == tmp_path / "sim.yaml"
    assert find_launch_file(tmp_path / "sim.yaml") == tmp_path / "sim.yaml"


def test_a_path_with_a_folder_is_only_that_path(tmp_path: Path) -> None:
    # deploy/launch/sim.yaml means the checkout's file: not looked up anywhere else
    assert find_launch_file("deploy/launch/sim.yaml", cwd=ROOT) == ROOT / "deploy/launch/sim.yaml"
    assert find_launch_file("deploy/launch/sim.yaml", cwd=tmp_path) == (
        tmp_path / "deploy/launch/sim.yaml")


def test_an_unknown_name_says_what_there_is(tmp_path: Path) -> None:
    with pytest.raises(LaunchError, match=r"launch file not found: nope\.yaml .*sim\.yaml.*--list"):
        find_launch_file("nope.yaml", cwd=tmp_path)


def test_describe_is_the_first_sentence_of_the_header(tmp_path: Path) -> None:
    f = tmp_path / "a.yaml"
    f.write_text("# One robot: the on-board\n#   services. More here.\n# And more.\nargs: {}\n")
    assert describe(f) == "One robot: the on-board services."
    f.write_text("#\n# Two lines\n# without a stop\n\n# later\nnodes: []\n")
    assert describe(f) == "Two lines without a stop"
    f.write_text("nodes: []\n# not a header\n")
    assert describe(f) == ""
    assert describe(tmp_path / "missing.yaml") == ""


def test_cli_list_names_each_launch_file_with_its_description(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["--list"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert str(launch_dir()) in out[0]
    rows = {line.split()[0]: line.split(None, 1)[1] for line in out[1:]}
    assert list(rows) == [p.name for p in launch_files()]
    assert rows["sim.yaml"] == describe(launch_dir() / "sim.yaml")
    assert rows["sim.yaml"].startswith("The whole simulated robot")


def test_cli_runs_a_bare_name_from_any_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["sim.yaml", "--show-args"]) == 0
    assert "rest_port (default: '3546')" in capsys.readouterr().out
    assert main(["sim", "rate:=5", "--print"]) == 0
    assert "gateway: " in capsys.readouterr().out
    assert main(["nope.yaml"]) == 3
    assert "launch file not found: nope.yaml" in capsys.readouterr().err
    assert main([]) == 2
    assert "give a launch file" in capsys.readouterr().err


def test_the_launch_files_dirname_reaches_the_demo_map() -> None:
    """sim.yaml's map default ($(dirname)/../maps/...) and the services' default map are the
    demo map, which installs beside the launch files (zenros.deploy)."""
    from zenros.services.chassis.config import DEMO_MAP as chassis_map
    from zenros.services.nav.params import DEMO_MAP as nav_map

    demo = deploy_dir() / "maps" / "office" / "office.yaml"
    assert demo.is_file()
    assert chassis_map.resolve() == nav_map.resolve() == demo.resolve()
    for name in ("sim.yaml", "robot.yaml"):
        maps = [Path(p["map"]) for spec in load_launch(launch_dir() / name).processes
                for p in spec.params if isinstance(p, dict) and "map" in p]
        assert maps and all(m.resolve() == demo.resolve() for m in maps), (name, maps)


def test_lifecycle_launch_file_runs_a_manager_over_its_nodes() -> None:
    desc = load_launch(launch_dir() / "lifecycle.yaml", {"bond_timeout": "2.5"})
    names = [p.name for p in desc.processes]
    assert names == ["cam", "planner", "driver", "lifecycle_manager"]
    manager = desc.processes[-1]
    assert manager.cmd[1:] == ("-m", "zenros.lifecycle.manager")
    assert manager.params[-1] == {"node_names": ["cam", "planner", "driver"],
                                  "autostart": True, "bond_timeout": 2.5}
    assert all(p.respawn for p in desc.processes[:3])
