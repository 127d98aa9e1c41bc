"""``$(expr ...)``: a small expression language over launch arguments, never Python.

    $(expr speed != 1)
    $(expr use_sim_time or speed != 1)
    $(expr robot == 'robot1' and not (rate > 10))

    $(expr 1.0 + (k - 1) * 0.8)

A bare name is the value of an argument; literals are numbers, ``'quoted'`` or ``"quoted"``
strings, and ``true``/``false``. Operators, loosest first: ``or``, ``and``, ``not``, one
comparison (``==``, ``!=``, ``<``, ``<=``, ``>``, ``>=``), then arithmetic on numbers (``+``
``-``, then ``*`` ``/`` ``%``, and a leading ``-``); parentheses group. Arithmetic gives a
number: a whole one is written without a decimal point (``3``, not ``3.0``). Two values that
are both numbers compare as numbers (``10 == 10.0``), two that are both booleans
(``true/false/yes/no/on/off/1/0``) as booleans, anything else as text; ``<`` and the other
orderings need numbers. ``and``, ``or`` and ``not`` need booleans. The result is ``true`` or
``false`` (or the value itself for an expression without an operator).

An argument's value is only ever data: it is compared, never parsed as part of the expression.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass

__all__ = ["ExprError", "evaluate"]

_TOKEN = re.compile(
    r"\s*(?:(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
    r"|(?P<str>'[^']*'|\"[^\"]*\")"
    r"|(?P<op>==|!=|<=|>=|<|>|\(|\)|[-+*/%])"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*))"
)
_TRUE = ("true", "yes", "on", "1")
_FALSE = ("false", "no", "off", "0")
_COMPARE = ("==", "!=", "<", "<=", ">", ">=")


class ExprError(ValueError):
    """A malformed expression, an unknown argument, or an operation on the wrong kind."""


@dataclass(frozen=True)
class _Tok:
    kind: str  # num, str, op, name, word (and/or/not/true/false), end
    text: str


def _tokens(text: str) -> list[_Tok]:
    out: list[_Tok] = []
    pos = 0
    while pos < len(text):
        if text[pos:].strip() == "":
            break
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            raise ExprError(f"cannot read {text[pos:].strip()!r}")
        kind = m.lastgroup or ""
        value = m.group(kind)
        if kind == "name" and value in ("and", "or", "not", "true", "false"):
            kind = "word"
        out.append(_Tok(kind, value))
        pos = m.end()
    out.append(_Tok("end", ""))
    return out


def _number(text: str) -> float | None:
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def _boolean(text: str) -> bool | None:
    low = text.strip().lower()
    return True if low in _TRUE else False if low in _FALSE else None


def _text(value: str | bool) -> str:
    return ("true" if value else "false") if isinstance(value, bool) else value


class _Parser:
    def __init__(self, text: str, names: Mapping[str, str]) -> None:
        self.toks = _tokens(text)
        self.i = 0
        self.names = names

    def peek(self) -> _Tok:
        return self.toks[self.i]

    def take(self) -> _Tok:
        tok = self.toks[self.i]
        self.i += 1
        return tok

    def parse(self) -> str | bool:
        value = self.or_()
        if self.peek().kind != "end":
            raise ExprError(f"unexpected {self.peek().text!r}")
        return value

    def or_(self) -> str | bool:
        left = self.and_()
        while self.peek().text == "or" and self.peek().kind == "word":
            self.take()
            right = self.and_()
            left = _truth(left, "or") | _truth(right, "or")
        return left

    def and_(self) -> str | bool:
        left = self.not_()
        while self.peek().text == "and" and self.peek().kind == "word":
            self.take()
            right = self.not_()
            left = _truth(left, "and") & _truth(right, "and")
        return left

    def not_(self) -> str | bool:
        if self.peek().kind == "word" and self.peek().text == "not":
            self.take()
            return not _truth(self.not_(), "not")
        return self.compare()

    def compare(self) -> str | bool:
        left = self.sum()
        if self.peek().kind == "op" and self.peek().text in _COMPARE:
            op = self.take().text
            return _compare(left, op, self.sum())
        return left

    def sum(self) -> str | bool:
        left = self.product()
        while self.peek().kind == "op" and self.peek().text in "+-":
            op = self.take().text
            left = _arith(left, op, self.product())
        return left

    def product(self) -> str | bool:
        left = self.unary()
        while self.peek().kind == "op" and self.peek().text in "*/%":
            op = self.take().text
            left = _arith(left, op, self.unary())
        return left

    def unary(self) -> str | bool:
        if self.peek().kind == "op" and self.peek().text in "+-":
            op = self.take().text
            return _arith("0", op, self.unary())
        return self.atom()

    def atom(self) -> str | bool:
        tok = self.take()
        if tok.kind == "num":
            return tok.text
        if tok.kind == "str":
            return tok.text[1:-1]
        if tok.kind == "word" and tok.text in ("true", "false"):
            return tok.text == "true"
        if tok.kind == "name":
            if tok.text not in self.names:
                known = ", ".join(self.names) or "none"
                raise ExprError(f"no such argument {tok.text!r}; declared: {known}")
            return self.names[tok.text]
        if tok.kind == "op" and tok.text == "(":
            value = self.or_()
            if self.take().text != ")":
                raise ExprError("missing ')'")
            return value
        raise ExprError("unexpected end" if tok.kind == "end" else f"unexpected {tok.text!r}")


def _truth(value: str | bool, op: str) -> bool:
    if isinstance(value, bool):
        return value
    b = _boolean(value)
    if b is None:
        raise ExprError(f"'{op}' needs true or false, got {value!r}")
    return b


def _arith(a: str | bool, op: str, b: str | bool) -> str:
    x = None if isinstance(a, bool) else _number(a)
    y = None if isinstance(b, bool) else _number(b)
    if x is None or y is None:
        raise ExprError(f"'{op}' needs two numbers, got {_text(a)!r} and {_text(b)!r}")
    if op in "/%" and y == 0:
        raise ExprError(f"'{op}' by zero")
    value = {"+": x + y, "-": x - y, "*": x * y, "/": x / y if y else 0.0,
             "%": math.fmod(x, y) if y else 0.0}[op]
    if not math.isfinite(value):
        raise ExprError(f"{_text(a)} {op} {_text(b)} is not a finite number")
    return str(int(value)) if value.is_integer() and abs(value) < 2**53 else repr(value)


def _compare(a: str | bool, op: str, b: str | bool) -> bool:
    na = None if isinstance(a, bool) else _number(a)
    nb = None if isinstance(b, bool) else _number(b)
    if na is not None and nb is not None:
        x: float | bool | str = na
        y: float | bool | str = nb
    elif op not in ("==", "!="):
        raise ExprError(f"'{op}' needs two numbers, got {_text(a)!r} and {_text(b)!r}")
    else:
        ba = a if isinstance(a, bool) else _boolean(a)
        bb = b if isinstance(b, bool) else _boolean(b)
        if ba is not None and bb is not None:
            x, y = ba, bb
        else:
            x, y = _text(a), _text(b)
    if op == "==":
        return x == y
    if op == "!=":
        return x != y
    assert isinstance(x, float) and isinstance(y, float)
    return {"<": x < y, "<=": x <= y, ">": x > y, ">=": x >= y}[op]


def evaluate(text: str, names: Mapping[str, str]) -> str:
    """The value of ``text`` with ``names`` (argument values) bound: ``true``, ``false`` or
    a value.

    Raises:
        ExprError: a malformed expression, an unknown name, or a wrong kind of operand.
    """
    if not text.strip():
        raise ExprError("empty expression")
    return _text(_Parser(text, names).parse())
