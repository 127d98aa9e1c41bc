"""Key tags: a sample names the key it was published on, so a misrouted one can be told.

Zenoh 1.10 can hand a subscriber a sample published on another key after a link between two
sessions dropped and came back (a process frozen past the lease, a box at load 100): the
sample arrives under the subscriber's own key, so nothing in it tells. zenros publishers attach
a short tag of their key to every sample, and subscribers drop a sample whose tag names
another key (docs/wire.md, "Misrouted samples"). A sample with no tag, or an attachment that
is not a tag (another tool's), is taken as it is.

Two kinds: ``zk1`` and 8 bytes of BLAKE2b of the key (11 bytes: action feedback and status),
and ``zk2``, the same 8 bytes and 8 of the sample's encoding (19 bytes: a topic's publisher).
A subscription whose sample carries exactly its own ``zk2`` tag knows the key and the type
without comparing the encoding.
"""

from __future__ import annotations

import hashlib
from typing import Any

__all__ = ["TAG_SIZE", "TYPED_TAG_SIZE", "key_tag", "misrouted"]

_MAGIC = b"zk1"
_MAGIC_TYPED = b"zk2"
TAG_SIZE = len(_MAGIC) + 8
TYPED_TAG_SIZE = TAG_SIZE + 8


def _digest(text: str) -> bytes:
    return hashlib.blake2b(text.encode(), digest_size=8).digest()


def key_tag(key: str, encoding: str | None = None) -> bytes:
    """The tag of a key expression, attached to each sample published on it; with
    ``encoding`` (``mime;type``), the typed tag that names the samples' encoding too."""
    if encoding is None:
        return _MAGIC + _digest(key)
    return _MAGIC_TYPED + _digest(key) + _digest(encoding)


def misrouted(attachment: Any, tag: bytes) -> bool:
    """True when ``attachment`` (a sample's, or None) is a key tag of either kind that names
    another key than ``tag`` (of either kind) does."""
    if attachment is None:
        return False
    data: bytes = attachment.to_bytes()
    if len(data) == TAG_SIZE:
        is_tag = data[:3] == _MAGIC
    else:
        is_tag = len(data) == TYPED_TAG_SIZE and data[:3] == _MAGIC_TYPED
    return is_tag and data[3:TAG_SIZE] != tag[3:TAG_SIZE]
