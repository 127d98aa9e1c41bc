"""Network namespaces for the system tests that run deploy/demo/demo.sh: whether this machine
can make them, and removing whatever a test's prefix left behind."""

from __future__ import annotations

import os
import secrets
import shutil
import subprocess


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
