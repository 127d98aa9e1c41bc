"""The values of .msg constants and field defaults (``int32 X=5``, ``float64[3] v [1, 2, 3]``,
``string s "a # b"``), parsed as rosidl reads them and checked against the type; nothing is
ever evaluated."""

from __future__ import annotations

import math
from typing import Any

from ..primitives import INT_BOUNDS
from ..ros2.idl import FieldType, InterfaceError

__all__ = ["parse_value"]

_ESCAPES = {"n": "\n", "t": "\t", "r": "\r", "\\": "\\", "'": "'", '"': '"', "0": "\0"}
_FLOAT32_MAX = 3.4028234663852886e38


def parse_value(t: FieldType, text: str, where: str) -> Any:
    """The Python value of ``text`` as a value of type ``t`` (a list for arrays)."""
    text = text.strip()
    if t.kind == "single":
        value, rest = _scalar(t, text, where)
        _no_rest(rest, where)
        return value
    if not text.startswith("["):
        raise InterfaceError(f"{where}: an array value is written [a, b, ...], got {text!r}")
    items: list[Any] = []
    rest = text[1:].lstrip()
    if rest.startswith("]"):
        rest = rest[1:]
    else:
        while True:
            value, rest = _scalar(t, rest, where, in_list=True)
            items.append(value)
            rest = rest.lstrip()
            if rest.startswith(","):
                rest = rest[1:].lstrip()
                continue
            if rest.startswith("]"):
                rest = rest[1:]
                break
            raise InterfaceError(f"{where}: expected ',' or ']' in {text!r}")
    _no_rest(rest, where)
    if t.kind == "array" and len(items) != t.size:
        raise InterfaceError(f"{where}: {t} takes {t.size} values, got {len(items)}")
    if t.kind == "bounded" and len(items) > t.size:
        raise InterfaceError(f"{where}: {t} takes at most {t.size} values, got {len(items)}")
    return items


def _no_rest(rest: str, where: str) -> None:
    rest = rest.strip()
    if rest and not rest.startswith("#"):
        raise InterfaceError(f"{where}: unexpected text after the value: {rest!r}")


def _scalar(t: FieldType, text: str, where: str, in_list: bool = False) -> tuple[Any, str]:
    """One value at the start of ``text`` and what follows it."""
    if t.is_nested:
        raise InterfaceError(f"{where}: a field of type {t.base} has no default value syntax")
    if t.is_string:
        if text[:1] in ("'", '"'):
            value, rest = _quoted(text, where)
        else:
            stop = _token_end(text, in_list, comment=True)
            value, rest = text[:stop].strip(), text[stop:]
        if t.string_bound and len(value) > t.string_bound:
            raise InterfaceError(f"{where}: {value!r} is longer than {t.string_bound}")
        return value, rest
    stop = _token_end(text, in_list, comment=True)
    token, rest = text[:stop].strip(), text[stop:]
    if not token:
        raise InterfaceError(f"{where}: a value is missing")
    if t.base == "bool":
        low = token.lower()
        if low in ("true", "1"):
            return True, rest
        if low in ("false", "0"):
            return False, rest
        raise InterfaceError(f"{where}: {token!r} is not a bool (true, false, 1 or 0)")
    if t.base in ("float32", "float64"):
        try:
            number = float(token)
        except ValueError:
            raise InterfaceError(f"{where}: {token!r} is not a number") from None
        if t.base == "float32" and math.isfinite(number) and abs(number) > _FLOAT32_MAX:
            raise InterfaceError(f"{where}: {token} is out of float32's range")
        return number, rest
    try:
        integer = int(token, 0)
    except ValueError:
        raise InterfaceError(f"{where}: {token!r} is not an integer") from None
    lo, hi = INT_BOUNDS[t.base]
    if not lo <= integer <= hi:
        raise InterfaceError(f"{where}: {integer} is out of {t.base}'s range {lo}..{hi}")
    return integer, rest


def _token_end(text: str, in_list: bool, comment: bool) -> int:
    """Where an unquoted value ends: a ',' or ']' inside a list, a ' #' comment, the end."""
    for i, ch in enumerate(text):
        if in_list and ch in ",]":
            return i
        if comment and ch == "#" and (i == 0 or text[i - 1].isspace()):
            return i
    return len(text)


def _quoted(text: str, where: str) -> tuple[str, str]:
    quote = text[0]
    out: list[str] = []
    i = 1
    while i < len(text):
        ch = text[i]
        if ch == "\\" and i + 1 < len(text):
            out.append(_ESCAPES.get(text[i + 1], "\\" + text[i + 1]))
            i += 2
            continue
        if ch == quote:
            return "".join(out), text[i + 1:]
        out.append(ch)
        i += 1
    raise InterfaceError(f"{where}: string {text!r} has no closing {quote}")
