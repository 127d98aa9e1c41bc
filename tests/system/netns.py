"""Network namespaces for the system tests that run deploy/demo/demo.sh: whether this machine
can make them, and removing whatever a test's prefix left behind."""

from __future__ import annotations

import contextlib
import os
import secrets
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

DEMO = Path(__file__).resolve().parents[2] / "deploy" / "demo" / "demo.sh"


def netns_unavailable() -> str | None:
    """Why this machine cannot run the demo, or None."""
    if os.geteuid() != 0:
        return "needs root to create network namespaces"
    if shutil.which("ip") is None:
        return "needs iproute2 (the ip command): apt-get install -y iproute2"
    probe = "zrprobe" + secrets.token_hex(3)
    added = subprocess.run(["ip", "netns", "add", probe], capture_output=True, text=True,
                           check=False)
    if added.returncode != 0:
        return f"cannot create a network namespace: {added.stderr.strip()}"
    subprocess.run(["ip", "netns", "del", probe], capture_output=True, check=False)
    return None


def ip(*args: str) -> str:
    """``ip ARGS``; its stdout (failures are left to the caller's checks)."""
    return subprocess.run(["ip", *args], capture_output=True, text=True, check=False).stdout


def cleanup(prefix: str) -> None:
    """Kill whatever still runs in the namespaces of ``prefix`` and delete them."""
    listed = ip("netns", "list")
    for name in (line.split()[0] for line in listed.splitlines() if line.strip()):
        if not name.startswith(prefix):
            continue
        pids = ip("netns", "pids", name).split()
        for pid in pids:
            try:
                os.kill(int(pid), 9)
            except ProcessLookupError:
                pass
        ip("netns", "del", name)


def demo_env(prefix: str, state: Path, **settings: str) -> dict[str, str]:
    """The environment of demo.sh for one test's demo: its prefix, state directory and
    ``settings`` (ZR_TOPOLOGY=..., ...)."""
    # Not this process's ZENOH_RUNTIME: the first session a test opened here set zenros's
    # default into os.environ, and the demo is to run with the runtime demo.sh chooses.
    inherited = {k: v for k, v in os.environ.items() if k != "ZENOH_RUNTIME"}
    return {**inherited, "ZR_PREFIX": prefix, "ZR_STATE": str(state),
            "PYTHON": sys.executable, "ZR_WAIT": "100", **settings}


def demo_sh(env: dict[str, str], *args: str, timeout: float = 30.0) -> str:
    """Run ``demo.sh ARGS``; its output, or a failure that shows it."""
    done = subprocess.run([str(DEMO), *args], env=env, capture_output=True, text=True,
                          timeout=timeout, check=False)
    out = done.stdout + done.stderr
    assert done.returncode == 0, f"demo.sh {' '.join(args)} exited {done.returncode}:\n{out}"
    return out


@contextlib.contextmanager
def demo_started(env: dict[str, str]) -> Iterator[None]:
    """The demo of ``env`` up and started (the station sees every robot); then down, and
    nothing of its prefix left."""
    prefix = env["ZR_PREFIX"]
    try:
        demo_sh(env, "up")
        demo_sh(env, "start", timeout=120)
        yield
    finally:
        try:
            subprocess.run([str(DEMO), "down"], env=env, capture_output=True, timeout=60,
                           check=False)
        finally:
            cleanup(prefix)
        listed = ip("netns", "list")
        assert prefix not in listed, f"namespaces left behind: {listed}"
