"""`zenros bag record|play|info|recover`: MCAP bags (see docs/bags.md)."""

from __future__ import annotations

import argparse
import datetime as dt
import gc
import os
import sys
import threading
import time
from pathlib import Path
from typing import Any

from ..bag.info import bag_info, format_info
from ..bag.keyboard import keyboard_controls
from ..bag.player import Player, PlayOptions
from ..bag.reader import BagError, bag_files, resolve_bag
from ..bag.recorder import Recorder, RecordOptions
from ..bag.recover import recover_bag
from ..bag.sink import FLUSH_INTERVAL, SplitPolicy
from ..bag.writer import COMPRESSIONS
from ..runtime import capture_signals
from .common import ToolNode, add_common, open_context

__all__ = ["add_play_arguments", "add_record_arguments", "play", "record", "register"]

PLAY_SWITCH_INTERVAL = 0.0005  # s: other threads hand the GIL back quickly near a deadline


def add_record_arguments(v: argparse.ArgumentParser) -> None:
    v.add_argument("topics", nargs="*", metavar="TOPIC", help="topics to record")
    v.add_argument("-a", "--all", action="store_true", dest="all_topics",
                   help="record every topic, also those that appear later")
    v.add_argument("-o", "--output", metavar="NAME",
                   help="bag directory to create, relative to the working directory as with "
                        "ros2 bag (default: rosbag2_<date>-<time> there)")
    g = v.add_mutually_exclusive_group()
    g.add_argument("--split-size", type=float, metavar="MB", default=0.0,
                   help="start a new file after MB megabytes")
    g.add_argument("--split-duration", type=float, metavar="S", default=0.0,
                   help="start a new file after S seconds of messages")
    v.add_argument("--compression", choices=COMPRESSIONS, default="zstd",
                   help="chunk compression (default zstd)")
    v.add_argument("--exclude", metavar="REGEX", help="do not record topics matching REGEX")
    v.add_argument("--bulk-json", action="store_true",
                   help="store MessagePack (bulk) types as JSON, for Foxglove; costs a decode "
                        "and an encode per bulk message")
    v.add_argument("--flush-interval", type=float, default=FLUSH_INTERVAL, metavar="S",
                   help=f"write the open chunk at least every S seconds (default "
                        f"{FLUSH_INTERVAL:g}): at most this much is lost if the recorder is killed")


def add_play_arguments(v: argparse.ArgumentParser) -> None:
    v.add_argument("bag", metavar="NAME", help="bag name or path (a directory or a .mcap file)")
    v.add_argument("--rate", type=float, default=1.0, help="speed factor (default 1)")
    v.add_argument("--loop", action="store_true", help="play again from the start")
    v.add_argument("--start", type=float, default=0.0, metavar="S",
                   help="start S seconds into the bag")
    v.add_argument("--topics", nargs="+", default=[], metavar="TOPIC", help="only these topics")
    v.add_argument("--clock", action="store_true",
                   help="publish /clock with the bag time (for nodes with use_sim_time)")


def register(sub: Any) -> None:
    p = sub.add_parser("bag", help="bags: record, play, info, recover (MCAP)")
    verbs = p.add_subparsers(dest="verb", required=True)
    v = verbs.add_parser("record", help="record topics to a bag")
    add_record_arguments(v)
    add_common(v)
    v = verbs.add_parser("play", help="publish a bag's messages on their original schedule")
    add_play_arguments(v)
    add_common(v)
    v = verbs.add_parser("info", help="what a bag holds")
    v.add_argument("bag", metavar="NAME")
    v = verbs.add_parser("recover", help="make the files of a killed recorder readable again")
    v.add_argument("bag", metavar="NAME")
    v.add_argument("--compression", choices=COMPRESSIONS, default="zstd")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    return int(_VERBS[args.verb](args))


def output_dir(name: str | None) -> Path:
    """Where a new bag goes, as ``ros2 bag record`` puts it: ``-o NAME`` relative to the
    working directory (or an absolute path), ``rosbag2_YYYY_MM_DD-HH_MM_SS`` there without
    ``-o``; a directory that already exists is refused (``Output folder ... already exists``).
    """
    path = Path(name or f"rosbag2_{dt.datetime.now():%Y_%m_%d-%H_%M_%S}").expanduser()
    if path.suffix == ".mcap":
        path = path.with_suffix("")
    if path.is_dir():
        raise BagError(f"output folder '{path}' already exists; choose another name with -o")
    return path.absolute()


def _node_name(args: argparse.Namespace, default: str) -> tuple[str, str | None]:
    return getattr(args, "name", None) or f"{default}_{os.getpid()}", getattr(args, "ns", None)


def record(args: argparse.Namespace) -> int:
    if not args.all_topics and not args.topics:
        raise BagError("give topics to record, or -a for all")
    mb = 1_000_000
    options = RecordOptions(
        directory=output_dir(args.output), topics=list(args.topics),
        all_topics=args.all_topics, exclude=args.exclude, compression=args.compression,
        split=SplitPolicy(int(args.split_size * mb), args.split_duration),
        flush_interval=args.flush_interval, bulk_json=args.bulk_json,
    )
    stop = threading.Event()
    ctx = open_context(args, settle=False)
    try:
        name, ns = _node_name(args, "zenros_bag_recorder")
        node = ToolNode(name, namespace=ns, context=ctx)
        try:
            with capture_signals(stop.set):
                rec = Recorder(ctx, options, node=node.fqn, on_channel=lambda t, ty: print(
                    f"Subscribed to topic '{t}' ({ty})", flush=True))
                print(f"Recording to {options.directory} (Ctrl-C stops)", flush=True)
                try:
                    while not stop.wait(0.5):  # wakes to run a signal another thread took
                        pass
                finally:
                    rec.close()
            counts = rec.counts()
            total = sum(counts.values())
            print(f"Recorded {total} messages on {len(counts)} topics to "
                  f"{', '.join(str(f) for f in rec.files)}", flush=True)
        finally:
            node.close()
    finally:
        ctx.close()
    return 0


def _progress(player: Player, done: threading.Event) -> None:
    tty = sys.stdout.isatty()
    period, last = (0.1, 0.0) if tty else (5.0, time.monotonic())
    while not done.wait(period):
        pos = max(0.0, (player.position - player.bag_start) / 1e9) if player.published else 0.0
        state = "PAUSED " if player.paused else "RUNNING"
        line = (f"[{state}] bag time {pos:8.3f} / {player.duration:.3f} s, "
                f"{player.published} messages")
        if tty:
            sys.stdout.write("\r" + line + ("  (space: pause/resume, s: step)" if player.paused
                                             else "  (space: pause)"))
            sys.stdout.flush()
        elif time.monotonic() - last >= period:
            print(line, flush=True)
            last = time.monotonic()


def play(args: argparse.Namespace) -> int:
    files = bag_files(resolve_bag(args.bag))
    options = PlayOptions(rate=args.rate, loop=args.loop, start=args.start,
                          topics=list(args.topics), clock=args.clock)
    sys.setswitchinterval(PLAY_SWITCH_INTERVAL)
    gc.freeze()  # what is loaded so far is never scanned again: shorter collection pauses
    ctx = open_context(args, settle=False)
    try:
        name, ns = _node_name(args, "zenros_bag_player")
        node = ToolNode(name, namespace=ns, context=ctx)
        player = Player(ctx, files, options, node=node)
        done = threading.Event()
        shown = threading.Thread(target=_progress, args=(player, done), daemon=True)
        try:
            print(f"Playing {len(files)} file(s), {player.duration:.3f} s at {args.rate:g}x",
                  flush=True)
            shown.start()
            def toggle() -> None:
                player.toggle_pause()
                print("\nPaused (space: resume, s: step)" if player.paused else "\nResumed",
                      flush=True)

            keys = {" ": toggle, "s": player.step}
            with capture_signals(player.stop), keyboard_controls(keys):
                n = player.play()
        finally:
            done.set()
            shown.join(1.0)
            player.close()
            node.close()
        late = sorted(player.lateness)
        p99 = late[min(len(late) - 1, int(0.99 * len(late)))] * 1e3 if late else 0.0
        print(f"\nPlayed {n} messages (timing error p99 {p99:.3f} ms)", flush=True)
    finally:
        ctx.close()
    return 0


def info(args: argparse.Namespace) -> int:
    print(format_info(bag_info(resolve_bag(args.bag))))
    return 0


def recover(args: argparse.Namespace) -> int:
    for r in recover_bag(resolve_bag(args.bag), args.compression):
        if r.already_valid:
            print(f"{r.path}: already valid ({r.messages} messages)")
            continue
        why = f"; reading stopped: {r.stopped}" if r.stopped else ""
        skipped = f"; {r.skipped_chunks} damaged chunk(s) skipped" if r.skipped_chunks else ""
        print(f"{r.path}: recovered {r.messages} messages{skipped}{why} "
              f"(original kept as {r.path.name}.damaged)")
    return 0


_VERBS = {"record": record, "play": play, "info": info, "recover": recover}
