"""Blockly programs (docs/robot-api.md §10), run by interpreting their block XML.

`parse` reads a program's ``blocklyxml`` into `Block` trees and refuses, naming it, a block
type outside the documented set (docs/tasks.md, "Blockly programs"), a missing field or a
malformed number; `Runner` walks the trees, each robot block a call of the `Robot` (the same
calls the task actions make), polling ``cancelled`` between steps. Received data is never run
as code: the program's ``py`` text is not even read.
"""

from __future__ import annotations

import math
import threading
import xml.etree.ElementTree as ET
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Final

from .robot import Feedback, Outcome, Robot

__all__ = ["MAX_STEPS", "MAX_XML", "STATEMENTS", "VALUES", "Block", "ProgramError", "Runner",
           "parse"]

MAX_XML: Final = 256 * 1024  # characters
MAX_STEPS: Final = 100_000  # blocks run, loops' rounds included
MAX_DEPTH: Final = 64  # blocks nested in one another
POLL: Final = 0.01

# block type -> its required fields (statements: do something; values: give a value)
STATEMENTS: Final[dict[str, tuple[str, ...]]] = {
    "robot_move": ("DISTANCE", "ANGLE"),
    "robot_go_to_nav_point": ("INDEX",),
    "robot_wait": (),            # value SECONDS (or field SECONDS)
    "robot_speak": (),           # value TEXT (or field TEXT)
    "robot_set_io": ("PORT", "LEVEL"),
    "robot_move_slide": ("POSE",),
    "robot_move_lift": ("POSE",),
    "controls_repeat_ext": (),   # value TIMES, statement DO
    "controls_repeat": ("TIMES",),
    "controls_whileUntil": ("MODE",),
    "controls_if": (),
    "controls_flow_statements": ("FLOW",),
}
VALUES: Final[dict[str, tuple[str, ...]]] = {
    "math_number": ("NUM",),
    "logic_boolean": ("BOOL",),
    "text": ("TEXT",),
    "logic_compare": ("OP",),
    "logic_operation": ("OP",),
    "logic_negate": (),
    "math_arithmetic": ("OP",),
    "robot_battery": (),
    "robot_io": ("BOARD", "PORT"),
}
_NUMBER_FIELDS: Final = {"DISTANCE", "ANGLE", "INDEX", "PORT", "LEVEL", "POSE", "TIMES", "NUM",
                         "SECONDS"}


class ProgramError(ValueError):
    """A program that cannot be read or run; the text says where."""


@dataclass(frozen=True)
class Block:
    type: str
    id: str
    fields: dict[str, str] = field(default_factory=dict)
    values: dict[str, Block] = field(default_factory=dict)
    statements: dict[str, Block] = field(default_factory=dict)
    next: Block | None = None

    def number(self, name: str) -> float:
        return float(self.fields[name])


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _block(el: ET.Element, depth: int) -> Block:
    if depth > MAX_DEPTH:
        raise ProgramError(f"blocks nested over {MAX_DEPTH} deep")
    kind = el.get("type", "")
    ident = el.get("id", "")
    where = f"block {kind!r}" + (f" ({ident})" if ident else "")
    if kind not in STATEMENTS and kind not in VALUES:
        raise ProgramError(f"{where}: not a block this robot runs; blocks: "
                           + ", ".join([*STATEMENTS, *VALUES]))
    fields: dict[str, str] = {}
    values: dict[str, Block] = {}
    statements: dict[str, Block] = {}
    nxt: Block | None = None
    for child in el:
        tag, name = _local(child.tag), child.get("name", "")
        if tag == "field":
            fields[name] = (child.text or "").strip()
        elif tag in ("value", "statement"):
            inner = [c for c in child if _local(c.tag) == "block"] or \
                [c for c in child if _local(c.tag) == "shadow"]
            if inner:
                (values if tag == "value" else statements)[name] = _block(inner[0], depth + 1)
        elif tag == "next":
            inner = [c for c in child if _local(c.tag) == "block"]
            if inner:
                nxt = _block(inner[0], depth)
    required = STATEMENTS.get(kind) or VALUES.get(kind) or ()
    for name in required:
        if name not in fields:
            raise ProgramError(f"{where}: missing field {name}")
    for name, text in fields.items():
        if name in _NUMBER_FIELDS:
            try:
                number = float(text)
            except ValueError:
                raise ProgramError(f"{where}: field {name} is not a number: {text!r}") \
                    from None
            if not math.isfinite(number):
                raise ProgramError(f"{where}: field {name} must be finite")
    return Block(kind, ident, fields, values, statements, nxt)


def parse(xml: str) -> list[Block]:
    """The program's top-level chains of blocks (the order the editor lists them).

    Raises:
        ProgramError: too long, not XML, not a Blockly document, or a block as above.
    """
    if len(xml) > MAX_XML:
        raise ProgramError(f"blocklyxml is over {MAX_XML} characters")
    if "<!DOCTYPE" in xml or "<!ENTITY" in xml:
        raise ProgramError("blocklyxml: a DOCTYPE or ENTITY is not allowed")
    try:
        root = ET.fromstring(xml)
    except ET.ParseError as exc:
        raise ProgramError(f"blocklyxml is not XML: {exc}") from None
    if _local(root.tag) != "xml":
        raise ProgramError("blocklyxml: the document's root must be <xml>")
    chains = [_block(el, 0) for el in root if _local(el.tag) == "block"]
    for chain in chains:
        if chain.type in VALUES:
            raise ProgramError(f"block {chain.type!r} gives a value: it must sit in another "
                               "block")
    return chains


class _Stop(Exception):
    def __init__(self, outcome: Outcome) -> None:
        super().__init__(outcome.reason)
        self.outcome = outcome


class _Break(Exception):
    pass


class _Continue(Exception):
    pass


Value = float | bool | str


class Runner:
    """Runs parsed chains on ``robot`` until they end, a robot call fails, ``cancelled``
    says so, or ``max_steps`` blocks have run."""

    def __init__(self, robot: Robot, cancelled: Callable[[], bool],
                 max_steps: int = MAX_STEPS) -> None:
        self.robot = robot
        self.cancelled = cancelled
        self.max_steps = max_steps
        self.steps = 0

    def run(self, chains: list[Block]) -> Outcome:
        try:
            for chain in chains:
                self._chain(chain)
        except _Stop as stop:
            return stop.outcome
        except (_Break, _Continue):
            return Outcome("error", "a break or continue block outside a loop")
        return Outcome("complete", f"program ran {self.steps} blocks")

    # ------------------------------------------------------------------ statements

    def _tick(self, block: Block) -> None:
        if self.cancelled():
            raise _Stop(Outcome("preempted"))
        self.steps += 1
        if self.steps > self.max_steps:
            raise _Stop(Outcome("error", f"the program ran over {self.max_steps} blocks "
                                         f"(at {block.type} {block.id})"))

    def _chain(self, block: Block | None) -> None:
        while block is not None:
            self._tick(block)
            self._statement(block)
            block = block.next

    def _must(self, out: Outcome, block: Block) -> None:
        if out.name != "complete":
            reason = f"{block.type} {block.id}: {out.reason}".strip()
            raise _Stop(Outcome(out.name, reason))

    def _statement(self, b: Block) -> None:
        kind = b.type
        robot, cancelled = self.robot, self.cancelled
        if kind == "robot_move":
            if abs(b.number("DISTANCE")) > 1e-6:
                self._must(robot.drive(b.number("DISTANCE"), 0.3, 0.0, _nothing, cancelled), b)
            if abs(b.number("ANGLE")) > 1e-6:
                self._must(robot.spin(b.number("ANGLE"), 0.0, _nothing, cancelled), b)
        elif kind == "robot_go_to_nav_point":
            try:
                x, y, theta = robot.nav_point(int(b.number("INDEX")), "", "")
            except LookupError as exc:
                raise _Stop(Outcome("error", f"{kind} {b.id}: {exc}")) from None
            self._must(robot.navigate(x, y, theta, 0.0, _no_feedback, cancelled), b)
        elif kind == "robot_wait":
            self._wait(float(self._number_of(b, "SECONDS")))
        elif kind == "robot_speak":
            robot.say(str(self._value_of(b, "TEXT")))
        elif kind == "robot_set_io":
            self._must(robot.set_io(int(b.number("PORT")), int(b.number("LEVEL"))), b)
        elif kind in ("robot_move_slide", "robot_move_lift"):
            axis = "slide" if kind == "robot_move_slide" else "jacking"
            self._must(robot.move_axis(axis, 3, b.number("POSE"), 0.0, 0.0, _nothing,
                                       cancelled), b)
        elif kind in ("controls_repeat_ext", "controls_repeat"):
            times = b.number("TIMES") if kind == "controls_repeat" else \
                self._number_of(b, "TIMES")
            for _ in range(max(0, int(times))):
                if not self._round(b):
                    break
        elif kind == "controls_whileUntil":
            until = b.fields["MODE"] == "UNTIL"
            while bool(self._value_of(b, "BOOL", False)) != until:
                self._tick(b)
                if not self._round(b):
                    break
        elif kind == "controls_if":
            self._if(b)
        elif kind == "controls_flow_statements":
            raise _Break() if b.fields["FLOW"] == "BREAK" else _Continue()
        else:
            raise _Stop(Outcome("error", f"block {kind!r} gives a value: it cannot stand "
                                         "alone"))

    def _round(self, b: Block) -> bool:
        """One round of a loop's DO; False after a break."""
        try:
            self._chain(b.statements.get("DO"))
        except _Break:
            return False
        except _Continue:
            pass
        return True

    def _if(self, b: Block) -> None:
        n = 0
        while f"IF{n}" in b.values or f"DO{n}" in b.statements:
            if self._value_of(b, f"IF{n}", False):
                self._chain(b.statements.get(f"DO{n}"))
                return
            n += 1
        self._chain(b.statements.get("ELSE"))

    def _wait(self, seconds: float) -> None:
        end = self.robot.now() + seconds
        event = threading.Event()
        while self.robot.now() < end:
            if self.cancelled():
                raise _Stop(Outcome("preempted"))
            event.wait(POLL)

    # ------------------------------------------------------------------ values

    def _value_of(self, b: Block, name: str, default: Value | None = None) -> Value:
        if name in b.values:
            return self._value(b.values[name])
        if name in b.fields:
            return b.fields[name]
        if default is not None:
            return default
        raise _Stop(Outcome("error", f"{b.type} {b.id}: nothing plugged into {name}"))

    def _number_of(self, b: Block, name: str) -> float:
        v = self._value_of(b, name)
        try:
            return float(v)
        except ValueError:
            raise _Stop(Outcome("error", f"{b.type} {b.id}: {name} is not a number: "
                                         f"{v!r}")) from None

    def _value(self, b: Block) -> Value:
        self._tick(b)
        kind = b.type
        if kind == "math_number":
            return b.number("NUM")
        if kind == "logic_boolean":
            return b.fields["BOOL"] == "TRUE"
        if kind == "text":
            return b.fields["TEXT"]
        if kind == "logic_negate":
            return not self._value_of(b, "BOOL", False)
        if kind == "logic_operation":
            a = bool(self._value_of(b, "A", False))
            return (a and bool(self._value_of(b, "B", False))) if b.fields["OP"] == "AND" \
                else (a or bool(self._value_of(b, "B", False)))
        if kind == "logic_compare":
            return _compare(b.fields["OP"], self._value_of(b, "A"), self._value_of(b, "B"))
        if kind == "math_arithmetic":
            return _arithmetic(b, self._number_of(b, "A"), self._number_of(b, "B"))
        if kind == "robot_battery":
            level = self.robot.battery_percent()
            if level is None:
                raise _Stop(Outcome("error", f"robot_battery {b.id}: no battery reading"))
            return level
        if kind == "robot_io":
            return float(self._io(b))
        raise _Stop(Outcome("error", f"block {kind!r} gives no value"))

    def _io(self, b: Block) -> int:
        try:
            main, ext_out, ext_in = self.robot.io_levels()
        except LookupError as exc:
            raise _Stop(Outcome("error", f"robot_io {b.id}: {exc}")) from None
        board = {"main": main, "ext_out": ext_out, "ext_in": ext_in}.get(b.fields["BOARD"])
        if board is None:
            raise _Stop(Outcome("error", f"robot_io {b.id}: BOARD is main, ext_out or ext_in"))
        port = int(b.number("PORT")) - (1 if b.fields["BOARD"] == "main" else 0)
        if not 0 <= port < len(board):
            raise _Stop(Outcome("error", f"robot_io {b.id}: no port {b.fields['PORT']} on "
                                         f"{b.fields['BOARD']}"))
        return board[port]


def _compare(op: str, a: Value, b: Value) -> bool:
    if op == "EQ":
        return a == b
    if op == "NEQ":
        return a != b
    try:
        x, y = float(a), float(b)
    except ValueError:
        raise _Stop(Outcome("error", f"compare {op}: {a!r} and {b!r} are not numbers")) \
            from None
    return {"LT": x < y, "LTE": x <= y, "GT": x > y, "GTE": x >= y}.get(op, False)


def _arithmetic(b: Block, x: float, y: float) -> float:
    op = b.fields["OP"]
    if op == "DIVIDE" and y == 0:
        raise _Stop(Outcome("error", f"math_arithmetic {b.id}: division by zero"))
    ops = {"ADD": x + y, "MINUS": x - y, "MULTIPLY": x * y}
    if op in ops:
        return ops[op]
    if op == "DIVIDE":
        return x / y
    raise _Stop(Outcome("error", f"math_arithmetic {b.id}: OP {op} is not ADD, MINUS, "
                                 "MULTIPLY or DIVIDE"))


def _nothing(_value: float) -> None:
    pass


def _no_feedback(_fb: Feedback) -> None:
    pass
