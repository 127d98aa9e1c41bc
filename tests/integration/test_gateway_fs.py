"""docs/robot-api.md §16 file system API through a real server: upload (multipart), download, list,
stat, rename, copy, cut, delete; traversal attempts, symlink escapes, the protected config file, an
oversized upload, tokens, unknown paths and wrong types."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
from zenros.context import Context
from zenros.services.gateway.node import GatewayNode
from zenros.services.gateway.testing import running_gateway


@pytest.fixture
def gw(ctx_pair: list[Context], tmp_path: Path) -> Iterator[GatewayNode]:
    (tmp_path / "root" / "slamdb").mkdir(parents=True)
    (tmp_path / "root" / "config.json").write_text('{"password": "admin"}')
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "passwd").write_text("root:x")
    with running_gateway(ctx_pair[0], tmp_path, fs_root=str(tmp_path / "root"),
                         fs_max_upload=1000,
                         config_file=str(tmp_path / "root" / "config.json")) as node:
        yield node


@pytest.fixture
def http(gw: GatewayNode) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=10) as c:
        token = c.get("/token").json()["token"]
        c.params = httpx.QueryParams({"token": token})
        yield c


def _refused(r: httpx.Response, status: int, words: str) -> None:
    assert r.status_code == status, r.text
    assert r.json()["status"] == "error" and words in r.json()["description"], r.text


def test_file_round_trip(gw: GatewayNode, http: httpx.Client, tmp_path: Path) -> None:
    root = tmp_path / "root"
    r = http.post("/fs/file_api", data={"path": "slamdb"},
                  files={"file": ("map.pgm", b"P5 data", "image/x-portable-graymap")})
    assert r.json() == {"status": "ok", "path": "slamdb/map.pgm", "size": 7}
    assert (root / "slamdb" / "map.pgm").read_bytes() == b"P5 data"
    # the path may also come in the query; an existing file is replaced
    r = http.post("/fs/file_api", params={"path": "slamdb/map.pgm"},
                  files={"file": ("whatever", b"P5 new")})
    assert r.status_code == 200 and (root / "slamdb" / "map.pgm").read_bytes() == b"P5 new"
    got = http.get("/fs/file_api", params={"path": "slamdb/map.pgm"})
    assert got.status_code == 200 and got.content == b"P5 new"
    assert http.get("/fs/dir_api", params={"path": "."}).json() == {
        "files": ["config.json"], "directories": ["slamdb"]}
    assert http.post("/fs/dir_api", json={"path": "Pictures/2026"}).json() == {"status": "ok"}
    _refused(http.post("/fs/dir_api", json={"path": "Pictures"}), 409, "exists")
    info = http.get("/fs/get_file_info", params={"path": "slamdb/map.pgm"}).json()
    assert info["size"] == 6 and info["mimetype"] == "image/x-portable-graymap"
    assert set(info) == {"mode", "size", "atime", "mtime", "ctime", "mimetype"}
    assert http.post("/fs/copy", json={"from": "slamdb", "to": "saved-slamdb"}).json()[
        "path"] == "saved-slamdb"
    assert http.put("/fs/file_api", json={"name": "saved-slamdb/map.pgm",
                                          "new_name": "saved-slamdb/old.pgm"}).status_code == 200
    assert http.post("/fs/cut", json={"from": "saved-slamdb/old.pgm", "to": "Pictures"}
                     ).json() == {"status": "ok", "path": "Pictures/old.pgm"}
    assert http.get("/fs/dir_api", params={"path": "Pictures"}).json() == {
        "files": ["old.pgm"], "directories": ["2026"]}
    assert http.delete("/fs/file_api", params={"path": "Pictures/old.pgm"}).json() == {
        "status": "ok"}
    assert http.delete("/fs/dir_api", params={"path": "saved-slamdb"}).status_code == 200
    assert http.post("/fs/delete", json={"delete": ["Pictures", "slamdb/map.pgm"]}
                     ).json() == {"status": "ok"}
    assert sorted(os.listdir(root)) == ["config.json", "slamdb"]
    # unknown paths: 404 naming the path
    _refused(http.get("/fs/file_api", params={"path": "slamdb/none"}), 404, "slamdb/none")
    _refused(http.delete("/fs/dir_api", params={"path": "nope"}), 404, "nope")
    _refused(http.post("/fs/delete", json={"delete": ["slamdb", "gone"]}), 404, "gone")
    assert (root / "slamdb").is_dir()


def test_traversal_and_escapes(gw: GatewayNode, http: httpx.Client, tmp_path: Path) -> None:
    root, outside = tmp_path / "root", tmp_path / "outside"
    for path in ("../outside/passwd", "slamdb/../../outside/passwd", ".."):
        _refused(http.get("/fs/file_api", params={"path": path}), 400, "'..'")
    # %2e%2e in the query decodes to '..' and is refused the same way
    base = str(http.base_url).rstrip("/")
    raw = f"{base}/fs/dir_api?path=%2e%2e%2foutside&token={http.params['token']}"
    _refused(httpx.get(raw, timeout=10), 400, "'..'")
    # a %2e%2e in the URL path is no endpoint at all
    assert http.get("/fs/%2e%2e/system/info").status_code == 404
    _refused(http.get("/fs/file_api", params={"path": str(outside / "passwd")}), 403,
             "outside the file root")
    _refused(http.get("/fs/dir_api", params={"path": "/etc"}), 403, "outside")
    assert http.get("/fs/dir_api", params={"path": str(root / "slamdb")}).status_code == 200
    os.symlink(outside, root / "slamdb" / "escape")
    for r in (http.get("/fs/file_api", params={"path": "slamdb/escape/passwd"}),
              http.get("/fs/dir_api", params={"path": "slamdb/escape"}),
              http.post("/fs/copy", json={"from": "slamdb/escape", "to": "stolen"}),
              http.post("/fs/file_api", data={"path": "slamdb/escape"},
                        files={"file": ("x", b"overwrite")})):
        _refused(r, 403, "symbolic link")
    assert (outside / "passwd").read_text() == "root:x"
    # the gateway's config file (the password) and the root itself are off limits
    _refused(http.get("/fs/file_api", params={"path": "config.json"}), 403, "protected")
    _refused(http.put("/fs/file_api", json={"name": "config.json", "new_name": "c"}), 403,
             "protected")
    _refused(http.delete("/fs/dir_api", params={"path": "."}), 403, "root itself")
    _refused(http.post("/fs/delete", json={"delete": ["."]}), 403, "root itself")
    _refused(http.post("/fs/cut", json={"from": "slamdb", "to": "slamdb/x"}), 409, "itself")


def test_bad_requests(gw: GatewayNode, http: httpx.Client, tmp_path: Path) -> None:
    # an oversized upload: 413 by Content-Length, nothing written
    r = http.post("/fs/file_api", data={"path": "slamdb"}, files={"file": ("big", b"x" * 5000)})
    _refused(r, 413, "too large")
    r = http.post("/fs/file_api", data={"path": "slamdb"},
                  files={"file": ("big", b"x" * 1001)})   # under the slack, over the limit
    _refused(r, 413, "too large")
    assert os.listdir(tmp_path / "root" / "slamdb") == []
    # an oversized body streamed without Content-Length
    def chunks() -> Iterator[bytes]:
        yield b"--b\r\nContent-Disposition: form-data; name=\"file\"; filename=\"f\"\r\n\r\n"
        for _ in range(100):
            yield b"y" * 4096
    r = http.post("/fs/file_api", params={"path": "slamdb"}, content=chunks(),
                  headers={"content-type": "multipart/form-data; boundary=b"})
    _refused(r, 413, "too large")
    _refused(http.post("/fs/file_api", json={"path": "slamdb"}), 400, "multipart")
    _refused(http.post("/fs/file_api", data={"path": "slamdb"}), 400, "multipart")
    _refused(http.post("/fs/file_api", data={"path": "slamdb", "x": "1"},
                       files={"file": ("f", b"1")}), 400, "unknown form field")
    _refused(http.post("/fs/file_api", files={"file": ("f", b"1")}), 400, "missing `path`")
    _refused(http.post("/fs/file_api", data={"path": "slamdb", "file": "text"}), 400, "file")
    _refused(http.post("/fs/file_api", content=b"--b\r\ngarbage",
                       params={"path": "slamdb"},
                       headers={"content-type": "multipart/form-data; boundary=b"}), 400, "")
    _refused(http.post("/fs/file_api", data={"path": "slamdb"},
                       files=[("file", ("a", b"1")), ("file", ("b", b"2"))]), 400, "multipart")
    # wrong types and missing fields
    _refused(http.post("/fs/delete", json={"delete": "slamdb"}), 400, "delete")
    _refused(http.post("/fs/copy", json={"from": 3, "to": "x"}), 400, "from")
    _refused(http.post("/fs/cut", json={"from": "slamdb"}), 400, "to")
    _refused(http.put("/fs/file_api", json={"name": "slamdb"}), 400, "new_name")
    _refused(http.get("/fs/dir_api"), 400, "path")
    _refused(http.get("/fs/dir_api", params={"path": "slamdb", "extra": 1}), 400, "extra")
    # every /fs endpoint checks the token
    with httpx.Client(base_url=str(http.base_url), timeout=10) as anon:
        _refused(anon.get("/fs/dir_api", params={"path": "."}), 401, "token")
        _refused(anon.post("/fs/file_api", data={"path": "slamdb"},
                           files={"file": ("f", b"1")}), 401, "token")
    assert os.listdir(tmp_path / "root" / "slamdb") == []
    # the server is still fine
    assert http.get("/fs/dir_api", params={"path": "slamdb"}).status_code == 200
