"""The frame tree as text and DOT, and frames read back from a buffer's YAML dump."""

from __future__ import annotations

from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.tf_srvs import FrameInfo
from zenros.tf import (
    Buffer,
    frames_as_dot,
    frames_as_tree,
    frames_from_yaml,
    transform_stamped,
)

FRAMES = [
    FrameInfo(frame_id="odom", parent="map", authority="/amcl", rate=20.0,
              most_recent=Time(sec=12, nanosec=500_000_000), delay=0.01, max_delay=0.02),
    FrameInfo(frame_id="base_link", parent="odom", authority="/chassis", rate=50.0,
              most_recent=Time(sec=12), delay=0.003),
    FrameInfo(frame_id="laser", parent="base_link", authority="/tf", static=True),
    FrameInfo(frame_id="imu", parent="base_link", authority="/tf", static=True),
]


def test_tree_lists_children_under_parents_with_authority_and_rate() -> None:
    assert frames_as_tree(FRAMES) == (
        "map\n"
        "└── odom  [/amcl, 20.0 Hz, most recent 12.500, delay 0.010 s]\n"
        "    └── base_link  [/chassis, 50.0 Hz, most recent 12.000, delay 0.003 s]\n"
        "        ├── imu  [static, /tf]\n"
        "        └── laser  [static, /tf]\n"
    )


def test_tree_of_nothing_and_of_a_forest() -> None:
    assert frames_as_tree([]) == "no frames\n"
    two = [FrameInfo(frame_id="b", parent="a", static=True, authority="x"),
           FrameInfo(frame_id="d", parent="c", static=True, authority="y")]
    assert frames_as_tree(two).splitlines() == [
        "a", "└── b  [static, x]", "c", "└── d  [static, y]"]


def test_a_loop_is_still_shown() -> None:
    loop = [FrameInfo(frame_id="a", parent="b", static=True, authority="x"),
            FrameInfo(frame_id="b", parent="a", static=True, authority="x")]
    text = frames_as_tree(loop)
    assert "(no root)" in text and "a  [static, x]" in text


def test_dot_has_one_edge_per_link_and_the_legend() -> None:
    dot = frames_as_dot(FRAMES, Time(sec=13))
    assert dot.startswith("digraph G {\n") and dot.endswith("}\n")
    assert '"map" -> "odom"[label=" Broadcaster: /amcl\\nAverage rate: 20.000\\n' in dot
    assert '"base_link" -> "laser"[label=" Broadcaster: /tf\\nStatic\\n"];' in dot
    assert '"Recorded at time: 13.000"' in dot and '}->"map";' in dot
    assert dot.count("->") == 5  # four links and the legend's edge


def test_dot_quotes_names() -> None:
    dot = frames_as_dot([FrameInfo(frame_id='we"ird', parent="p", static=True, authority="a")])
    assert '"we\\"ird"' in dot


def test_frames_from_a_buffer_dump() -> None:
    buf = Buffer()
    for sec in (1, 2, 3):
        buf.set_transform(transform_stamped("odom", "base_link", (sec, 0, 0, 0, 0, 0, 1),
                                            Time(sec=sec)), "/chassis")
    buf.set_transform_static(transform_stamped("base_link", "laser", (0, 0, 0, 0, 0, 0, 1)),
                             "/urdf")
    base, laser = frames_from_yaml(buf.all_frames_as_yaml(Time(sec=4)))
    assert (base.frame_id, base.parent, base.authority) == ("base_link", "odom", "/chassis")
    assert not base.static and base.rate > 0 and base.most_recent == Time(sec=3)
    assert base.delay == 1.0
    assert laser.static and laser.rate == 0.0 and laser.delay == 0.0
    assert frames_from_yaml("{}\n") == []
