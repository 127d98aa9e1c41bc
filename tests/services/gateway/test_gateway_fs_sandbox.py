"""`FileRoot` without HTTP: paths confined to the root (``..``, absolute paths, symbolic
links), protected files, the root itself, and each file operation's answers."""

from __future__ import annotations

import io
import os
from pathlib import Path

import pytest
from zenros.services.gateway.ports.fs_sandbox import (
    BadPath,
    Conflict,
    FileRoot,
    Forbidden,
    NotFound,
    TooLarge,
)


@pytest.fixture
def tree(tmp_path: Path) -> tuple[FileRoot, Path, Path]:
    root = tmp_path / "root"
    outside = tmp_path / "outside"
    (root / "maps").mkdir(parents=True)
    (root / "maps" / "a.pgm").write_bytes(b"P5 map")
    (root / "secret").mkdir()
    (root / "secret" / "config.json").write_text('{"password": "x"}')
    outside.mkdir()
    (outside / "passwd").write_text("root:x")
    return FileRoot(root, [root / "secret" / "config.json"], max_upload=100), root, outside


def test_paths_stay_inside(tree: tuple[FileRoot, Path, Path]) -> None:
    fr, root, outside = tree
    assert fr.resolve("maps/a.pgm") == fr.root / "maps" / "a.pgm"
    assert fr.resolve(".") == fr.root and fr.resolve("./maps//a.pgm") == fr.root / "maps/a.pgm"
    assert fr.resolve(str(fr.root / "maps")) == fr.root / "maps"   # absolute inside: ok
    for bad in ("../outside/passwd", "maps/../../outside", "..", "maps/..", ""):
        with pytest.raises(BadPath):
            fr.resolve(bad)
    with pytest.raises(BadPath, match="NUL"):
        fr.resolve("maps/a\x00")
    with pytest.raises(Forbidden, match="outside the file root"):
        fr.resolve(str(outside / "passwd"))
    with pytest.raises(Forbidden):
        fr.resolve("/etc/passwd")
    os.symlink(outside, root / "escape")
    os.symlink(outside / "passwd", root / "maps" / "pw")
    for bad in ("escape", "escape/passwd", "maps/pw"):
        with pytest.raises(Forbidden, match="symbolic link"):
            fr.resolve(bad)
    os.symlink(root / "maps" / "a.pgm", root / "inner")     # a link that stays inside: ok
    assert fr.file("inner").read_bytes() == b"P5 map"


def test_protected_and_root(tree: tuple[FileRoot, Path, Path]) -> None:
    fr, root, _ = tree
    with pytest.raises(Forbidden, match="protected"):
        fr.file("secret/config.json")
    os.symlink(root / "secret" / "config.json", root / "alias")
    with pytest.raises(Forbidden, match="protected"):
        fr.file("alias")
    with pytest.raises(Forbidden, match="protected"):
        fr.remove_dir("secret")
    with pytest.raises(Forbidden, match="protected"):
        fr.move("secret", "moved")
    for delete in (fr.remove_dir, fr.remove_file):
        with pytest.raises(Forbidden, match="root itself"):
            delete(".")
    with pytest.raises(Forbidden, match="root itself"):
        fr.remove_many(["maps", "."])
    assert (root / "maps" / "a.pgm").exists()   # nothing deleted when one path is refused
    with pytest.raises(Forbidden):
        fr.move(".", "elsewhere")


def test_reads(tree: tuple[FileRoot, Path, Path]) -> None:
    fr, root, _ = tree
    (root / "maps" / "sub").mkdir()
    assert fr.list_dir(".") == {"files": [], "directories": ["maps", "secret"]}
    assert fr.list_dir("maps") == {"files": ["a.pgm"], "directories": ["sub"]}
    info = fr.info("maps/a.pgm")
    assert info["size"] == 6 and info["mimetype"] == "image/x-portable-graymap"
    assert isinstance(info["mtime"], int) and info["mode"] & 0o100000
    assert fr.info("maps")["mimetype"] == "inode/directory"
    with pytest.raises(NotFound):
        fr.info("maps/none")
    with pytest.raises(BadPath, match="not a folder"):
        fr.list_dir("maps/a.pgm")
    with pytest.raises(BadPath, match="not a file"):
        fr.file("maps")


def test_changes(tree: tuple[FileRoot, Path, Path]) -> None:
    fr, root, _ = tree
    fr.make_dir("new/deeper")
    assert (root / "new" / "deeper").is_dir()
    with pytest.raises(Conflict):
        fr.make_dir("new")
    assert fr.copy("maps/a.pgm", "new") == "new/a.pgm"          # into a folder
    assert fr.copy("maps", "maps2") == "maps2"                  # a folder
    assert (root / "maps2" / "a.pgm").read_bytes() == b"P5 map"
    with pytest.raises(Conflict, match="exists"):
        fr.copy("maps/a.pgm", "new/a.pgm")
    with pytest.raises(Conflict, match="into itself"):
        fr.copy("maps", "maps/inside")
    with pytest.raises(NotFound):
        fr.copy("maps/a.pgm", "nofolder/x.pgm")
    assert fr.move("new/a.pgm", "new/b.pgm") == "new/b.pgm"
    assert fr.move("new/b.pgm", "maps2") == "maps2/b.pgm"
    with pytest.raises(NotFound):
        fr.move("new/b.pgm", "x")
    with pytest.raises(BadPath, match="is a folder"):
        fr.remove_file("maps2")
    with pytest.raises(BadPath, match="not a folder"):
        fr.remove_dir("maps2/b.pgm")
    fr.remove_file("maps2/b.pgm")
    fr.remove_dir("maps2")
    with pytest.raises(NotFound):
        fr.remove_many(["new", "gone"])
    assert (root / "new").exists()
    fr.remove_many(["new", "maps/a.pgm"])
    assert not (root / "new").exists() and not (root / "maps" / "a.pgm").exists()


def test_copy_keeps_links_as_links(tree: tuple[FileRoot, Path, Path]) -> None:
    fr, root, outside = tree
    os.symlink(outside / "passwd", root / "maps" / "pw")
    fr.copy("maps", "copy")   # the link is copied as a link, never the outside file
    assert (root / "copy" / "pw").is_symlink()
    with pytest.raises(Forbidden):
        fr.file("copy/pw")


def test_upload(tree: tuple[FileRoot, Path, Path]) -> None:
    fr, root, _ = tree
    target = fr.upload_target("maps", "../../evil.txt")   # only the name counts
    assert target == fr.root / "maps" / "evil.txt"
    assert fr.write(target, io.BytesIO(b"hello")) == 5
    assert fr.upload_target("maps/x.bin", "ignored") == fr.root / "maps" / "x.bin"
    with pytest.raises(NotFound, match="no such folder"):   # folders are not made
        fr.upload_target("fresh/", "f.txt")
    fr.make_dir("fresh")
    assert fr.upload_target("fresh/", "f.txt") == fr.root / "fresh" / "f.txt"
    with pytest.raises(BadPath, match="no file name"):
        fr.upload_target("maps", "..")
    with pytest.raises(TooLarge):
        fr.write(fr.root / "maps" / "big", io.BytesIO(b"x" * 101))
    assert sorted(p.name for p in (root / "maps").iterdir()) == ["a.pgm", "evil.txt"]
    with pytest.raises(Forbidden):
        fr.upload_target("secret/config.json", "c")
