"""The launch supervisor with real processes: output, logs, respawn, required, stop, exit codes."""

from __future__ import annotations

import asyncio
import io
import os
import re
import signal
import subprocess
import sys
import textwrap
import time
from collections.abc import AsyncIterator, Callable
from pathlib import Path
from typing import Any

import pytest
from zenros.launch.model import ProcessSpec
from zenros.launch.supervisor import Event, Supervisor, SupervisorConfig

pytestmark = pytest.mark.system


def py(code: str) -> tuple[str, ...]:
    return (sys.executable, "-c", textwrap.dedent(code))


IGNORE_SIGINT = """
    import signal, sys, time
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    print("ready", flush=True)
    while True:
        time.sleep(1)
"""
IGNORE_SIGINT_AND_SIGTERM = IGNORE_SIGINT.replace(
    "signal.SIG_IGN)", "signal.SIG_IGN)\n    signal.signal(signal.SIGTERM, signal.SIG_IGN)"
)
SLEEP = """
    import time
    print("ready", flush=True)
    time.sleep(300)
"""


class Screen(io.StringIO):
    """A captured screen that wakes waiters on every write."""

    def __init__(self, changed: asyncio.Event) -> None:
        super().__init__()
        self.changed = changed

    def write(self, s: str) -> int:
        n = super().write(s)
        self.changed.set()
        return n


class Harness:
    """One supervisor under test, with its events, screens and the task running it."""

    def __init__(self, specs: list[ProcessSpec], log_dir: Path, **config: Any) -> None:
        self.changed = asyncio.Event()
        self.events: list[tuple[float, Event]] = []
        self.screen, self.screen_err = Screen(self.changed), Screen(self.changed)
        self.sup = Supervisor(specs, SupervisorConfig(
            log_dir=log_dir, screen=self.screen, screen_err=self.screen_err,
            on_event=self._on_event, **config,
        ))
        self.task: asyncio.Task[int] | None = None

    def _on_event(self, event: Event) -> None:
        self.events.append((time.monotonic(), event))
        self.changed.set()

    def start(self) -> None:
        self.task = asyncio.create_task(self.sup.run())
        self.task.add_done_callback(lambda _: self.changed.set())

    async def result(self, timeout: float = 20) -> int:
        assert self.task is not None
        return await asyncio.wait_for(self.task, timeout)

    async def until(self, cond: Callable[[], bool], timeout: float = 10) -> None:
        """Wait for ``cond`` (re-checked on every output line and event)."""
        async def loop() -> None:
            while not cond():
                assert self.task is None or not self.task.done(), "the launch ended first"
                self.changed.clear()
                await self.changed.wait()
        await asyncio.wait_for(loop(), timeout)

    def kinds(self, label: str | None = None) -> list[str]:
        return [e.kind for _, e in self.events if label is None or e.label == label]

    def first(self, kind: str, label: str, nth: int = 0) -> tuple[float, Event]:
        return [(t, e) for t, e in self.events if e.kind == kind and e.label == label][nth]


@pytest.fixture
async def harness(tmp_path: Path) -> AsyncIterator[Callable[..., Harness]]:
    made: list[Harness] = []

    def make(specs: list[ProcessSpec], **config: Any) -> Harness:
        h = Harness(specs, tmp_path / "logs", **config)
        made.append(h)
        return h

    yield make
    for h in made:
        h.sup.kill_all()
        if h.task is not None and not h.task.done():
            h.task.cancel()
            await asyncio.gather(h.task, return_exceptions=True)


async def test_output_is_prefixed_and_logged(harness: Callable[..., Harness],
                                             tmp_path: Path) -> None:
    h = harness([
        ProcessSpec("talker", py("""
            import sys
            print("hello")
            print("to stderr", file=sys.stderr)
            sys.stdout.write("no newline")
        """), namespace="/r1"),
        ProcessSpec("quiet", py("print('only in the log')"), output="log"),
    ])
    h.start()
    assert await h.result() == 0
    out, err = h.screen.getvalue(), h.screen_err.getvalue()
    assert "[r1/talker] hello\n" in out and "[r1/talker] no newline\n" in out
    assert "[r1/talker] to stderr\n" in err
    assert "[quiet]" not in out + err
    logs = tmp_path / "logs"
    talker_log = (logs / "r1.talker.log").read_text()
    assert "hello\n" in talker_log and "to stderr" in talker_log and "exited with code 0" in talker_log
    assert "only in the log" in (logs / "quiet.log").read_text()
    assert "started r1/talker" in (logs / "launch.log").read_text()
    assert "[launch] started r1/talker (pid" in err


async def test_crashed_process_is_respawned_within_3_s(harness: Callable[..., Harness],
                                                     tmp_path: Path) -> None:
    marker = tmp_path / "crashed-once"
    h = harness([ProcessSpec("flaky", py(f"""
        import pathlib, sys, time
        marker = pathlib.Path({str(marker)!r})
        print("up", flush=True)
        if not marker.exists():
            marker.touch()
            sys.exit(1)
        time.sleep(300)
    """), respawn=True)])
    h.start()
    await h.until(lambda: h.kinds("flaky").count("start") == 2)
    t_exit, exit_event = h.first("exit", "flaky")
    t_back, _ = h.first("start", "flaky", 1)
    assert exit_event.returncode == 1
    assert t_back - t_exit < 3.0
    await h.until(lambda: h.screen.getvalue().count("[flaky] up") == 2)
    h.sup.stop()
    assert await h.result() == 0  # the last run ended by our SIGINT: clean
    assert h.sup.states["flaky"].starts == 2


async def test_respawn_delay_is_honoured(harness: Callable[..., Harness]) -> None:
    h = harness([ProcessSpec("blip", py("pass"), respawn=True, respawn_delay=0.3)],
                crash_delay=0.0)
    h.start()
    await h.until(lambda: h.kinds("blip").count("start") >= 3)
    starts = [t for t, e in h.events if e.kind == "start"]
    exits = [t for t, e in h.events if e.kind == "exit"]
    assert all(b - a >= 0.3 for a, b in zip(exits, starts[1:], strict=False))
    h.sup.stop()
    await h.result()  # 0, or 1 if the SIGINT caught a run still starting up


@pytest.mark.parametrize(("code", "expected"), [(0, 0), (4, 1)])
async def test_required_exit_stops_everything(harness: Callable[..., Harness], tmp_path: Path,
                                             code: int, expected: int) -> None:
    marker = tmp_path / "worker-up"
    h = harness([
        ProcessSpec("worker", py(f"""
            import pathlib, time
            pathlib.Path({str(marker)!r}).touch()
            time.sleep(300)
        """)),
        ProcessSpec("boss", py(f"""
            import pathlib, sys, time
            while not pathlib.Path({str(marker)!r}).exists():  # SIGINT in startup is not clean
                time.sleep(0.01)
            print("done", flush=True)
            sys.exit({code})
        """), required=True),
    ])
    h.start()
    assert await h.result() == expected
    assert h.first("exit", "worker")[1].returncode == -signal.SIGINT
    assert h.sup.states["worker"].stop_signal == signal.SIGINT
    assert any("required process boss ended" in e.detail for _, e in h.events)


async def test_sigint_ignored_escalates_to_sigterm(harness: Callable[..., Harness]) -> None:
    h = harness([ProcessSpec("stubborn", py(IGNORE_SIGINT))],
                sigterm_timeout=0.5, sigkill_timeout=5)
    h.start()
    await h.until(lambda: "[stubborn] ready" in h.screen.getvalue())
    t0 = time.monotonic()
    h.sup.stop()
    assert await h.result() == 1  # it needed SIGTERM: not a clean end
    assert time.monotonic() - t0 < 5
    sent = [e.detail for _, e in h.events if e.kind == "signal"]
    assert sent == ["SIGINT", "SIGTERM"]
    assert h.first("exit", "stubborn")[1].returncode == -signal.SIGTERM


async def test_sigterm_ignored_escalates_to_sigkill(harness: Callable[..., Harness]) -> None:
    h = harness([ProcessSpec("mule", py(IGNORE_SIGINT_AND_SIGTERM))],
                sigterm_timeout=0.3, sigkill_timeout=0.3)
    h.start()
    await h.until(lambda: "[mule] ready" in h.screen.getvalue())
    h.sup.stop()
    assert await h.result() == 1
    assert [e.detail for _, e in h.events if e.kind == "signal"] == ["SIGINT", "SIGTERM", "SIGKILL"]
    assert h.first("exit", "mule")[1].returncode == -signal.SIGKILL


async def test_second_stop_skips_the_wait(harness: Callable[..., Harness]) -> None:
    h = harness([ProcessSpec("stubborn", py(IGNORE_SIGINT))],
                sigterm_timeout=60, sigkill_timeout=60)
    h.start()
    await h.until(lambda: "[stubborn] ready" in h.screen.getvalue())
    h.sup.stop()
    await h.until(lambda: "signal" in h.kinds())
    t0 = time.monotonic()
    h.sup.stop()  # the second Ctrl-C
    assert await h.result() == 1
    assert time.monotonic() - t0 < 5


async def test_stop_last_processes_get_sigint_after_the_others_ended(
    harness: Callable[..., Harness],
) -> None:
    """master-like processes outlive the nodes that use them, so no node reports them gone."""
    h = harness([ProcessSpec("base", py(SLEEP)), ProcessSpec("user", py(SLEEP)),
                 ProcessSpec("other", py(SLEEP))],
                stop_last=lambda spec: spec.name == "base")
    h.start()
    await h.until(lambda: all(f"[{n}] ready" in h.screen.getvalue()
                              for n in ("base", "user", "other")))
    h.sup.stop()
    assert await h.result() == 0
    base_signal = h.first("signal", "base")[0]
    assert all(h.first("exit", n)[0] <= base_signal for n in ("user", "other"))
    assert [e.detail for _, e in h.events if e.kind == "signal" and e.label == "base"] == \
        ["SIGINT"]


class ClosedScreen(io.StringIO):
    """A terminal that went away: every write fails as on a closed pipe."""

    def write(self, s: str) -> int:
        raise BrokenPipeError(32, "Broken pipe")


async def test_a_closed_screen_does_not_stop_supervision(tmp_path: Path) -> None:
    """With stdout and stderr gone (the reader of a pipe died), output still reaches the log
    files and a stop still stops everything."""
    sup = Supervisor([ProcessSpec("chatty", py("import time\nfor i in range(3):\n"
                                               "    print('line', i, flush=True)\n"
                                               "time.sleep(300)"))],
                     SupervisorConfig(log_dir=tmp_path, screen=ClosedScreen(),
                                      screen_err=ClosedScreen()))
    task = asyncio.create_task(sup.run())
    log = tmp_path / "chatty.log"
    deadline = time.monotonic() + 20
    while "line 2" not in (log.read_text() if log.exists() else ""):
        assert time.monotonic() < deadline and not task.done()
        await asyncio.sleep(0.05)
    sup.stop()
    assert await asyncio.wait_for(task, 20) == 0
    assert "launch finished with exit code 0" in (tmp_path / "launch.log").read_text()


async def test_clean_exits_and_failures(harness: Callable[..., Harness]) -> None:
    ok = harness([ProcessSpec("a", py("pass")), ProcessSpec("b", py("print(1)"))])
    ok.start()
    assert await ok.result() == 0
    bad = harness([ProcessSpec("a", py("pass")), ProcessSpec("b", py("raise SystemExit(3)"))])
    bad.start()
    assert await bad.result() == 1


async def test_a_process_that_cannot_start_stops_the_launch(
    harness: Callable[..., Harness]
) -> None:
    h = harness([
        ProcessSpec("first", py(SLEEP)),
        ProcessSpec("ghost", ("/nonexistent/program",)),
        ProcessSpec("never", py(SLEEP)),
    ])
    h.start()
    assert await h.result() == 3
    assert "cannot start ghost" in h.screen_err.getvalue()
    assert h.first("exit", "first")[1].returncode is not None  # stopped, maybe mid-startup
    # asked with SIGINT first. A SIGINT that lands while the interpreter is still starting
    # (before Python's own handler is in place) can be lost, as with any Python program;
    # then SIGTERM follows after the timeout, as it should.
    seen = [(round(t, 3), e.kind, e.detail, e.returncode) for t, e in h.events
            if e.label == "first"]
    assert h.first("signal", "first")[1].detail == "SIGINT", seen
    assert h.sup.states["never"].starts == 0


CONFIG_FAILURE = """
    import sys
    print("chassis: startup failed: parameter 'map': no such file", file=sys.stderr)
    sys.exit(3)
"""
CRASH = """
    import sys
    print("starting", flush=True)
    raise ModuleNotFoundError("No module named 'websockets'")
"""


def _lines(screen: str, label: str) -> str:
    """The process's own lines of a screen (the launcher's start line echoes its code)."""
    return "".join(ln for ln in screen.splitlines(keepends=True) if ln.startswith(f"[{label}] "))


async def test_a_configuration_failure_is_not_restarted(harness: Callable[..., Harness]) -> None:
    """Exit code 3 (startup failed: its configuration) stops that process for good, with its
    error on the terminal once; the rest of the launch goes on."""
    h = harness([ProcessSpec("chassis", py(CONFIG_FAILURE), respawn=True),
                 ProcessSpec("other", py(SLEEP))])
    h.start()
    await h.until(lambda: "startup_failed" in h.kinds("chassis"))
    await h.until(lambda: "[other] ready" in h.screen.getvalue())
    await asyncio.sleep(1.5)  # past the 1 s respawn of a quick exit: nothing comes back
    assert h.kinds("chassis").count("start") == 1
    err = _lines(h.screen_err.getvalue(), "chassis")
    assert err.count("startup failed: parameter 'map'") == 1, err
    line = h.first("startup_failed", "chassis")[1].detail
    assert "chassis could not start" in line and "not restarting it" in line
    h.sup.stop()
    assert await h.result() == 1  # chassis did not end cleanly


async def test_a_required_configuration_failure_stops_the_launch(
    harness: Callable[..., Harness]
) -> None:
    h = harness([ProcessSpec("other", py(SLEEP)),
                 ProcessSpec("chassis", py(CONFIG_FAILURE), respawn=True, required=True)])
    h.start()
    assert await h.result() == 3
    assert h.kinds("chassis").count("start") == 1
    stops = [e.detail for _, e in h.events if e.kind == "stop"]
    assert any("required process chassis could not start (exit code 3, its error is above)"
               in d for d in stops), stops
    assert _lines(h.screen_err.getvalue(), "chassis").count("startup failed: parameter 'map'") == 1


async def test_a_crash_loop_backs_off_and_gives_up(harness: Callable[..., Harness]) -> None:
    h = harness([ProcessSpec("gateway", py(CRASH), respawn=True)],
                crash_delay=0.2, crash_limit=4, crash_window=5.0)
    h.start()
    await h.until(lambda: "gave_up" in h.kinds("gateway"), 20)
    await asyncio.sleep(0.5)
    assert h.kinds("gateway").count("start") == 4
    exits = [t for t, e in h.events if e.kind == "exit"]
    starts = [t for t, e in h.events if e.kind == "start"]
    waits = [b - a for a, b in zip(exits, starts[1:], strict=False)]
    assert len(waits) == 3
    assert waits[1] >= 0.2 and waits[2] >= 0.4, waits  # doubling from the second failure
    gave_up = [e.detail for _, e in h.events if e.kind == "gave_up"]
    assert gave_up == [("gateway failed 4 times in a row, each within 5 s of starting; not "
                        "restarting it. Last error: ModuleNotFoundError: No module named "
                        "'websockets'")], gave_up
    assert h.screen_err.getvalue().count("[launch] gateway failed 4 times") == 1
    assert await h.result() == 1  # nothing left to run: the launch ends


async def test_a_required_crash_loop_stops_the_launch(harness: Callable[..., Harness]) -> None:
    h = harness([ProcessSpec("other", py(SLEEP)),
                 ProcessSpec("gateway", py(CRASH), respawn=True, required=True)],
                crash_delay=0.05, crash_limit=3)
    h.start()
    assert await h.result() == 1
    assert h.kinds("gateway").count("start") == 3
    assert any("required process gateway keeps failing" in e.detail
               for _, e in h.events if e.kind == "stop")


async def test_a_run_that_lasts_resets_the_crash_count(harness: Callable[..., Harness],
                                                     tmp_path: Path) -> None:
    """Only quick failures in a row count: a process that ran a while is restarted again."""
    count = tmp_path / "runs"
    h = harness([ProcessSpec("flaky", py(f"""
        import pathlib, sys, time
        f = pathlib.Path({str(count)!r})
        n = int(f.read_text()) if f.exists() else 0
        f.write_text(str(n + 1))
        time.sleep(0.6 if n % 2 else 0)  # every other run lasts past the crash window
        sys.exit(1)
    """), respawn=True)], crash_delay=0.05, crash_limit=2, crash_window=0.5)
    h.start()
    await h.until(lambda: h.kinds("flaky").count("start") >= 6, 20)
    assert "gave_up" not in h.kinds("flaky")
    h.sup.stop()
    await h.result()


async def test_a_quiet_screen_keeps_info_chatter_in_the_log(harness: Callable[..., Harness],
                                                          tmp_path: Path) -> None:
    h = harness([ProcessSpec("listener", py("""
        import sys
        for i in range(50):
            print(f"[INFO] [1764770000.{i:03d}] [/listener]: I heard: [hello world {i}]")
        print("[DEBUG] [1764770000.100] [/listener]: details")
        print("[WARNING] [1764770000.200] [/listener]: odd message", file=sys.stderr)
        print("[ERROR] [1764770000.300] [/listener]: bad message", file=sys.stderr)
        print("a plain print")
        print("[INFO] [1764770000.400] [/listener]: on stderr", file=sys.stderr)
    """))], quiet=True)
    h.start()
    assert await h.result() == 0
    screen = _lines(h.screen.getvalue() + h.screen_err.getvalue(), "listener")
    assert "I heard" not in screen and "details" not in screen and "on stderr" not in screen
    assert "[listener] [WARNING] [1764770000.200] [/listener]: odd message" in screen
    assert "[listener] [ERROR] [1764770000.300] [/listener]: bad message" in screen
    assert "[listener] a plain print" in screen
    assert "[launch] started listener" in h.screen_err.getvalue()
    log = (tmp_path / "logs" / "listener.log").read_text()
    assert len(re.findall(r"I heard: \[hello world \d+\]", log)) == 50
    assert "]: details" in log and "]: on stderr" in log


async def test_hooks_before_start_and_wait_ready(harness: Callable[..., Harness]) -> None:
    calls: list[str] = []

    async def before_start(spec: ProcessSpec) -> ProcessSpec:
        calls.append(spec.name)
        return ProcessSpec(spec.name, spec.cmd, env={**spec.env, "ZR_HOOK": "injected"})

    late = asyncio.Event()  # "slow" is ready once this is set

    def wait_ready(spec: ProcessSpec) -> bool:
        ready: bool = spec.name == "good" or late.is_set()
        return ready

    code = "import os; print(os.environ['ZR_HOOK'], flush=True); import time; time.sleep(300)"
    h = harness([ProcessSpec("good", py(code)), ProcessSpec("slow", py(code))],
                before_start=before_start, wait_ready=wait_ready)
    h.start()
    await h.until(lambda: {"ready", "not_ready"} <= set(h.kinds()))
    await h.until(lambda: h.screen.getvalue().count("injected") == 2)
    assert calls == ["good", "slow"]
    assert h.sup.states["good"].ready is True and h.sup.states["slow"].ready is False
    assert "[launch] slow did not become ready; still watching for it" in \
        h.screen_err.getvalue() + h.screen.getvalue()
    late.set()  # a slow node's readiness is still reported, with how long it took
    await h.until(lambda: h.sup.states["slow"].ready is True)
    assert re.search(r"\[launch\] slow is ready \(\d+ s after its start\)",
                     h.screen_err.getvalue() + h.screen.getvalue())
    assert h.kinds().count("not_ready") == 1
    h.sup.stop()
    assert await h.result() == 0


async def test_process_groups_are_stopped_whole(harness: Callable[..., Harness]) -> None:
    h = harness([ProcessSpec("parent", py("""
        import subprocess, time
        child = subprocess.Popen(["sleep", "300"])
        print("child", child.pid, flush=True)
        child.wait()
    """))])
    h.start()
    await h.until(lambda: "[parent] child " in h.screen.getvalue())
    found = re.search(r"\[parent\] child (\d+)", h.screen.getvalue())
    assert found is not None
    pid = int(found.group(1))
    h.sup.stop()
    await h.result()
    await asyncio.wait_for(_gone(pid), 5)


async def _gone(pid: int) -> None:
    while True:
        try:
            state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except FileNotFoundError:
            return
        if state in ("Z", "X"):
            return
        await asyncio.sleep(0.05)


# ------------------------------------------------------------------ the command line


def _launch_pids(run_dir: Path) -> list[int]:
    log = run_dir / "launch.log"
    return [int(p) for p in re.findall(r"\(pid (\d+)\)", log.read_text())] if log.exists() else []


def test_cli_runs_and_stops_on_ctrl_c(tmp_path: Path) -> None:
    launch = tmp_path / "demo.yaml"
    launch.write_text(textwrap.dedent(f"""
        args: {{word: hi}}
        nodes:
          - name: talker
            cmd: [{sys.executable!r}, -c, "import time; print('$(arg word)', flush=True); time.sleep(300)"]
          - name: once
            cmd: [echo, done]
    """))
    data = tmp_path / "data"
    # --sigterm-timeout: a bound for the talker's exit on SIGINT (a loaded suite once took
    # longer than the default, and the launch then ended it with SIGTERM and exit code 1)
    argv = [sys.executable, "-m", "zenros.launch", str(launch), "word:=hello", "--data-dir",
            str(data), "--no-router", "--sigterm-timeout", "15"]
    with subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as proc:
        try:
            assert proc.stdout is not None
            lines = []
            for line in proc.stdout:  # both ran (on a loaded box `once` may come second)
                lines.append(line)
                if {"[talker] hello\n", "[once] done\n"} <= set(lines):
                    break
            proc.send_signal(signal.SIGINT)
            _out, err = proc.communicate(timeout=40)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
            for pid in _launch_pids(data / "logs" / "latest"):
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
    assert proc.returncode == 0, err
    assert "[once] done\n" in lines
    assert "received SIGINT" in err and "sent SIGINT to talker" in err
    latest = data / "logs" / "latest"
    assert "hello" in (latest / "talker.log").read_text()
    assert (latest / "once.log").exists() and (latest / "launch.log").exists()


def test_cli_exit_codes_for_bad_input(tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("nodes: [{cmd: a, respawn: maybe}]\n")

    def run(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run([sys.executable, "-m", "zenros.launch", *args],
                              check=False, capture_output=True, text=True, timeout=30)

    r = run(str(bad), "--data-dir", str(tmp_path))
    assert r.returncode == 3 and "respawn: expected true or false" in r.stderr
    r = run(str(bad), "oops", "--data-dir", str(tmp_path))
    assert r.returncode == 2 and "name:=value" in r.stderr
    r = run(str(tmp_path / "missing.yaml"))
    assert r.returncode == 3 and "launch file not found" in r.stderr
