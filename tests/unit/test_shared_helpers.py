"""The geometry helpers the services share exist once: one Pose2 (`zenros.se2`), one
yaw <-> quaternion pair (`zenros.tf.quaternion`, its message forms in `zenros.tf.convert`),
the angle wraps of `zenros.se2` (and ROS's of `zenros.tf.quaternion`), and one reader of a
QoS tag (`QoSProfile.from_tag`). A copy elsewhere is reported with its file and line."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SOURCES = sorted(p for d in ("shared", "services") for p in (ROOT / d).rglob("*.py"))

# (what, pattern, the files allowed to hold it)
RULES = [
    ("a Pose2 class", r"^class Pose2\b", {"shared/se2.py"}),
    ("a yaw from a quaternion", r"atan2\(\s*2(\.0)?\s*\*\s*\(\s*w\s*\*\s*z",
     {"shared/tf/quaternion.py"}),
    ("an angle wrap", r"math\.remainder\(|% \(?2(\.0)? \* (math\.)?pi\)?|% math\.tau",
     {"shared/se2.py", "shared/tf/quaternion.py"}),
    ("a QoS tag read by substring",
     r"\"(reliable|best_effort|transient_local|volatile|keep_all)\" in ", {"shared/qos.py"}),
]


@pytest.mark.parametrize(("what", "pattern", "allowed"), RULES, ids=[r[0] for r in RULES])
def test_one_copy(what: str, pattern: str, allowed: set[str]) -> None:
    rx = re.compile(pattern, re.MULTILINE)
    found = [f"{p.relative_to(ROOT)}:{p.read_text()[:m.start()].count(chr(10)) + 1}"
             for p in SOURCES if str(p.relative_to(ROOT)) not in allowed
             for m in rx.finditer(p.read_text())]
    assert not found, f"{what} outside {sorted(allowed)}: {found}"


@pytest.mark.parametrize(("text", "caught"), [
    ("class Pose2(NamedTuple):", True),
    ("yaw = math.atan2(2.0 * (w * z + x * y), 1 - 2 * (y * y + z * z))", True),
    ("a = math.remainder(a, math.tau)", True),
    ("a = (a + math.pi) % (2.0 * math.pi) - math.pi", True),
    ('latched = "transient_local" in tag', True),
    ("p = Pose2(1.0, 2.0, wrap_angle(t))", False),
])
def test_the_rules_catch_a_copy(text: str, caught: bool) -> None:
    assert any(re.search(r[1], text, re.MULTILINE) for r in RULES) == caught
