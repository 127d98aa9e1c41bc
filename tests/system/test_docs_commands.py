"""Every shell command of README.md and docs/*.md works as written against a launched sim.

`zenros launch deploy/launch/sim.yaml` runs in a temporary ZENROS_HOME with its own key
prefix and router port; the gateway's fixed ports (REST 3546, topic WebSocket 3547, Modbus
3551, rosbridge 9090) are moved to free ones by storing them on master before the launch, and
the commands' ``127.0.0.1:<default port>`` are rewritten to match. Each command runs in bash
from a scratch directory of its page's own that links the repository's top-level entries (so
files it writes stay out of the tree and out of other pages' way); ``zenros launch
deploy/launch/sim.yaml`` lines are the sim itself and are not run again. Pages are checked
side by side (three at a time), each page's blocks in order; the blocks that drive the robot
one at a time, in the pages' order (`DriveTurns`). A command passes when it exits 0, or, for a
streaming one, when it was
still running GRACE seconds after it first printed on stdout. Blocks and lines that cannot
run against the sim are marked in the page (see docs_commands.py for the markers); blocks
marked ``doc-check: fleet`` run against `deploy/launch/fleet.yaml robots:=3` (its gateway's
ports moved to free ones the same way), launched when the first of them comes.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import IO

import pytest
from docs_commands import Block, Command, doc_blocks, doc_pages
from zenros.testing import Proc, free_port, store_on_master, unique_prefix, wait_for

# a whole sim and a three-robot fleet: never beside the other whole sims (the ten-robot fleet
# missed a node's token for 60 s with this module's sim and fleet running beside it in CI)
pytestmark = [pytest.mark.system, pytest.mark.xdist_group("sim")]

ROOT = Path(__file__).resolve().parents[2]
GRACE = 1.5  # a command still running this long after its first output is a streaming one
COMMAND_LIMIT = 45.0  # a command that neither ends nor prints fails after this long
LAUNCHED = "zenros launch deploy/launch/sim.yaml"  # what the check runs: not run again
GATEWAY_PORTS = {"rest_port": 3546, "ws_port": 3547, "modbus_port": 3551, "rosbridge_port": 9090}
PAGES = [p for p in doc_pages(ROOT) if any(b.commands for b in doc_blocks(p, ROOT))]
# Commands that move the robot: nav goals (each preempts the running one), tasks, REST
# navigation, cmd_vel; and those that change how nav drives (its parameters, walls, maps, the
# speed limits). Blocks with one run one at a time (see `results`).
DRIVES = re.compile(r"send_goal\s+/?(?!fibonacci)\w|/navigation/|move_to_index|/tasks?\b|tasks/"
                    r"|patrol|navigate|local_move|/teleport|cmd_vel|dock"
                    r"|start_\w*(task|move|patrol|charge|dock)"
                    r"|param set /nav/|virtual_walls|import_map|system/speed|system/config")
FLEET_ROBOTS = 3  # the fleet `doc-check: fleet` blocks run against
WORKERS = 3  # pages side by side; their driving blocks still take turns (DriveTurns)


class DriveTurns:
    """The blocks that drive the robot take turns, one at a time in the pages' order, while
    the other blocks run beside them: a page may leave a task of its own running that a
    later page's goal meets (tasks.md's before gateway.md's: a 409), and one nav goal
    preempts another. A key is (page index, block index); a page ending releases its keys
    not yet taken, so a page that failed early never holds the others up."""

    def __init__(self, keys: list[tuple[int, int]]) -> None:
        self._keys = keys
        self._done: set[tuple[int, int]] = set()
        self._cond = threading.Condition()

    def _first_pending(self) -> tuple[int, int] | None:
        return next((k for k in self._keys if k not in self._done), None)

    @contextmanager
    def turn(self, key: tuple[int, int]) -> Iterator[None]:
        with self._cond:
            self._cond.wait_for(lambda: self._first_pending() == key)
        try:
            yield
        finally:
            self.release([key])

    def release(self, keys: list[tuple[int, int]]) -> None:
        with self._cond:
            self._done.update(keys)
            self._cond.notify_all()


@dataclass
class Sim:
    env: dict[str, str]
    workdir: Path
    ports: dict[int, int]  # documented default port -> this sim's


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Sim]:
    home = tmp_path_factory.mktemp("home")
    workdir = tmp_path_factory.mktemp("work")
    for entry in ROOT.iterdir():
        if not entry.name.startswith("."):
            (workdir / entry.name).symlink_to(entry)
    endpoint, prefix = f"tcp/127.0.0.1:{free_port()}", unique_prefix()
    env = {**os.environ, "ZENROS_HOME": str(home), "ZENROS_PREFIX": prefix,
           "ZENROS_CONNECT": endpoint,
           "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"}
    ports = {name: free_port() for name in GATEWAY_PORTS}
    # stored before the launch: nodes read stored values over their launch file's
    store_on_master(env["ZENROS_HOME"], env["ZENROS_PREFIX"],
                    {f"/gateway/{k}": v for k, v in ports.items()} | {"/gateway/discovery_port": -1})
    proc = Proc([sys.executable, "-m", "zenros.cli", "launch",
                 str(ROOT / "deploy" / "launch" / "sim.yaml")],
                env={k: env[k] for k in ("ZENROS_HOME", "ZENROS_PREFIX", "ZENROS_CONNECT")})
    try:
        assert _all_ready(proc, 90), proc.output
        yield Sim(env, workdir, {GATEWAY_PORTS[k]: v for k, v in ports.items()})
    finally:
        proc.stop(timeout=30)


class Fleet:
    """`deploy/launch/fleet.yaml robots:=3`, its gateway on free ports, in a ZENROS_HOME,
    prefix and router of its own: launched by the first ``doc-check: fleet`` block (`get`),
    stopped with the check (`stop`)."""

    def __init__(self, base: Sim, home: Path) -> None:
        self.base, self.home = base, home
        self.sim: Sim | None = None
        self.proc: Proc | None = None
        self.failed: str | None = None  # why the one launch did not come up
        self._lock = threading.Lock()

    def get(self) -> Sim:
        """The launched fleet, every robot served by its gateway.

        Raises:
            RuntimeError: the fleet did not come up (with the launch's output).
        """
        with self._lock:
            if self.failed is not None:  # one launch only: a second would meet the first's
                raise RuntimeError(self.failed)  # database and ports (a cascade, not a cause)
            if self.sim is None:
                try:
                    self.sim = self._launch()
                except RuntimeError as exc:
                    self.failed = str(exc)
                    self.stop()
                    raise
            return self.sim

    def _launch(self) -> Sim:
        ports = {name: free_port() for name in GATEWAY_PORTS}
        env = {**self.base.env, "ZENROS_HOME": str(self.home), "ZENROS_PREFIX": unique_prefix(),
               "ZENROS_CONNECT": f"tcp/127.0.0.1:{free_port()}"}
        self.proc = Proc([sys.executable, "-m", "zenros.cli", "launch",
                          str(ROOT / "deploy" / "launch" / "fleet.yaml"),
                          f"robots:={FLEET_ROBOTS}", f"data:={self.home}",
                          *(f"{k}:={v}" for k, v in ports.items())],
                         env={k: env[k] for k in ("ZENROS_HOME", "ZENROS_PREFIX",
                                                  "ZENROS_CONNECT")})
        lines = ["gateway is ready", *(f"robot{k}/robot is ready"
                                       for k in range(1, FLEET_ROBOTS + 1))]
        config = f"http://127.0.0.1:{ports['rest_port']}/config.json"
        if not (all(self.proc.wait_line(line, 240) for line in lines) and wait_for(
                lambda: len(_robots_served(config)) == FLEET_ROBOTS, 60)):
            raise RuntimeError(f"the fleet did not come up:\n{self.proc.output[-3000:]}")
        return Sim(env, self.base.workdir, {GATEWAY_PORTS[k]: v for k, v in ports.items()})

    def stop(self) -> None:
        if self.proc is not None:
            self.proc.stop(timeout=60)


def _robots_served(config_url: str) -> list[str]:
    """The robots a fleet gateway serves now (its dashboard's config.json), [] if it does
    not answer."""
    import httpx

    try:
        robots: list[str] = httpx.get(config_url, timeout=5).json().get("robots", [])
    except (httpx.HTTPError, ValueError):
        return []
    return robots


def _all_ready(proc: Proc, timeout: float) -> bool:
    """Every process the launch started is reported ready."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        out = proc.output
        started = set(re.findall(r"\[launch\] started (\S+) \(pid", out))
        ready = set(re.findall(r"\[launch\] (\S+) is ready", out))
        if started and "gateway" in started and started <= ready:
            return True
        if proc.popen.poll() is not None:
            return False
        time.sleep(0.2)
    return False


def _on_sim_ports(text: str, sim: Sim) -> str:
    """``text`` with the gateway's default ports (127.0.0.1:3546, ...) made the sim's."""
    for default, port in sim.ports.items():
        text = re.sub(rf"(127\.0\.0\.1|localhost):{default}\b", rf"\g<1>:{port}", text)
    return text


def _run(cmd: Command, sim: Sim, cwd: Path, env: dict[str, str]) -> str | None:
    """None when the command worked, else why not (with its output).

    It worked if it exited 0; or if it printed on stdout and was still running GRACE seconds
    later (a streaming command: echo, hz, pub -r, tf echo), when it is stopped with SIGINT.
    Either way it must not print a DeprecationWarning: a reader copying it would meet one
    (docs/fleet.md's websockets one-liners did, issue 37.11).
    """
    text = _on_sim_ports(cmd.text, sim)
    p = subprocess.Popen(["bash", "-c", text], cwd=cwd, env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         start_new_session=True)
    out: list[str] = []
    err: list[str] = []
    readers = [threading.Thread(target=_drain, args=(f, sink), daemon=True)
               for f, sink in ((p.stdout, out), (p.stderr, err))]
    for r in readers:
        r.start()
    deadline = time.monotonic() + COMMAND_LIMIT
    first_output: float | None = None
    streaming = False
    while p.poll() is None:
        now = time.monotonic()
        if first_output is None and out:
            first_output = now
        if first_output is not None and now - first_output >= GRACE or now >= deadline:
            streaming = first_output is not None
            _stop(p)
            break
        time.sleep(0.05)
    for r in readers:
        r.join(5)
    for f in (p.stdout, p.stderr):
        if f is not None:
            f.close()
    warned = "DeprecationWarning" in "".join(err)
    if (streaming or p.returncode == 0) and not warned:
        return None
    how = ("printed a DeprecationWarning" if warned
           else f"neither ended nor printed in {COMMAND_LIMIT:g} s" if p.returncode is None
           or p.returncode < 0 else f"exit {p.returncode}")
    return (f"{cmd.where}: `{cmd.text}`: {how}\n  stdout: {''.join(out)[-600:]!r}\n"
            f"  stderr: {''.join(err)[-600:]!r}")


def _drain(stream: IO[str] | None, sink: list[str]) -> None:
    assert stream is not None
    for line in stream:
        sink.append(line)  # noqa: PERF402 -- one at a time: _run watches the list grow


def _stop(p: subprocess.Popen[str]) -> None:
    """SIGINT to the command's process group (Ctrl-C), then SIGKILL."""
    try:
        os.killpg(p.pid, signal.SIGINT)
        p.wait(10)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.wait(5)
    except ProcessLookupError:
        p.wait(5)


_CD = re.compile(r"^cd\s+(\S+)$")
# NAME=VALUE alone on its line (VALUE one word, a quoted string or a $(...)); a line that
# goes on with a command after the value (``NAME=VALUE cmd ...``) is a command
_ASSIGN = re.compile(r"""^([A-Za-z_][A-Za-z0-9_]*)=(\$\(.*\)|"[^"]*"|'[^']*'|\S+)$""")


def _run_block(block: Block, sim: Sim, workdir: Path) -> list[str]:
    """The block's commands in order, as one shell session would run them: a ``cd DIR`` line
    moves the later ones, a ``NAME=VALUE`` line (``id=$(...)``) sets a variable for them."""
    failures: list[str] = []
    cwd, env = workdir, dict(sim.env)
    for cmd in block.runnable():
        if cmd.text.startswith(LAUNCHED):
            continue  # the sim the check runs against
        if m := _CD.match(cmd.text):
            cwd = (cwd / m.group(1)).resolve()
            continue
        if m := _ASSIGN.match(cmd.text):
            try:
                r = subprocess.run(["bash", "-c",
                                    f'{_on_sim_ports(cmd.text, sim)}\nprintf %s "${m.group(1)}"'],
                                   cwd=cwd, env=env, capture_output=True, text=True,
                                   timeout=COMMAND_LIMIT, check=False)
            except subprocess.TimeoutExpired:
                failures.append(f"{cmd.where}: `{cmd.text}`: no value in {COMMAND_LIMIT:g} s")
                return failures
            if r.returncode != 0 or not r.stdout:
                failures.append(f"{cmd.where}: `{cmd.text}`: exit {r.returncode}, value "
                                f"{r.stdout!r}\n  stderr: {r.stderr[-600:]!r}")
                return failures  # later lines need the value
            env[m.group(1)] = r.stdout
            continue
        start = time.monotonic()
        why = _run(cmd, sim, cwd, env)
        print(f"{time.monotonic() - start:5.1f} s  {cmd.where}  {cmd.text[:70]}", flush=True)
        if why is not None:
            failures.append(why)
    return failures


def _runnable_blocks(page: Path) -> list[Block]:
    return [b for b in doc_blocks(page, ROOT) if b.runnable()]


def _run_page(index: int, page: Path, sim: Sim, turns: DriveTurns, fleet: Fleet
              ) -> list[str] | None:
    """The failures of one page's blocks (in order, in a scratch folder of the page's own, so
    a file a block writes is there for the page's later blocks only); None if nothing of it
    is runnable. A block that drives the robot waits for its turn (``turns``, keyed by the
    page's ``index`` and the block's); a ``doc-check: fleet`` block runs against ``fleet``."""
    blocks = _runnable_blocks(page)
    if not blocks:
        return None
    try:
        return _run_blocks(index, blocks, page, sim, turns, fleet)
    finally:
        turns.release([(index, i) for i, b in enumerate(blocks) if _drives(b)])


def _run_blocks(index: int, blocks: list[Block], page: Path, sim: Sim, turns: DriveTurns,
                fleet: Fleet) -> list[str]:
    workdir = sim.workdir / "pages" / page.relative_to(ROOT).as_posix().replace("/", "_")
    workdir.mkdir(parents=True)
    for entry in sim.workdir.iterdir():
        if entry.name != "pages":
            (workdir / entry.name).symlink_to(entry.resolve())
    failures: list[str] = []
    for i, b in enumerate(blocks):
        if b.fleet:
            try:
                failures += _run_block(b, fleet.get(), workdir)
            except RuntimeError as exc:
                failures.append(f"{b.page}:{b.line}: {exc}")
        elif _drives(b):
            with turns.turn((index, i)):
                failures += _run_block(b, sim, workdir)
        else:
            failures += _run_block(b, sim, workdir)
    return failures


def _drives(block: Block) -> bool:
    """True if a command of the block moves the robot (a nav goal, a task, cmd_vel) or
    changes how nav drives (a bag recorder only listens, whatever topics it names)."""
    return any(DRIVES.search(c.text) for c in block.runnable()
               if not c.text.startswith("zenros bag record"))


def _selected_pages(request: pytest.FixtureRequest) -> list[Path]:
    """The pages whose test this session runs, in `PAGES` order (``-k README`` checks the
    README alone)."""
    chosen = {item.callspec.params["page"] for item in request.session.items
              if item.module is request.module and hasattr(item, "callspec")
              and "page" in item.callspec.params}
    return [p for p in PAGES if p in chosen]


@pytest.fixture(scope="module")
def results(sim: Sim, tmp_path_factory: pytest.TempPathFactory, request: pytest.FixtureRequest
            ) -> Iterator[dict[Path, list[str] | None]]:
    """Every selected page checked (each page's blocks in order), pages side by side; blocks
    that drive the robot one at a time in the pages' order, since one nav goal preempts
    another (a page's patrol ended "preempted by a new goal" when another page's goal came,
    under a CPU hog). The pool starts pages in their order, so the page whose turn is next is
    always running: none waits on a page not started."""
    pages = _selected_pages(request)
    turns = DriveTurns([(i, j) for i, page in enumerate(pages)
                        for j, b in enumerate(_runnable_blocks(page)) if _drives(b)])
    fleet = Fleet(sim, tmp_path_factory.mktemp("fleet"))
    try:
        with ThreadPoolExecutor(max_workers=WORKERS) as pool:
            yield dict(zip(pages, pool.map(lambda ip: _run_page(*ip, sim, turns, fleet),
                                           enumerate(pages)), strict=True))
    finally:
        fleet.stop()


@pytest.mark.timeout(600)
@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_every_command_of_the_page_works(page: Path, results: dict[Path, list[str] | None]
                                         ) -> None:
    failures = results[page]
    if failures is None:
        pytest.skip("every shell block of the page is marked doc-check: skip")
    assert not failures, "\n".join(failures)


def test_the_markers_are_read(tmp_path: Path) -> None:
    page = tmp_path / "docs" / "page.md"
    page.parent.mkdir()
    page.write_text(
        "text\n\n<!-- doc-check: skip needs a robot -->\n```bash\nzenros robot go\n```\n\n"
        "<!-- doc-check: skip-line zenros router -->\n\n```sh\n# a comment\n"
        "zenros router\nzenros topic echo /x \\\n  --once\n$ zenros node list\n```\n"
        "```python\nprint(1)\n```\n"
        "<!-- doc-check: fleet -->\n```bash\ncurl -sf http://127.0.0.1:3546/api/v1/robots\n```\n"
    )
    first, second, third = doc_blocks(page, tmp_path)
    assert first.skip == "needs a robot" and first.runnable() == []
    assert not first.fleet and not second.fleet and third.fleet
    assert [c.text for c in third.runnable()] == ["curl -sf http://127.0.0.1:3546/api/v1/robots"]
    assert [c.text for c in second.runnable()] == ["zenros topic echo /x --once",
                                                   "zenros node list"]
    assert second.runnable()[0].where == "docs/page.md:13"


_CURL_FAIL = re.compile(r"\bcurl\s+(?:\S+\s+)*?-[a-zA-Z]*f[a-zA-Z]*\b")


def test_no_curl_command_hides_the_error_body() -> None:
    """``curl -f`` (``-sf``) prints nothing when the gateway answers an error, hiding why (a
    stale token's 401 says "invalid token"): the pages use ``--fail-with-body`` or ``-s``
    (issue 37.9)."""
    hiding = [f"{c.where}: {c.text}" for page in doc_pages(ROOT)
              for block in doc_blocks(page, ROOT) for c in block.commands
              if _CURL_FAIL.search(c.text) and "--fail-with-body" not in c.text]
    assert not hiding, "\n".join(hiding)


def test_every_type_the_sim_serves_is_callable_from_the_cli(sim: Sim) -> None:
    """`zenros service list -t` / `action list -t` name only types `service call` and
    `action send_goal` can build."""
    from zenros.cli.common import find_action_type, find_service_type

    for noun, find in (("service", find_service_type), ("action", find_action_type)):
        r = subprocess.run(["zenros", noun, "list", "-t"], cwd=sim.workdir, env=sim.env,
                           capture_output=True, text=True, timeout=60, check=False)
        assert r.returncode == 0, r.stderr
        types = {t for line in r.stdout.splitlines()
                 for t in line.split(" [", 1)[1].rstrip("]").split(", ")}
        assert types, r.stdout
        for name in sorted(types):
            find(name)  # raises UnknownTypeError with the name


def test_the_websocket_one_liners_print_no_deprecation_warning(tmp_path: Path) -> None:
    """docs/fleet.md's and docs/gateway.md's ``python3 -c`` websockets clients, run by the
    docs check's own `_run` against a local WebSocket server on their ports: each works and
    prints no DeprecationWarning (``connect()`` used as a context manager; issue 37.11)."""
    from websockets.sync.server import ServerConnection, serve

    def hello_then_echo(ws: ServerConnection) -> None:
        ws.send('{"op": "hello"}')
        for message in ws:
            ws.send(message)

    commands = [c for page in doc_pages(ROOT) for block in doc_blocks(page, ROOT)
                for c in block.runnable() if "from websockets" in c.text]
    assert len(commands) >= 3, [c.where for c in commands]
    (tmp_path / "token").write_text("0" * 32)
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}"
                                 f"{os.environ.get('PATH', '')}"}
    with serve(hello_then_echo, "127.0.0.1", 0) as server:
        port = server.socket.getsockname()[1]
        worker = threading.Thread(target=server.serve_forever, daemon=True)
        worker.start()
        sim = Sim(env, tmp_path, {default: port for default in GATEWAY_PORTS.values()})
        failures = [why for c in commands if (why := _run(c, sim, tmp_path, env)) is not None]
        server.shutdown()
    assert not failures, "\n".join(failures)
