"""`zenros map save NAME` (map_saver_cli's job) and `zenros map show` (the live map's size,
coverage and the mapping node's state). docs/cli.md, docs/mapping.md "CLI".

``save``: while the mapping node maps (its latched ``slam/state`` says so), it saves what it
built (``slam/save``: the map and its pose graph, so ``/map/update`` can continue it);
otherwise nav's ``map_saver/save_map`` stores the grid on the ``map`` topic, as Nav2's
map_saver_cli does. Either way the map lands in nav's maps store under NAME.
"""

from __future__ import annotations

import argparse
import json
import threading
import time
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ..msgs.nav2_msgs import SaveMap, SaveMapRequest
from ..msgs.nav_msgs import OccupancyGrid
from ..msgs.zenros_msgs.result import ResultCode
from ..msgs.zenros_msgs.slam import MappingState, SaveSlamMap, SaveSlamMapRequest
from ..names import resolve
from ..qos import QOS_LATCHED
from ..rpc import Client
from ..tf.convert import yaw_from_msg
from .common import CliError, ToolNode, add_common, open_context

__all__ = ["MapSummary", "register", "summarize"]

STATE_WAIT = 1.0   # s to wait for the latched slam/state (absent: no mapping node)


@dataclass(frozen=True)
class MapSummary:
    """What ``map show`` prints: the grid's size, and how much of it is known."""

    width: int
    height: int
    resolution: float
    origin: tuple[float, float, float]
    known_m2: float
    free_m2: float
    occupied_m2: float
    coverage: float      # known cells / all cells


def summarize(grid: OccupancyGrid) -> MapSummary:
    """The size and coverage of an occupancy grid (occupied: >= 65, map_server's 0.65)."""
    info = grid.info
    cells = np.asarray(grid.data, dtype=np.int16)
    area = info.resolution * info.resolution
    free = int(((cells >= 0) & (cells < 65)).sum())
    occupied = int((cells >= 65).sum())
    o = info.origin.position
    return MapSummary(width=info.width, height=info.height, resolution=info.resolution,
                      origin=(o.x, o.y, yaw_from_msg(info.origin.orientation)),
                      known_m2=(free + occupied) * area, free_m2=free * area,
                      occupied_m2=occupied * area,
                      coverage=(free + occupied) / cells.size if cells.size else 0.0)


def register(sub: Any) -> None:
    p = sub.add_parser("map", help="maps: save the live map, show its size and coverage")
    verbs = p.add_subparsers(dest="verb", required=True)
    v = verbs.add_parser("save", help="save the live map into the maps store as NAME "
                                      "(map_saver_cli)")
    v.add_argument("name", help="the map's name (letters, digits, _ . -)")
    v.add_argument("--type", choices=("floor", "elevator"), default="floor",
                   help="floor (default) or elevator (while mapping)")
    v.add_argument("--levels", type=int, nargs="*", default=[],
                   help="the floors the map serves (while mapping)")
    v = verbs.add_parser("show", help="the live map's size, resolution, known area and "
                                      "the mapping state")
    v.add_argument("--json", action="store_true", help="print JSON")
    for verb in verbs.choices.values():
        verb.add_argument("--ns", default="/", help="the robot's namespace (default /)")
        verb.add_argument("--timeout", type=float, default=10.0)
        add_common(verb)
    p.set_defaults(func=run)


class _Latest:
    def __init__(self) -> None:
        self.grid: OccupancyGrid | None = None
        self.state: MappingState | None = None
        self.got_grid = threading.Event()
        self.got_state = threading.Event()

    def on_grid(self, msg: OccupancyGrid) -> None:
        self.grid = msg
        self.got_grid.set()

    def on_state(self, msg: MappingState) -> None:
        self.state = msg
        self.got_state.set()


def run(args: argparse.Namespace) -> int:
    ctx = open_context(args, settle=False, required=True)
    try:
        node = ToolNode(f"zenros_map_{args.verb}", context=ctx, namespace=args.ns)
        latest = _Latest()
        node.create_subscription(MappingState, "slam/state", latest.on_state, QOS_LATCHED)
        if args.verb == "show":
            node.create_subscription(OccupancyGrid, "map", latest.on_grid, QOS_LATCHED)
            return _show(args, latest)
        latest.got_state.wait(STATE_WAIT)
        if latest.state is not None and latest.state.state == "mapping":
            return _save_slam(args, ctx)
        return _save_nav(args, ctx)
    finally:
        ctx.close()


def _client(ctx: Any, srv: Any, name: str, ns: str, timeout: float, hint: str) -> Client:
    full = resolve(name, namespace=ns, kind="service")
    client = Client(ctx, srv, full)
    if not client.wait_for_service(min(timeout, 5.0)):
        raise CliError(f"service {full} is not available: {hint}")
    return client


def _save_slam(args: argparse.Namespace, ctx: Any) -> int:
    client = _client(ctx, SaveSlamMap, "slam/save", args.ns, args.timeout,
                     "is the mapping node running?")
    res = client.call(SaveSlamMapRequest(name=args.name, type=args.type, levels=args.levels),
                      timeout=args.timeout, grace=args.timeout)
    if res.code != ResultCode.OK:
        raise CliError(f"save: {res.message} ({ResultCode(res.code).name})")
    print(f"saved map {res.name or args.name!r} (slam/save: the map being built, and its "
          "pose graph)")
    return 0


def _save_nav(args: argparse.Namespace, ctx: Any) -> int:
    client = _client(ctx, SaveMap, "map_saver/save_map", args.ns, args.timeout,
                     "is nav running? (zenros launch deploy/launch/sim.yaml starts it)")
    res = client.call(SaveMapRequest(map_topic="map", map_url=args.name),
                      timeout=args.timeout, grace=args.timeout)
    if not res.result:
        raise CliError(f"save: map_saver/save_map did not save {args.name!r} (no map on "
                       "the map topic, or the name is refused: see nav's log)")
    print(f"saved map {args.name!r} (map_saver/save_map: the grid on the map topic)")
    return 0


def _show(args: argparse.Namespace, latest: _Latest) -> int:
    deadline = time.monotonic() + args.timeout
    if not latest.got_grid.wait(args.timeout):
        raise CliError(f"no map on {resolve('map', namespace=args.ns)} within "
                       f"{args.timeout:g} s (is nav or the mapping node running?)")
    latest.got_state.wait(max(0.0, min(STATE_WAIT, deadline - time.monotonic())))
    assert latest.grid is not None
    s = summarize(latest.grid)
    st = latest.state
    if args.json:
        out: dict[str, Any] = {"map": asdict(s), "mapping": None}
        if st is not None:
            out["mapping"] = {"state": st.state, "mode": st.mode, "map_name": st.map_name,
                              "scans": st.scans, "nodes": st.nodes,
                              "loop_closures": st.loop_closures, "message": st.message}
        print(json.dumps(out))
        return 0
    print(f"map: {s.width} x {s.height} cells at {s.resolution:.3f} m "
          f"({s.width * s.resolution:.2f} x {s.height * s.resolution:.2f} m), origin "
          f"({s.origin[0]:.2f}, {s.origin[1]:.2f}, {s.origin[2]:.2f})")
    print(f"known: {s.known_m2:.2f} m2 ({s.coverage * 100:.1f} % of the grid): free "
          f"{s.free_m2:.2f} m2, occupied {s.occupied_m2:.2f} m2")
    if st is None:
        print("mapping: no mapping node (the map is nav's)")
    elif st.state == "idle":
        print(f"mapping: idle (the map is nav's){': ' + st.message if st.message else ''}")
    else:
        what = f"extending {st.map_name!r}" if st.map_name else "a new map"
        print(f"mapping: {st.state} ({st.mode or 'laser'}, {what}), {st.scans} scans, "
              f"{st.nodes} nodes, {st.loop_closures} loop closures")
    return 0
