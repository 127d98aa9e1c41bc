"""CDR (XCDR1, the encoding ROS 2 uses on DDS and rmw_zenoh) <-> zenros messages.

A `CdrCodec` is compiled once per (ROS 2 definition, zenros class): the generator walks the
definition, inlines nested structures, packs every run of fixed-size fields with one
precomputed `struct.Struct` (one variant per start offset modulo 8, since CDR aligns each
primitive to its size from the start of the payload), and emits Python source for one encode
and one decode function; sequences of primitives are numpy buffers or one `struct` call.
Payloads carry the 4-byte encapsulation header: ``00 01 00 00`` (little endian, written) or
``00 00 00 00`` (big endian, read too). Malformed input raises `DecodeError`, never anything else.
"""

from __future__ import annotations

import struct
import typing
from collections.abc import Callable
from functools import cache, partial
from typing import Any, Generic, TypeVar

import msgspec
import numpy as np

from ..errors import DecodeError, EncodeError
from ..message import Message, _TypedArray, to_array
from .idl import PRIMITIVES, FieldType, InterfaceError, MsgDef
from .registry import definition, ros_name_of, zenros_class_of

__all__ = ["CdrCodec", "cdr_codec", "cdr_codec_for_name", "plain_class"]

M = TypeVar("M", bound=Message)

HEADER_LE = b"\x00\x01\x00\x00"
_NP = {"?": "?", "B": "u1", "b": "i1", "h": "i2", "H": "u2", "i": "i4", "I": "u4",
       "q": "i8", "Q": "u8", "f": "f4", "d": "f8"}
_ZERO = {"?": "False", "f": "0.0", "d": "0.0"}
_U32 = {"<": struct.Struct("<I"), ">": struct.Struct(">I")}


# ------------------------------------------------------------------ runtime helpers


def _pad(b: bytearray, align: int) -> None:
    n = (4 - len(b)) & (align - 1)  # the payload starts after the 4-byte header
    if n:
        b += bytes(n)


def _w_str(b: bytearray, s: str, bound: int, where: str) -> None:
    data = s.encode()
    if bound and len(data) > bound:
        raise EncodeError(f"{where}: string of {len(data)} bytes exceeds its bound {bound}")
    _pad(b, 4)
    b += _U32["<"].pack(len(data) + 1)
    b += data
    b.append(0)


def _r_str(buf: Any, o: int, e: str, bound: int, where: str) -> tuple[str, int]:
    o += (4 - o) & 3
    (n,) = _U32[e].unpack_from(buf, o)
    o += 4
    end = o + n
    if end > len(buf):
        raise DecodeError(f"{where}: string of {n} bytes runs past the end ({len(buf)})")
    if bound and n > bound + 1:
        raise DecodeError(f"{where}: string of {n - 1} bytes exceeds its bound {bound}")
    s = str(buf[o:end - 1 if n and buf[end - 1] == 0 else end], "utf-8")
    return s, end


def _count(v: Any, kind: str, size: int, where: str) -> int:
    n = len(v)
    if kind == "array" and n != size:
        raise EncodeError(f"{where}: fixed array needs {size} elements, got {n}")
    if kind == "bounded" and n > size:
        raise EncodeError(f"{where}: {n} elements exceed the bound {size}")
    return n


def _w_prims(b: bytearray, v: Any, ch: str, size: int, kind: str, bound: int, where: str) -> None:
    n = _count(v, kind, bound, where)
    if kind != "array":
        _pad(b, 4)
        b += _U32["<"].pack(n)
    if not n:
        return
    _pad(b, size)
    if isinstance(v, np.ndarray):
        b += np.ascontiguousarray(v, dtype="<" + _NP[ch]).data.cast("B")
    elif isinstance(v, (bytes, bytearray, memoryview)) and size == 1:
        b += v
    else:
        try:
            b += struct.pack(f"<{n}{ch}", *v)
        except struct.error as exc:
            raise EncodeError(f"{where}: {exc}") from None


def _r_count(buf: Any, o: int, e: str, kind: str, size: int, where: str) -> tuple[int, int]:
    if kind == "array":
        return size, o
    o += (4 - o) & 3
    (n,) = _U32[e].unpack_from(buf, o)
    if kind == "bounded" and n > size:
        raise DecodeError(f"{where}: {n} elements exceed the bound {size}")
    return n, o + 4


def _r_prims(buf: Any, o: int, e: str, ch: str, size: int, kind: str, bound: int, out: Any,
             where: str) -> tuple[Any, int]:
    n, o = _r_count(buf, o, e, kind, bound, where)
    if n:
        o += (4 - o) & (size - 1)
    end = o + n * size
    if end > len(buf):
        raise DecodeError(f"{where}: {n} elements of {size} bytes run past the end ({len(buf)})")
    if out is bytes:
        return bytes(buf[o:end]), end
    arr = np.frombuffer(buf, dtype=e + _NP[ch], count=n, offset=o)
    if out is list:
        return arr.tolist(), end
    if arr.dtype != out.dtype_ or e == ">":
        arr = arr.astype(out.dtype_)
    return arr.view(out), end


def _w_strs(b: bytearray, v: Any, kind: str, size: int, bound: int, where: str) -> None:
    n = _count(v, kind, size, where)
    if kind != "array":
        _pad(b, 4)
        b += _U32["<"].pack(n)
    for s in v:
        _w_str(b, s, bound, where)


def _r_strs(buf: Any, o: int, e: str, kind: str, size: int, bound: int,
            where: str) -> tuple[list[str], int]:
    n, o = _r_count(buf, o, e, kind, size, where)
    if n * 4 > len(buf) - o:
        raise DecodeError(f"{where}: {n} strings cannot fit in {len(buf) - o} bytes")
    out = []
    for _ in range(n):
        s, o = _r_str(buf, o, e, bound, where)
        out.append(s)
    return out, o


def _w_structs(b: bytearray, v: Any, kind: str, size: int, enc: Callable[[Any, bytearray], None],
               where: str) -> None:
    n = _count(v, kind, size, where)
    if kind != "array":
        _pad(b, 4)
        b += _U32["<"].pack(n)
    for item in v:
        enc(item, b)


def _r_structs(buf: Any, o: int, e: str, kind: str, size: int,
               dec: Callable[[Any, int], tuple[Any, int]], where: str) -> tuple[list[Any], int]:
    n, o = _r_count(buf, o, e, kind, size, where)
    if n > len(buf) - o:
        raise DecodeError(f"{where}: {n} elements cannot fit in {len(buf) - o} bytes")
    out = []
    for _ in range(n):
        item, o = dec(buf, o)
        out.append(item)
    return out, o


def _fixed(v: Any, n: int, where: str) -> Any:
    if len(v) != n:
        raise EncodeError(f"{where}: fixed array needs {n} elements, got {len(v)}")
    return v.tolist() if isinstance(v, np.ndarray) else v


_HELPERS = {k: v for k, v in globals().items() if k.startswith(("_w_", "_r_", "_fixed", "_pad"))}


# ------------------------------------------------------------------ field-type analysis


def _unwrap(tp: Any) -> Any:
    while typing.get_origin(tp) is typing.Annotated:
        tp = typing.get_args(tp)[0]
    return tp


def _py_fields(cls: type | None) -> dict[str, Any]:
    if cls is None:
        return {}
    return {f.name: _unwrap(f.type) for f in msgspec.structs.fields(cls)}


def _container(tp: Any, where: str) -> Any:
    """How a zenros field holds a ROS array/sequence of primitives: list, bytes or a numpy class."""
    if tp is bytes:
        return bytes
    if isinstance(tp, type) and issubclass(tp, _TypedArray):
        return tp
    if typing.get_origin(tp) in (list, tuple):
        return list
    raise InterfaceError(f"{where}: a ROS array/sequence cannot map to {tp!r}")


def _element_class(tp: Any, where: str) -> type | None:
    if typing.get_origin(tp) is list:
        (item,) = typing.get_args(tp)
        return typing.cast(type, _unwrap(item))
    raise InterfaceError(f"{where}: a ROS sequence of structures cannot map to {tp!r}")


def _filled(value: Any, n: int) -> list[Any]:
    """A fixed-size array's default: ``n`` times ``value``."""
    return [value] * n


@cache
def plain_class(ros_name: str) -> type[Message]:
    """A msgspec Struct for a ROS 2 type zenros has no class for (action parts, UUIDs...):
    primitives as int/float/bool, strings as str, uint8/byte/char arrays as bytes, other
    arrays as lists, nested types as their zenros class when there is one."""
    d = definition(ros_name)
    spec: list[Any] = []
    for f in d.fields:
        t = f.type
        if t.is_nested:
            inner: Any = class_for(t.base)
            if t.kind == "single":
                spec.append((f.name, inner, msgspec.field(default_factory=inner)))
                continue
            tp: Any = list[inner]
        elif t.is_string:
            tp = str if t.kind == "single" else list[str]
        else:
            ch = PRIMITIVES[t.base][0]
            scalar: Any = bool if ch == "?" else float if ch in "fd" else int
            if t.kind == "single":
                spec.append((f.name, scalar, scalar()))
                continue
            if ch == "B":  # byte, char and uint8 arrays and sequences
                tp = bytes
                default = bytes(t.size if t.kind == "array" else 0)
                spec.append((f.name, tp, default))
                continue
            tp = list[scalar]
        if t.kind == "array" and not t.is_nested:
            zero = "" if t.is_string else tp.__args__[0]()
            spec.append((f.name, tp, msgspec.field(default_factory=partial(_filled, zero, t.size))))
        else:
            spec.append((f.name, tp, msgspec.field(default_factory=list)))
    short = ros_name.replace("/", "_")
    return msgspec.defstruct(short, spec, bases=(Message,), kw_only=True)  # type: ignore[return-value]


def class_for(ros_name: str) -> type[Message]:
    """The zenros class of a ROS 2 type, or a `plain_class` when zenros has none."""
    return zenros_class_of(ros_name) or plain_class(ros_name)


# ------------------------------------------------------------------ the generator


class _Gen:
    """Emits the encode and decode functions of one (definition, class) and its element types."""

    def __init__(self) -> None:
        self.ns: dict[str, Any] = {"EncodeError": EncodeError, **_HELPERS}
        self.src: list[str] = []
        self.n = 0
        self.funcs: dict[tuple[str, type | None, bool], tuple[str, str]] = {}

    def name(self, prefix: str) -> str:
        self.n += 1
        return f"{prefix}{self.n}"

    def const(self, value: Any, prefix: str = "K") -> str:
        n = self.name(prefix)
        self.ns[n] = value
        return n

    def function(self, d: MsgDef, cls: type | None, top: bool) -> tuple[str, str]:
        key = (d.name, cls, top)
        if key in self.funcs:
            return self.funcs[key]
        enc_name, dec_name = self.name("enc"), self.name("dec")
        self.funcs[key] = (enc_name, dec_name)
        body = _Body(self, residue=0 if top else None)
        expr = body.struct(d, cls, "m", d.name)
        body.flush()
        self.src.append(f"def {enc_name}(m, b):\n" + "".join(f"    {x}\n" for x in body.enc)
                        + "    return None\n")
        self.src.append(f"def {dec_name}(buf, o):\n" + "".join(f"    {x}\n" for x in body.dec)
                        + f"    return {expr}, o\n")
        return enc_name, dec_name


class _Body:
    def __init__(self, gen: _Gen, residue: int | None) -> None:
        self.g = gen
        self.enc: list[str] = []
        self.dec: list[str] = []
        self.residue = residue  # payload offset modulo 8, when known at generation time
        self.run: list[tuple[str, int, int, str, str]] = []  # (char, size, count, enc expr, dec var)

    # -- runs of fixed-size primitives
    def prim(self, ch: str, size: int, count: int, enc_expr: str) -> str:
        """Queue a primitive (or a fixed array of them); return the decode expression slot."""
        var = self.g.name("v")
        self.run.append((ch, size, count, enc_expr, var))
        return var

    def flush(self) -> None:
        if not self.run:
            return
        run, self.run = self.run, []

        def layout(start: int) -> tuple[str, int]:
            fmt, off = "", start
            for ch, size, count, _, _ in run:
                pad = (-off) % size
                fmt += "x" * pad + (f"{count}s" if ch == "s" else f"{count}{ch}" if count > 1 else ch)
                off += pad + size * count
            return fmt, off - start

        values = ", ".join(e for *_, e, _ in run)
        if self.residue is not None:
            fmt, length = layout(self.residue)
            s_le, s_be = struct.Struct("<" + fmt), struct.Struct(">" + fmt)
            s = self.g.const((s_le, s_be), "S")
            self.enc.append(f"b += {s}[0].pack({values})")
            self.dec.append(f"t = {s}[EI].unpack_from(buf, o)")
            self.dec.append(f"o += {length}")
            self.residue = (self.residue + length) % 8
        else:
            variants = [layout(r) for r in range(8)]
            s = self.g.const(tuple((struct.Struct("<" + f), struct.Struct(">" + f))
                                   for f, _ in variants), "S")
            self.enc.append(f"b += {s}[(len(b) + 4) & 7][0].pack({values})")
            self.dec.append(f"s = {s}[(o + 4) & 7][EI]")
            self.dec.append("t = s.unpack_from(buf, o)")
            self.dec.append("o += s.size")
        i = 0
        for ch, _, count, _, var in run:
            if count == 1 or ch == "s":
                self.dec.append(f"{var} = t[{i}]")
                i += 1
            else:
                self.dec.append(f"{var} = t[{i}:{i + count}]")
                i += count

    def dynamic(self, enc_line: str, dec_line: str) -> None:
        self.flush()
        self.enc.append(enc_line)
        self.dec.append(dec_line)
        self.residue = None

    # -- the walk
    def struct(self, d: MsgDef, cls: type | None, path: str | None, where: str) -> str:
        """Emit code for structure ``d`` read from ``path`` (None: not in the zenros class:
        write defaults); return the expression that builds it on decode."""
        pyf = _py_fields(cls)
        kwargs = []
        for f in d.fields:
            here = f"{where}.{f.name}"
            tp = pyf.get(f.name)
            fpath = f"{path}.{f.name}" if path is not None and tp is not None else None
            expr = self.field(f.type, tp, fpath, here)
            if tp is not None and expr is not None:
                kwargs.append(f"{f.name}={expr}")
        if cls is None:
            return "None"
        c = self.g.const(cls, "C")
        return f"{c}({', '.join(kwargs)})"

    def field(self, t: FieldType, tp: Any, path: str | None, where: str) -> str | None:
        w = self.g.const(where, "W")
        if t.is_nested:
            sub = definition(t.base)
            if t.kind == "single":
                sub_cls = tp if tp is not None else None
                if sub_cls is not None and not (isinstance(sub_cls, type)
                                                and issubclass(sub_cls, msgspec.Struct)):
                    raise InterfaceError(f"{where}: a ROS structure cannot map to {tp!r}")
                return self.struct(sub, sub_cls, path, where)
            elem = _element_class(tp, where) if tp is not None else None
            _, dec_fn = self.g.function(sub, elem, top=False)
            if path is not None:
                src = path
                enc_fn, _ = self.g.function(sub, elem, top=False)
            elif t.kind == "array":  # not in the zenros class: default elements
                pc = class_for(t.base)
                src = self.g.const([pc() for _ in range(t.size)])
                enc_fn, _ = self.g.function(sub, pc, top=False)
            else:
                src, enc_fn = "()", "None"
            var = self.g.name("v")
            self.dynamic(f"_w_structs(b, {src}, {t.kind!r}, {t.size}, {enc_fn}, {w})",
                         f"{var}, o = _r_structs(buf, o, E, {t.kind!r}, {t.size}, {dec_fn}, {w})")
            return var
        if t.is_string:
            if t.base == "wstring":
                raise InterfaceError(f"{where}: wstring is not supported")
            var = self.g.name("v")
            if t.kind == "single":
                if tp is not None and tp is not str and typing.get_origin(tp) is not typing.Literal:
                    raise InterfaceError(f"{where}: a ROS string cannot map to {tp!r}")
                src = path if path is not None else "''"
                self.dynamic(f"_w_str(b, {src}, {t.string_bound}, {w})",
                             f"{var}, o = _r_str(buf, o, E, {t.string_bound}, {w})")
            else:
                src = path if path is not None else (
                    self.g.const([""] * t.size) if t.kind == "array" else "()")
                self.dynamic(
                    f"_w_strs(b, {src}, {t.kind!r}, {t.size}, {t.string_bound}, {w})",
                    f"{var}, o = _r_strs(buf, o, E, {t.kind!r}, {t.size}, {t.string_bound}, {w})")
            return var
        ch, size = PRIMITIVES[t.base]
        if t.kind == "single":
            if tp is not None and tp not in (int, float, bool):
                raise InterfaceError(f"{where}: a ROS {t.base} cannot map to {tp!r}")
            src = path if path is not None else _ZERO.get(ch, "0")
            var = self.prim(ch, size, 1, src)
            if tp is bool and ch != "?":
                return f"bool({var})"
            return var
        out = _container(tp, where) if tp is not None else list
        if t.kind == "array" and (size * t.size <= 4096):
            if out is bytes and size == 1:
                src = path if path is not None else self.g.const(bytes(t.size))
                var = self.prim("s", 1, t.size, f"_fixed({src}, {t.size}, {w})")
                return var
            src = (f"*_fixed({path}, {t.size}, {w})" if path is not None
                   else f"*{self.g.const([0] * t.size)}")
            var = self.prim(ch, size, t.size, src)
            if out is list:
                return f"list({var})"
            if out is bytes:
                return f"bytes({var})"
            return f"_to_array({self.g.const(out)}, {var})"
        var = self.g.name("v")
        src = path if path is not None else (self.g.const([0] * t.size) if t.kind == "array" else "()")
        out_c = self.g.const(out)
        self.dynamic(f"_w_prims(b, {src}, {ch!r}, {size}, {t.kind!r}, {t.size}, {w})",
                     f"{var}, o = _r_prims(buf, o, E, {ch!r}, {size}, {t.kind!r}, {t.size}, "
                     f"{out_c}, {w})")
        return var


# ------------------------------------------------------------------ the codec


class CdrCodec(Generic[M]):
    """CDR encoder and decoder of one zenros class under one ROS 2 definition."""

    __slots__ = ("_dec_be", "_dec_le", "_enc", "definition", "ros_name", "source", "type")

    def __init__(self, msg_type: type[M], ros_name: str | None = None) -> None:
        self.type = msg_type
        self.ros_name = ros_name or ros_name_of(msg_type)
        self.definition = definition(self.ros_name)
        gen = _Gen()
        enc_name, dec_name = gen.function(self.definition, msg_type, top=True)
        self.source = "\n".join(gen.src)
        code = compile(self.source, f"<cdr {self.ros_name}>", "exec")
        # E: the helpers' struct prefix; EI: which of a run's two Structs
        ns_le = {**gen.ns, "E": "<", "EI": 0, "_to_array": to_array}
        ns_be = {**gen.ns, "E": ">", "EI": 1, "_to_array": to_array}
        exec(code, ns_le)  # noqa: S102  (source generated above from the definition)
        exec(code, ns_be)  # noqa: S102
        self._enc = ns_le[enc_name]
        self._dec_le = ns_le[dec_name]
        self._dec_be = ns_be[dec_name]

    def encode(self, msg: M) -> bytes:
        """CDR bytes (little endian, with the encapsulation header) of ``msg``."""
        b = bytearray(HEADER_LE)
        try:
            self._enc(msg, b)
        except EncodeError:
            raise
        except (struct.error, TypeError, ValueError, AttributeError, OverflowError) as exc:
            raise EncodeError(f"cannot encode {self.ros_name}: {exc}") from None
        return bytes(b)

    def decode(self, data: bytes | bytearray | memoryview) -> M:
        """Parse CDR bytes; raises `DecodeError` on anything malformed."""
        if len(data) < 4:
            raise DecodeError(f"expected {self.ros_name} CDR: {len(data)} bytes, no header")
        if data[0] != 0 or data[1] not in (0, 1):
            raise DecodeError(f"expected {self.ros_name} CDR: unsupported encapsulation "
                              f"{bytes(data[:2]).hex()} (plain CDR 0000/0001 only)")
        dec = self._dec_le if data[1] == 1 else self._dec_be
        try:
            msg: M = dec(data, 4)[0]
        except DecodeError as exc:
            raise DecodeError(f"expected {self.ros_name} CDR: {exc}") from None
        except (struct.error, IndexError, ValueError, TypeError, UnicodeDecodeError,
                OverflowError) as exc:
            raise DecodeError(f"expected {self.ros_name} CDR: {type(exc).__name__}: {exc}") \
                from None
        return msg


_CDR_CODECS: dict[type[Message], CdrCodec[Any]] = {}


def cdr_codec(msg_type: type[M]) -> CdrCodec[M]:
    """The cached CDR codec of a zenros class (under its own ROS 2 name; a dict, as
    `zenros.codec.codec_for`)."""
    codec: CdrCodec[M] | None = _CDR_CODECS.get(msg_type)
    if codec is None:
        codec = _CDR_CODECS[msg_type] = CdrCodec(msg_type)
    return codec


@cache
def cdr_codec_for_name(ros_name: str) -> CdrCodec[Message]:
    """The cached CDR codec of a ROS 2 type name, with its zenros or plain class."""
    return CdrCodec(class_for(ros_name), ros_name)
