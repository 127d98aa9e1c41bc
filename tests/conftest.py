"""Shared fixtures: isolated Zenoh sessions on loopback, a router process, node factories.

How a test uses them, and how the suite runs in parallel (pytest-xdist, ``-n`` and
``--dist loadgroup`` in pyproject's addopts; see tests/README.md):

- ``prefix``: a fresh key prefix per test. Every rig below is shared between tests, so a test
  is isolated from the others by its prefix (and free ports), never by a fresh process.
- ``router``: the endpoint of a Zenoh router process shared by every test of one xdist worker
  (started at the first test that asks for it, restarted if a test ended it). A test that
  needs a router of its own (to stop, restart or configure it) starts one with ``Proc``.
- ``observer``: a session of the test's own on the shared ``router``, on the test's ``prefix``.
- ``ctx_pair`` / ``make_node``: two meshed sessions on loopback for one test (function scope).
- ``procs``: child processes a test starts, stopped at teardown.

xdist groups: a test whose module has a module- or class-scoped fixture (a rig built once per
module: a sim, a robot, a gateway) is put in the xdist group of its module, so the rig is built
on one worker only, once. Tests that must not run beside each other (whole sims, network
namespaces, a browser) share ``pytest.mark.xdist_group("sim")``. Add the mark to a new test
of that kind; other tests need nothing.
"""

from __future__ import annotations

import importlib.util
import os
import resource
import signal
import sys
import threading
import time
import traceback
from collections.abc import Callable, Iterator
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
from zenros.context import Context
from zenros.node import Node
from zenros.session import SessionOptions
from zenros.testing import Proc, free_port, linked_contexts, unique_prefix, wait_for

# A suite started in the background of a non-interactive shell (`.ci/run &`, a CI runner)
# inherits SIGINT ignored, and so would every process it starts: a CLI command that stops on
# Ctrl-C (``topic echo``, ``tf echo``, ``hz``, ``pub -r``) then ignored the tests' SIGINT and
# was killed 10 s later (docs check: every streaming command 13.5 s, not 3.5). The suite's
# processes get SIGINT as a terminal gives it; a handler, unlike SIG_IGN, is not inherited.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


@pytest.fixture
def prefix() -> str:
    return unique_prefix()


@pytest.fixture
def ctx_pair(prefix: str) -> Iterator[list[Context]]:
    """Two sessions (as two processes would have) meshed on loopback, one key prefix."""
    with linked_contexts(2, prefix) as ctxs:
        yield ctxs


@pytest.fixture
def make_node(ctx_pair: list[Context]) -> Iterator[Callable[..., Any]]:
    """``make_node(name, side=0|1, cls=Node, **kw)``: nodes closed at teardown."""
    nodes: list[Node] = []

    def factory(name: str, side: int = 0, cls: type[Node] = Node, **kw: Any) -> Any:
        node = cls(name, context=ctx_pair[side], **kw)
        nodes.append(node)
        return node

    yield factory
    for n in reversed(nodes):
        n.close()


class _SharedRouter:
    """One router process per test session (per xdist worker), restarted when it died."""

    def __init__(self) -> None:
        self.proc: Proc | None = None
        self.endpoint = ""

    def get(self) -> str:
        if self.proc is None or self.proc.popen.poll() is not None:
            self.endpoint = f"tcp/127.0.0.1:{free_port()}"
            self.proc = Proc([sys.executable, "-m", "zenros.router", "-l", self.endpoint])
            assert self.proc.wait_line("router listening", 15), self.proc.output
        return self.endpoint

    def close(self) -> None:
        if self.proc is not None:
            self.proc.stop()


@pytest.fixture(scope="session")
def _shared_router() -> Iterator[_SharedRouter]:
    shared = _SharedRouter()
    try:
        yield shared
    finally:
        shared.close()


@pytest.fixture
def router(_shared_router: _SharedRouter) -> str:
    """The endpoint of a real Zenoh router process on a free loopback port, shared by the
    tests of one worker (they are kept apart by their ``prefix``)."""
    return _shared_router.get()


@pytest.fixture
def observer(router: str, prefix: str) -> Iterator[Context]:
    """A session of the test's own on the ``router``, to watch the graph and make calls."""
    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    try:
        yield ctx
    finally:
        ctx.close()


@pytest.fixture
def procs() -> Iterator[list[Proc]]:
    """Child processes a test starts; each is stopped (SIGINT, then SIGKILL) at teardown."""
    started: list[Proc] = []
    yield started
    for p in started:
        p.stop()


def pytest_xdist_auto_num_workers(config: pytest.Config) -> int:
    """``-n auto`` (README's command 2, `.ci/run`): one worker more than the cores when the
    box is idle, as many as the cores when something else keeps it busy.

    Most tests wait (a sim driving, a link outage, a process starting), and the workers end
    together, so on an idle 2-core box a third worker fills the waits: `.ci/run` 338 s against
    462 s. Beside a CPU hog, three workers starved in-process rigs past their 1 s Zenoh lease
    (docs/benchmarks.md), so a busy box gets one worker per core, as ``make -l`` starts no new
    job above a load. Busy: more than half a core in use over a quarter of a second, by
    /proc/stat (one worker per core where there is no /proc/stat).
    """
    cores = os.cpu_count() or 1
    busy = _cores_in_use(0.25)
    return cores if busy is None or busy > 0.5 else cores + 1


def _cores_in_use(seconds: float) -> float | None:
    """How many cores were busy over the next ``seconds``; None without /proc/stat."""
    def sample() -> tuple[int, int]:
        with open("/proc/stat", encoding="ascii") as f:
            ticks = [int(v) for v in f.readline().split()[1:]]
        return sum(ticks), ticks[3] + ticks[4]  # all, idle + iowait

    try:
        total0, idle0 = sample()
        time.sleep(seconds)  # a measurement over an interval, not a wait for a condition
        total1, idle1 = sample()
    except (OSError, ValueError, IndexError):
        return None
    total = total1 - total0
    return (os.cpu_count() or 1) * (total - (idle1 - idle0)) / total if total > 0 else None


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption("--cpu-report", metavar="FILE", default=None,
                     help="append a line per test: node id, CPU of the worker and of the "
                          "children it reaped, wall time, start, worker (tests/README.md)")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem: pytest.Item | None
                            ) -> Iterator[None]:
    """``--cpu-report FILE``: where the suite's CPU goes, a test at a time. A child's CPU
    counts when it is reaped: a module's rig shows at the test that ends it."""
    path = item.config.getoption("--cpu-report")
    if not path:
        yield
        return
    before, start, wall = _cpu(), time.time(), time.monotonic()
    yield
    after = _cpu()
    with open(path, "a", encoding="utf-8") as f:
        f.write(f"{item.nodeid}\t{after[0] - before[0]:.3f}\t{after[1] - before[1]:.3f}\t"
                f"{time.monotonic() - wall:.3f}\t{start:.3f}\t"
                f"{os.environ.get('PYTEST_XDIST_WORKER', '-')}\n")


def _cpu() -> tuple[float, float]:
    own, children = (resource.getrusage(w) for w in (resource.RUSAGE_SELF,
                                                      resource.RUSAGE_CHILDREN))
    return own.ru_utime + own.ru_stime, children.ru_utime + children.ru_stime


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]
                              ) -> Iterator[None]:
    """A failed test's report carries the stack of every thread of the process when it
    failed: a rig in this process (a nav, a chassis, an action server) stuck on a lock or a
    callback shows where, which a failure seen once under load otherwise never tells."""
    outcome = yield
    report = outcome.get_result()
    if report.failed and call.excinfo is not None \
            and not call.excinfo.errisinstance(KeyboardInterrupt):
        report.sections.append(("threads at the failure", _thread_stacks()))


def _thread_stacks() -> str:
    names = {t.ident: t.name for t in threading.enumerate()}
    return "\n".join(
        f"--- {names.get(ident, '?')} ({ident})\n" + "".join(traceback.format_stack(frame))
        for ident, frame in sys._current_frames().items())


@pytest.hookimpl(tryfirst=True)  # before xdist reads the groups
def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """A test using a module- or class-scoped fixture joins its module's xdist group."""
    for item in items:
        if item.get_closest_marker("xdist_group") is not None:
            continue
        info = getattr(item, "_fixtureinfo", None)
        if info is None:
            continue
        if any(d.scope in ("module", "class", "package")
               for defs in info.name2fixturedefs.values() for d in defs):
            item.add_marker(pytest.mark.xdist_group(item.nodeid.split("::", 1)[0]))



ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def doc_module(tmp_path: Path) -> Callable[[str, str], ModuleType]:
    """``doc_module(page, first_line)``: the Python block of ``docs/<page>`` that opens with
    the comment ``first_line`` (``# services/chassis/devices/lift.py``), imported as the
    module that comment names, so that an example of "one new module" is run as written."""

    def load(page: str, first_line: str) -> ModuleType:
        text = (ROOT / "docs" / page).read_text()
        code = text.split(first_line + "\n", 1)[1].split("```", 1)[0]
        path = first_line.removeprefix("# ")
        name = "zenros." + path.removeprefix("shared/").removesuffix(".py").replace("/", ".")
        (tmp_path / Path(path).name).write_text(code)
        spec = importlib.util.spec_from_file_location(name, tmp_path / Path(path).name)
        assert spec is not None and spec.loader is not None, first_line
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module

    return load


__all__ = ["wait_for"]
