"""Message codec: JSON (default) or MessagePack (bulk types), one cached coder per type."""

from __future__ import annotations

import base64
import binascii
import contextlib
import math
from collections.abc import Callable
from typing import Any, Generic, TypeVar

import msgspec
import msgspec.inspect as mi
import numpy as np

from .errors import DecodeError, EncodeError, TypeMismatchError
from .message import Message, UInt8Array, _TypedArray, normalize_type_name, to_array
from .registry import lookup_type

__all__ = [
    "JSON",
    "MSGPACK",
    "Codec",
    "codec_for",
    "decode_any",
    "encoding_of",
    "from_builtins",
    "json_bytes",
    "split_encoding",
    "to_builtins",
]

M = TypeVar("M", bound=Message)

JSON = "application/json"
MSGPACK = "application/msgpack"


def _enc_json(obj: Any) -> Any:
    if isinstance(obj, UInt8Array):  # uint8[] / byte[] / char[]: base64, as rosbridge sends it
        return base64.b64encode(np.ascontiguousarray(obj).data).decode("ascii")
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    raise NotImplementedError(f"cannot encode {type(obj).__name__}")


def _enc_msgpack(obj: Any) -> Any:
    if isinstance(obj, np.ndarray):
        return memoryview(np.ascontiguousarray(obj)).cast("B")  # type: ignore[arg-type]
    if isinstance(obj, np.generic):
        return obj.item()
    raise NotImplementedError(f"cannot encode {type(obj).__name__}")


def _dec(tp: type, obj: Any) -> Any:
    if isinstance(tp, type) and issubclass(tp, _TypedArray):
        if isinstance(obj, str) and issubclass(tp, UInt8Array):
            try:
                return to_array(tp, base64.b64decode(obj, validate=True))
            except binascii.Error as exc:
                raise TypeError(f"expected a list of numbers or base64, got a string that is "
                                f"not base64 ({exc})") from None
        if not isinstance(obj, (bytes, bytearray, memoryview, list)):
            raise TypeError(f"expected an array, got {type(obj).__name__}")
        return to_array(tp, obj)
    raise NotImplementedError(f"unsupported type {tp!r}")


_JSON_ENCODER = msgspec.json.Encoder(enc_hook=_enc_json)
_MSGPACK_ENCODER = msgspec.msgpack.Encoder(enc_hook=_enc_msgpack)


class Codec(Generic[M]):
    """Encoder and decoder for one message type; build it with `codec_for`."""

    __slots__ = ("_arrays", "_decode", "_encode", "_fast_decode", "bulk", "encoding", "mime",
                 "type", "type_name")

    def __init__(self, msg_type: type[M]) -> None:
        self.type = msg_type
        self.type_name = msg_type.__msgtype__ or msg_type.__qualname__
        self.bulk = msg_type.__bulk__
        self.mime = MSGPACK if self.bulk else JSON
        self.encoding = f"{self.mime};{self.type_name}"
        self._arrays = _array_fields(msg_type) if self.bulk else {}
        if self.bulk:
            self._encode = _MSGPACK_ENCODER.encode
            self._decode = self._fast_decode = _bulk_decoder(msg_type)
        else:
            self._encode = _JSON_ENCODER.encode
            self._fast_decode = msgspec.json.Decoder(msg_type, dec_hook=_dec).decode
            self._decode = _json_decoder(msg_type, self._fast_decode)

    def encode(self, msg: M) -> bytes:
        """Serialize ``msg``; raises `EncodeError` if it is not of this codec's type."""
        if type(msg) is not self.type:
            raise EncodeError(
                f"expected {self.type_name}, got {type(msg).__name__}: publish the declared type"
            )
        try:
            if self._arrays:  # raw bytes carry no dtype: send the declared one
                msg = msgspec.structs.replace(
                    msg, **{n: to_array(c, getattr(msg, n)) for n, c in self._arrays.items()}
                )
            return self._encode(msg)
        except (TypeError, ValueError, NotImplementedError) as exc:
            raise EncodeError(f"cannot encode {self.type_name}: {exc}") from exc

    def decode(self, data: bytes | bytearray | memoryview) -> M:
        """Parse ``data``; raises `DecodeError` naming the failing path (``$.pose.x``)."""
        with contextlib.suppress(Exception):  # the usual message: msgspec's decoder alone
            fast: M = self._fast_decode(data)
            return fast
        try:
            msg: M = self._decode(data)
            return msg
        except (msgspec.DecodeError, ValueError, TypeError) as exc:
            raise DecodeError(f"expected {self.type_name}: {exc}") from exc
        except RecursionError:  # deep nesting ([[[[...): hostile or broken, never a message
            raise DecodeError(f"expected {self.type_name}: nested too deeply") from None
        except Exception as exc:
            raise DecodeError(f"expected {self.type_name}: {type(exc).__name__}: {exc}") from exc

    def check_encoding(self, encoding: str) -> None:
        """Raise `TypeMismatchError` when a sample's encoding names another type."""
        if encoding != self.encoding:
            mime, schema = split_encoding(encoding)
            if schema and normalize_type_name(schema) != self.type_name:
                raise TypeMismatchError(f"type mismatch: expected {self.type_name}, got {schema}")
            if mime not in (JSON, MSGPACK, ""):
                raise TypeMismatchError(f"expected {self.mime}, got encoding {mime}")


def _bulk_decoder(msg_type: type[M]) -> Callable[[Any], M]:
    """A MessagePack decoder whose top-level array fields are zero-copy views of the payload.

    msgspec decodes ``bin`` into a fresh ``bytes`` (one copy of the whole array) unless the
    field is typed ``memoryview``; so decode into a twin struct with memoryview fields, then
    wrap them with ``np.frombuffer``. Nested arrays (rare in bulk types) take the plain path.
    """
    fields = msgspec.structs.fields(msg_type)
    arrays = _array_fields(msg_type)
    plain = msgspec.msgpack.Decoder(msg_type, dec_hook=_dec).decode
    if not arrays:
        return plain
    spec: list[Any] = []
    for f in fields:
        if f.name in arrays:
            spec.append((f.name, memoryview | list[float],
                         msgspec.field(default_factory=lambda: memoryview(b""))))
        elif f.default is not msgspec.NODEFAULT:
            spec.append((f.name, f.type, f.default))
        elif f.default_factory is not msgspec.NODEFAULT:
            spec.append((f.name, f.type, msgspec.field(default_factory=f.default_factory)))
        else:
            spec.append((f.name, f.type))
    twin = msgspec.defstruct(f"{msg_type.__name__}Wire", spec, kw_only=True)
    twin_decode = msgspec.msgpack.Decoder(twin, dec_hook=_dec).decode
    names = [f.name for f in fields]

    def decode(data: Any) -> M:
        wire = twin_decode(data)
        values = {n: getattr(wire, n) for n in names}
        for name, cls in arrays.items():
            try:
                values[name] = to_array(cls, values[name])
            except (ValueError, TypeError) as exc:
                raise ValueError(f"{exc} - at `$.{name}`") from exc
        return msg_type(**values)

    return decode


def _array_fields(msg_type: type[Message]) -> dict[str, type[_TypedArray]]:
    return {f.name: f.type for f in msgspec.structs.fields(msg_type)
            if isinstance(f.type, type) and issubclass(f.type, _TypedArray)}


def _json_decoder(msg_type: type[M], fast: Callable[[Any], M] | None = None
                  ) -> Callable[[Any], M]:
    """A JSON decoder that also reads ``null`` in a float field as NaN.

    msgspec (like rosbridge) writes NaN and infinities as ``null``; ROS uses NaN for unknown
    values (BatteryState). ``fast`` (msgspec's decoder of the type, made here if not given)
    decodes; only a sample it refuses is retried. `Codec.decode` and a subscription's receive
    path call ``fast`` first and this only when it raised: 90 ns a message less.
    """
    if fast is None:
        fast = msgspec.json.Decoder(msg_type, dec_hook=_dec).decode

    def decode(data: Any) -> M:
        try:
            msg: M = fast(data)
            return msg
        except msgspec.ValidationError as exc:
            obj = _null_floats_to_nan(mi.type_info(msg_type), msgspec.json.decode(data))
            try:
                again: M = msgspec.convert(obj, msg_type, dec_hook=_dec)
            except (msgspec.ValidationError, ValueError, TypeError):
                raise exc from None
            return again

    return decode


def _null_floats_to_nan(t: mi.Type, obj: Any) -> Any:
    if obj is None and isinstance(t, mi.FloatType):
        return math.nan
    if isinstance(t, mi.StructType) and isinstance(obj, dict):
        fields = {f.encode_name: f.type for f in t.fields}
        return {k: _null_floats_to_nan(fields[k], v) if k in fields else v for k, v in obj.items()}
    if isinstance(t, mi.ListType) and isinstance(obj, list):
        return [_null_floats_to_nan(t.item_type, v) for v in obj]
    return obj


_CODECS: dict[type[Message], Codec[Any]] = {}


def codec_for(msg_type: type[M]) -> Codec[M]:
    """The cached codec of a message type (a dict, not `functools.cache`: the type checker
    takes any message class here, a generic one's ``type[Any]`` included)."""
    codec: Codec[M] | None = _CODECS.get(msg_type)
    if codec is None:
        codec = _CODECS[msg_type] = Codec(msg_type)
    return codec


def encoding_of(msg_type: type[Message]) -> str:
    """The Zenoh encoding string of a type: ``application/json;geometry_msgs/Twist``."""
    return codec_for(msg_type).encoding


def split_encoding(encoding: str) -> tuple[str, str]:
    """Split ``mime;schema`` into its two halves (schema may be empty)."""
    mime, _, schema = encoding.partition(";")
    return mime, schema


def decode_any(data: bytes, encoding: str) -> Message:
    """Decode a payload whose type is named in its encoding's schema (for tools)."""
    _, schema = split_encoding(encoding)
    if not schema:
        raise DecodeError(f"payload encoding {encoding!r} names no message type")
    msg: Message = codec_for(lookup_type(schema)).decode(data)
    return msg


def json_bytes(obj: Any) -> bytes:
    """Any message (bulk types too) or plain data as JSON in one pass, numpy arrays as lists
    (NaN and infinities become ``null``): what the gateway's JSON protocols send."""
    data: bytes = _JSON_ENCODER.encode(obj)
    return data


def to_builtins(msg: Message) -> Any:
    """A message as plain dicts, lists and numbers (numpy arrays become lists)."""
    return msgspec.to_builtins(msg, enc_hook=_enc_json)


def from_builtins(obj: Any, msg_type: type[M]) -> M:
    """Build a message from plain data (YAML/JSON objects), strictly, with path errors.

    Unlike the wire decoders (which skip fields they do not know, so that newer senders can
    talk to older receivers), a field name that the type does not have is an error here:
    a typo on a command line must not silently send zeros.
    """
    info = mi.type_info(msg_type)
    obj = _ros_forms(info, obj)
    unknown = _unknown_fields(info, obj, "$")
    if unknown:
        raise DecodeError(f"expected {codec_for(msg_type).type_name}: " + "; ".join(unknown))
    try:
        return msgspec.convert(obj, msg_type, dec_hook=_dec, strict=False)
    except msgspec.ValidationError as exc:
        raise DecodeError(f"expected {codec_for(msg_type).type_name}: {exc}") from exc


_TIME_TYPES = ("builtin_interfaces/Time", "builtin_interfaces/Duration")
_ROS1_TIME_NAMES = {"secs": "sec", "nsecs": "nanosec"}


def _ros_forms(t: mi.Type, obj: Any) -> Any:
    """``obj`` in ROS 2 spelling: ROS 1's ``secs``/``nsecs`` renamed ``sec``/``nanosec`` in
    every builtin_interfaces/Time and Duration it holds (the reference rosbridge accepts
    both), and ROS 1's ``std_msgs/Header.seq`` (gone in ROS 2) dropped; ``obj`` itself when
    it has none of them (no copy). A list of numbers for a bytes field (``uint8[]``, as
    ``ros2 topic pub`` takes it) becomes bytes."""
    if isinstance(t, mi.BytesType) and isinstance(obj, list):
        try:
            return bytes(obj)
        except (TypeError, ValueError):
            return obj  # msgspec names the field and what it expected
    if isinstance(t, mi.StructType) and isinstance(obj, dict):
        msgtype = getattr(t.cls, "__msgtype__", None)
        if msgtype == "std_msgs/Header" and "seq" in obj:
            obj = {k: v for k, v in obj.items() if k != "seq"}
        if msgtype in _TIME_TYPES:
            if not any(k in obj for k in _ROS1_TIME_NAMES):
                return obj
            return {_ROS1_TIME_NAMES.get(k, k) if _ROS1_TIME_NAMES.get(k, k) not in obj else k: v
                    for k, v in obj.items()}
        fields = {f.encode_name: f.type for f in t.fields}
        out = obj
        for k, v in obj.items():
            ft = fields.get(k)
            if ft is None or not isinstance(v, (dict, list)):
                continue
            nv = _ros_forms(ft, v)
            if nv is not v:
                if out is obj:
                    out = dict(obj)
                out[k] = nv
        return out
    if (isinstance(t, (mi.ListType, mi.VarTupleType)) and isinstance(obj, list)
            and isinstance(t.item_type, (mi.StructType, mi.UnionType))):
        items = [_ros_forms(t.item_type, v) for v in obj]
        return items if any(a is not b for a, b in zip(items, obj, strict=True)) else obj
    if isinstance(t, mi.UnionType):
        structs = [u for u in t.types if isinstance(u, mi.StructType)]
        if len(structs) == 1:
            return _ros_forms(structs[0], obj)
    return obj


def _unknown_fields(t: mi.Type, obj: Any, path: str) -> list[str]:
    """Keys of ``obj`` (at ``path``) that name no field of the struct type ``t``, recursively."""
    if isinstance(t, mi.StructType) and isinstance(obj, dict):
        fields = {f.encode_name: f.type for f in t.fields}
        out: list[str] = []
        for k, v in obj.items():
            if k in fields:
                out += _unknown_fields(fields[k], v, f"{path}.{k}")
            else:
                name = getattr(t.cls, "__msgtype__", t.cls.__name__)
                out.append(f"unknown field {k!r} at {path} ({name} has: {', '.join(fields)})")
        return out
    if isinstance(t, (mi.ListType, mi.VarTupleType, mi.FrozenSetType, mi.SetType)) and isinstance(
        obj, list
    ):
        return [e for i, v in enumerate(obj) for e in _unknown_fields(t.item_type, v, f"{path}[{i}]")]
    if isinstance(t, mi.UnionType):
        structs = [u for u in t.types if isinstance(u, mi.StructType)]
        if len(structs) == 1:
            return _unknown_fields(structs[0], obj, path)
    return []
