"""zenros.diagnostics' core, no Zenoh: the status helper, the standard tasks and the
aggregator's analyzers, with diagnostic_updater's and diagnostic_aggregator's answers."""

from __future__ import annotations

from typing import Any

import pytest
from zenros.clock import ManualClock
from zenros.diagnostics import (
    ERROR,
    OK,
    STALE,
    WARN,
    Aggregator,
    CompositeDiagnosticTask,
    DiagnosticStatusWrapper,
    FrequencyStatus,
    FrequencyStatusParam,
    FunctionDiagnosticTask,
    GenericAnalyzer,
    TimeStampStatus,
    TimeStampStatusParam,
    analyzers_from_params,
)
from zenros.diagnostics.aggregator import remove_leading_chaff
from zenros.diagnostics.tree import format_tree
from zenros.errors import ConfigError
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.diagnostic_msgs import DiagnosticStatus

S = 1_000_000_000


def st(name: str, level: int = OK, message: str = "ok") -> DiagnosticStatus:
    return DiagnosticStatus(name=name, level=level, message=message)


def values(s: DiagnosticStatus) -> dict[str, str]:
    return {kv.key: kv.value for kv in s.values}


# ------------------------------------------------------------------ DiagnosticStatusWrapper

def test_merge_summary_joins_messages_of_a_kind_and_keeps_the_worst() -> None:
    s = DiagnosticStatusWrapper()
    s.summary(OK, "fine")
    s.merge_summary(OK, "also fine")
    assert (s.level, s.message) == (OK, "fine; also fine")
    s.merge_summary(WARN, "hot")
    assert (s.level, s.message) == (WARN, "hot")
    s.mergeSummary(ERROR, "stalled")
    assert (s.level, s.message) == (ERROR, "hot; stalled")
    s.merge_summary(OK, "ignored")
    assert (s.level, s.message) == (ERROR, "hot; stalled")
    s.clear_summary()
    assert (s.level, s.message) == (OK, "")


def test_add_returns_the_value_and_summary_checks_levels() -> None:
    s = DiagnosticStatusWrapper()
    assert s.add("temp", 41.5) == 41.5 and values(s) == {"temp": "41.5"}
    with pytest.raises(ValueError):
        s.summary(7, "no such level")
    s.summary(b"\x01", "rclpy's bytes")
    assert s.level == WARN


def test_composite_task_merges_its_tasks() -> None:
    comp = CompositeDiagnosticTask("drive")
    comp.add_task(FunctionDiagnosticTask("a", lambda s: s.summary(WARN, "slow")))
    comp.add_task(FunctionDiagnosticTask("b", lambda s: (s.summary(OK, "fine"), s.add("k", 1))))
    out = comp.run(DiagnosticStatusWrapper(level=OK, message=""))
    assert (out.level, out.message) == (WARN, "slow") and values(out) == {"k": "1"}


# ------------------------------------------------------------------ FrequencyStatus

def test_frequency_status_levels() -> None:
    clock = ManualClock(Time(sec=100))
    fs = FrequencyStatus(FrequencyStatusParam({"min": 9.0, "max": 11.0}, 0.1, 5), clock=clock)
    first = fs.run(DiagnosticStatusWrapper())
    assert (first.level, first.message) == (ERROR, "No events recorded.")
    for _ in range(10):
        fs.tick()
    clock.advance(1.0)
    ok = fs.run(DiagnosticStatusWrapper())
    assert (ok.level, ok.message) == (OK, "Desired frequency met")
    assert values(ok)["Events in window"] == "10"
    assert "Target frequency (Hz)" not in values(ok)  # only when min == max
    assert values(ok)["Minimum acceptable frequency (Hz)"] == "8.100000"
    for _ in range(3):
        fs.tick()
    clock.advance(1.0)
    low = fs.run(DiagnosticStatusWrapper())  # window from t=100: 13 events in 2 s
    assert (low.level, low.message) == (WARN, "Frequency too low.")
    fast = FrequencyStatus(FrequencyStatusParam({"min": 1.0, "max": 2.0}), clock=clock)
    for _ in range(30):
        fast.tick()
    clock.advance(1.0)
    high = fast.run(DiagnosticStatusWrapper())
    assert (high.level, high.message) == (WARN, "Frequency too high.")
    assert values(high)["Maximum acceptable frequency (Hz)"] == "2.200000"


def test_frequency_param_checks() -> None:
    with pytest.raises(ValueError):
        FrequencyStatusParam({"min": 1}, window_size=0)
    with pytest.raises(ValueError):
        FrequencyStatusParam({"mn": 1})


# ------------------------------------------------------------------ TimeStampStatus

@pytest.mark.parametrize("stamp,level,message", [
    (None, WARN, "No data since last update."),
    (99.5, OK, "Timestamps are reasonable."),
    (102.0, ERROR, "Timestamps too far in future seen."),
    (90.0, ERROR, "Timestamps too far in past seen."),
    (0.0, ERROR, "Zero timestamp seen."),
])
def test_timestamp_status(stamp: float | None, level: int, message: str) -> None:
    clock = ManualClock(Time(sec=100))
    ts = TimeStampStatus(TimeStampStatusParam(), clock=clock)
    if stamp is not None:
        ts.tick(Time.from_seconds(stamp) if stamp else 0.0)
    out = ts.run(DiagnosticStatusWrapper())
    assert (out.level, out.message) == (level, message)
    again = ts.run(DiagnosticStatusWrapper())  # each run starts over
    assert (again.level, again.message) == (WARN, "No data since last update.")


# ------------------------------------------------------------------ the aggregator

def test_remove_leading_chaff() -> None:
    assert remove_leading_chaff("/Sensors/hokuyo: Connection", "hokuyo") == "/Sensors/Connection"
    assert remove_leading_chaff("/Sensors/other: x", "hokuyo") == "/Sensors/other: x"


def test_generic_analyzer_tree_and_header() -> None:
    a = GenericAnalyzer("Motors", startswith=["chassis: motor"], remove_prefix=["chassis"])
    agg = Aggregator([a])
    agg.add([st("chassis: motor left"), st("chassis: motor right", WARN, "hot"),
             st("nav: localisation")], 0)
    tree, top = agg.report(1 * S)
    names = [s.name for s in tree]
    assert names == ["/Motors", "/Motors/motor left", "/Motors/motor right", "/Other",
                     "/Other/nav: localisation"]
    assert (tree[0].level, tree[0].message) == (WARN, "Warning")
    assert values(tree[0]) == {"chassis: motor left": "ok", "chassis: motor right": "hot"}
    assert (top.name, top.level) == ("toplevel_state", WARN)


def test_silent_items_go_stale_and_the_header_errors() -> None:
    a = GenericAnalyzer("Power", contains=["battery", "charger"], timeout=5.0)
    agg = Aggregator([a])
    agg.add([st("chassis: battery")], 0)
    agg.add([st("chassis: charger")], 4 * S)
    tree, top = agg.report(6 * S)
    assert [s.level for s in tree] == [ERROR, STALE, OK]  # some stale: ERROR
    assert top.level == ERROR
    tree, top = agg.report(10 * S)
    assert [s.level for s in tree] == [STALE, STALE, STALE]  # all stale: STALE
    assert tree[0].message == "Stale" and top.level == STALE


def test_expected_items_missing_make_the_header_error() -> None:
    a = GenericAnalyzer("Laser", expected=["chassis: laser"], startswith=["chassis: scan"])
    agg = Aggregator([a])
    tree, _ = agg.report(0)
    assert [(s.name, s.level, s.message) for s in tree] == [
        ("/Laser", STALE, "Stale"), ("/Laser/chassis: laser", STALE, "Missing")]
    agg.add([st("chassis: scan rate")], 0)
    tree, top = agg.report(1)
    assert (tree[0].level, tree[0].message) == (ERROR, "Error")
    assert values(tree[0])["chassis: laser"] == "Missing" and top.level == ERROR
    agg.add([st("chassis: laser")], 1)
    tree, top = agg.report(2)
    assert tree[0].level == OK and top.level == OK


def test_num_items_regex_and_discard_stale() -> None:
    a = GenericAnalyzer("Cams", regex=[r"cam\d: .*"], num_items=2, discard_stale=True,
                        timeout=1.0)
    agg = Aggregator([a])
    agg.add([st("cam1: fps"), st("cam12x")], 0)
    tree, _ = agg.report(0)
    assert (tree[0].level, tree[0].message) == (ERROR, "Expected 2, found 1")
    tree, _ = agg.report(2 * S)  # the one item timed out and is dropped
    assert (tree[0].level, tree[0].message) == (ERROR, "No items found, expected 2")
    assert [s.name for s in tree] == ["/Cams", "/Other", "/Other/cam12x"]


def test_other_as_errors_and_an_empty_aggregator() -> None:
    agg = Aggregator([], other_as_errors=True)
    tree, top = agg.report(0)
    assert tree == [] and top.level == ERROR  # nothing at all: ERROR
    agg.add([st("x")], 0)
    tree, top = agg.report(0)
    assert tree[0].message == 'Unanalyzed items found in "Other"' and top.level == ERROR


def test_a_status_goes_to_every_matching_analyzer_under_the_base_path() -> None:
    a = GenericAnalyzer("A", startswith=["n"], base_path="/robot")
    b = GenericAnalyzer("B", contains=["x"], base_path="/robot")
    agg = Aggregator([a, b], base_path="/robot")
    agg.add([st("n: x/y")], 0)
    tree, _ = agg.report(0)
    assert [s.name for s in tree] == ["/robot/A", "/robot/A/n: x y", "/robot/B", "/robot/B/n: x y"]


def test_analyzers_from_params() -> None:
    params: dict[str, Any] = {
        "analyzers.motors.type": "diagnostic_aggregator/GenericAnalyzer",
        "analyzers.motors.path": "Motors",
        "analyzers.motors.startswith": "chassis: motor",
        "analyzers.motors.timeout": 2,
        "analyzers.power.type": "diagnostic_aggregator/GenericAnalyzer",
        "analyzers.power.path": "Power",
        "analyzers.power.contains": ["battery"],
        "pub_rate": 1.0,
    }
    motors, power = analyzers_from_params(params)
    assert (motors.path, motors.startswith, motors.timeout) == ("/Motors", ["chassis: motor"], 2.0)
    assert power.contains == ["battery"]


@pytest.mark.parametrize("params,match", [
    ({"analyzers.a.type": "diagnostic_aggregator/AnalyzerGroup", "analyzers.a.path": "A",
      "analyzers.a.contains": ["x"]}, "not supported"),
    ({"analyzers.a.type": "GenericAnalyzer", "analyzers.a.contains": ["x"]}, "path is missing"),
    ({"analyzers.a.type": "GenericAnalyzer", "analyzers.a.path": "A"}, "no way of matching"),
    ({"analyzers.a.type": "GenericAnalyzer", "analyzers.a.path": "A",
      "analyzers.a.regex": ["("]}, "bad regex"),
    ({"analyzers.a.colour": "red"}, "key one of"),
    ({"analyzers.a.timeout": "soon"}, "a float"),
])
def test_bad_analyzer_parameters_are_refused(params: dict[str, Any], match: str) -> None:
    with pytest.raises(ConfigError, match=match):
        analyzers_from_params(params)


def test_format_tree_indents_by_path() -> None:
    text = format_tree([st("/Motors"), st("/Motors/left", WARN, "hot")],
                       DiagnosticStatus(level=WARN), values=False)
    lines = text.splitlines()
    assert lines[0].split() == ["(robot)", "WARNING"]
    assert lines[1].split()[:2] == ["Motors", "OK"]
    assert lines[2].startswith("  left") and lines[2].split()[1:] == ["WARNING", "hot"]
