"""Replay benchmark: deterministic replay of a recorded nav run (docs/replay.md).

replay_rtf: simulated seconds per wall second of ``zenros.replay.replay_bag`` running nav
alone on a 90 s bag made here with tests/scenarios/make_bags.py (odometry and ground truth
at 20 Hz, scans at 10 Hz, three loops of the room's patrol past a box the map does not
show), median over the repeats (scenario_rtf: the 20 s scenario bag of the tests); the nodes' setup is inside the wall time, the
imports are not; replay_rtf_cpu: per CPU second of the process instead, which the load
of a shared box does not change. The reference is real-time play: ``zenros bag play`` takes the bag's
duration (rtf 1.0), read from the same bag here.
replay_identical: how many of N replays of the bag in this process write a file
byte-identical to the first; replay_identical_processes: the same for M replays through
the CLI in fresh processes, each with another PYTHONHASHSEED.
gain_change: a replay with nav's controller gain ``cost_scaling_gain`` changed (1.0 ->
0.5) compared with the first: the first differing message must be a /cmd_vel.
Prints one JSON line.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

from _harness import emit

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "scenarios"))
import make_bags
from zenros.bag.info import bag_info
from zenros.replay.bagrun import replay_bag
from zenros.replay.compare import compare_bags

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = ROOT / "tests" / "scenarios"
SHORT = SCENARIOS / "goal_around_obstacle.in.mcap"
LONG = {"seconds": 90.0, "box": True,  # three loops of the room's patrol, past the box
        "goal": ("/patrol_goal", make_bags.PatrolGoal(map_name="room", path_name="patrol",
                                                      loops=3))}


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=20, help="in-process replays (default 20)")
    ap.add_argument("--processes", type=int, default=3,
                    help="replays through the CLI in fresh processes (default 3)")
    a = ap.parse_args()
    work = Path(tempfile.mkdtemp(prefix="zenros_replay_bench_"))
    try:
        shutil.copytree(SCENARIOS / "maps", work / "maps")
        nav: dict[str, Any] = {"maps_dir": str(work / "maps"),
                               "map": str(work / "maps" / "room" / "room.yaml")}
        bag = work / "long.in.mcap"
        make_bags.simulate("long", work / "maps", bag, LONG)
        info = bag_info(bag)
        duration = (info.end - info.start) / 1e9  # what real-time play takes
        rtfs: list[float] = []
        cpu_rtfs: list[float] = []
        walls: list[float] = []
        digests: list[str] = []
        sim = 0.0
        reads = 0
        for i in range(a.repeats):
            res = replay_bag(bag, ["nav"], work / f"run{i}.mcap", params={"nav": nav})
            rtfs.append(res.rtf)
            cpu_rtfs.append(res.rtf_cpu)
            walls.append(res.wall_seconds)
            sim = res.sim_seconds
            reads += len(res.wall_reads)
            digests.append(digest(res.output))
        same = sum(d == digests[0] for d in digests)
        cli_same = 0
        for k in range(a.processes):
            out = work / f"cli{k}.mcap"
            subprocess.run(
                [sys.executable, "-m", "zenros.cli", "replay", str(bag), "--nodes", "nav",
                 "-o", str(out), "-p", f"nav:maps_dir:={nav['maps_dir']}",
                 "-p", f"nav:map:={nav['map']}"],
                check=True, capture_output=True, env={**os.environ, "PYTHONHASHSEED": str(k + 1)})
            cli_same += digest(out) == digests[0]
        gain = replay_bag(bag, ["nav"], work / "gain.mcap",
                          params={"nav": {**nav, "cost_scaling_gain": 0.5}})
        diff = compare_bags(work / "run0.mcap", gain.output)
        short = [replay_bag(SHORT, ["nav"], work / f"short{i}.mcap", params={"nav": nav}).rtf
                 for i in range(5)]
    finally:
        shutil.rmtree(work, ignore_errors=True)
    emit("replay", {
        "replay_rtf": round(statistics.median(rtfs), 1),
        "replay_rtf_min": round(min(rtfs), 1),
        "replay_rtf_cpu": round(statistics.median(cpu_rtfs), 1),
        "replay_wall_s": round(statistics.median(walls), 3),
        "replay_sim_s": round(sim, 3),
        "reference_play_s": round(duration, 3),
        "reference_rtf": 1.0,
        "scenario_rtf": round(statistics.median(short), 1),
    }, replay_identical=f"{same} of {a.repeats}",
        replay_identical_processes=f"{cli_same} of {a.processes}",
        wall_clock_reads=reads, bag_messages=info.messages,
        gain_change=None if diff is None else {"topic": diff.topic, "time_s": diff.time_ns / 1e9,
                                               "field": diff.path, "before": diff.a,
                                               "after": diff.b, "message_index": diff.index},
        gain_change_first_is_cmd_vel=diff is not None and diff.topic == "/cmd_vel",
        nodes="nav", loadavg=os.getloadavg()[0],
        stat="rtf: median (and min) over the in-process replays; rtf_cpu: simulated seconds "
             "per CPU second of this process (what the box's load does not change); "
             "scenario_rtf: median of 5 replays of the 20 s scenario bag")


if __name__ == "__main__":
    main()
