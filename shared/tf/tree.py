"""The frame tree as text: an indented tree with authorities and rates, and DOT (view_frames)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import yaml

from ..msgs.builtin_interfaces import Time
from ..msgs.tf_srvs import FrameInfo
from .stamps import NS, from_ns

__all__ = ["frames_as_dot", "frames_as_tree", "frames_from_yaml"]


def _children(frames: Sequence[FrameInfo]) -> tuple[list[str], dict[str, list[FrameInfo]]]:
    """The roots (parents that are nobody's child), and each frame's children, sorted."""
    kids: dict[str, list[FrameInfo]] = {}
    for f in frames:
        kids.setdefault(f.parent, []).append(f)
    for v in kids.values():
        v.sort(key=lambda f: f.frame_id)
    children = {f.frame_id for f in frames}
    roots = sorted(p for p in kids if p not in children)
    return roots, kids


def _secs(t: Time) -> str:
    return f"{(t.sec * NS + t.nanosec) / NS:.3f}"


def _describe(f: FrameInfo) -> str:
    if f.static:
        return f"static, {f.authority}"
    return (f"{f.authority}, {f.rate:.1f} Hz, most recent {_secs(f.most_recent)}, "
            f"delay {f.delay:.3f} s")


def frames_as_tree(frames: Sequence[FrameInfo]) -> str:
    """One line per frame, children indented under their parent, e.g.::

        map
        └── odom  [chassis, 50.0 Hz, most recent 12.340, delay 0.003 s]
            └── base_link  [...]
    """
    roots, kids = _children(frames)
    lines: list[str] = []
    seen: set[str] = set()

    def walk(frame: str, prefix: str) -> None:
        items = kids.get(frame, [])
        for i, f in enumerate(items):
            if f.frame_id in seen:
                continue
            seen.add(f.frame_id)
            last = i == len(items) - 1
            lines.append(f"{prefix}{'└── ' if last else '├── '}{f.frame_id}  [{_describe(f)}]")
            walk(f.frame_id, prefix + ("    " if last else "│   "))

    for root in roots:
        lines.append(root)
        walk(root, "")
    rest = sorted(f.parent for f in frames if f.frame_id not in seen)
    for parent in dict.fromkeys(rest):  # frames on a loop (no root): shown from any parent
        if any(f.frame_id not in seen for f in kids.get(parent, [])):
            lines.append(f"{parent}  (no root)")
            walk(parent, "")
    return "\n".join(lines) + "\n" if lines else "no frames\n"


def _q(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def frames_as_dot(frames: Sequence[FrameInfo], stamp: Time | None = None) -> str:
    """The tree in Graphviz DOT, edges labelled as tf2's view_frames labels them."""
    out = ["digraph G {"]
    for f in sorted(frames, key=lambda f: (f.parent, f.frame_id)):
        if f.static:
            label = f"Broadcaster: {f.authority}\\nStatic\\n"
        else:
            label = (f"Broadcaster: {f.authority}\\nAverage rate: {f.rate:.3f}\\n"
                     f"Most recent transform: {_secs(f.most_recent)}\\n"
                     f"Delay: {f.delay:.3f}\\nMax delay: {f.max_delay:.3f}\\n")
        out.append(f'{_q(f.parent)} -> {_q(f.frame_id)}[label=" {label}"];')
    roots, _ = _children(frames)
    if roots:
        out.append("edge [style=invis];")
        out.append(' subgraph cluster_legend { style=bold; color=black; label ="view_frames '
                   'Result";')
        recorded = _secs(stamp) if stamp is not None else "unknown"
        out.append(f'"Recorded at time: {recorded}"[ shape=plaintext ] ;')
        out.append(f"}}->{_q(roots[0])};")
    out.append("}")
    return "\n".join(out) + "\n"


def frames_from_yaml(text: str) -> list[FrameInfo]:
    """`FrameInfo` entries from a buffer's ``all_frames_as_yaml`` (statics: most recent 0)."""
    doc: Any = yaml.safe_load(text) or {}
    out = []
    for child, d in sorted(doc.items()):
        newest = float(d.get("most_recent_transform", 0.0))
        static = newest == 0.0 and float(d.get("oldest_transform", 0.0)) == 0.0
        delay = float(d.get("transform_delay", 0.0)) if not static else 0.0
        out.append(FrameInfo(
            frame_id=str(child), parent=str(d.get("parent", "")),
            authority=str(d.get("broadcaster", "")), static=static,
            rate=0.0 if static else float(d.get("rate", 0.0)),
            most_recent=from_ns(round(newest * NS)), delay=delay, max_delay=delay,
        ))  # fmt: skip
    return out
