"""`zenros bag` as real processes: record, kill -9 and recover, info, play, launch node."""

from __future__ import annotations

import json
import re
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from zenros.context import Context
from zenros.testing import Proc, wait_for

pytestmark = pytest.mark.system


def zenros(*args: str, timeout: float = 30) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "zenros.cli", *args], capture_output=True,
                          text=True, timeout=timeout, check=False)


def inproc(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    """A verb that needs no network (info, recover, argument errors), run in this process:
    the same code as the console script without paying for a process start each time."""
    from zenros.cli.__main__ import main

    capsys.readouterr()
    try:
        rc = main(list(args))
    except SystemExit as exc:  # argparse usage errors
        rc = int(exc.code or 0)
    out, err = capsys.readouterr()
    return rc, out, err


@pytest.fixture
def talker(router: str, prefix: str) -> Iterator[Proc]:
    p = Proc([sys.executable, "-m", "zenros.examples.talker", "-e", router, "--prefix", prefix,
              "-p", "rate:=200.0"])
    try:
        assert p.wait_line("started", 15), p.output
        yield p
    finally:
        p.stop()


def numbers(bag: Path) -> list[int]:
    from zenros.bag import bag_files, iter_messages

    return [int(json.loads(m.data)["data"].split()[-1]) for m in iter_messages(bag_files(bag))]


def record(router: str, prefix: str, *args: str) -> Proc:
    p = Proc([sys.executable, "-m", "zenros.cli", "bag", "record", *args, "-e", router,
              "--prefix", prefix])
    assert p.wait_line("Subscribed to topic '/chatter'", 15), p.output
    return p


def test_kill_9_then_recover(router: str, prefix: str, talker: Proc, tmp_path: Path,
                             capsys: pytest.CaptureFixture[str]) -> None:
    bag = tmp_path / "crash"
    rec = record(router, prefix, "/chatter", "-o", str(bag), "--flush-interval", "0.1")
    try:
        data = bag / "crash_0.mcap"
        # a few flushed chunks on disk (each 0.1 s of messages)
        assert wait_for(lambda: data.exists() and data.stat().st_size > 3000, 15)
        rec.popen.send_signal(signal.SIGKILL)
        rec.wait(10)
    finally:
        rec.stop()
    rc, out, err = inproc(capsys, "bag", "info", str(bag))
    assert rc == 1 and "zenros bag recover" in err and "Traceback" not in err
    rc, out, err = inproc(capsys, "bag", "recover", str(bag))
    assert rc == 0, err
    n = int(re.search(r"recovered (\d+) messages", out).group(1))  # type: ignore[union-attr]
    assert n > 0
    assert (bag / "crash_0.mcap.damaged").exists()
    rc, out, err = inproc(capsys, "bag", "info", str(bag))
    assert rc == 0 and f"Messages:          {n}" in out
    got = numbers(bag)
    assert got == list(range(got[0], got[0] + n))  # no gaps up to the last flushed chunk


def test_record_info_play(router: str, prefix: str, talker: Proc, tmp_path: Path,
                          capsys: pytest.CaptureFixture[str]) -> None:
    bag = tmp_path / "run"
    rec = record(router, prefix, "-a", "-o", str(bag), "--exclude", "^/rosout$",
                 "--compression", "lz4")
    from zenros.session import SessionOptions

    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    try:
        assert ctx.graph.wait_for(lambda: any(
            t.name == "/chatter" and t.node.startswith("/zenros_bag_recorder")
            for t in ctx.graph.subscribers("/chatter")), 10)
        assert wait_for(lambda: (bag / "run_0.mcap").exists()
                        and (bag / "run_0.mcap").stat().st_size > 2000, 15)
    finally:
        assert rec.stop() == 0, rec.output
        ctx.close()
    assert re.search(r"Recorded \d+ messages on 1 topics", rec.output), rec.output
    rc, out, err = inproc(capsys, "bag", "info", str(bag))
    assert rc == 0, err
    assert "Compression:       lz4" in out
    assert re.search(r"Topic: /chatter \| Type: std_msgs/String \| Count: \d+", out)
    recorded = numbers(bag)
    talker.stop()
    from zenros.msgs.std_msgs import String
    from zenros.node import Node
    from zenros.testing import Collector

    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    node = Node("bag_listener", context=ctx)
    got: Collector[String] = Collector()
    try:
        node.create_subscription(String, "/chatter", got)
        r = zenros("bag", "play", str(bag), "--rate", "4", "-e", router, "--prefix", prefix)
        assert r.returncode == 0, r.stdout + r.stderr
        assert f"Played {len(recorded)} messages" in r.stdout
        assert got.wait(len(recorded), 10), len(got)
    finally:
        node.close()
        ctx.close()
    assert [int(m.data.split()[-1]) for m in got.items] == recorded


def test_launch_node_form(router: str, prefix: str, talker: Proc, tmp_path: Path) -> None:
    """`python -m zenros.bag` takes the node flags a launch file adds before the verb."""
    bag = tmp_path / "launched"
    p = Proc([sys.executable, "-m", "zenros.bag", "--name", "recorder", "--ns", "/tools",
              "-e", router, "--prefix", prefix, "record", "/chatter", "-o", str(bag)])
    from zenros.session import SessionOptions

    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    try:
        assert ctx.graph.wait_for_node("/tools/recorder", 15), p.output
        assert p.wait_line("Subscribed to topic '/chatter'", 15), p.output  # a first sample
    finally:
        ctx.close()
        assert p.stop() == 0, p.output
    assert numbers(bag)


def test_bad_arguments(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    r = zenros("bag", "record")  # one real process: the console script's exit code
    assert r.returncode == 1 and "give topics to record, or -a" in r.stderr
    rc, _, err = inproc(capsys, "bag", "play", str(tmp_path / "none"))
    assert rc == 1 and "no bag" in err
    (tmp_path / "taken").mkdir()
    (tmp_path / "taken" / "x").write_text("x")
    rc, _, err = inproc(capsys, "bag", "record", "-a", "-o", str(tmp_path / "taken"))
    assert rc == 1 and "already exists" in err
    rc, _, err = inproc(capsys, "bag", "record", "-a", "--compression", "gzip")
    assert rc == 2 and "invalid choice: 'gzip'" in err
    rc, _, err = inproc(capsys, "bag", "play", str(tmp_path / "taken"), "--rate", "0")
    assert rc == 1 and "no .mcap files" in err


def test_keyboard_pause_and_step(router: str, prefix: str, talker: Proc, tmp_path: Path) -> None:
    """Space pauses and resumes, `s` steps, when stdin is a terminal."""
    import os
    import pty

    from zenros.msgs.std_msgs import String
    from zenros.node import Node
    from zenros.session import SessionOptions
    from zenros.testing import Collector

    bag = tmp_path / "keys"
    rec = record(router, prefix, "/chatter", "-o", str(bag))
    assert wait_for(lambda: (bag / "keys_0.mcap").exists()
                    and (bag / "keys_0.mcap").stat().st_size > 3000, 15)
    assert rec.stop() == 0
    talker.stop()
    recorded = numbers(bag)
    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    node = Node("key_listener", context=ctx)
    got: Collector[String] = Collector()
    node.create_subscription(String, "/chatter", got)
    master, slave = pty.openpty()
    play = subprocess.Popen(
        [sys.executable, "-m", "zenros.cli", "bag", "play", str(bag), "--rate", "0.2",
         "-e", router, "--prefix", prefix],
        stdin=slave, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        start_new_session=True)
    os.close(slave)
    try:
        assert got.wait(1, 20)
        os.write(master, b" ")
        assert play.stdout is not None
        assert "Paused" in _read_until(play.stdout, "Paused")
        paused_at = len(got)
        for _ in range(3):
            os.write(master, b"s")
        assert got.wait(paused_at + 3, 10)
        assert len(got) < len(recorded)  # at 0.2x the rest takes seconds
        os.write(master, b" ")
        assert got.wait(len(recorded), 60), (len(got), len(recorded))
        assert play.wait(20) == 0
    finally:
        if play.poll() is None:
            play.kill()
            play.wait()
        if play.stdout is not None:
            play.stdout.close()
        os.close(master)
        node.close()
        ctx.close()
    assert [int(m.data.split()[-1]) for m in got.items] == recorded


def _read_until(stream: object, needle: str) -> str:
    lines = []
    for line in stream:  # type: ignore[attr-defined]
        lines.append(line)
        if needle in line:
            break
    return "".join(lines)
