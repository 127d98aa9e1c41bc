"""Text about the buffer: tf2's insert-refusal reasons, frame errors, and the frame dumps."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from ..errors import InvalidArgumentException, LookupException
from .cache import Cache
from .rigid import Tf
from .stamps import NS

__all__ = [
    "frame_error",
    "frame_listing",
    "frames_as_string",
    "frames_as_yaml",
    "insert_problems",
    "unknown_frame",
]

_MAX_LISTED = 50


def insert_problems(parent: str, child: str, authority: str, v: Tf) -> list[str]:
    """Every reason tf2 would refuse this link (empty if it is acceptable).

    ``parent`` and ``child`` have had one leading '/' stripped already.
    """
    out = []
    if parent == child:
        out.append(
            f'TF_SELF_TRANSFORM: Ignoring transform from authority "{authority}" with frame_id '
            f'and child_frame_id "{child}" because they are the same'
        )
    if not child:
        out.append(
            f'TF_NO_CHILD_FRAME_ID: Ignoring transform from authority "{authority}" because '
            "child_frame_id not set"
        )
    if not parent:
        out.append(
            f'TF_NO_FRAME_ID: Ignoring transform with child_frame_id "{child}" from authority '
            f'"{authority}" because frame_id not set'
        )
    if any(c - c != 0.0 for c in v):
        out.append(
            f'TF_NAN_INPUT: Ignoring transform for child_frame_id "{child}" from authority '
            f'"{authority}" because of a nan (or infinite) value in the transform '
            f"({v[0]} {v[1]} {v[2]}) ({v[3]} {v[4]} {v[5]} {v[6]})"
        )
    n = v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]
    if not abs(n - 1.0) < 0.01:
        out.append(
            f'TF_DENORMALIZED_QUATERNION: Ignoring transform for child_frame_id "{child}" from '
            f'authority "{authority}" because of an invalid quaternion in the transform '
            f"({v[3]} {v[4]} {v[5]} {v[6]}): squared norm {n}, expected 1 ± 0.01"
        )
    return out


def frame_listing(frames: Iterable[str]) -> str:
    """Sorted frame names, comma separated, cut after 50."""
    names = sorted(frames)
    if not names:
        return "none"
    shown = ", ".join(names[:_MAX_LISTED])
    more = len(names) - _MAX_LISTED
    return shown + (f", ... ({more} more)" if more > 0 else "")


def unknown_frame(frame: str, arg: str, frames: Iterable[str]) -> LookupException:
    """tf2's "does not exist" error, plus the list of known frames."""
    return LookupException(
        f'"{frame}" passed to {arg} does not exist. Known frames: {frame_listing(frames)}'
    )


def frame_error(frame: str, arg: str) -> InvalidArgumentException | None:
    """tf2's error for an empty or '/'-prefixed frame id in a query, else None."""
    if not frame:
        return InvalidArgumentException(
            f"Invalid argument passed to {arg} in tf2 frame_ids cannot be empty"
        )
    if frame[0] == "/":
        return InvalidArgumentException(
            f"Invalid argument \"{frame}\" passed to {arg} - in tf2 frame_ids cannot start "
            "with a '/'"
        )
    return None


def frames_as_string(caches: Mapping[str, Cache]) -> str:
    """One line per child frame: ``Frame X exists with parent Y.`` (tf2's format)."""
    lines = []
    for child, cache in caches.items():
        latest = cache.latest()
        parent = latest[1] if latest is not None else "NO_PARENT"
        lines.append(f"Frame {child} exists with parent {parent}.\n")
    return "".join(lines)


def frames_as_yaml(
    caches: Mapping[str, Cache], authority: Mapping[str, str], now_ns: int = 0
) -> str:
    """tf2's ``allFramesAsYAML``: parent, broadcaster, rate and time span per child frame.

    Frames whose cache is empty are left out, as in tf2. With ``now_ns`` (not 0), each
    entry also gets ``transform_delay`` (now minus the newest stamp). The text is valid
    YAML; an empty buffer gives ``{}``.
    """
    out = []
    for child, cache in caches.items():
        latest = cache.latest()
        if latest is None:
            continue
        newest, oldest = cache.newest(), cache.oldest()
        span = (newest - oldest) / NS
        rate = len(cache) / max(span, 0.0001)
        out.append(
            f"'{_q(child)}':\n"
            f"  parent: '{_q(latest[1])}'\n"
            f"  broadcaster: '{_q(authority.get(child, 'no recorded authority'))}'\n"
            f"  rate: {rate:.3f}\n"
            f"  most_recent_transform: {newest / NS:.3f}\n"
            f"  oldest_transform: {oldest / NS:.3f}\n"
            + (f"  transform_delay: {(now_ns - newest) / NS:.3f}\n" if now_ns else "")
            + f"  buffer_length: {span:.3f}\n"
        )
    return "".join(out) if out else "{}\n"


def _q(s: str) -> str:
    return s.replace("'", "''")
