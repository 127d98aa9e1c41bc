"""Zenoh plumbing shared by action servers and clients: encodings, query decoding, the latched
status topic and error payloads."""

from __future__ import annotations

import json
import threading
from collections.abc import Callable
from functools import cache
from typing import Any, TypeVar

import zenoh
from zenoh import ext as zext

from ..codec import Codec, codec_for, split_encoding
from ..errors import CodecError
from ..message import Message
from ..msgs.builtin_interfaces import Time
from ..rpc import error_payload

__all__ = [
    "accepted_attachment",
    "accepted_stamp",
    "answer",
    "answer_err",
    "decode_query",
    "encoding_for",
    "error_payload",
    "parse_error",
    "query_once",
    "query_replies",
    "status_publisher",
    "status_subscriber",
]

M = TypeVar("M", bound=Message)

RESULT_ON_GOAL = b"result"
"""The send_goal attachment that asks the server to answer the goal's result on the same
query, as a second reply after the acceptance (a zenros addition; see docs/actions.md)."""

_ACCEPTED = b"accepted "


def accepted_attachment(stamp: Time) -> bytes:
    """The attachment of a result reply that also carries the goal's acceptance (a goal that
    ended before its acceptance was sent): ``accepted <sec> <nanosec>``."""
    return b"%s%d %d" % (_ACCEPTED, stamp.sec, stamp.nanosec)


def accepted_stamp(sample: zenoh.Sample) -> Time | None:
    """The acceptance stamp a result reply carries, or None if it carries none."""
    att = sample.attachment
    if att is None:
        return None
    raw = att.to_bytes()
    if not raw.startswith(_ACCEPTED):
        return None
    try:
        sec, nanosec = raw[len(_ACCEPTED):].split()
        return Time(sec=int(sec), nanosec=int(nanosec))
    except ValueError:  # malformed: the result still counts, the stamp stays unknown
        return Time()


@cache
def encoding_for(msg_type: type[Message]) -> zenoh.Encoding:
    """The Zenoh encoding of a type: its MIME type with the wire type name as schema."""
    codec = codec_for(msg_type)
    return zenoh.Encoding(codec.mime).with_schema(codec.type_name)


def answer(query: zenoh.Query, data: bytes, encoding: zenoh.Encoding,
           attachment: bytes | None = None) -> None:
    """Reply and finalize at once: Zenoh sends a query's replies only when it is dropped, so
    a reply followed by more work in the same callback would wait for that work."""
    query.reply(query.key_expr, data, encoding=encoding, attachment=attachment)
    query.drop()  # type: ignore[no-untyped-call]


def answer_err(query: zenoh.Query, kind: str, message: str) -> None:
    """An error reply (``{"error": kind, "message": ...}``), finalized at once."""
    query.reply_err(error_payload(kind, message))
    query.drop()  # type: ignore[no-untyped-call]


def parse_error(data: bytes) -> tuple[str, str]:
    """``(kind, message)`` of an error reply; Zenoh's own errors (``Timeout``) have no JSON."""
    try:
        body = json.loads(data)
        return str(body["error"]), str(body["message"])
    except (ValueError, KeyError, TypeError):
        text = data.decode("utf-8", "replace")
        return text, text


def decode_query(query: zenoh.Query, codec: Codec[M], what: str) -> M | str:
    """The request of ``query``, or (a string) why it cannot be decoded; the caller replies."""
    payload = query.payload
    if payload is None:
        return f"{what}: empty request; expected {codec.type_name}"
    enc = query.encoding
    # The schema must match when one is given; a bare MIME type (z_get sends zenoh/bytes)
    # is accepted and the payload decides. The usual case, the exact encoding, is one compare.
    schema = "" if enc is None or enc == encoding_for(codec.type) else split_encoding(str(enc))[1]
    if schema and schema != codec.type_name:
        return f"{what}: type mismatch: expected {codec.type_name}, got {schema}"
    try:
        return codec.decode(payload.to_bytes())
    except CodecError as exc:
        return f"{what}: {exc}"


def status_publisher(session: zenoh.Session, key: str, msg_type: type[Message]) -> Any:
    """A latched publisher (last sample cached for late joiners), as QOS_LATCHED topics use."""
    return zext.declare_advanced_publisher(
        session, key, encoding=encoding_for(msg_type),
        congestion_control=zenoh.CongestionControl.BLOCK,
        cache=zext.CacheConfig(max_samples=1),
        sample_miss_detection=zext.MissDetectionConfig(heartbeat=None, sporadic_heartbeat=0.5),
        publisher_detection=True,
    )


def status_subscriber(session: zenoh.Session, key: str,
                      callback: Callable[[zenoh.Sample], None]) -> Any:
    """A subscriber that also fetches the latched sample of publishers already there."""
    return zext.declare_advanced_subscriber(
        session, key, callback,
        history=zext.HistoryConfig(detect_late_publishers=True, max_samples=1),
        recovery=zext.RecoveryConfig(heartbeat=True, periodic_queries=None),
        subscriber_detection=True,
    )


def query_once(session: zenoh.Session, key: str, payload: bytes, encoding: zenoh.Encoding,
               timeout: float, done: Callable[[zenoh.Reply | None], None],
               destination: zenoh.Locality = zenoh.Locality.ANY) -> None:
    """A non-blocking query to the best-matching queryable: ``done(reply)`` runs once, with
    the first reply, or with None when the query ends without one (no server).

    ``done`` runs on a Zenoh network thread (``indirect=False``: the default would start a
    thread per query). It must be quick and must not call Zenoh: a new query from there can
    deadlock. Hand further work to another thread.
    """
    lock = threading.Lock()
    called = False

    def once(reply: zenoh.Reply | None) -> None:
        nonlocal called
        with lock:
            if called:
                return
            called = True
        done(reply)

    session.get(key, zenoh.handlers.Callback(once, lambda: once(None), indirect=False),
                payload=payload, encoding=encoding, target=zenoh.QueryTarget.BEST_MATCHING,
                timeout=timeout, allowed_destination=destination)


def query_replies(session: zenoh.Session, key: str | zenoh.KeyExpr, payload: bytes,
                  encoding: zenoh.Encoding, timeout: float,
                  on_reply: Callable[[zenoh.Reply], None], on_final: Callable[[], None],
                  attachment: bytes | None = None,
                  destination: zenoh.Locality = zenoh.Locality.ANY) -> None:
    """A non-blocking query whose every reply is handed to ``on_reply`` as it arrives (no
    consolidation: a server may answer more than once, e.g. acceptance then result), then
    ``on_final()`` once the query ended (the server dropped it, or ``timeout``).

    Both run on a Zenoh network thread, with the rules of `query_once`.
    """
    session.get(key, zenoh.handlers.Callback(on_reply, on_final, indirect=False),
                payload=payload, encoding=encoding, target=zenoh.QueryTarget.BEST_MATCHING,
                consolidation=zenoh.ConsolidationMode.NONE, timeout=timeout,
                attachment=attachment, allowed_destination=destination)
