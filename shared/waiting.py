"""Waiting on a condition in a test: `wait_for` and `wait_until`, and `Waited`, what they saw.

``assert wait_for(lambda: len(got) >= 3, 10)`` keeps working as it always has (the result is
truthy when the condition came true), and when it fails pytest prints the result's repr
beside the assert: what it waited for (the lambda's source, a function's name, or the
``what`` given), how long, and the condition's last value::

    AssertionError: assert <timed out after 10 s waiting for `len(got) >= 3`: last False, 402 polls>

`wait_until` is the raising form, for a wait that is a step rather than the thing a test
checks: `WaitTimeout` (an AssertionError) with the same text.
"""

from __future__ import annotations

import ast
import asyncio
import functools
import reprlib
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

__all__ = ["WaitTimeout", "Waited", "describe", "wait_for", "wait_for_async", "wait_until"]

_REPR = reprlib.Repr()
_REPR.maxstring = 160
_REPR.maxother = 160
_REPR.maxlist = _REPR.maxtuple = _REPR.maxset = _REPR.maxdict = 8
_REPR.maxlevel = 3


class WaitTimeout(AssertionError):
    """`wait_until` ran out of time; the message says what it waited for and saw."""


@dataclass(eq=False)
class Waited:
    """What a wait saw. Truthy (and ``== True``) when the condition came true, falsy (and
    ``== False``) when the time ran out; its repr names the condition, the time and the last
    value, so a failing ``assert wait_for(...)`` explains itself."""

    ok: bool
    """The condition came true in time."""
    value: Any
    """The condition's last value (its true value on success)."""
    elapsed: float
    """Seconds waited."""
    timeout: float
    polls: int
    pred: Callable[..., Any] = field(repr=False)
    what: str | None = None
    """What was waited for, as given; else the condition's source (`describe`)."""
    _last: str = field(default="", repr=False)

    def __post_init__(self) -> None:
        if not self.ok:  # the value may change later: say what it was at the time
            self._last = _REPR.repr(self.value)

    def __bool__(self) -> bool:
        return self.ok

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Waited):
            return self.ok == other.ok
        if isinstance(other, bool):
            return self.ok == other
        return NotImplemented

    def __hash__(self) -> int:
        return hash(self.ok)

    @property
    def description(self) -> str:
        """What was waited for: the ``what`` given, or the condition's source."""
        return self.what or describe(self.pred)

    def __repr__(self) -> str:
        if self.ok:
            return (f"<waited {self.elapsed:.2f} s for {self.description}: "
                    f"{_REPR.repr(self.value)}>")
        return (f"<timed out after {self.timeout:g} s waiting for {self.description}: "
                f"last {self._last}, {self.polls} polls>")

    __str__ = __repr__

    def check(self) -> Waited:
        """Itself if the condition came true, else `WaitTimeout` saying what it waited for."""
        if not self.ok:
            raise WaitTimeout(repr(self))
        return self


class _Polling:
    """One wait's state: `step` calls the condition once, and answers the `Waited` once it
    came true or the time ran out (None: poll again)."""

    def __init__(self, pred: Callable[[], Any], timeout: float, what: str | None) -> None:
        self.pred, self.timeout, self.what = pred, timeout, what
        self.start = time.monotonic()
        self.polls = 0

    def step(self) -> Waited | None:
        value = self.pred()
        self.polls += 1
        elapsed = time.monotonic() - self.start
        if value or elapsed >= self.timeout:
            return Waited(bool(value), value, elapsed, self.timeout, self.polls, self.pred,
                          self.what)
        return None


def wait_for(pred: Callable[[], Any], timeout: float = 5.0, interval: float = 0.005, *,
             what: str | None = None) -> Waited:
    """Poll ``pred`` every ``interval`` s until it returns something true, for ``timeout`` s
    at most: a `Waited`, false when the time ran out (``what`` names the condition in its
    repr; default the lambda's source or the function's name)."""
    polling = _Polling(pred, timeout, what)
    while (done := polling.step()) is None:
        time.sleep(interval)
    return done


def wait_until(pred: Callable[[], Any], timeout: float = 5.0, interval: float = 0.005, *,
               what: str | None = None) -> Waited:
    """`wait_for` that raises `WaitTimeout` (an AssertionError naming the condition, the time
    and the last value) when the time runs out.

    Raises:
        WaitTimeout: ``pred`` did not come true within ``timeout`` s.
    """
    return wait_for(pred, timeout, interval, what=what).check()


async def wait_for_async(pred: Callable[[], Any], timeout: float = 5.0, *,
                         what: str | None = None) -> Waited:
    """`wait_for` for a coroutine: polls ``pred`` between ``asyncio.sleep``s."""
    polling = _Polling(pred, timeout, what)
    while (done := polling.step()) is None:
        await asyncio.sleep(0.005)
    return done


# ---------------------------------------------------------------- what a condition is


def describe(pred: Callable[..., Any]) -> str:
    """A condition as a reader knows it: a lambda's source in backquotes (`` `len(got) > 2` ``),
    a function's or method's name with ``()``, else its repr."""
    code = getattr(pred, "__code__", None)
    if code is None:
        name = getattr(pred, "__qualname__", None)
        return f"{name}()" if name else repr(pred)
    if code.co_name != "<lambda>":
        return f"{getattr(pred, '__qualname__', code.co_name)}()"
    body = _lambda_body(code.co_filename, code.co_firstlineno, _first_position(code))
    return f"`{body}`" if body else f"a lambda at {code.co_filename}:{code.co_firstlineno}"


def _first_position(code: Any) -> tuple[int, int] | None:
    for line, _, col, end_col in code.co_positions():
        if line is not None and col is not None and end_col:  # (not RESUME's 0, 0)
            return line, col
    return None


@functools.cache
def _parsed(filename: str) -> tuple[str, ast.Module] | None:
    try:
        with open(filename, encoding="utf-8") as f:
            text = f.read()
        return text, ast.parse(text)
    except (OSError, SyntaxError, ValueError):
        return None


def _lambda_body(filename: str, line: int, at: tuple[int, int] | None) -> str | None:
    """The source of the body of the lambda defined on ``line`` of ``filename`` whose code
    starts at ``at`` (the innermost lambda there holding it), whitespace folded."""
    parsed = _parsed(filename)
    if parsed is None:
        return None
    text, tree = parsed
    found: list[ast.Lambda] = []
    for n in ast.walk(tree):
        if not isinstance(n, ast.Lambda) or n.lineno != line:
            continue
        b = n.body
        if at is None or ((b.lineno, b.col_offset) <= at
                          <= (b.end_lineno or b.lineno, b.end_col_offset or 0)):
            found.append(n)
    if not found:
        return None
    inner = min(found, key=lambda n: ((n.end_lineno or 0) - n.lineno,
                                      (n.end_col_offset or 0) - n.col_offset))
    segment = ast.get_source_segment(text, inner.body)
    return " ".join(segment.split()) if segment else None
