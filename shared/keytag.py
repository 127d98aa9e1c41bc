"""Key tags: a sample names the key it was published on, so a misrouted one can be told.

Zenoh 1.10 can hand a subscriber a sample published on another key after a link between two
sessions dropped and came back (a process frozen past the lease, a box at load 100): the
sample arrives under the subscriber's own key, so nothing in it tells. zenros publishers attach
a short tag of their key (11 bytes: ``zk1`` and 8 bytes of BLAKE2b) to every sample, and
subscribers drop a sample whose tag names another key (docs/wire.md, "Misrouted samples").
A sample with no tag, or an attachment that is not a tag (another tool's), is taken as it is.
"""

from __future__ import annotations

import hashlib
from typing import Any

__all__ = ["TAG_SIZE", "key_tag", "misrouted"]

_MAGIC = b"zk1"
TAG_SIZE = len(_MAGIC) + 8


def key_tag(key: str) -> bytes:
    """The tag of a key expression, attached to each sample published on it."""
    return _MAGIC + hashlib.blake2b(key.encode(), digest_size=8).digest()


def misrouted(attachment: Any, tag: bytes) -> bool:
    """True when ``attachment`` (a sample's, or None) is a key tag other than ``tag``."""
    if attachment is None:
        return False
    data: bytes = attachment.to_bytes()
    return len(data) == TAG_SIZE and data[:3] == _MAGIC and data != tag
