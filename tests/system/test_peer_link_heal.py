"""A lost link between two gossip-linked peers comes back (multihop gossip, the zenros
router's default): docs/zenoh-config.md, "A lost link between two peers". Runs in a private
network namespace (root, iptables)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = [pytest.mark.system, pytest.mark.netns, pytest.mark.timeout(120)]

SCENARIO = Path(__file__).with_name("peer_link_scenario.py")
NETNS = "ip link set lo up && exec \"$@\""


def run_scenario(*cfg: str) -> dict[str, object]:
    if os.geteuid() != 0:
        pytest.skip("needs root for a network namespace (unshare -n) and iptables")
    if not shutil.which("unshare") or not shutil.which("iptables"):
        pytest.skip("needs unshare and iptables (util-linux, iptables)")
    proc = subprocess.run(["unshare", "-n", "sh", "-c", NETNS, "sh", sys.executable,
                           str(SCENARIO), *cfg], capture_output=True, text=True, timeout=90,
                          check=False)
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    assert proc.returncode == 0 and lines, (proc.stdout, proc.stderr[-2000:])
    return json.loads(lines[-1])


def test_multihop_peers_link_again_after_their_link_was_lost() -> None:
    out = run_scenario("scouting/gossip/multihop:true")
    print("peer link heal:", json.dumps(out))
    assert out["linked"] and out["dropped"], out
    assert out["healed"], out
