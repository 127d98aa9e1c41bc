"""docs/robot-api.md §3.4 software updates with real pip, from a folder of wheels: check finds
the newer version (a pre-release only with use_dev), start installs it in the background into
a fresh virtual environment with its log, cancel stops one under way; refusals (updates off,
no source) with the reason."""

from __future__ import annotations

import base64
import hashlib
import json
import subprocess
import venv
import zipfile
from contextlib import AbstractContextManager
from pathlib import Path
from typing import Any

import httpx
import pytest
from zenros.context import Context
from zenros.services.gateway.testing import running_gateway
from zenros.testing import wait_for

pytestmark = pytest.mark.timeout(180)

PACKAGE = "zenros-update-probe"


def make_wheel(folder: Path, version: str) -> Path:
    """A real (tiny) wheel of PACKAGE at ``version``, as a build tool makes one."""
    mod, info = "zenros_update_probe", f"zenros_update_probe-{version}.dist-info"
    files = {f"{mod}/__init__.py": f"VERSION = {version!r}\n".encode(),
             f"{info}/METADATA": (f"Metadata-Version: 2.1\nName: {PACKAGE}\n"
                                  f"Version: {version}\n").encode(),
             f"{info}/WHEEL": b"Wheel-Version: 1.0\nGenerator: test\nRoot-Is-Purelib: true\n"
                              b"Tag: py3-none-any\n"}
    record = []
    for name, data in files.items():
        digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
        record.append(f"{name},sha256={digest},{len(data)}")
    record.append(f"{info}/RECORD,,")
    path = folder / f"zenros_update_probe-{version}-py3-none-any.whl"
    with zipfile.ZipFile(path, "w") as zf:
        for name, data in files.items():
            zf.writestr(name, data)
        zf.writestr(f"{info}/RECORD", "\n".join(record) + "\n")
    return path


def _gateway(ctx: Context, home: Path, **config: object) -> AbstractContextManager[Any]:
    home.mkdir(parents=True, exist_ok=True)
    (home / "config.json").write_text(json.dumps(config))
    return running_gateway(ctx, home, no_token_check=True)


def test_check_use_dev_and_an_update_installed_in_the_background(
        ctx_pair: list[Context], tmp_path: Path) -> None:
    wheels = tmp_path / "wheels"
    wheels.mkdir()
    make_wheel(wheels, "2.0.0")
    make_wheel(wheels, "2.1.0rc1")
    target = tmp_path / "venv"
    venv.create(target, with_pip=True)
    python = str(target / "bin" / "python")
    with _gateway(ctx_pair[0], tmp_path / "gw", allow_update=True, update_source=str(wheels),
                  update_package=PACKAGE) as gw, \
            httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=150) as http:
        updater = gw.robot.context.updater
        assert updater is not None
        updater.python = python  # the robot's software lives in this venv here
        r = http.get("/system/update/check")
        assert r.status_code == 200, r.text
        assert r.json() == {"status": "ok", "need_update": True, "current": "",
                            "latest": "2.0.0", "use_dev": False}
        assert http.get("/system/use_dev").json() == {"use_dev": False}
        assert http.put("/system/use_dev", json={"use_dev": True}).json() == {"use_dev": True}
        assert http.get("/system/update/check").json()["latest"] == "2.1.0rc1"
        assert http.put("/system/use_dev", json={"use_dev": False}).json() == {"use_dev": False}
        assert http.get("/system/update/log").json() == {"status": "idle", "log": "",
                                                         "is_complete": False}
        r = http.get("/system/update/start")
        assert r.status_code == 200 and r.json() == {"status": "updating"}, r.text
        assert wait_for(lambda: http.get("/system/update/log").json()["is_complete"], 120)
        log = http.get("/system/update/log").json()
        assert log["status"] == "complete", log
        assert f"Successfully installed {PACKAGE}-2.0.0" in log["log"], log["log"]
        assert "restart the robot" in log["log"]
        out = subprocess.run([python, "-c", "import zenros_update_probe as m; print(m.VERSION)"],
                             capture_output=True, text=True, check=True, timeout=60)
        assert out.stdout.strip() == "2.0.0"
        assert (tmp_path / "gw" / "data" / "update.log").is_file()
        r = http.get("/system/update/cancel")
        assert r.status_code == 409 and "no update is under way" in r.json()["description"]


def test_refusals(ctx_pair: list[Context], tmp_path: Path) -> None:
    with _gateway(ctx_pair[0], tmp_path / "off", update_source=str(tmp_path)) as gw, \
            httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=60) as http:
        r = http.get("/system/update/start")
        assert r.status_code == 403 and "allow_update" in r.json()["description"], r.text
        r = http.put("/system/use_dev", json={"use_dev": "yes"})
        assert r.status_code == 400, r.text
    with _gateway(ctx_pair[0], tmp_path / "nosrc", allow_update=True) as gw, \
            httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=60) as http:
        for path in ("/system/update/check", "/system/update/start"):
            r = http.get(path)
            assert r.status_code == 503 and "no update source" in r.json()["description"]


def test_cancel_stops_an_update_under_way(ctx_pair: list[Context], tmp_path: Path) -> None:
    """An index that never answers keeps pip waiting: cancel ends it."""
    import socket

    silent = socket.socket()
    silent.bind(("127.0.0.1", 0))
    silent.listen(8)
    port = silent.getsockname()[1]
    try:
        with _gateway(ctx_pair[0], tmp_path / "gw", allow_update=True,
                      update_source=f"http://127.0.0.1:{port}/simple",
                      update_package=PACKAGE) as gw, \
                httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1",
                             timeout=60) as http:
            assert http.get("/system/update/start").json() == {"status": "updating"}
            r = http.get("/system/update/start")
            assert r.status_code == 409 and "under way" in r.json()["description"]
            assert http.get("/system/update/log").json()["status"] == "updating"
            r = http.get("/system/update/cancel")
            assert r.status_code == 200 and r.json() == {"status": "cancelled"}, r.text
            log = http.get("/system/update/log").json()
            assert log["status"] == "cancelled" and log["is_complete"], log
    finally:
        silent.close()
