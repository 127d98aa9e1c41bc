"""Bags recorded with ROS: rosbag2 (SQLite3 or MCAP storage, CDR) and ROS 1 ``.bag`` files,
read with rosbags (the ``rosbags`` extra) and handed out in zenros's own shape.

Each ROS message becomes the zenros message of the same ROS type, encoded as zenros publishes
it (JSON, or MessagePack for bulk types), in a `BagMessage` whose channel and schema look like
one `Recorder` wrote: the player, ``bag info`` and replay need no special case. A ROS 2
message whose definition is zenros's own (same RIHS01 type hash) is decoded by zenros's CDR
codec straight into its class; any other (ROS 1 bags, another distro's definition) is
deserialised by rosbags with the bag's own definitions and converted field by field
(`zenros.bag.ros_convert`). Topics of a type zenros lacks are skipped with one warning per
topic, and `bag info` says so; a message that does not decode is skipped with one warning per
topic. A bag rosbags cannot open (corrupt, cut, a rosbag2 topic not in CDR) is one
`BagError` naming the file.
"""

from __future__ import annotations

import logging
import struct
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from mcap.records import Channel, Schema

from ..codec import codec_for
from ..errors import ZenrosError
from ..qos import QoSProfile
from ..ros2 import cdr_codec_for_name, type_hash
from ..ros2.registry import zenros_class_of
from .records import BagError, BagMessage
from .ros_convert import builder_for, ros1_alias
from .schema import message_encoding, schema_for
from .writer import MAGIC

if TYPE_CHECKING:
    from rosbags.highlevel import AnyReader

__all__ = ["EXTRA_HINT", "ForeignSummary", "ForeignTopic", "foreign_files", "foreign_span",
           "foreign_summary", "is_foreign", "iter_foreign"]

_log = logging.getLogger("zenros.bag")

EXTRA_HINT = "pip install 'zenros[rosbags]'"
ROS1_MAGIC = b"#ROSBAG V2.0\n"
SQLITE_MAGIC = b"SQLite format 3\x00"
ROS2_SUFFIXES = (".db3", ".mcap")
ROS2_COMPRESSED = (".db3.zstd", ".mcap.zstd")  # rosbag2's file compression


def _is_ros2_storage(p: Path) -> bool:
    return p.suffix in ROS2_SUFFIXES or p.name.endswith(ROS2_COMPRESSED)


# ------------------------------------------------------------------ detection


def _mcap_profile(path: Path) -> str | None:
    """The profile of an MCAP file's header record, None if it has none readable."""
    try:
        with open(path, "rb") as f:
            head = f.read(8 + 1 + 8 + 4 + 256)
    except OSError:
        return None
    if head[:8] != MAGIC or len(head) < 21 or head[8] != 0x01:
        return None
    (n,) = struct.unpack_from("<I", head, 17)
    return head[21:21 + n].decode("utf-8", "replace") if 21 + n <= len(head) else None


def _file_kind(path: Path) -> str | None:
    """``rosbag2``, ``ros1`` or None (zenros's own MCAP, or not a bag at all)."""
    if path.suffix == ".bag":
        return "ros1"
    if path.suffix == ".db3" or (path.parent / "metadata.yaml").is_file() and (
            _is_ros2_storage(path)):
        return "rosbag2"
    try:
        with open(path, "rb") as f:
            head = f.read(16)
    except OSError:
        return None
    if head.startswith(ROS1_MAGIC[:12]):
        return "ros1"
    if head == SQLITE_MAGIC:
        return "rosbag2"
    if path.suffix == ".mcap" and _mcap_profile(path) == "ros2":
        return "rosbag2"
    return None


def is_foreign(files: list[Path]) -> bool:
    """Whether ``files`` (as `zenros.bag.bag_files` gives them) are a bag recorded with ROS."""
    return bool(files) and _file_kind(files[0]) is not None


def _split_key(p: Path) -> tuple[str, int, str]:
    stem, _, idx = p.name.split(".", 1)[0].rpartition("_")
    return (stem, int(idx), p.name) if idx.isdigit() else (p.stem, 0, p.name)


def foreign_files(directory: Path) -> list[Path] | None:
    """The storage files of a rosbag2 directory (one with ``metadata.yaml``, or only ``.db3``
    files) or a directory of ROS 1 ``.bag`` files, in order; None for any other directory."""
    ros2 = sorted((p for p in directory.iterdir() if _is_ros2_storage(p)), key=_split_key)
    if (directory / "metadata.yaml").is_file():
        if not ros2:
            raise BagError(f"{directory} has a rosbag2 metadata.yaml but no .db3 or .mcap file")
        return ros2
    ros2 = [p for p in ros2 if p.suffix in ROS2_SUFFIXES]  # compressed: only with metadata
    if any(p.suffix == ".mcap" for p in ros2):
        return None  # zenros's own split bag (or ROS 2 MCAP files: `is_foreign` tells)
    if ros2:
        return ros2
    ros1 = sorted(p for p in directory.iterdir() if p.suffix == ".bag")
    return ros1 or None


# ------------------------------------------------------------------ opening


def _rosbags() -> Any:
    try:
        import rosbags.highlevel
        import rosbags.typesys
    except ImportError as exc:
        raise BagError(f"this is a bag recorded with ROS; reading it needs the rosbags package: "
                       f"{EXTRA_HINT}") from exc
    return rosbags


def _paths(files: list[Path]) -> list[Path]:
    """What rosbags opens: the rosbag2 directory when ``files`` are all its storage files (its
    metadata.yaml has the QoS), else the files themselves."""
    parent = files[0].parent
    if (parent / "metadata.yaml").is_file() and all(f.parent == parent for f in files):
        try:
            whole = foreign_files(parent)
        except BagError:
            whole = None
        if whole is not None and sorted(whole) == sorted(files):
            return [parent]
    kinds = {_file_kind(f) for f in files}
    if len(kinds) != 1:
        raise BagError(f"{files[0].parent}: these files are not one kind of bag (ROS 1, "
                       f"rosbag2, zenros MCAP): {', '.join(f.name for f in files)}")
    if kinds == {"ros1"} and any(f.suffix != ".bag" for f in files):
        raise BagError(f"{files[0]}: a ROS 1 bag must be named *.bag to be read")
    return files


@contextmanager
def _open(files: list[Path]) -> Iterator[AnyReader]:
    lib = _rosbags()
    paths = _paths(files)
    where = paths[0] if len(paths) == 1 else paths[0].parent
    default = lib.typesys.get_typestore(lib.typesys.Stores.LATEST)
    try:
        reader = lib.highlevel.AnyReader(paths, default_typestore=default)
        reader.open()
    except FileNotFoundError as exc:
        raise BagError(f"no such bag: {exc}") from exc
    except Exception as exc:  # rosbags raises its own errors, sqlite3's and OSError
        raise BagError(f"{where}: not a readable ROS bag ({type(exc).__name__}: {exc})") from exc
    try:
        yield reader
    finally:
        reader.close()


# ------------------------------------------------------------------ topics


@dataclass
class ForeignTopic:
    """One topic of a ROS bag: its ROS type and encoding, and how zenros plays it (``channel``
    and ``schema``), or why it does not (``skipped``)."""

    topic: str
    ros_type: str
    encoding: str
    qos: str
    count: int = 0
    channel: Channel | None = None
    schema: Schema | None = None
    convert: Callable[[bytes], bytes] | None = None
    skipped: str = ""
    connections: list[Any] = field(default_factory=list)


def _qos_tag(conn: Any) -> str:
    ext = conn.ext
    profiles = getattr(ext, "offered_qos_profiles", None)
    if profiles is None:  # ROS 1: latched or not
        return "rel+tl+1" if getattr(ext, "latching", 0) else "rel+10"
    if not profiles:
        return "rel+10"
    q = profiles[0]
    reliable = q.reliability.name != "BEST_EFFORT"
    latched = q.durability.name == "TRANSIENT_LOCAL"
    depth = q.depth if isinstance(q.depth, int) and q.depth > 0 else (1 if latched else 10)
    tag = ("rel" if reliable else "be") + ("+tl" if latched else "") + f"+{depth}"
    return QoSProfile.from_tag(tag).tag


def _converter(reader: AnyReader, conn: Any, ros_type: str) -> Callable[[bytes], bytes]:
    """raw ROS payload -> zenros payload for one connection (`LookupError` if zenros has no
    class for the type)."""
    cls = zenros_class_of(ros_type)
    if cls is None:
        raise LookupError(f"zenros has no type {ros_type}")
    encode = codec_for(cls).encode
    if reader.is2:
        try:
            same = reader.typestore.hash_rihs01(conn.msgtype) == type_hash(ros_type)
        except Exception:  # noqa: BLE001  # a definition either side cannot hash: no fast path
            same = False
        if same:
            decode = cdr_codec_for_name(ros_type).decode
            return lambda raw: encode(decode(raw))
    build = builder_for(cls)
    deserialize = reader.deserialize
    msgtype = conn.msgtype
    return lambda raw: encode(build(deserialize(raw, msgtype)))


def _topics(reader: AnyReader) -> list[ForeignTopic]:
    """Every topic of the bag, with the channel zenros plays it on or why it does not."""
    out: dict[tuple[str, str], ForeignTopic] = {}
    next_id = 1
    for conn in reader.connections:
        ros_type = ros1_alias(conn.msgtype) if not reader.is2 else conn.msgtype
        encoding = getattr(conn.ext, "serialization_format", "ros1")
        key = (conn.topic, conn.msgtype)
        t = out.get(key)
        if t is None:
            # as the bag's own tools name it: ROS 1's pkg/Type, ROS 2's pkg/msg/Type
            shown = conn.msgtype if reader.is2 else conn.msgtype.replace("/msg/", "/", 1)
            t = out[key] = ForeignTopic(conn.topic, shown, encoding, _qos_tag(conn))
            if encoding not in ("cdr", "ros1"):
                t.skipped = f"encoding {encoding!r} is not CDR"
            else:
                try:
                    t.convert = _converter(reader, conn, ros_type)
                except (LookupError, ZenrosError) as exc:
                    t.skipped = f"{exc}"
            if t.convert is not None:
                cls = zenros_class_of(ros_type)
                assert cls is not None
                codec = codec_for(cls)
                schema_encoding, schema_data = schema_for(codec.type_name)
                t.schema = Schema(id=next_id, name=codec.type_name, encoding=schema_encoding,
                                  data=schema_data)
                t.channel = Channel(
                    id=next_id, topic=conn.topic, message_encoding=message_encoding(codec.mime),
                    schema_id=next_id,
                    metadata={"zenoh_encoding": codec.encoding, "qos": t.qos,
                              "ros_type": shown, "ros_encoding": encoding})
                next_id += 1
        t.count += conn.msgcount
        t.connections.append(conn)
    return sorted(out.values(), key=lambda t: (t.topic, t.ros_type))


# ------------------------------------------------------------------ public

_warned: set[tuple[str, str, str]] = set()


def _warn_once(files: list[Path], t: ForeignTopic, kind: str, what: str) -> None:
    """One warning per bag, topic and ``kind`` of trouble, however often the bag is read."""
    bag = str(files[0].parent if len(files) > 1 or files[0].suffix != ".bag" else files[0])
    key = (bag, t.topic, kind)
    if key not in _warned:
        _warned.add(key)
        _log.warning("bag %s: topic %s: %s", bag, t.topic, what)



@dataclass
class ForeignSummary:
    """What ``bag info`` shows of a ROS bag."""

    storage: str
    start: int
    end: int
    messages: int
    topics: list[ForeignTopic]
    compression: str = ""  # rosbag2's: "zstd (file)", "zstd (message)"


def _storage(files: list[Path]) -> str:
    name = files[0].name
    for part, storage in ((".db3", "sqlite3"), (".mcap", "mcap"), (".bag", "rosbag1")):
        if part in name:
            return storage
    return files[0].suffix


def _compression(reader: AnyReader) -> str:
    first = reader.readers[0] if reader.is2 and reader.readers else None
    fmt = getattr(first, "compression_format", None)
    return f"{fmt} ({getattr(first, 'compression_mode', None) or '?'})" if fmt else ""


def _last(reader: AnyReader) -> int:
    """The last message's time: rosbags' end time is one past it."""
    return max(reader.start_time, reader.end_time - 1) if reader.message_count else 0


def foreign_summary(files: list[Path]) -> ForeignSummary:
    """The topics, counts and time span of a ROS bag."""
    with _open(files) as reader:
        count = reader.message_count
        start = reader.start_time if count else 0
        return ForeignSummary(_storage(files), start, _last(reader), count, _topics(reader),
                              _compression(reader))


def foreign_span(files: list[Path]) -> tuple[int, int, list[tuple[Channel, Schema | None]]]:
    """(first, last message time, the channels zenros plays) of a ROS bag."""
    s = foreign_summary(files)
    for t in s.topics:
        if t.skipped:
            _warn_once(files, t, "skipped", f"not played: {t.skipped}")
    return s.start, s.end, [(t.channel, t.schema) for t in s.topics if t.channel is not None]


def iter_foreign(files: list[Path], topics: list[str] | None = None,
                 start: int | None = None) -> Iterator[BagMessage]:
    """Every message of a ROS bag zenros has a type for, converted, in log-time order.

    A message that does not decode is skipped (one warning per topic); so are topics zenros
    cannot play (one warning each)."""
    with _open(files) as reader:
        wanted = set(topics or ())
        plan = [t for t in _topics(reader) if not wanted or t.topic in wanted]
        by_conn: dict[int, ForeignTopic] = {}
        for t in plan:
            if t.skipped:
                _warn_once(files, t, "skipped", f"not played: {t.skipped}")
                continue
            for c in t.connections:
                by_conn[id(c)] = t
        if not by_conn:
            return
        conns = [c for t in plan if not t.skipped for c in t.connections]
        sequence: dict[int, int] = {}
        try:
            for conn, stamp, raw in reader.messages(connections=conns, start=start):
                t = by_conn[id(conn)]
                assert t.convert is not None and t.channel is not None
                try:
                    data = t.convert(raw)
                except Exception as exc:  # noqa: BLE001  # zenros, numpy or rosbags: a bad payload
                    _warn_once(files, t, "undecodable",
                               f"a message at {stamp} does not decode as {t.ros_type}, skipped "
                               f"({type(exc).__name__}: {exc}); so is any other that does not")
                    continue
                seq = sequence.get(t.channel.id, 0)
                sequence[t.channel.id] = seq + 1
                yield BagMessage(stamp, stamp, seq, t.channel, t.schema, data)
        except BagError:
            raise
        except Exception as exc:  # sqlite3's, OSError, rosbags' reader errors
            raise BagError(f"{files[0]}: corrupt ROS bag data ({type(exc).__name__}: "
                           f"{exc})") from exc
