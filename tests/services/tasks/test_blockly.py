"""Blockly programs: the block XML parsed with refusals that name the block, and run by the
interpreter over a robot double: moves, nav points, IO, speech, waits, loops with break and
continue, conditions on battery and IO, arithmetic; cancel, a step budget, failures passed on."""

from __future__ import annotations

import itertools
from collections.abc import Callable
from typing import Any

import pytest
from zenros.services.tasks.blockly import ProgramError, Runner, parse
from zenros.services.tasks.robot import Outcome

NS = 'xmlns="https://developers.google.com/blockly/xml"'


class Robot:
    def __init__(self) -> None:
        self.calls: list[tuple[Any, ...]] = []
        self.battery: float | None = 80.0
        self.io = [0, 0, 0]
        self.outcome = Outcome("complete")
        self.clock = 0.0

    def now(self) -> float:
        self.clock += 0.05  # each look at the clock is 50 ms of simulated time
        return self.clock

    def drive(self, distance: float, speed: float, timeout: float,
              progress: Callable[[float], None], cancelled: Callable[[], bool]) -> Outcome:
        self.calls.append(("drive", distance))
        return self.outcome

    def spin(self, angle: float, timeout: float, progress: Callable[[float], None],
             cancelled: Callable[[], bool]) -> Outcome:
        self.calls.append(("spin", angle))
        return self.outcome

    def nav_point(self, index: int, map_name: str, path: str) -> tuple[float, float, float]:
        if index > 2:
            raise LookupError(f"no nav point {index}: path 'p' has 3 (0..2)")
        return float(index), 0.0, 0.0

    def navigate(self, x: float, y: float, theta: float, timeout: float, feedback: Any,
                 cancelled: Callable[[], bool]) -> Outcome:
        self.calls.append(("navigate", x))
        return self.outcome

    def set_io(self, port: int, level: int) -> Outcome:
        self.calls.append(("io", port, level))
        self.io[port - 1] = level
        return self.outcome

    def say(self, text: str) -> None:
        self.calls.append(("say", text))

    def move_axis(self, axis: str, mode: int, target: float, speed: float, duration: float,
                  progress: Any, cancelled: Any) -> Outcome:
        self.calls.append((axis, target))
        return self.outcome

    def battery_percent(self) -> float | None:
        return self.battery

    def io_levels(self) -> tuple[list[int], list[int], list[int]]:
        return list(self.io), [0] * 8, [1] + [0] * 15


def run(xml: str, robot: Robot | None = None, cancelled: Callable[[], bool] = lambda: False,
        max_steps: int = 100_000) -> tuple[Outcome, Robot]:
    robot = robot or Robot()
    return Runner(robot, cancelled, max_steps).run(parse(xml)), robot  # type: ignore[arg-type]


def num(n: float) -> str:
    return f'<block type="math_number"><field name="NUM">{n}</field></block>'


def text(t: str) -> str:
    return f'<block type="text"><field name="TEXT">{t}</field></block>'


def test_a_program_drives_speaks_and_sets_io_in_order() -> None:
    out, robot = run(f"""<xml {NS}>
      <block type="robot_move" id="m1"><field name="DISTANCE">0.5</field>
        <field name="ANGLE">1.57</field>
        <next><block type="robot_go_to_nav_point"><field name="INDEX">2</field>
        <next><block type="robot_set_io"><field name="PORT">1</field><field name="LEVEL">1</field>
        <next><block type="robot_speak"><value name="TEXT">{text("hello")}</value>
        <next><block type="robot_move_lift"><field name="POSE">0.03</field>
        <next><block type="robot_wait"><value name="SECONDS">{num(0.2)}</value>
        </block></next></block></next></block></next></block></next></block></next>
      </block></xml>""")
    assert out.name == "complete", out
    assert robot.calls == [("drive", 0.5), ("spin", 1.57), ("navigate", 2.0), ("io", 1, 1),
                           ("say", "hello"), ("jacking", 0.03)]


def test_loops_conditions_and_values() -> None:
    out, robot = run(f"""<xml {NS}><block type="controls_repeat_ext">
      <value name="TIMES">{num(5)}</value>
      <statement name="DO"><block type="controls_if">
        <mutation elseif="1" else="1"/>
        <value name="IF0"><block type="logic_compare"><field name="OP">GT</field>
          <value name="A"><block type="robot_battery"/></value>
          <value name="B">{num(50)}</value></block></value>
        <statement name="DO0"><block type="robot_speak"><value name="TEXT">{text("ok")}</value>
          <next><block type="controls_flow_statements"><field name="FLOW">BREAK</field>
          </block></next></block></statement>
      </block></statement></block></xml>""")
    assert out.name == "complete" and robot.calls == [("say", "ok")]  # broke out at once
    # while an output is low: set it, counting rounds with arithmetic in the speech
    out, robot = run(f"""<xml {NS}><block type="controls_whileUntil"><field name="MODE">WHILE</field>
      <value name="BOOL"><block type="logic_compare"><field name="OP">EQ</field>
        <value name="A"><block type="robot_io"><field name="BOARD">main</field>
          <field name="PORT">2</field></block></value>
        <value name="B">{num(0)}</value></block></value>
      <statement name="DO"><block type="robot_set_io"><field name="PORT">2</field>
        <field name="LEVEL">1</field></block></statement></block>
      <block type="controls_if"><value name="IF0"><block type="logic_operation">
        <field name="OP">AND</field>
        <value name="A"><block type="robot_io"><field name="BOARD">ext_in</field>
          <field name="PORT">0</field></block></value>
        <value name="B"><block type="logic_negate"><value name="BOOL">
          <block type="logic_boolean"><field name="BOOL">FALSE</field></block></value>
        </block></value></block></value>
        <statement name="DO0"><block type="robot_speak"><value name="TEXT">
          <block type="math_arithmetic"><field name="OP">MULTIPLY</field>
            <value name="A">{num(6)}</value><value name="B">{num(7)}</value></block>
        </value></block></statement>
        <statement name="ELSE"><block type="robot_speak"><field name="TEXT">no</field>
        </block></statement></block></xml>""")
    assert out.name == "complete", out
    assert robot.calls == [("io", 2, 1), ("say", "42.0")]


def test_failures_cancel_and_the_step_budget() -> None:
    robot = Robot()
    robot.outcome = Outcome("error", "drive 1.00 m: aborted (error 723: collision ahead)")
    out, _ = run(f"""<xml {NS}><block type="robot_move" id="m9"><field name="DISTANCE">1</field>
      <field name="ANGLE">0</field></block></xml>""", robot)
    assert out.name == "error" and out.reason.startswith("robot_move m9: drive 1.00 m")
    out, _ = run(f"""<xml {NS}><block type="robot_go_to_nav_point" id="g"><field name="INDEX">7
      </field></block></xml>""")
    assert out.name == "error" and "no nav point 7" in out.reason
    forever = f"""<xml {NS}><block type="controls_whileUntil"><field name="MODE">UNTIL</field>
      <value name="BOOL"><block type="logic_boolean"><field name="BOOL">FALSE</field></block>
      </value><statement name="DO"><block type="robot_wait"><field name="SECONDS">0.01</field>
      </block></statement></block></xml>"""
    out, _ = run(forever, max_steps=500)
    assert out.name == "error" and "over 500 blocks" in out.reason
    looks = itertools.count()  # cancelled at the 50th look, however fast the box runs
    out, _ = run(forever, cancelled=lambda: next(looks) >= 50)
    assert out.name == "preempted", out
    out, _ = run(f"""<xml {NS}><block type="robot_speak"><value name="TEXT">
      <block type="math_arithmetic"><field name="OP">DIVIDE</field><value name="A">{num(1)}</value>
      <value name="B">{num(0)}</value></block></value></block></xml>""")
    assert out.name == "error" and "division by zero" in out.reason
    robot = Robot()
    robot.battery = None
    out, _ = run(f"""<xml {NS}><block type="controls_if"><value name="IF0">
      <block type="robot_battery"/></value></block></xml>""", robot)
    assert out.name == "error" and "no battery reading" in out.reason


@pytest.mark.parametrize(("xml", "words"), [
    ("<xml><block type='os_system'/></xml>", "'os_system': not a block this robot runs"),
    ("<xml><block type='robot_move'><field name='DISTANCE'>1</field></block></xml>",
     "missing field ANGLE"),
    ("<xml><block type='robot_move'><field name='DISTANCE'>x</field>"
     "<field name='ANGLE'>0</field></block></xml>", "DISTANCE is not a number"),
    ("<xml><block type='robot_move'><field name='DISTANCE'>nan</field>"
     "<field name='ANGLE'>0</field></block></xml>", "must be finite"),
    ("<xml><block type='math_number'><field name='NUM'>1</field></block></xml>",
     "must sit in another block"),
    ("<root/>", "root must be <xml>"),
    ("<xml><block", "not XML"),
    ('<!DOCTYPE x [<!ENTITY a "aaaa">]><xml>&a;</xml>', "DOCTYPE"),
    ("<xml>" + "<block type='controls_repeat'><field name='TIMES'>1</field>"
     "<statement name='DO'>" * 70 + "</statement></block>" * 70 + "</xml>", "nested over"),
])
def test_programs_that_are_refused(xml: str, words: str) -> None:
    with pytest.raises(ProgramError, match=words.replace("(", r"\(").replace(")", r"\)")):
        parse(xml)
