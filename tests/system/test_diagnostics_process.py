"""The aggregator as a process (python -m zenros.services.diagnostics) and `zenros diag`."""

from __future__ import annotations

import json
import subprocess
import sys
from typing import Any

import pytest
from zenros import Node
from zenros.context import Context
from zenros.diagnostics import WARN, Updater
from zenros.session import SessionOptions
from zenros.testing import Proc

pytestmark = pytest.mark.system

PARAMS = ["-p", "pub_rate:=5.0",
          "-p", "analyzers.power.type:=diagnostic_aggregator/GenericAnalyzer",
          "-p", "analyzers.power.path:=Power",
          "-p", "analyzers.power.contains:=[battery]"]


def diag(router: str, prefix: str, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "zenros.cli", "diag", *args, "-e", router,
                           "--prefix", prefix], capture_output=True, text=True, timeout=60,
                          check=False)


def test_zenros_diag_prints_the_aggregated_tree(router: str, prefix: str,
                                                procs: list[Proc]) -> None:
    agg = Proc([sys.executable, "-m", "zenros.services.diagnostics", "-e", router,
                "--prefix", prefix, *PARAMS])
    procs.append(agg)
    assert agg.wait_line("started", 20), agg.output
    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    try:
        node = Node("chassis", context=ctx)
        up = Updater(node, period=0.2)
        up.add("battery", lambda s: (s.summary(WARN, "low: 18%"), s.add("percentage", 18)))
        r = diag(router, prefix, "--once", "--timeout", "20", "-v")
        assert r.returncode == 0, r.stderr
        # the first tree may predate the battery's first status: ask until it is in
        for _ in range(5):
            if "low: 18%" in r.stdout:
                break
            r = diag(router, prefix, "--once", "--timeout", "20", "-v")
        lines = r.stdout.splitlines()
        assert lines[0].split() == ["(robot)", "WARNING"], r.stdout
        assert lines[1].split() == ["Power", "WARNING", "Warning"], r.stdout
        assert lines[2].split() == ["chassis:", "battery", "low:", "18%"], r.stdout  # a value
        assert lines[3].split() == ["chassis:", "battery", "WARNING", "low:", "18%"], r.stdout
        assert lines[4].split() == ["percentage", "18"], r.stdout
        assert lines[3].index("chassis") == lines[1].index("Power") + 2  # one level deeper
        j = diag(router, prefix, "--once", "--json", "--timeout", "20")
        data: dict[str, Any] = json.loads(j.stdout.splitlines()[0])
        assert data["status"][0]["name"] == "/Power"
    finally:
        ctx.close()


def test_zenros_diag_without_an_aggregator_says_so(router: str, prefix: str) -> None:
    r = diag(router, prefix, "--once", "--timeout", "1")
    assert r.returncode == 1
    assert "is the aggregator running?" in r.stderr


def test_a_bad_analyzer_is_refused_at_start(router: str, prefix: str) -> None:
    r = subprocess.run([sys.executable, "-m", "zenros.services.diagnostics", "-e", router,
                        "--prefix", prefix, "-p", "analyzers.x.type:=GenericAnalyzer",
                        "-p", "analyzers.x.path:=X"],
                       capture_output=True, text=True, timeout=60, check=False)
    assert r.returncode == 3, r.stderr
    assert "no way of matching" in r.stderr
