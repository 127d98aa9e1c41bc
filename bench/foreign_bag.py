"""Reading bags recorded with ROS: messages/s that `zenros.bag.iter_messages` hands out
(read, converted to zenros's message, encoded as zenros publishes it) against rosbags' own
read + deserialise of the same bag (``AnyReader.messages`` and ``deserialize``: rosbags'
objects, nothing encoded), in the same run.

The bags are ``scripts/make_ros_bag.py``'s (rosbags' writers): STEPS steps of a Twist, an
Odometry, a 36-beam LaserScan and a TFMessage, in rosbag2 SQLite3 and MCAP storage (ROS 2
definitions equal to zenros's: its CDR codec decodes them) and a ROS 1 bag (rosbags
deserialises, zenros converts field by field). Each figure is the best of ROUNDS reads,
zenros and the reference alternating, timed in this process's CPU time (the box is shared:
wall time would count other work's turns). Needs rosbags (``pip install -e '.[rosbags]'``).
Prints one JSON line.
"""

from __future__ import annotations

import importlib.util
import os
import sys
import tempfile
import time
from pathlib import Path

from _harness import emit, missing_extra

ROOT = Path(__file__).resolve().parents[1]
STEPS = 2500
ROUNDS = 5


def _script():  # type: ignore[no-untyped-def]
    spec = importlib.util.spec_from_file_location("make_ros_bag", ROOT / "scripts" / "make_ros_bag.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _zenros(bag: Path) -> tuple[int, float]:
    from zenros.bag import bag_files, iter_messages

    t0 = time.process_time()
    n = sum(1 for _ in iter_messages(bag_files(bag)))
    return n, time.process_time() - t0


def _rosbags(bag: Path) -> tuple[int, float]:
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    t0 = time.process_time()
    n = 0
    with AnyReader([bag], default_typestore=get_typestore(Stores.LATEST)) as reader:
        for conn, _, raw in reader.messages():
            reader.deserialize(raw, conn.msgtype)
            n += 1
    return n, time.process_time() - t0


def main() -> None:
    try:
        script = _script()
    except ModuleNotFoundError as err:
        sys.exit(missing_extra(err, "rosbags"))
    metrics: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as d:
        for storage in ("sqlite3", "mcap", "ros1"):
            bag = Path(d) / (f"{storage}.bag" if storage == "ros1" else storage)
            script.write_bag(bag, storage, STEPS)
            best_z = best_r = float("inf")
            count = 0
            for _ in range(ROUNDS):
                n, dt = _zenros(bag)
                best_z = min(best_z, dt)
                count = n
                n_ref, dt = _rosbags(bag)
                assert n_ref == n, (n_ref, n)
                best_r = min(best_r, dt)
            metrics[f"{storage}_msgs_per_s"] = round(count / best_z)
            metrics[f"{storage}_rosbags_msgs_per_s"] = round(count / best_r)
            metrics[f"{storage}_ratio"] = round(best_r / best_z, 3)
        metrics["messages"] = count
    emit("foreign_bag", metrics, loadavg=round(os.getloadavg()[0], 1))


if __name__ == "__main__":
    main()
