"""The tf service as a process (statics from parameters, lookup/can_transform/frames services)
and `zenros tf echo|frames|static`, through a real router."""

from __future__ import annotations

import json
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from zenros.context import Context
from zenros.errors import LookupException
from zenros.msgs.builtin_interfaces import Time
from zenros.node import Node
from zenros.session import SessionOptions
from zenros.testing import Proc, wait_for
from zenros.tf import LATEST, BufferClient, TransformBroadcaster, transform_stamped

pytestmark = pytest.mark.system

STATICS = '["0.1 0 0.2 0 0 0 base_link laser", {parent: base_link, child: imu, z: 0.3}]'


def zenros(router: str, prefix: str, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "zenros.cli", *args, "-e", router, "--prefix", prefix],
        capture_output=True, text=True, timeout=40, check=False,
    )


@pytest.fixture
def system(router: str, prefix: str) -> Iterator[tuple[str, str, Node]]:
    """The tf service with two statics, and (in this process) a chassis broadcasting
    odom → base_link at 20 Hz."""
    tf = Proc([sys.executable, "-m", "zenros.services.tf", "-e", router, "--prefix", prefix,
               "-p", f"static_transforms:={STATICS}"])
    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    try:
        assert tf.wait_line("started", 15), tf.output
        assert "static transform base_link -> laser" in tf.output
        chassis = Node("chassis", context=ctx)
        br = TransformBroadcaster(chassis)
        x = [0.0]

        def tick() -> None:
            x[0] += 0.01
            br.send_transform(transform_stamped("odom", "base_link", (x[0], 0, 0, 0, 0, 0, 1),
                                                chassis.now()))

        chassis.create_timer(0.05, tick)
        yield router, prefix, chassis
        chassis.close()
    finally:
        ctx.close()
        assert tf.stop() == 0, tf.output


def test_lookups_through_the_service(system: tuple[str, str, Node]) -> None:
    client = BufferClient(system[2])
    assert client.wait_for_server(10)
    assert client.can_transform("odom", "laser", LATEST, timeout=10.0)
    t = client.lookup_transform("base_link", "imu", LATEST)
    assert (t.transform.translation.z, t.header.stamp) == (0.3, Time())
    t = client.lookup_transform("odom", "laser", LATEST)
    assert t.transform.translation.x > 0.1 and t.transform.translation.z == pytest.approx(0.2)
    with pytest.raises(LookupException, match='"nowhere" passed to lookupTransform'):
        client.lookup_transform("odom", "nowhere", LATEST)


def test_tf_echo_prints_translation_rotation_and_matrix(system: tuple[str, str, Node]) -> None:
    r = zenros(system[0], system[1], "tf", "echo", "base_link", "laser", "--once",
               "--timeout", "20")
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("At time 0.000000000\n")
    assert "- Translation: [0.100, 0.000, 0.200]" in r.stdout
    assert "- Rotation: in Quaternion (xyzw) [0.000, 0.000, 0.000, 1.000]" in r.stdout
    assert "- Rotation: in RPY (degree) [0.000, 0.000, 0.000]" in r.stdout
    assert "   1.000  0.000  0.000  0.100" in r.stdout
    r = zenros(system[0], system[1], "tf", "echo", "odom", "laser", "-n", "2", "-r", "10",
               "--json", "--timeout", "20")
    assert r.returncode == 0, r.stderr
    first, second = (json.loads(line) for line in r.stdout.splitlines())
    # tf2_echo prints the latest transform each period: a loaded box may publish none between
    # two prints, and the same stamp comes twice
    assert second["stamp"] >= first["stamp"] > 0 and first["translation"][2] == 0.2
    assert len(first["matrix"]) == 4 and first["target"] == "odom"


def test_tf_echo_gives_up_after_its_timeout(system: tuple[str, str, Node]) -> None:
    r = zenros(system[0], system[1], "tf", "echo", "odom", "nowhere", "--timeout", "1")
    assert r.returncode == 1 and "Waiting for transform odom -> nowhere" in r.stderr


def test_tf_static_then_frames_and_dot(system: tuple[str, str, Node], tmp_path: Path) -> None:
    router, prefix, _ = system
    static = Proc([sys.executable, "-m", "zenros.cli", "tf", "static", "0", "0", "0.5",
                   "-1.5707963", "0", "0", "base_link", "mast", "--node-name", "mast_tf",
                   "-e", router, "--prefix", prefix])
    try:
        assert static.wait_line("publishing static transform base_link -> mast", 15)
        r = zenros(router, prefix, "tf", "echo", "base_link", "mast", "--once", "--json",
                   "--timeout", "20")
        assert r.returncode == 0, r.stderr
        body = json.loads(r.stdout)
        assert body["translation"] == [0.0, 0.0, 0.5]
        assert body["rpy"][2] == pytest.approx(-1.5707963)

        def frames() -> Any:
            return zenros(router, prefix, "tf", "frames")

        assert wait_for(lambda: "mast  [static, /mast_tf]" in frames().stdout, 20)
        lines = frames().stdout.splitlines()
        assert lines[0] == "odom" and lines[1].startswith("└── base_link  [/chassis, ")
        assert lines[2:] == ["    ├── imu  [static, /tf]", "    ├── laser  [static, /tf]",
                             "    └── mast  [static, /mast_tf]"]
        rate = float(lines[1].split(", ")[1].split()[0])
        assert 5 < rate < 40  # published at 20 Hz
        r = zenros(router, prefix, "tf", "frames", "--dot")
        assert r.stdout.startswith("digraph G {") and '"base_link" -> "mast"' in r.stdout
        out = tmp_path / "frames.gv"
        r = zenros(router, prefix, "tf", "frames", "-o", str(out))
        assert r.returncode == 0 and '"odom" -> "base_link"' in out.read_text()
    finally:
        assert static.stop() == 0, static.output


def test_tf_frames_without_the_service_listens(system: tuple[str, str, Node]) -> None:
    r = zenros(system[0], system[1], "tf", "frames", "--no-server", "--wait", "1.5")
    assert r.returncode == 0, r.stderr
    assert "└── base_link  [default_authority, " in r.stdout
    assert "laser  [static, default_authority]" in r.stdout


def test_bad_static_parameter_fails_at_startup(router: str, prefix: str) -> None:
    r = subprocess.run([sys.executable, "-m", "zenros.services.tf", "-e", router, "--prefix",
                        prefix, "-p", 'static_transforms:=["1 2 base_link"]'],
                       capture_output=True, text=True, timeout=30, check=False)
    assert r.returncode == 3
    assert "startup failed: parameter 'static_transforms'[0]" in r.stderr
